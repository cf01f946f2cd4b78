// Which figure to put in a filter: the model's read-off or the data's (choose_noise_figures),
// the reports that pair them, and the Kalman terms of the chosen figures
// (docs/noise-figures.md, "Which figure to use").
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/noise_figures.h"
#include "noise_figures_internal.h"

namespace gmwm {

using figures::fmt;
using figures::kFloorAgreement;
using figures::quantization_scale;
using figures::ramp_scale;
using figures::shows;
using figures::walk_scale;
using figures::white_scale;

const char* to_string(FigureSource s) {
  switch (s) {
    case FigureSource::kModel:
      return "model";
    case FigureSource::kData:
      return "data";
    case FigureSource::kBound:
      return "bound";
  }
  return "?";
}

std::optional<FigureSource> parse_figure_source(const std::string& name) {
  for (FigureSource s : {FigureSource::kModel, FigureSource::kData, FigureSource::kBound})
    if (name == to_string(s)) return s;
  return std::nullopt;
}

namespace {

std::size_t nearest_point(const AllanDeviation& adev, double tau) {
  std::size_t at = 0;
  for (std::size_t i = 1; i < adev.size(); ++i)
    if (std::abs(adev.tau[i] - tau) < std::abs(adev.tau[at] - tau)) at = i;
  return at;
}

// A model's bound bounds the sensor only where its curve is not below what the data show:
// the line touching the model's curve at tau is an upper bound for the model's term, and the
// sensor's only if the model's curve there is at or above the low end of the data's interval
// (a usable point). A model fitted below the data's long scales (a record whose gaps leave
// only short complete windows: issue 47, imu1 gyro_z, the model's K bound 10x below the
// data's) would otherwise bound the figure by its own extrapolation.
bool model_bound_holds(const Readoff& model, const AllanDeviation& adev, std::span<const double> model_adev,
                       const ReadoffOptions& o) {
  if (!model.available() || !std::isfinite(model.tau) || adev.size() == 0) return false;
  const std::size_t at = nearest_point(adev, model.tau);
  return at < model_adev.size() && adev.edf[at] >= o.min_edf && model_adev[at] >= adev.ci_low[at];
}

// The line of the figure's slope touching the data's curve from below: the lowest
// adev(tau) * scale(tau) over the usable points.
Readoff touching_bound(const AllanDeviation& adev, double (*scale)(double), const ReadoffOptions& o) {
  Readoff b;
  for (std::size_t i = 0; i < adev.size(); ++i) {
    if (!(adev.edf[i] >= o.min_edf) || !(adev.adev[i] > 0.0)) continue;
    const double v = adev.adev[i] * scale(adev.tau[i]);
    if (!(v >= b.value)) b.value = v, b.tau = adev.tau[i];
  }
  return b;
}

// B's source is tested over the data's whole floor, not only at its lowest point: in a flat
// bottom the lowest point wanders with the noise (imu2 gyro_x with 5% of its samples
// removed: 41 s on the complete record, 69 s on the gappy one), so a model that leaves the
// data's interval anywhere on the floor would be chosen or not by where that point fell.
// The rule leans towards the data's B: each point's 95% interval holds at that point, so a
// model that follows the data misses one of several floor points more often than 5% of the
// time (neighbouring points share most of their windows, so less often than independent
// tests would); the figure written is then the data's own read-off, the IEEE 952 one, at the
// price of its noise rather than of a model's bias. The first usable point of [from, to]
// where the model's curve is outside the data's interval, or has no value (adev.size() when
// it is inside at every one).
std::size_t first_miss_over(const AllanDeviation& adev, std::span<const double> model_adev, double from, double to,
                            const ReadoffOptions& o) {
  for (std::size_t i = 0; i < adev.size(); ++i) {
    if (!(adev.tau[i] >= from && adev.tau[i] <= to) || !(adev.edf[i] >= o.min_edf)) continue;
    const double mv = i < model_adev.size() ? model_adev[i] : NAN;
    if (!(std::isfinite(mv) && mv >= adev.ci_low[i] && mv <= adev.ci_high[i])) return i;
  }
  return adev.size();
}

// The points around the data's minimum `at` that the data cannot tell from it: the
// contiguous usable points whose interval reaches the minimum's (the floor B is read from, as
// seen through the record's length), as [from, to] in seconds.
std::pair<double, double> floor_span(const AllanDeviation& adev, std::size_t at, const ReadoffOptions& o) {
  auto on_floor = [&](std::size_t i) { return adev.edf[i] >= o.min_edf && adev.ci_low[i] <= adev.ci_high[at]; };
  std::size_t a = at, b = at;
  while (a > 0 && on_floor(a - 1)) --a;
  while (b + 1 < adev.size() && on_floor(b + 1)) ++b;
  return {adev.tau[a], adev.tau[b]};
}

// Why the data's bound is written where the model's is smaller: "" when it is not.
std::string model_bound_set_aside(const Readoff& model, double written) {
  if (!model.available() || !(model.value < written)) return {};
  return "; the model's smaller bound " + fmt(model.value) + " is set aside: its curve at " + fmt(model.tau) +
         " s lies below the data's interval";
}

// Where the data's figure is read, is the model's curve inside the data's interval? At the
// point nearest data.tau; for B (`floor`) at every point of the data's floor.
struct WhereRead {
  std::size_t at = 0;        ///< the point checked (for B the first one missed, if any)
  double model_value = NAN;  ///< the model's Allan deviation there
  bool inside = false;
  double from = NAN, to = NAN;  ///< seconds: the points checked
};

WhereRead check_where_read(const Readoff& data, const AllanDeviation& adev, std::span<const double> model_adev,
                           bool floor, const ReadoffOptions& o) {
  WhereRead w;
  w.at = nearest_point(adev, data.tau);
  w.model_value = w.at < model_adev.size() ? model_adev[w.at] : NAN;
  w.inside = std::isfinite(w.model_value) && w.model_value >= adev.ci_low[w.at] && w.model_value <= adev.ci_high[w.at];
  w.from = w.to = data.tau;
  if (!floor) return w;
  const auto [from, to] = floor_span(adev, w.at, o);
  w.from = std::min(from, data.tau);
  w.to = std::max(to, data.tau);
  if (data.region_to > data.region_from)  // the flat part, whatever its intervals
    w.from = std::min(w.from, data.region_from), w.to = std::max(w.to, data.region_to);
  if (w.inside && w.to > w.from) {
    const std::size_t miss = first_miss_over(adev, model_adev, w.from, w.to, o);
    if (miss < adev.size())
      w.at = miss, w.model_value = miss < model_adev.size() ? model_adev[miss] : NAN, w.inside = false;
  }
  return w;
}

ChosenFigure choose(const Readoff& model, const Readoff& data, const AllanDeviation& adev,
                    std::span<const double> model_adev, const char* name, const char* feature, double (*scale)(double),
                    const ReadoffOptions& o) {
  ChosenFigure c;
  c.model = model;
  c.data = data;
  const bool data_shows = data.available() && data.status != ReadoffStatus::kBound;
  const bool model_shows = model.available() && model.status != ReadoffStatus::kBound;
  if (data_shows) {
    const auto [at, mv, inside, floor_from, floor_to] = check_where_read(data, adev, model_adev, !scale, o);
    // B is the curve's level at its minimum, where the record holds the fewest averages and
    // the interval is widest (imu3 gyro_x: a model 35% above the data's minimum at 390 s
    // was inside it): the model's value must also be within kFloorAgreement of the data's.
    const bool floor_agrees = scale || std::abs(mv / adev.adev[at] - 1.0) <= kFloorAgreement;
    if (model_shows && inside && !floor_agrees) {
      c.figure = data;
      c.source = FigureSource::kData;
      c.note = std::string(name) + " from the data's Allan deviation: the model's curve at " + fmt(data.tau) +
               " s is inside the data's interval but " + fmt(100.0 * std::abs(mv / adev.adev[at] - 1.0)) +
               "% off their minimum (more than " + fmt(100.0 * kFloorAgreement) + "%); the model's " + name + " is " +
               fmt(model.value);
      return c;
    }
    if (model_shows && inside) {
      c.figure = model;
      c.source = FigureSource::kModel;
      c.note = std::string(name) + " from the model, read where the data show the " + feature +
               ": its Allan deviation is inside the data's interval there (" + fmt(data.tau) + " s)";
      return c;
    }
    if (inside && scale && model.available() && model.status == ReadoffStatus::kBound) {
      // The model follows the data where they show the slope, and says what makes it: no
      // term of that kind (a white noise crossing into a drift is no random walk). The
      // figure is then only bounded, by the smaller of the data's and the model's bounds.
      const Readoff b = touching_bound(adev, scale, o);
      const bool use_data =
          b.available() && (!(model.value < b.value) || !model_bound_holds(model, adev, model_adev, o));
      c.figure = use_data ? b : model;
      c.figure.status = ReadoffStatus::kBound;
      c.figure.low = NAN;
      c.figure.high = c.figure.value;
      c.source = FigureSource::kBound;
      std::string shares;
      for (const auto& [component, share] : model.sources)
        shares += (shares.empty() ? "" : ", ") + component + " " + fmt(100.0 * share) + "%";
      c.note = std::string(name) + " not read: the data's " + feature + " at " + fmt(data.tau) +
               " s follows the model's curve (inside the data's interval there), and " +
               model.how.substr(0, model.how.find(": an upper bound")) +
               (shares.empty() ? std::string() : ": other terms crossing (" + shares + ")") +
               "; written as the upper bound " + fmt(c.figure.value) + " (the line touching the " +
               (use_data ? "data's" : "model's") + " curve at " + fmt(c.figure.tau) + " s)" +
               (use_data ? model_bound_set_aside(model, b.value) : std::string());
      return c;
    }
    c.figure = data;
    c.source = FigureSource::kData;
    if (!model_shows)
      c.note = std::string(name) + " from the data's Allan deviation: the model's shows no " + feature;
    else
      c.note = std::string(name) + " from the data's Allan deviation: the model misses it at " + fmt(adev.tau[at]) +
               " s" +
               (floor_to > floor_from ? " on their floor (" + fmt(floor_from) + "-" + fmt(floor_to) +
                                            " s, the points around the minimum whose intervals reach its own, and "
                                            "the flat part)"
                                      : std::string()) +
               " (model/data " + fmt(mv / adev.adev[at]) + ", outside the data's " + fmt(100.0 * (1.0 - adev.alpha)) +
               "% interval); the model's " + name + " is " + fmt(model.value) + " (read at " + fmt(data.tau) + " s)";
    return c;
  }
  if (model_shows) {
    const bool below = !data.available() || model.value <= data.value;
    if (below) {
      c.figure = model;
      c.source = FigureSource::kModel;
      c.note = std::string(name) + " from the model (the data alone show no " + feature +
               (data.available() ? ", only a bound of " + fmt(data.value) : std::string()) + ")";
      return c;
    }
  }
  // A bound: the smaller of what either curve allows (the model's where it holds).
  const bool use_data = data.available() && (!model.available() || data.value <= model.value ||
                                             !model_bound_holds(model, adev, model_adev, o));
  c.figure = use_data ? data : model;
  c.figure.status = ReadoffStatus::kBound;
  c.figure.low = NAN;
  c.figure.high = c.figure.value;
  c.source = FigureSource::kBound;
  const std::string where = std::isfinite(c.figure.tau)
                                ? " (the line touching the " + std::string(use_data ? "data's" : "model's") +
                                      " curve at " + fmt(c.figure.tau) + " s)"
                                : std::string();
  // A model bound with a region: its curve shows the slope, but no term of that kind makes it.
  const bool model_crossing = model.available() && !model_shows && std::isfinite(model.region_from);
  c.note = std::string(name) + " not read: " +
           (model_shows ? "the data show no " + std::string(feature) + " and the model's value " + fmt(model.value) +
                              " exceeds their upper bound"
            : model_crossing ? "the data show no " + std::string(feature) + ", and " + model.how
                             : "neither the data's nor the model's Allan deviation shows a " + std::string(feature)) +
           "; written as the upper bound " + fmt(c.figure.value) + where +
           (use_data ? model_bound_set_aside(model, data.value) : std::string());
  return c;
}

}  // namespace

ChosenFigures choose_noise_figures(const NoiseFigures& model, const NoiseFigures& data, const AllanDeviation& data_adev,
                                   std::span<const double> model_adev, const ReadoffOptions& options) {
  ChosenFigures out;
  out.white = choose(model.white, data.white, data_adev, model_adev, "N", "-1/2 slope", white_scale, options);
  // A bump bending the curve near 1 s is said with N (the export header carries the note):
  // the model's names its component; the data's where the model has none.
  const std::string& bends = !model.white.bends.empty() ? model.white.bends : data.white.bends;
  if (!bends.empty()) {
    out.white.note += "; " + bends;
    out.white.figure.bends = bends;
  }
  out.walk = choose(model.walk, data.walk, data_adev, model_adev, "K", "+1/2 slope", walk_scale, options);
  out.instability =
      choose(model.instability, data.instability, data_adev, model_adev, "B", "minimum", nullptr, options);
  out.quantization = choose(model.quantization, data.quantization, data_adev, model_adev, "Q", "-1 slope",
                            quantization_scale, options);
  out.ramp = choose(model.ramp, data.ramp, data_adev, model_adev, "R", "+1 slope", ramp_scale, options);
  return out;
}

namespace {

// The figures when only one curve is at hand: each its read-off (source `shown`) or its
// bound, and the read-offs recorded on that side.
ChosenFigures one_sided_choice(const NoiseFigures& f, FigureSource shown, const std::string& curve) {
  auto take = [&](const Readoff& r, const char* name) {
    ChosenFigure c;
    c.figure = r;
    (shown == FigureSource::kData ? c.data : c.model) = r;
    const bool shows = r.available() && r.status != ReadoffStatus::kBound;
    c.source = shows ? shown : FigureSource::kBound;
    c.note = std::string(name) + (shows ? " from " + curve : " not read in " + curve + ": " + r.how);
    return c;
  };
  ChosenFigures out;
  for (int k = 0; k < kFigureCount; ++k) out[k] = take(f[k], std::string(1, kFigureNames[k].symbol).c_str());
  return out;
}

}  // namespace

FigureReport noise_figure_report(std::span<const double> x, double freq, const Model& model,
                                 const Eigen::VectorXd& theta, const Eigen::MatrixXd* covariance,
                                 const AllanOptions& allan, const ReadoffOptions& readoff) {
  return noise_figure_report(allan_deviation(x, freq, allan), model, theta, covariance, readoff);
}

FigureReport noise_figure_report(AllanDeviation adev, const Model& model, const Eigen::VectorXd& theta,
                                 const Eigen::MatrixXd* covariance, const ReadoffOptions& readoff) {
  FigureReport r;
  r.adev = std::move(adev);
  r.data = read_noise_figures(r.adev, readoff);
  r.model_adev = model_allan_deviation(model, theta, r.adev.m);
  const Eigen::MatrixXd* cov = covariance && covariance->size() > 0 ? covariance : nullptr;
  r.model = model_noise_figures(model, theta, r.adev, cov, readoff, &r.data);
  r.chosen = choose_noise_figures(r.model, r.data, r.adev, r.model_adev, readoff);
  return r;
}

FigureReport noise_figure_report_from_wv(const WaveletVariance& wv, double freq, const Model& model,
                                         const Eigen::VectorXd& theta, const Eigen::MatrixXd* covariance,
                                         const ReadoffOptions& readoff) {
  check_positive("noise_figure_report_from_wv", "freq", freq);
  FigureReport r;
  AllanDeviation& a = r.adev;
  a.freq = freq;
  a.n = wv.n;
  a.alpha = wv.alpha;
  const double eff = wv.efficiency.value_or(1.0);
  for (int j = 0; j < wv.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j);
    if (!(wv.wv[i] > 0.0)) continue;
    a.m.push_back(static_cast<std::int64_t>(wv.tau[i] / 2.0));
    a.tau.push_back(wv.tau[i] / 2.0 / freq);
    a.adev.push_back(std::sqrt(2.0 * wv.wv[i]));
    a.ci_low.push_back(std::sqrt(2.0 * std::max(wv.ci_low[i], 0.0)));
    a.ci_high.push_back(std::sqrt(2.0 * wv.ci_high[i]));
    a.edf.push_back(wv.eta[i] * eff);
  }
  r.data = read_noise_figures(a, readoff);
  r.model_adev = model_allan_deviation(model, theta, a.m);
  const Eigen::MatrixXd* cov = covariance && covariance->size() > 0 ? covariance : nullptr;
  r.model = model_noise_figures(model, theta, a, cov, readoff, &r.data);
  r.chosen = choose_noise_figures(r.model, r.data, a, r.model_adev, readoff);
  return r;
}

