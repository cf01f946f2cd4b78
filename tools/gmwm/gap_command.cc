// gmwm gap INPUT (--model SPEC_WITH_VALUES | --kalibr imu.yaml | --gazebo FILE.sdf | --fit SPEC)
//              [--units gyro=deg/s,accel=g] [--sensor gyro|accel] [--replicates B]
// Where a simulator's (or a fitted) noise model departs from each column's WV, which
// unmodelled effect explains it, and how much of the gap it removes (docs/gap.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <iostream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include <tbb/parallel_for.h>

#include "common.h"
#include "units_tables.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/engine/physical.h"
#include "gmwm/selection/cross_axis.h"
#include "gmwm/selection/gap.h"

namespace gmwm::cli {
namespace {

struct GapArgs {
  InputOptions input;
  std::string model;   ///< --model SPEC_WITH_VALUES
  std::string kalibr;  ///< --kalibr imu.yaml
  std::string gazebo;  ///< --gazebo FILE.sdf (gz-sensors <noise> blocks or a RotorS/PX4 IMU plugin)
  std::string fit;     ///< --fit SPEC
  std::string units;   ///< --units gyro=deg/s,accel=g
  std::string sensor;  ///< --sensor gyro|accel (all columns)
  std::string temperature;  ///< --temperature COLUMN
  int replicates = selection::GapOptions{}.replicates;
  bool no_unit_check = false;  ///< --no-unit-check
};

// A simulator's Gauss-Markov bias whose correlation time is at least this many records
// long is a random walk over the record: its WV differs from RW(gamma2 = its innovation
// variance)'s by about tau / (2 T) relative, at most 5% at the coarsest scale.
constexpr double kRandomWalkLikeRecords = 10.0;

// Such a bias replaced by that random walk, said in the conversions: a Kalibr yaml and an
// SDF or RotorS file carrying the same densities then give the same baseline (and the
// same diagnosis). Nothing else is simplified: a term too small to show in one record's
// WV still belongs to the simulator's noise.
void random_walk_like(Model& base, Eigen::VectorXd& theta, std::int64_t n, std::vector<std::string>& conversions) {
  std::vector<Component> comps;
  std::vector<double> values;
  bool changed = false;
  for (int c = 0; c < base.num_components(); ++c) {
    const Component& comp = base.components()[static_cast<std::size_t>(c)];
    const Process& p = *comp.process;
    const double* th = theta.data() + base.offset(c);
    const double T = p.name() == "AR1" && th[0] > 0.0 && th[0] < 1.0 ? -1.0 / std::log(th[0]) : 0.0;
    if (T >= kRandomWalkLikeRecords * static_cast<double>(n)) {
      const Model rw = parse_model("RW(gamma2=" + fmt(th[1], 17) + ")", p.context());
      comps.push_back(rw.components()[0]);
      values.push_back(th[1]);
      conversions.push_back("over this record (" + std::to_string(n) + " samples) the Gauss-Markov bias " +
                            p.name() + " (correlation time " + fmt(T, 3) + " samples, " +
                            fmt(T / static_cast<double>(n), 3) + " records) is RW-like: RW(gamma2 = its innovation "
                            "variance " + fmt(th[1], 6) + "), as a random-walk density gives");
      changed = true;
      continue;
    }
    comps.push_back(comp);
    values.insert(values.end(), th, th + p.size());
  }
  if (!changed) return;
  Eigen::VectorXd t = Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  base = Model(std::move(comps)).canonical(&t);
  theta = t;
}

// The finest levels compared for a unit mix-up (white noise dominates there on an IMU).
constexpr int kUnitCheckLevels = 3;

// Before diagnosing: a data / baseline ratio at the finest levels near a unit factor
// ((180/pi)^2 for deg/s read as rad/s, 9.80665^2 for m/s^2 read as g, ...) is a unit
// mix-up, not a gap: stop with one line naming the --units that fits.
void check_units(const std::string& path, const std::string& column, const WaveletVariance& wv, const Model& base,
                 const Eigen::VectorXd& theta, const std::map<io::SensorKind, io::Unit>& units,
                 std::optional<io::SensorKind> sensor) {
  io::SensorKind kind;
  try {
    kind = sensor ? *sensor : io::sensor_kind_of_column(column);
  } catch (const InputError&) {
    return;  // neither a gyro nor an accelerometer: no unit to suggest
  }
  const Eigen::VectorXd nu = base.wv(theta, wv.tau);
  std::vector<double> r;
  for (int j = 0; j < std::min(kUnitCheckLevels, wv.levels()); ++j) r.push_back(wv.wv[static_cast<std::size_t>(j)] / nu(j));
  if (r.empty()) return;
  std::sort(r.begin(), r.end());
  const double ratio = r[r.size() / 2];
  const io::Unit& declared = units.at(kind);
  const auto s = io::suggest_unit(ratio, kind, declared);
  if (!s) return;
  throw InputError(path + ": column '" + column + "': its WV at the finest scales is " + fmt(ratio, 3) +
                   " x the baseline's, near (" + s->unit.name + " per " + declared.name + ")^2 = " + fmt(s->factor, 4) +
                   ": the data look like " + s->unit.name + ", not " + declared.name + "; give --units " +
                   io::to_string(kind) + "=" + s->unit.name + " (or --no-unit-check if the sensor really is that far "
                   "from the baseline)");
}

std::string seconds_text(double tau, const io::SignalSet& set) {
  return set.freq_known ? fmt(tau / set.freq, 3) + " s" : fmt(tau, 6) + " samples";
}

std::string summary_line(const std::string& name, const selection::GapResult& g) { return name + ": " + g.headline; }

// The first added effect's parameters with their bootstrap intervals, discrete and in
// the continuous units a navigation engineer uses.
std::string effect_table(const selection::GapResult& g, const io::SignalSet& set, const std::string& unit) {
  const FitResult& f = g.final_fit;
  if (f.status == FitStatus::kFailed || f.theta.size() != f.model.num_parameters() || f.theta.size() == 0) return {};
  Table t({"effect parameter", "value", "95% interval (bootstrap)", "unit"}, 1);
  for (const auto& r : io::parameter_rows(f))
    t.add({r.process + " " + r.name, fmt(r.value, 5), fmt(r.ci_low, 4) + " - " + fmt(r.ci_high, 4), "discrete"});
  if (set.freq_known && f.ci_low.size() == f.theta.size())
    for (int k = 0; k < f.model.num_components(); ++k) {
      const Process& p = *f.model.components()[static_cast<std::size_t>(k)].process;
      const std::span<const double> th(f.theta.data() + f.model.offset(k), static_cast<std::size_t>(p.size()));
      const auto q = p.physical(th, set.freq);
      const auto iv = physical_interval(
          p, th, std::span<const double>(f.ci_low.data() + f.model.offset(k), static_cast<std::size_t>(p.size())),
          std::span<const double>(f.ci_high.data() + f.model.offset(k), static_cast<std::size_t>(p.size())), set.freq);
      for (std::size_t i = 0; i < q.size(); ++i)
        if (!q[i].unit_pattern.empty())
          t.add({p.name() + " " + q[i].name, fmt(q[i].value, 5),
                 i < iv.size() ? fmt(iv[i].low, 4) + " - " + fmt(iv[i].high, 4) : "",
                 render_unit(q[i].unit_pattern, unit.empty() ? "U" : unit)});
    }
  return t.str();
}

std::string terminal_report(const std::string& name, const selection::GapResult& g, const io::SignalSet& set,
                            const std::vector<std::string>& conversions, const std::string& unit) {
  std::ostringstream os;
  os << summary_line(name, g) << '\n';
  os << "  baseline: " << g.baseline.to_string(g.baseline_theta) << '\n';
  for (const auto& c : conversions) os << "  conversion: " << c << '\n';
  Table levels({"tau", "ratio", "z", "reference band", "outside"});
  for (const auto& l : g.levels)
    levels.add({seconds_text(l.tau, set), fmt(l.ratio, 4), fmt(l.z, 3), fmt(l.ref_low, 3) + " - " + fmt(l.ref_high, 3),
                l.outside ? "yes" : ""});
  os << levels.str();
  if (!g.candidates.empty()) {
    Table cand({"candidate", "improvement", "threshold", "2 x optimism (WVIC)", "cleared", "fit"}, 1);
    for (const auto& c : g.candidates)
      cand.add({selection::to_string(c.effect), fmt(c.improvement, 5), fmt(c.threshold, 4), fmt(2.0 * c.optimism, 4),
                c.cleared ? "yes" : "", c.model});
    os << cand.str();
  }
  const auto& s = g.shrinkage;
  os << "  objective " << fmt(s.objective_before) << " -> " << fmt(s.objective_after) << " (null mean "
     << fmt(s.null_mean, 4) << " -> " << fmt(s.null_mean_after, 4) << "), levels outside " << s.levels_outside_before << " -> " << s.levels_outside_after
     << ", global p " << fmt(s.p_value_before, 3) << " -> " << fmt(s.p_value_after, 3) << '\n';
  int disjoint = 0;
  for (const auto& h : g.split_half) disjoint += h.disjoint;
  if (!g.split_half.empty())
    os << "  split halves: " << disjoint << " of " << g.split_half.size()
       << " levels disagree (95% CIs disjoint)" << (disjoint ? ": the record is not stationary" : "") << '\n';
  os << effect_table(g, set, unit);
  if (std::isfinite(g.navigation.rms_without))
    os << "  integrated error after " << fmt(g.navigation.horizon_seconds, 3)
       << " s (attitude for a gyro, velocity for an accelerometer): " << fmt(g.navigation.rms_without, 3) << " -> "
       << fmt(g.navigation.rms_with, 3) << " " << render_unit("U*s", unit.empty() ? "U" : unit)
       << " RMS (baseline -> with the effects)\n";
  if (g.contamination_screened) {
    os << "  contamination screen: ";
    if (g.contaminated_levels.empty()) os << "no level flagged";
    for (std::size_t i = 0; i < g.contaminated_levels.size(); ++i)
      os << (i ? ", " : "levels flagged at ")
         << seconds_text(g.levels[static_cast<std::size_t>(g.contaminated_levels[i] - 1)].tau, set);
    os << " (robust WV below the classical one beyond the data's rounding, with far outliers)\n";
  }
  for (const auto& r : g.refused) os << "  refused (does not make the fit better): " << r << '\n';
  for (const auto& n : g.notes) os << "  note: " << n << '\n';
  return os.str();
}

// One line per correlated pair: the scales where its cross-axis correlation is significant.
std::string cross_axis_text(const std::vector<selection::CrossAxisPair>& pairs, const io::SignalSet& set) {
  std::map<std::pair<int, int>, std::vector<const selection::CrossAxisPair*>> by_pair;
  for (const auto& p : pairs)
    if (p.significant) by_pair[{p.a, p.b}].push_back(&p);
  std::string out;
  for (const auto& [ab, v] : by_pair) {
    double peak = 0.0;
    for (const auto* p : v)
      if (std::abs(p->rho) > std::abs(peak)) peak = p->rho;
    out += "  cross-axis: " + set.signals[static_cast<std::size_t>(ab.first)].name + " & " +
           set.signals[static_cast<std::size_t>(ab.second)].name + " correlated at " + seconds_text(v.front()->tau, set) +
           (v.size() > 1 ? " - " + seconds_text(v.back()->tau, set) : "") + " (" + std::to_string(v.size()) +
           (v.size() > 1 ? " levels" : " level") + ", rho up to " + fmt(peak, 3) + "): a shared effect\n";
  }
  return out;
}

// --temperature COLUMN: that column's values, taken out of the analysed signals.
std::vector<double> take_temperature(io::SignalSet& set, const std::string& column) {
  if (column.empty()) return {};
  std::string names;
  for (auto it = set.signals.begin(); it != set.signals.end(); ++it) {
    if (it->name == column) {
      std::vector<double> t = std::move(it->values);
      set.signals.erase(it);
      if (set.signals.empty()) throw InputError("--temperature '" + column + "': no other column is left to diagnose");
      return t;
    }
    names += (names.empty() ? "" : ", ") + it->name;
  }
  throw InputError("--temperature '" + column + "': no such column among those read (" + names +
                   "); include it in --columns");
}

// --kalibr FILE[:imuN]: the file, and the IMU of a chain (empty: the file is one IMU).
// Split at the last ':' only when the whole text is not a file, its head is, and its
// tail names an IMU (a file name may contain ':').
std::pair<std::string, std::string> kalibr_source(const std::string& text) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || fs::exists(text, ec)) return {text, ""};
  const std::string imu = text.substr(colon + 1);
  const bool names_imu =
      imu.size() > 3 && imu.rfind("imu", 0) == 0 && imu.find_first_not_of("0123456789", 3) == std::string::npos;
  if (names_imu) return {text.substr(0, colon), imu};  // a missing FILE is then reported by its own name
  if (!fs::exists(text.substr(0, colon), ec)) return {text, ""};
  throw InputError("--kalibr " + text + ": expected FILE or FILE:imuN (e.g. imu_chain.yaml:imu1), got '" + imu + "'");
}

