// The noise figures of an export: each column's continuous figures from its fitted model
// (axis_noise), what the chosen format can hold of them, the per-sensor aggregation, and
// the header every exported file carries (plan_export).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include "export_internal.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/physical.h"
#include "gmwm/version.h"
#include "gmwm/io/sim_config.h"

namespace gmwm::io {
namespace {

using export_detail::num;

// A Gauss-Markov term faster than this is white noise where N is read (IEEE 952 reads N
// at 1 s): it is part of N, not a bias of its own.
constexpr double kBiasMinCorrelationTime = 1.0;
// The record assumed for the model's Allan deviation when the result does not say how
// many samples there were (only the range of taus over which slopes are sought depends on it).
constexpr std::int64_t kAssumedRecordSamples = 1000000;

// "AR1(phi=0.99,sigma2=1e-06)": one component with its values.
std::string component_text(const Component& c, std::span<const double> th) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(th.size()));
  for (std::size_t i = 0; i < th.size(); ++i) theta(static_cast<Eigen::Index>(i)) = th[i];
  return Model(std::vector<Component>{c}).to_string(theta);
}

const char* title(ExportFormat f) {
  switch (f) {
    case ExportFormat::kKalibr:
      return "Kalibr imu.yaml";
    case ExportFormat::kOpenVins:
      return "OpenVINS kalibr_imu_chain.yaml";
    case ExportFormat::kVins:
      return "VINS-Mono/VINS-Fusion config (acc_n, gyr_n, acc_w, gyr_w)";
    case ExportFormat::kOrbSlam3:
      return "ORB-SLAM3 settings (IMU.NoiseGyro, ...)";
    case ExportFormat::kBasalt:
      return "Basalt calib.json IMU noise fields";
    case ExportFormat::kGzSdf:
      return "gz-sensors SDF IMU <noise> blocks";
    case ExportFormat::kRotors:
      return "RotorS/PX4 IMU plugin parameters";
  }
  return "?";
}

const char* kind_word(SensorKind k) { return k == SensorKind::kGyro ? "gyroscope" : "accelerometer"; }

// The figures a format writes for one column, and the lines for what it leaves out.
WrittenNoise written(const AxisNoise& a, const ExportOptions& o, std::vector<std::string>& dropped) {
  const export_detail::SiNames si = export_detail::si_names(a.kind);
  const double x = o.inflate;
  WrittenNoise w;
  w.noise_density = a.white * x;
  auto gm_line = [&](const GaussMarkovNoise& g, const std::string& why) {
    dropped.push_back(g.text + " (correlation time " + num(g.correlation_time) + " s, stationary sigma " +
                      num(g.sigma) + " " + si.value + "): " + why);
  };
  if (!export_detail::simulates_bias(o.format)) {
    w.random_walk = a.walk * o.inflate_walk.value_or(x);
    for (const auto& g : a.gauss_markov)
      gm_line(g, "a Gauss-Markov bias; the format models the bias as a random walk only");
  } else if (!a.gauss_markov.empty()) {
    const GaussMarkovNoise& g = a.gauss_markov.back();
    w.bias_drive = g.drive * x;
    w.bias_correlation_time = g.correlation_time;
    for (std::size_t i = 0; i + 1 < a.gauss_markov.size(); ++i)
      gm_line(a.gauss_markov[i], "the simulator models one bias, written from the longest correlation time");
    if (a.walk > 0.0 && a.figures.walk.source != "bound")
      dropped.push_back("RW (K = " + num(a.walk) + " " + si.walk +
                        "): the simulator models one bias, written from the Gauss-Markov term");
  } else if (a.walk > 0.0 && a.figures.walk.source != "bound") {
    // A bias is simulated only from a random walk the model or the data show; a mere
    // upper bound (no +1/2 slope) leaves the simulated bias off (said in the header).
    w.bias_drive = a.walk * x;
    w.bias_correlation_time = a.record_seconds > 0.0 ? export_detail::kRandomWalkTimeRecords * a.record_seconds
                                                     : export_detail::kRandomWalkFallbackTime;
    w.bias_from_random_walk = true;
  }
  for (const auto& other : a.others) dropped.push_back(other + ": no such term in the format");
  return w;
}