FigureReport data_figure_report(std::span<const double> x, double freq, const AllanOptions& allan,
                                const ReadoffOptions& readoff) {
  return data_figure_report(allan_deviation(x, freq, allan), readoff);
}

FigureReport data_figure_report(AllanDeviation adev, const ReadoffOptions& readoff) {
  FigureReport r;
  r.adev = std::move(adev);
  r.data = read_noise_figures(r.adev, readoff);
  r.chosen = one_sided_choice(r.data, FigureSource::kData, "the data's Allan deviation");
  return r;
}

ChosenFigures model_only_figures(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                 const ReadoffOptions& readoff, const Eigen::MatrixXd* covariance,
                                 const std::string& why) {
  check_positive("model_only_figures", "freq", freq);
  check_at_least("model_only_figures", "n", static_cast<double>(n), 4.0);
  AllanDeviation grid;
  grid.freq = freq;
  grid.n = n;
  grid.alpha = readoff.alpha;
  grid.m = allan_factors(n, AllanOptions{}.points_per_octave);
  for (std::int64_t m : grid.m) {
    grid.tau.push_back(static_cast<double>(m) / freq);
    grid.edf.push_back(std::max(static_cast<double>(n - 2 * m + 1) / static_cast<double>(2 * m), 1.0));
  }
  grid.adev = model_allan_deviation(model, theta, grid.m);
  grid.ci_low = grid.ci_high = grid.adev;
  const NoiseFigures f = model_noise_figures(model, theta, grid, covariance, readoff);
  return one_sided_choice(f, FigureSource::kModel, why);
}