int run_gap(const GapArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const WvOptions wv_opts = wv_options(args.input);
  declare_input(common, args.input.input);
  const auto [kalibr_path, kalibr_imu] = kalibr_source(args.kalibr);
  declare_input(common, kalibr_path);
  declare_input(common, args.gazebo);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  const int given = !args.model.empty() + !args.kalibr.empty() + !args.gazebo.empty() + !args.fit.empty();
  if (given != 1)
    throw InputError("gap: give exactly one baseline: --model SPEC_WITH_VALUES, --kalibr imu.yaml, --gazebo FILE.sdf "
                     "or --fit SPEC");
  const auto units = io::parse_units(args.units);
  std::optional<io::SensorKind> sensor;
  if (!args.sensor.empty()) sensor = args.sensor == "gyro" ? io::SensorKind::kGyro : io::SensorKind::kAccel;
  selection::GapOptions options;
  options.replicates = args.replicates;
  options.seed = common.seed;
  options.alpha = args.input.alpha;
  options.refit_baseline = !args.fit.empty();
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("gap: " + why);

  Stopwatch read_clock;
  io::SignalSet set = read_input(args.input);
  const std::vector<double> temperature = take_temperature(set, args.temperature);
  const double read_seconds = read_clock.seconds();
  const ProcessContext ctx{set.freq, set.freq_known};
  options.context = ctx;
  std::optional<io::SimConfig> config;
  if (!args.kalibr.empty()) config = io::read_kalibr_imu_yaml(kalibr_path, set.freq, units, kalibr_imu);
  if (!args.gazebo.empty()) config = io::read_gazebo_sdf(args.gazebo, set.freq, units);
  const std::string& config_path = !args.kalibr.empty() ? kalibr_path : args.gazebo;
  const std::optional<Model> spec_model =
      !args.model.empty() ? std::optional<Model>(parse_model(args.model, ctx))
                          : !args.fit.empty() ? std::optional<Model>(parse_model(args.fit, ctx)) : std::nullopt;
  if (spec_model && !args.model.empty()) {
    const Eigen::VectorXd v = spec_model->given_values();
    if (const std::string why = spec_model->validate(v); !why.empty() || !v.allFinite())
      throw InputError("--model '" + args.model + "': give every parameter's value (SPEC_WITH_VALUES), e.g. "
                       "WN(sigma2=2.5e-5)+RW(gamma2=1e-12)");
  }
  // Each column's baseline and the conversions behind it.
  const std::size_t K = set.signals.size();
  std::vector<Model> baselines(K);
  std::vector<std::vector<std::string>> conversions(K);
  for (std::size_t k = 0; k < K; ++k) {
    if (config) {
      const io::SensorKind kind = sensor ? *sensor : io::sensor_kind_of_column(set.signals[k].name);
      // The kind's model, or the column's axis's when the simulator's axes differ.
      auto b = io::baseline_for_column(*config, kind, set.signals[k].name);
      if (!b)
        throw InputError(config_path + ": every " + std::string(io::to_string(kind)) +
                         " figure is zero or absent, nothing to compare column '" + set.signals[k].name + "' with");
      baselines[k] = std::move(b->model);
      conversions[k] = std::move(b->conversions);
    } else {
      baselines[k] = *spec_model;
    }
  }
  Stopwatch wv_clock;
  const std::vector<WaveletVariance> wvs = compute_wv(set, wv_opts);
  robust::RobustWvOptions ropts;
  ropts.levels = wv_opts.levels;
  ropts.alpha = wv_opts.alpha;
  const std::vector<WaveletVariance> robust_wvs = compute_robust_wv(set, ropts);
  const double wv_seconds = wv_clock.seconds();

  // --fit: the family fitted on each column first.
  std::vector<Eigen::VectorXd> thetas(K);
  for (std::size_t k = 0; k < K; ++k) {
    check_model_fits_levels(baselines[k], wvs[k].levels());
    if (args.fit.empty()) {
      thetas[k] = baselines[k].given_values();
      if (config) random_walk_like(baselines[k], thetas[k], wvs[k].n, conversions[k]);
      if (!args.no_unit_check)
        check_units(set.path, set.signals[k].name, wvs[k], baselines[k], thetas[k], units, sensor);
      continue;
    }
    FitOptions fo;
    fo.inference = false;
    const FitResult f = fit_gmwm(wvs[k], baselines[k], fo);
    if (f.status == FitStatus::kFailed)
      throw InputError("--fit '" + args.fit + "': the fit failed on column '" + set.signals[k].name + "'");
    baselines[k] = f.model;
    thetas[k] = f.theta;
    conversions[k].push_back("baseline fitted on the column: " + f.model.to_string(f.theta));
  }

  // Progress on a terminal: per column, its reference replicates (half of its cost) and
  // then its attribution (the other half), with the time left.
  ProgressBar bar("gap: columns x steps", common);
  Stopwatch gap_clock;
  std::vector<selection::GapResult> results(K);
  const double per_column = 2.0 * options.replicates;
  for (std::size_t k = 0; k < K; ++k) {
    selection::GapOptions o = options;
    o.seed = common.seed + k;  // each column its own reference streams
    if (bar.enabled())
      o.progress = [&, k](int done, int) { bar.update(static_cast<double>(k) * per_column + done, K * per_column); };
    const std::vector<double>& x = set.signals[k].values;
    results[k] = selection::diagnose_gap(wvs[k], baselines[k], thetas[k], o, &robust_wvs[k], &x,
                                         temperature.empty() ? nullptr : &temperature);
    bar.update(static_cast<double>(k + 1) * per_column, K * per_column);
  }
  const double gap_seconds = gap_clock.seconds();

  io::Json doc = io::json_document("gap");
  doc["input"] = set.path;
  doc["baseline_source"] = config ? config->source : !args.fit.empty() ? "fit " + args.fit : "model";
  doc["replicates"] = args.replicates;
  doc["seed"] = common.seed;
  if (set.timing) doc["timing"] = io::timing_json(*set.timing);
  // The data unit of each column, when declared (--units, or a simulator's SI figures).
  std::vector<std::string> column_units(K);
  for (std::size_t k = 0; k < K; ++k)
    if (!args.units.empty() || config) column_units[k] = unit_of_column(units, sensor, set.signals[k].name);
  if (!temperature.empty()) doc["temperature_column"] = args.temperature;
  // Cross-axis wavelet correlation (docs/gap.md, method note 2) when several columns are given.
  std::vector<std::span<const double>> spans;
  for (const auto& sig : set.signals) spans.emplace_back(sig.values);
  const auto cross = selection::cross_axis_correlation(spans, wv_opts.levels, options.alpha);
  io::Json cross_json = io::Json::array();
  for (const auto& p : cross)
    if (p.significant)
      cross_json.push_back({{"a", set.signals[static_cast<std::size_t>(p.a)].name},
                            {"b", set.signals[static_cast<std::size_t>(p.b)].name},
                            {"tau", p.tau},
                            {"tau_seconds", set.freq_known ? io::Json(p.tau / set.freq) : io::Json(nullptr)},
                            {"rho", io::json_number(p.rho)},
                            {"z", io::json_number(p.z)}});
  doc["cross_axis"] = {{"tested", cross.size()}, {"significant", std::move(cross_json)}};
  for (std::size_t k = 0; k < K; ++k) {
    io::ColumnInfo info = column_info(set, k);
    info.unit = column_units[k];
    doc["columns"].push_back(io::gap_column_json(info, results[k], conversions[k]));
  }
  std::string report;
  if (common.show_table()) {
    if (set.timing) report += set.timing->summary() + "\n";
    for (std::size_t k = 0; k < K; ++k)
      report += (k ? "\n" : "") + terminal_report(set.signals[k].name, results[k], set, conversions[k], column_units[k]);
    report += "\nsummary:\n";
    for (std::size_t k = 0; k < K; ++k) report += "  " + summary_line(set.signals[k].name, results[k]) + "\n";
    report += cross_axis_text(cross, set);
  }
  warn_about_timing(set);
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds}, {"wv", wv_seconds}, {"gap", gap_seconds}, {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty()) {
    io::ReportData rep =
        report_data("gap", set, !args.model.empty() ? args.model : !args.fit.empty() ? "fit " + args.fit : config_path);
    for (std::size_t k = 0; k < K; ++k) {
      rep.columns[k].wvs = {wvs[k], robust_wvs[k]};
      rep.columns[k].gap = results[k];
      rep.columns[k].conversions = conversions[k];
      if (!column_units[k].empty()) rep.columns[k].unit = column_units[k];
    }
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) {
    std::cout << report;
    std::cout.flush();
  }
  return 0;
}

}  // namespace