WrittenNoise aggregate(const std::vector<WrittenNoise>& ws, Aggregation how) {
  const bool worst = how == Aggregation::kWorst;
  // A correlation time is averaged over the columns with a bias: those with a fitted
  // Gauss-Markov bias when there are any (a random walk's long T would swamp theirs).
  bool any_gm = false;
  for (const auto& w : ws) any_gm = any_gm || (w.bias_drive > 0.0 && !w.bias_from_random_walk);
  auto over = [&](auto get, bool only_biased) {
    double sum = 0.0, top = 0.0;
    int count = 0;
    for (const auto& w : ws) {
      if (only_biased && (!(w.bias_drive > 0.0) || (any_gm && w.bias_from_random_walk))) continue;
      sum += get(w);
      top = std::max(top, get(w));
      ++count;
    }
    return count == 0 ? 0.0 : worst ? top : sum / count;
  };
  WrittenNoise c;
  c.noise_density = over([](const WrittenNoise& w) { return w.noise_density; }, false);
  c.random_walk = over([](const WrittenNoise& w) { return w.random_walk; }, false);
  c.bias_drive = over([](const WrittenNoise& w) { return w.bias_drive; }, false);
  c.bias_correlation_time = over([](const WrittenNoise& w) { return w.bias_correlation_time; }, true);
  bool any = false, all_walk = true;
  for (const auto& w : ws)
    if (w.bias_drive > 0.0) {
      any = true;
      all_walk = all_walk && w.bias_from_random_walk;
    }
  c.bias_from_random_walk = any && all_walk;
  return c;
}

std::string figures_text(const AxisNoise& a) {
  const export_detail::SiNames si = export_detail::si_names(a.kind);
  std::vector<std::string> parts;
  parts.push_back("N = " + num(a.white) + " " + si.density + " (" + a.figures.white.source + ")");
  parts.push_back("K = " + num(a.walk) + " " + si.walk + " (" + a.figures.walk.source + ")");
  parts.push_back("B = " + num(a.instability) + " " + si.value + " (" + a.figures.instability.source + ")");
  for (const auto& g : a.gauss_markov)
    parts.push_back("Gauss-Markov T = " + num(g.correlation_time) + " s, sigma = " + num(g.sigma) + " " + si.value +
                    " (driving density " + num(g.drive) + " " + si.walk + ")");
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

std::string units_line(const std::vector<AxisNoise>& columns) {
  std::string out = "Units: ";
  bool first = true;
  for (SensorKind k : {SensorKind::kGyro, SensorKind::kAccel}) {
    const AxisNoise* a = nullptr;
    for (const auto& c : columns)
      if (c.kind == k) a = &c;
    if (!a) continue;
    const Unit si = si_unit(k);
    out += first ? "" : "; ";
    first = false;
    out += std::string(to_string(k)) + " data in " + a->unit.name;
    if (a->unit.per_si == 1.0)
      out += " (SI, unchanged)";
    else
      out += " -> " + si.name + ": each figure divided by " + num(a->unit.per_si) + " " + a->unit.name + " per " +
             si.name + " (x " + num(1.0 / a->unit.per_si) + ")";
  }
  return out;
}

}  // namespace

ExportFigures export_figures(const ChosenFigures& f) {
  auto one = [](const ChosenFigure& c) { return ExportFigure{c.figure.value, to_string(c.source), c.note}; };
  return {one(f.white), one(f.walk), one(f.instability)};
}

