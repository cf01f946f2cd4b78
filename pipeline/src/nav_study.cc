// The navigation study (nav_study.h) as named stages: sources -> models in SI per axis ->
// covariance analysis -> Monte Carlo (when asked).
#include "gmwm/pipeline/nav_study.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/export.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/sim_config.h"

namespace gmwm::pipeline {

namespace {

// The Allan deviation grid a model's N and K are read on when no record length is known:
// the export's own assumption for a saved model (io/src/outputs/export_noise.cc), 1e6
// samples (2.8 h at 100 Hz), long enough for a random walk's +1/2 slope to show.
constexpr std::int64_t kAssumedRecordSamples = 1000000;

constexpr const char* kAxes[] = {"x", "y", "z"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A decimal number in full ("*5", "*1.5e1"), or nullopt.
std::optional<double> number_of(const std::string& s) {
  if (s.empty()) return std::nullopt;
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(x) || s.find_first_of("xXpPnN") != std::string::npos) return std::nullopt;
  return x;
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

}  // namespace

NavSource parse_nav_source(const std::string& given) {
  NavSource src;
  src.text = given;
  std::string body = trim(given);
  if (body.empty()) throw InputError("a model source is empty; expected truth, wnrw, a file or gyro=SPEC;accel=SPEC");
  // A trailing "*X": an inflation (a model string's own '*' is "2*AR1", never last).
  if (const auto star = body.rfind('*'); star != std::string::npos && body.find(')', star) == std::string::npos &&
                                         body.find('+', star) == std::string::npos) {
    const std::string factor = trim(body.substr(star + 1));
    const auto x = number_of(factor);
    if (!x || !(*x > 0.0))
      throw InputError("model source '" + given + "': the inflation after '*' must be a positive number, got '" +
                       factor + "'");
    src.inflate = *x;
    body = trim(body.substr(0, star));
  }
  if (body == "truth") {
    src.what = TruthModel{};
  } else if (body == "wnrw") {
    src.what = WnRwProjection{};
  } else if (body.find('=') != std::string::npos && (body.rfind("gyro", 0) == 0 || body.rfind("accel", 0) == 0)) {
    ModelStrings m;
    std::size_t from = 0;
    while (from <= body.size()) {
      const auto semi = body.find(';', from);
      const std::string part = trim(body.substr(from, semi == std::string::npos ? std::string::npos : semi - from));
      const auto eq = part.find('=');
      const std::string key = eq == std::string::npos ? part : trim(part.substr(0, eq));
      if (eq == std::string::npos || (key != "gyro" && key != "accel"))
        throw InputError("model source '" + given + "': '" + part + "' is not gyro=SPEC or accel=SPEC");
      (key == "gyro" ? m.gyro : m.accel) = trim(part.substr(eq + 1));
      if (semi == std::string::npos) break;
      from = semi + 1;
    }
    if (m.gyro.empty() || m.accel.empty())
      throw InputError("model source '" + given + "': give both sensors, gyro=SPEC;accel=SPEC");
    src.what = m;
  } else {
    src.what = ModelFile{body};
  }
  return src;
}

std::string NavStudyOptions::Validate() const {
  if (const std::string why = scenario.Validate(); !why.empty()) return "scenario: " + why;
  if (rate && (!(*rate > 0.0) || !std::isfinite(*rate))) return "rate: must be positive (Hz)";
  if (monte_carlo_runs < 0 || monte_carlo_runs == 1) return "Monte-Carlo runs: 0 (none) or at least 2";
  if (labels.size() > std::max<std::size_t>(filters.size(), 2))
    return "labels: " + std::to_string(labels.size()) + " given for " + std::to_string(filters.size()) +
           " filter models";
  for (const std::string& l : labels)
    if (l.empty()) return "labels: an empty label";
  return {};
}

namespace {

// ---- Stage 1: sources -> per-axis sensor models ----

// Sensor models per axis of one kind, from several named pieces.
struct KindModels {
  std::array<std::optional<nav::SensorModel>, 3> axes;
  std::optional<nav::SensorModel> all;  // the same on every axis
};

nav::SensorModel sensor_of(const Model& m, const Eigen::VectorXd& theta, double freq, double to_si) {
  nav::SensorModel s;
  s.model = m;
  s.theta = theta;
  s.freq = freq;
  s.to_si = to_si;
  return s;
}

// Fills the three axes of a kind, or says what is missing.
std::array<nav::SensorModel, 3> three_axes(const KindModels& k, const std::string& what, const std::string& who) {
  std::array<nav::SensorModel, 3> out;
  for (std::size_t a = 0; a < 3; ++a) {
    if (k.axes[a])
      out[a] = *k.axes[a];
    else if (k.all)
      out[a] = *k.all;
    else
      throw InputError(who + ": no " + what + " model for the " + kAxes[a] +
                       " axis (give a column or term per axis, or one for all)");
  }
  return out;
}

double rate_for(const NavStudyOptions& o, const NavModelInfo* truth, const std::string& who) {
  if (o.rate) return *o.rate;
  if (truth) return truth->model.gyro[0].freq;
  throw InputError(who + ": give the rate (Hz) at which its values are given");
}

io::Unit unit_of(const NavStudyOptions& o, io::SensorKind k) {
  const auto it = o.units.find(k);
  return it == o.units.end() ? io::si_unit(k) : it->second;
}

NavModelInfo from_result(const std::string& path, const NavStudyOptions& o) {
  io::ResultReadOptions ro;
  ro.rate = o.rate;
  if (!o.units.empty()) ro.units = o.units;
  const io::ResultColumns r = io::read_result_columns(path, ro);
  NavModelInfo info = imu_model_of(r.columns, path);
  info.source = "gmwm " + r.command + " result " + path;
  return info;
}

bool has_extension(const std::string& path, std::initializer_list<const char*> exts) {
  const std::string e = lower(std::filesystem::path(path).extension().string());
  for (const char* x : exts)
    if (e == x) return true;
  return false;
}

NavModelInfo from_config(const std::string& path, const NavStudyOptions& o, const NavModelInfo* truth) {
  const double f = rate_for(o, truth, path);
  const std::map<io::SensorKind, io::Unit> si;  // the readers' default: SI
  io::SimConfig c;
  if (has_extension(path, {".sdf", ".xml", ".urdf", ".world"})) {
    c = io::read_gazebo_sdf(path, f, si);
  } else {
    const std::string text = io::read_side_file(path, "a Kalibr imu.yaml or a datasheet yaml");
    c = text.find("accelerometer_noise_density") != std::string::npos ? io::parse_kalibr_imu_yaml(text, path, f, si)
                                                                      : io::parse_datasheet_yaml(text, path, f, si);
  }
  NavModelInfo info;
  info.source = c.source;
  for (const auto kind : {io::SensorKind::kGyro, io::SensorKind::kAccel}) {
    KindModels k;
    if (const auto it = c.models.find(kind); it != c.models.end())
      k.all = sensor_of(it->second, it->second.given_values(), f, 1.0);
    for (std::size_t a = 0; a < 3; ++a)
      if (const auto it = c.axis_models.find(std::string(io::to_string(kind)) + "_" + kAxes[a]);
          it != c.axis_models.end())
        k.axes[a] = sensor_of(it->second, it->second.given_values(), f, 1.0);
    const bool gyro = kind == io::SensorKind::kGyro;
    (gyro ? info.model.gyro : info.model.accel) = three_axes(k, gyro ? "gyroscope" : "accelerometer", path);
  }
  for (const auto& [kind, lines] : c.conversions)
    for (const auto& l : lines) info.lines.push_back(std::string(io::to_string(kind)) + ": " + l);
  for (const auto& n : c.notes) info.lines.push_back(n);
  return info;
}

NavModelInfo from_strings(const ModelStrings& m, const NavStudyOptions& o, const NavModelInfo* truth,
                          const std::string& text) {
  const double f = rate_for(o, truth, "model source '" + text + "'");
  NavModelInfo info;
  info.source = "models " + text;
  for (const auto kind : {io::SensorKind::kGyro, io::SensorKind::kAccel}) {
    const bool gyro = kind == io::SensorKind::kGyro;
    const std::string& spec = gyro ? m.gyro : m.accel;
    const Model model = parse_model(spec, ProcessContext{f, true});
    if (!model.fully_specified())
      throw InputError("model source '" + text + "': " + (gyro ? "gyro" : "accel") + "=" + spec +
                       ": give every parameter's value, e.g. WN(sigma2=1e-6)+RW(gamma2=1e-12)");
    const io::Unit u = unit_of(o, kind);
    (gyro ? info.model.gyro : info.model.accel).fill(sensor_of(model, model.given_values(), f, 1.0 / u.per_si));
  }
  return info;
}

// The figures N and K (SI) of one axis' model: read off its Allan deviation.
std::array<double, 2> white_and_walk(const nav::SensorModel& s) {
  const ChosenFigures f = model_only_figures(s.model, s.theta, s.freq, kAssumedRecordSamples);
  const double n = f.white.figure.available() ? f.white.figure.value : 0.0;
  const double k = f.walk.figure.available() ? f.walk.figure.value : 0.0;
  return {n * s.to_si, k * s.to_si};
}

nav::SensorModel projected(const nav::SensorModel& s) {
  const auto [n, k] = white_and_walk(s);
  const double f = s.freq;
  const Model m = parse_model(k > 0.0 ? "WN+RW" : "WN", ProcessContext{f, true});
  Eigen::VectorXd theta(m.num_parameters());
  theta(0) = n * n * f;               // sigma2 = N^2 f
  if (k > 0.0) theta(1) = k * k / f;  // gamma2 = K^2 / f
  return sensor_of(m, theta, f, 1.0);
}

// Each sensor's model in SI, one line per axis (the three on one line when alike).
std::vector<std::string> model_lines(const nav::ImuModel& m) {
  std::vector<std::string> out;
  for (const auto* kind : {&m.gyro, &m.accel}) {
    const std::string name = kind == &m.gyro ? "gyroscope" : "accelerometer";
    const std::string unit = kind == &m.gyro ? "rad/s" : "m/s^2";
    auto text = [&](const nav::SensorModel& s) {
      std::string t = s.model.to_string(s.theta);
      if (s.to_si != 1.0) t += " (values in a unit of " + std::to_string(s.to_si) + " " + unit + ")";
      return t + " at " + std::to_string(static_cast<long long>(std::lround(s.freq))) + " Hz";
    };
    const std::string x = text((*kind)[0]);
    if (text((*kind)[1]) == x && text((*kind)[2]) == x) {
      out.push_back(name + " (x, y, z): " + x);
    } else {
      for (std::size_t a = 0; a < 3; ++a) out.push_back(name + " " + kAxes[a] + ": " + text((*kind)[a]));
    }
  }
  return out;
}

}  // namespace

NavModelInfo imu_model_of(const std::vector<io::ExportColumn>& columns, const std::string& who) {
  KindModels gyro, accel;
  int count[2] = {0, 0};
  for (const io::ExportColumn& c : columns) ++count[c.kind == io::SensorKind::kGyro ? 0 : 1];
  for (const io::ExportColumn& c : columns) {
    KindModels& k = c.kind == io::SensorKind::kGyro ? gyro : accel;
    const nav::SensorModel s = sensor_of(c.model, c.theta, c.freq, 1.0 / c.unit.per_si);
    const char axis = io::column_axis(c.name);
    if (count[c.kind == io::SensorKind::kGyro ? 0 : 1] == 1) {
      k.all = s;  // one column of the kind stands for its three axes
    } else if (axis == 0) {
      throw InputError(who + ": column '" + c.name + "' names no axis (x, y or z) among several " +
                       io::to_string(c.kind) + " columns");
    } else {
      k.axes[static_cast<std::size_t>(std::tolower(axis) - 'x')] = s;
    }
  }
  NavModelInfo info;
  info.source = who;
  info.model.gyro = three_axes(gyro, "gyroscope", who);
  info.model.accel = three_axes(accel, "accelerometer", who);
  for (const char* kind : {"gyroscope", "accelerometer"})
    if ((kind[0] == 'g' ? gyro : accel).all)
      info.lines.push_back(std::string(kind) + ": one column for the three axes");
  return info;
}

nav::ImuModel wn_rw_projection(const nav::ImuModel& model, const std::string& label) {
  nav::ImuModel out;
  out.label = label;
  for (std::size_t a = 0; a < 3; ++a) {
    out.gyro[a] = projected(model.gyro[a]);
    out.accel[a] = projected(model.accel[a]);
  }
  return out;
}

NavModelInfo read_nav_model(const NavSource& source, const NavStudyOptions& options, const NavModelInfo* truth) {
  NavModelInfo info;
  if (std::holds_alternative<TruthModel>(source.what) || std::holds_alternative<WnRwProjection>(source.what)) {
    if (!truth) throw InputError("the truth cannot be '" + source.text + "': give a file or gyro=SPEC;accel=SPEC");
    if (std::holds_alternative<TruthModel>(source.what)) {
      info = *truth;
      info.source = "the truth's model";
    } else {
      info.model = wn_rw_projection(truth->model, source.text);
      info.source = "the truth's white noise and random walk (N and K read off each axis' Allan deviation)";
    }
    info.lines.clear();
  } else if (const auto* file = std::get_if<ModelFile>(&source.what)) {
    info = has_extension(file->path, {".json"}) ? from_result(file->path, options)
                                                : from_config(file->path, options, truth);
  } else {
    info = from_strings(std::get<ModelStrings>(source.what), options, truth, source.text);
  }
  info.model.label = source.text;
  if (source.inflate != 1.0) {
    for (auto* kind : {&info.model.gyro, &info.model.accel})
      for (nav::SensorModel& s : *kind) s.to_si *= source.inflate;
    info.source += ", every noise figure x " + std::to_string(source.inflate);
  }
  if (const std::string why = info.model.Validate(); !why.empty())
    throw InputError("model source '" + source.text + "': " + why);
  const auto lines = model_lines(info.model);
  info.lines.insert(info.lines.begin(), lines.begin(), lines.end());
  return info;
}

NavStudy study_nav(const NavStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  NavStudy out;
  out.scenario = options.scenario;
  out.monte_carlo_runs = options.monte_carlo_runs;
  out.seed = options.seed;
  // Stage 1: the models.
  out.truth = read_nav_model(options.truth, options, nullptr);
  out.truth.model.label = "truth";
  std::vector<NavSource> filters = options.filters;
  if (filters.empty()) filters = {parse_nav_source("truth"), parse_nav_source("wnrw")};
  std::vector<nav::ImuModel> models;
  for (std::size_t i = 0; i < filters.size(); ++i) {
    out.filters.push_back(read_nav_model(filters[i], options, &out.truth));
    if (i < options.labels.size()) out.filters.back().model.label = options.labels[i];
    models.push_back(out.filters.back().model);
  }
  // Stage 2: the covariance analysis; stage 3: its Monte-Carlo check.
  const auto t0 = std::chrono::steady_clock::now();
  out.exact = nav::analyse(out.truth.model, models, options.scenario, options.progress);
  const auto t1 = std::chrono::steady_clock::now();
  out.seconds_exact = std::chrono::duration<double>(t1 - t0).count();
  if (options.monte_carlo_runs > 0) {
    out.sampled = nav::monte_carlo(out.truth.model, models, options.scenario, options.monte_carlo_runs, options.seed,
                                   options.progress);
    out.seconds_sampled = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  return out;
}

std::string ConsistencyOptions::Validate() const {
  if (!(update_rate > 0.0) || !std::isfinite(update_rate)) return "the update rate must be positive (Hz)";
  if (!(horizon > 0.0) || !std::isfinite(horizon)) return "the horizon must be positive (s)";
  if (!(fix_sigma > 0.0) || !std::isfinite(fix_sigma)) return "the update's error must be positive (m)";
  if (!(precision > 0.0 && precision < 1.0)) return "the precision must be in (0, 1)";
  return {};
}

std::optional<ConsistencyOptions> consistency_from(std::span<const double> values) {
  if (values.size() < 2 || values.size() > 3) return std::nullopt;
  for (const double v : values)
    if (!(v > 0.0) || !std::isfinite(v)) return std::nullopt;
  ConsistencyOptions c;
  c.update_rate = values[0];
  c.horizon = values[1];
  if (values.size() == 3) c.fix_sigma = values[2];
  return c;
}

namespace {

// A filter is optimistic by nav's one verdict (nav::finish_verdict: not in band at 95% of the
// judged times, and above it at least as often as below); the search looks for the smallest
// factor with any other verdict, so that the figure it writes and the verdict it prints are
// the same statement (a second rule here, "above the band at <= 5% of times", once called a
// filter "the smallest keeping it from being optimistic" while its verdict said optimistic).
bool optimistic(const nav::FilterErrors& e) { return e.verdict == nav::Verdict::kOptimistic; }
constexpr double kLargestFactor = 1000.0;
// The warm-up before the judged stretch: 10 minutes aided, or 5 horizons when longer (a
// WN + RW filter started without a bias prior needs ~5 minutes to settle on the ADIS16405
// units at 20 Hz updates: NEES 13.6 -> 9.1 over 0-1200 s, docs/nav.md).
constexpr double kWarmUpSeconds = 600.0;
constexpr double kWarmUpHorizons = 5.0;

nav::ImuModel inflated(nav::ImuModel m, double x) {
  for (auto* kind : {&m.gyro, &m.accel})
    for (nav::SensorModel& s : *kind) s.to_si *= x;
  return m;
}

// The random walks' variances times x^2 (a WN + RW model: every RW component).
nav::ImuModel walk_inflated(nav::ImuModel m, double x) {
  for (auto* kind : {&m.gyro, &m.accel})
    for (nav::SensorModel& s : *kind)
      for (int c = 0; c < s.model.num_components(); ++c)
        if (s.model.components()[static_cast<std::size_t>(c)].process->role() == ProcessRole::kWalk)
          s.theta(s.model.offset(c)) *= x * x;
  return m;
}

// The smallest x of `inflate` keeping the filter from being optimistic (nav's verdict), the
// errors there, and the next smaller factor's verdict (the search's precision below it).
struct Found {
  double x = 1.0, smaller = 0.0, smaller_above = 0.0;
  nav::Verdict smaller_verdict = nav::Verdict::kOptimistic;
  nav::FilterErrors at;
};

Found smallest_factor(const std::function<nav::FilterErrors(const nav::ImuModel&)>& run,
                      const std::function<nav::ImuModel(double)>& inflate, const ConsistencyOptions& options) {
  Found f;
  f.at = run(inflate(1.0));
  if (!optimistic(f.at)) return f;
  double lo = 1.0, hi = 2.0;
  while (true) {  // grow until not optimistic
    f.at = run(inflate(hi));
    if (!optimistic(f.at)) break;
    lo = hi;
    hi *= 2.0;
    if (hi > kLargestFactor)
      throw InputError("--consistent-for: no inflation up to x" + std::to_string(static_cast<int>(kLargestFactor)) +
                       " keeps the WN + RW filter from being optimistic against the fitted model");
    if (options.progress && !options.progress(0.3)) throw InputError("cancelled");
  }
  while (hi / lo > 1.0 + options.precision) {  // then bisect on log x
    const double mid = std::sqrt(lo * hi);
    nav::FilterErrors m = run(inflate(mid));
    if (!optimistic(m)) {
      hi = mid;
      f.at = std::move(m);
    } else {
      lo = mid;
    }
  }
  f.x = hi;
  f.smaller = hi / (1.0 + options.precision);
  const nav::FilterErrors below = run(inflate(f.smaller));
  f.smaller_above = below.nees_above;
  f.smaller_verdict = below.verdict;
  return f;
}

}  // namespace

static std::string lacking(const nav::ImuModel& truth);

ConsistentInflation consistent_inflation(const nav::ImuModel& truth, const nav::ImuModel& filter,
                                         const ConsistencyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("--consistent-for: " + why);
  // The filter has run aided for a warm-up W before the stretch on the IMU alone, so that
  // its start (bias states at zero with no prior) is behind it; the NEES is judged over
  // [W - H, W + 2H): H aided, H on the IMU alone, H aided again.
  const double warm_up = std::max(kWarmUpSeconds, kWarmUpHorizons * options.horizon);
  nav::Scenario s;
  s.fix_rate = options.update_rate;
  s.fix_sigma = options.fix_sigma;
  s.horizon = warm_up + 2.0 * options.horizon;
  s.outages = {{warm_up, warm_up + options.horizon}};
  // Outputs about every second, a whole number of update periods.
  s.output_interval = std::max(1.0, std::round(options.update_rate)) / options.update_rate;
  s.judge_from = warm_up - options.horizon;
  const auto run = [&](const nav::ImuModel& model) { return nav::analyse(truth, {model}, s).filters.front(); };
  ConsistentInflation out;
  Found found = smallest_factor(
      run, [&](double x) { return walk_inflated(filter, x); }, options);
  if (found.at.verdict != nav::Verdict::kConsistent) {
    const Found both = smallest_factor(
        run, [&](double x) { return inflated(filter, x); }, options);
    if (both.at.verdict == nav::Verdict::kConsistent || both.at.nees_inside > found.at.nees_inside) {
      found = both;
      out.white = both.x;
    }
  }
  out.factor = found.x;
  out.smaller = found.smaller;
  out.smaller_above = found.smaller_above;
  out.smaller_verdict = found.smaller_verdict;
  out.verdict = found.at.verdict;
  out.nees_inside = found.at.nees_inside;
  char text[600];
  std::snprintf(
      text, sizeof text,
      "the smallest factor (to %.0f%%, %s) with which a filter assuming these WN + RW figures is not optimistic "
      "(its expected NEES inside its 95%% band at >= 95%% of times, or outside it more often below than above) "
      "against the full fitted model, updates at %g Hz "
      "(%g m), after %g s aided, %g s on the IMU alone; there its NEES is in band %.0f%% of the time (%s)",
      100.0 * options.precision, out.white == 1.0 ? "on K alone" : "on N and K", options.update_rate, options.fix_sigma,
      warm_up, options.horizon, 100.0 * out.nees_inside, nav::to_string(out.verdict));
  std::string reason = text;
  if (out.verdict != nav::Verdict::kConsistent)
    reason +=
        ": no inflation of N and K makes a WN + RW filter consistent here; it stays conservative (NEES below "
        "the band) where it is not inside; what it lacks: " +
        lacking(truth) + " (a filter with a Gauss-Markov bias state, or gmwm nav, shows the difference)";
  out.reason = reason;
  return out;
}

// The truth's components a WN + RW filter cannot represent, by process, with the range of
// their correlation times over the axes: "AR1 (T 7.15-12.4 s)".
static std::string lacking(const nav::ImuModel& truth) {
  std::vector<std::pair<std::string, std::array<double, 2>>> seen;  // name, T range (NaN: none)
  for (const auto* kind : {&truth.gyro, &truth.accel})
    for (const nav::SensorModel& s : *kind)
      for (int c = 0; c < s.model.num_components(); ++c) {
        const Process& p = *s.model.components()[static_cast<std::size_t>(c)].process;
        if (p.role() == ProcessRole::kWhite || p.role() == ProcessRole::kWalk || p.role() == ProcessRole::kQuantization)
          continue;
        const auto form =
            p.continuous_form({s.theta.data() + s.model.offset(c), static_cast<std::size_t>(p.size())}, s.freq);
        const double T = form && form->states() == 1 && form->F(0, 0) < 0.0 ? -1.0 / form->F(0, 0) : NAN;
        auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& e) { return e.first == p.name(); });
        if (it == seen.end()) {
          seen.push_back({p.name(), {T, T}});
        } else if (std::isfinite(T)) {
          it->second = {std::fmin(it->second[0], T), std::fmax(it->second[1], T)};
        }
      }
  std::string out;
  for (const auto& [name, t] : seen) {
    char range[96] = "";
    if (std::isfinite(t[0]))
      std::snprintf(range, sizeof range, t[0] == t[1] ? " (T %.3g s)" : " (T %.3g-%.3g s)", t[0], t[1]);
    out += (out.empty() ? "" : ", ") + name + range;
  }
  return out.empty() ? "nothing the model has beyond WN, RW and QN" : out;
}

}  // namespace gmwm::pipeline