Command add_gap_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<GapArgs>();
  CLI::App* sub = app.add_subcommand(
      "gap", "Where a simulator's or fitted noise model departs from each column, which effect explains it, and by how much");
  add_input_options(*sub, args->input);
  auto* m = sub->add_option("--model", args->model, "Baseline with every value, e.g. 'WN(sigma2=2.5e-5)+RW(gamma2=1e-12)'")
                ->type_name("SPEC_WITH_VALUES");
  auto* k = sub->add_option("--kalibr", args->kalibr, "Baseline from a Kalibr imu.yaml (noise densities and random walks); "
                            "FILE:imuN takes one IMU of a chain (imu0, imu1, ...)")
                ->type_name("imu.yaml[:imuN]");
  auto* z = sub->add_option("--gazebo", args->gazebo,
                            "Baseline from a Gazebo SDF: gz-sensors IMU <noise> blocks or RotorS/PX4 IMU plugin "
                            "parameters")
                ->type_name("FILE.sdf");
  auto* f = sub->add_option("--fit", args->fit, "Fit this family on each column first, then diagnose what it lacks")
                ->type_name("SPEC");
  m->excludes(k)->excludes(z)->excludes(f);
  k->excludes(z)->excludes(f);
  z->excludes(f);
  sub->add_option("--units", args->units, "Units of the columns, e.g. gyro=deg/s,accel=g (SI by default)")
      ->type_name("KIND=UNIT,...");
  sub->add_option("--sensor", args->sensor, "Treat every column as this sensor (else told by its name)")
      ->check(CLI::IsMember({"gyro", "accel"}));
  sub->add_option("--temperature", args->temperature,
                  "A temperature column: each signal's coupling to it is tested (TEMPERATURE); it is not diagnosed itself")
      ->type_name("COLUMN");
  sub->add_option("--replicates", args->replicates, "Reference replicates (parametric bootstrap of the baseline)")
      ->type_name("B")
      ->check(CLI::Range(20, 100000))
      ->capture_default_str();
  sub->add_flag("--no-unit-check", args->no_unit_check,
                "Diagnose even when a column's finest scales sit at a unit factor ((180/pi)^2, 9.80665^2, ...) "
                "from the baseline");
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_gap(*args, common); }};
}

}  // namespace gmwm::cli