AxisNoise axis_noise(const ExportColumn& column) {
  check_positive("axis_noise", "freq", column.freq);
  check_positive("axis_noise", "unit.per_si", column.unit.per_si);
  const Model& m = column.model;
  if (column.theta.size() != m.num_parameters())
    throw InvalidArgument("axis_noise: theta has " + std::to_string(column.theta.size()) + " values, but the model " +
                          m.to_string() + " has " + std::to_string(m.num_parameters()) + " parameters");
  AxisNoise a;
  a.column = column.name;
  a.kind = column.kind;
  a.axis = column_axis(column.name);
  a.freq = column.freq;
  a.record_seconds = column.n > 0 ? static_cast<double>(column.n) / column.freq : 0.0;
  a.model = m.to_string(column.theta);
  a.unit = column.unit;
  const double u = column.unit.per_si;  // data units per SI unit
  // N, K, B of the model as a whole (IEEE 952 read-offs), as the result chose them
  // against the data, else from the model's own Allan deviation over the record.
  a.figures = column.figures ? *column.figures
                             : export_figures(model_only_figures(m, column.theta, column.freq,
                                                                 column.n > 0 ? column.n : kAssumedRecordSamples));
  a.white = a.figures.white.value / u;
  a.walk = a.figures.walk.value / u;
  a.instability = a.figures.instability.value / u;
  for (int k = 0; k < m.num_components(); ++k) {
    const Component& c = m.components()[static_cast<std::size_t>(k)];
    const Process& p = *c.process;
    const std::span<const double> th(column.theta.data() + m.offset(k), static_cast<std::size_t>(p.size()));
    // The components by their continuous quantities (engine/physical.h), picked by kind so
    // that any process stating them maps the same way.
    const auto q = p.physical(th, column.freq);
    const double white = quantity_of_kind(q, PhysicalKind::kNoiseDensity);
    const double walk = quantity_of_kind(q, PhysicalKind::kRandomWalk);
    const double T = quantity_of_kind(q, PhysicalKind::kCorrelationTime);
    const double sigma = quantity_of_kind(q, PhysicalKind::kStationarySigma);
    // A Gauss-Markov bias has a positive lag-1 autocovariance; an AR1 with phi < 0 (an
    // alternating process) shares the quantities' names but is no bias.
    double g[2] = {0.0, 0.0};
    if (std::isfinite(T)) p.generalized_autocovariance(th, g);
    if (std::isfinite(white) || std::isfinite(walk)) continue;  // in N and K
    if (std::isfinite(T) && T > 0.0 && std::isfinite(sigma) && g[1] > 0.0) {
      const double s = sigma / u;
      const GaussMarkovNoise gm{T, s, s * std::sqrt(2.0 / T), component_text(c, th)};
      if (T >= kBiasMinCorrelationTime)
        a.gauss_markov.push_back(gm);
      else
        a.absorbed.push_back(gm.text + " (correlation time " + num(T) + " s)");
      continue;
    }
    std::string text = component_text(c, th);
    std::string figures;
    for (const auto& x : q)
      if (!x.unit_pattern.empty() || x.kind == PhysicalKind::kFrequency)
        figures += (figures.empty() ? "" : ", ") + x.name + " " + num(x.value) + " " +
                   render_unit(x.unit_pattern, column.unit.name);
    a.others.push_back(figures.empty() ? text : text + " (" + figures + ", " + column.unit.name + " data)");
  }
  std::sort(a.gauss_markov.begin(), a.gauss_markov.end(), [](const GaussMarkovNoise& x, const GaussMarkovNoise& y) {
    return x.correlation_time < y.correlation_time;
  });
  return a;
}