std::vector<KalmanTerm> kalman_terms(const ChosenFigures& figures, double filter_rate) {
  check_positive("kalman_terms", "filter_rate", filter_rate);
  std::vector<KalmanTerm> out;
  const double N = figures.white.figure.value, K = figures.walk.figure.value;
  if (std::isfinite(N)) {
    KalmanTerm t;
    t.role = "white measurement noise R (from N)";
    t.q = N * N;
    t.q_unit = "U^2/Hz";
    t.discrete = N * N * filter_rate;
    t.discrete_unit = "U^2";
    t.note = "R = N^2 f_k: every white-looking term at 1 s, fast AR1s included (N: " +
             std::string(to_string(figures.white.source)) + ")";
    out.push_back(t);
  }
  if (std::isfinite(K)) {
    KalmanTerm t;
    t.role = "bias random walk state (from K)";
    t.q = K * K;
    t.q_unit = "U^2/s";
    t.transition = 1.0;
    t.discrete = K * K / filter_rate;
    t.discrete_unit = "U^2";
    t.note = std::string("F = 1, Q_d = K^2 / f_k") +
             (figures.walk.source == FigureSource::kBound ? " (K is an upper bound: no +1/2 slope)" : "");
    out.push_back(t);
  }
  const Readoff& B = figures.instability.figure;
  if (B.available() && B.status != ReadoffStatus::kBound && std::isfinite(B.tau)) {
    const double sigma = kBiasInstabilityFactor * B.value / kGaussMarkovPeakAdev;
    KalmanTerm t = gauss_markov_term(B.tau / kGaussMarkovPeakTau, sigma * sigma, filter_rate);
    t.role = "bias instability as a Gauss-Markov state (from B)";
    t.note =
        "T = tau_B / 1.8926, sigma = 0.664 B / 0.6174: its Allan deviation peaks at the flat minimum "
        "(an approximation of a flicker floor); " +
        t.note;
    out.push_back(t);
  }
  const Readoff& Q = figures.quantization.figure;
  if (shows(Q) && figures.quantization.source != FigureSource::kBound) {
    // A bound would add a noise no curve shows: the -1 line touching a white curve at its first
    // point tau_1 gives, at f_k = 1 / tau_1, 2 Q^2 f_k^2 = (2/3) AVAR(tau_1): the white noise's R again.
    KalmanTerm t;
    t.role = "quantization measurement noise R (from Q)";
    t.discrete = 2.0 * Q.value * Q.value * filter_rate * filter_rate;
    t.discrete_unit = "U^2";
    t.note =
        "R = 2 Q^2 f_k^2: the rate averaged over 1 / f_k is the difference of two roundings of its integral, "
        "lag-1 correlated (a white R is the usual approximation); not part of N (Q: " +
        std::string(to_string(figures.quantization.source)) + ")";
    out.push_back(t);
  }
  return out;
}

}  // namespace gmwm