namespace export_detail {

void plan_export(const std::vector<ExportColumn>& columns, const ExportOptions& o, const std::string& source,
                 ExportResult& r) {
  // The update rate: --rate, else the data's (one rate for all columns).
  const double f0 = columns.front().freq;
  bool same_rate = true;
  std::string rates;
  for (const auto& c : columns) {
    same_rate = same_rate && std::abs(c.freq - f0) <= 1e-9 * f0;
    rates += (rates.empty() ? "" : ", ") + c.name + " " + num(c.freq) + " Hz";
  }
  if (!o.rate && !same_rate)
    throw InputError("export: the columns were sampled at different rates (" + rates +
                     "); give --rate HZ, the IMU rate for the update-rate fields");
  // A rate estimated from timestamps carries rounding noise in its last digits (1 / median
  // step = 199.99999999999997 Hz): the update rate keeps 10 significant digits of it.
  r.rate = o.rate ? *o.rate : std::strtod(num(f0, 10).c_str(), nullptr);
  for (const auto& c : columns) r.columns.push_back(axis_noise(c));

  std::vector<std::string> not_representable;
  std::vector<WrittenNoise> per_column;
  for (const auto& a : r.columns) {
    std::vector<std::string> dropped;
    per_column.push_back(written(a, o, dropped));
    if (dropped.empty()) continue;
    std::string names;
    for (const auto& d : dropped) {
      not_representable.push_back("  " + a.column + ": " + d);
      names += (names.empty() ? "" : ", ") + d.substr(0, d.find_first_of("( "));
    }
    r.warnings.push_back("column '" + a.column + "': " + names + " not representable in " + title(o.format) +
                         ": left out (listed in the file's header)");
  }

  std::vector<std::string> missing;
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel}) {
    KindExport k;
    k.kind = kind;
    std::vector<WrittenNoise> ws;
    std::array<int, 3> at{-1, -1, -1};
    bool axes_ok = true;
    for (std::size_t i = 0; i < r.columns.size(); ++i) {
      if (r.columns[i].kind != kind) continue;
      k.columns.push_back(r.columns[i].column);
      ws.push_back(per_column[i]);
      const char axis = r.columns[i].axis;
      const int slot = axis ? axis - 'x' : -1;
      if (slot < 0 || at[static_cast<std::size_t>(slot)] >= 0)
        axes_ok = false;
      else
        at[static_cast<std::size_t>(slot)] = static_cast<int>(ws.size()) - 1;
    }
    if (k.columns.empty()) {
      missing.push_back(kind_word(kind));
      r.kinds.push_back(k);
      continue;
    }
    if (o.aggregation == Aggregation::kPerAxis) {
      if (!axes_ok || ws.size() != 3) {
        std::string list;
        for (const auto& c : k.columns) list += (list.empty() ? "" : ", ") + c;
        throw InputError(std::string("--aggregate per-axis: expected one ") + to_string(kind) +
                         " column for each of the axes x, y and z (names ending in the axis letter, e.g. " +
                         to_string(kind) + "_x), found " + list + "; or use --aggregate mean or worst");
      }
      k.per_axis = true;
      for (std::size_t s = 0; s < 3; ++s) k.axes[s] = ws[static_cast<std::size_t>(at[s])];
    }
    k.combined = aggregate(ws, o.aggregation == Aggregation::kWorst ? Aggregation::kWorst : Aggregation::kMean);
    // The figures come from the Allan deviation (a bound where no slope shows), so they
    // are positive for any noise; a zero would mean a degenerate fit.
    const bool zero_white = k.per_axis ? std::any_of(k.axes.begin(), k.axes.end(),
                                                     [](const WrittenNoise& w) { return !(w.noise_density > 0.0); })
                                       : !(k.combined.noise_density > 0.0);
    if (zero_white)
      r.warnings.push_back(std::string(to_string(kind)) + ": the fitted model implies no white noise at all: the " +
                           kind_word(kind) + " noise density is written as 0 (check the fit)");
    r.kinds.push_back(k);
  }
  if (!missing.empty() && o.missing == MissingSensor::kRefuse) {
    const std::string word = missing.front(), other = word == "gyroscope" ? "accelerometer" : "gyroscope";
    throw InputError("export: no " + word + " column in the source, and a " + std::string(to_string(o.format)) +
                     " file has " + word + " fields: a 0 (or a field left out, which some readers take as 0) " +
                     "would be read as a perfect " + word + "; export a result that has " + word +
                     " columns too, or give --partial to write the " + other +
                     "'s fields alone (to paste into a file that has the " + word + "'s)");
  }

  // The header.
  auto& h = r.header;
  h.push_back(std::string("Generated by gmwm ") + library_version() + " (gmwm export, format " + to_string(o.format) +
              "): " + title(o.format));
  h.push_back("Source: " + source);
  h.push_back("Fitted models (discrete, per sample, in the data's unit) and their continuous figures (SI):");
  for (const auto& a : r.columns)
    h.push_back("  " + a.column + " (" + to_string(a.kind) + ", " + a.unit.name + " at " + num(a.freq) + " Hz" +
                (a.record_seconds > 0.0 ? ", " + num(a.record_seconds) + " s record" : std::string()) +
                "): " + a.model + " -> " + figures_text(a));
  h.push_back(
      "Noise figures: IEEE Std 952 read-offs of the Allan deviation of the model as a whole (N on the -1/2 "
      "slope at 1 s, K on the +1/2 slope at 3 s, B = flat minimum / 0.664), or of the data where the model "
      "misses them; a figure neither shows is its upper bound. Per column:");
  for (const auto& a : r.columns) {
    for (const ExportFigure* f : {&a.figures.white, &a.figures.walk, &a.figures.instability})
      h.push_back("  " + a.column + " (" + a.unit.name + " data): " + f->note);
    for (const auto& x : a.absorbed) h.push_back("  " + a.column + ": " + x + ": part of N (faster than 1 s)");
  }
  std::string agg = std::string("Aggregation: ") + to_string(o.aggregation) + ": ";
  agg += o.aggregation == Aggregation::kPerAxis ? "one figure per axis"
         : o.aggregation == Aggregation::kMean  ? "the arithmetic mean of each figure over a sensor's columns"
                                                : "the largest value of each figure over a sensor's columns";
  if (simulates_bias(o.format) && o.aggregation != Aggregation::kPerAxis)
    agg +=
        " (a bias correlation time over the columns with a fitted Gauss-Markov bias, else over those with a "
        "random walk)";
  for (const auto& k : r.kinds)
    if (!k.columns.empty()) {
      std::string list;
      for (const auto& c : k.columns) list += (list.empty() ? "" : ", ") + c;
      agg += "; " + std::string(to_string(k.kind)) + ": " + list;
    }
  h.push_back(agg);
  if (o.inflate_walk && *o.inflate_walk != o.inflate)
    h.push_back("Inflation: x" + num(o.inflate) + " on the noise densities N, x" + num(*o.inflate_walk) +
                " on the random walks K (variances x" + num(o.inflate * o.inflate) + " and x" +
                num(*o.inflate_walk * *o.inflate_walk) + ")" +
                (o.inflation_reason.empty() ? std::string() : "; " + o.inflation_reason));
  else
    h.push_back(o.inflate == 1.0
                    ? "Inflation: x1 (the fitted figures as they are)"
                    : "Inflation: x" + num(o.inflate) +
                          " on every noise figure written (noise densities, random walks, standard deviations and bias "
                          "driving densities; not on variances, which grow x" +
                          num(o.inflate * o.inflate) + "); correlation times unchanged" +
                          (o.inflation_reason.empty() ? std::string() : "; " + o.inflation_reason));
  h.push_back(units_line(r.columns));
  h.push_back(o.rate && (!same_rate || std::abs(*o.rate - f0) > 1e-9 * f0)
                  ? "Rate: " + num(r.rate) + " Hz (as given; the data: " + rates + ")"
                  : "Rate: " + num(r.rate) + " Hz (the data's rate)");
  bool walk_as_bias = false;
  for (const auto& a : r.columns)
    walk_as_bias = walk_as_bias || (simulates_bias(o.format) && a.gauss_markov.empty() && a.walk > 0.0);
  if (walk_as_bias)
    h.push_back(
        "Random walk as a bias: no exact form in the simulator's Gauss-Markov bias; written as a bias driven "
        "by K with a correlation time " +
        num(kRandomWalkTimeRecords) + " x the record's length (" + num(kRandomWalkFallbackTime) +
        " s when unknown): over the record it drifts like the random walk to within 0.05%");
  if (not_representable.empty()) {
    h.push_back(std::string("Not representable in ") + title(o.format) + ": none");
  } else {
    h.push_back(std::string("Not representable in ") + title(o.format) + " (left out):");
    h.insert(h.end(), not_representable.begin(), not_representable.end());
  }
  for (const auto& word : missing) {
    const std::string line =
        o.missing == MissingSensor::kZero
            ? std::string("No ") + word + " column in the source: the " + word + " figures are written as 0"
            : std::string("No ") + word + " column in the source (--partial): the " + word +
                  " fields are left out; add your own before using the file";
    h.push_back(line);
    r.warnings.push_back(line);
  }
}

}  // namespace export_detail
}  // namespace gmwm::io
