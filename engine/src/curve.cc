// A model fitted to a given curve (curve.h; docs/curve-fit.md).
#include "gmwm/engine/curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/choice.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/number_text.h"

namespace gmwm {
namespace {

constexpr CurveQuantity kQuantities[] = {CurveQuantity::kAdev, CurveQuantity::kAvar, CurveQuantity::kWv};
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
// A rate read off a curve's finest tau keeps 12 significant digits: printed taus carry their
// writer's rounding (gmwm wv --adev-csv's tau_seconds of a 100 Hz record, m / f with the rate
// its stamps measured, read back as 100.0000000000909 Hz), far below anything a fit resolves.
constexpr int kCurveRateDigits = 12;

std::string num(double x) { return significant(x, 6); }

// Above this many degrees of freedom a chi-square's quantile is Wilson and Hilferty's cube-root
// normal form (1931): it matches Boost.Math's to 1e-10 relative from 1e6 to 1e10 (measured),
// where Boost's series stop converging near 1e12 (kMaxCurveEdf).
constexpr double kWilsonHilfertyEdf = 1e6;

// The chi-square quantile at probability p with eta degrees of freedom.
double chi_square_quantile(double eta, double p) {
  if (eta <= kWilsonHilfertyEdf) return boost::math::quantile(boost::math::chi_squared(eta), p);
  const double z = boost::math::quantile(boost::math::normal(), p);
  const double c = 2.0 / (9.0 * eta);
  const double r = 1.0 - c + z * std::sqrt(c);
  return eta * r * r * r;
}

// The chi-square interval of a WV nu2 with eta degrees of freedom at level 1 - alpha.
std::pair<double, double> chi_square_interval(double nu2, double eta, double alpha) {
  return {eta * nu2 / chi_square_quantile(eta, 1.0 - alpha / 2.0), eta * nu2 / chi_square_quantile(eta, alpha / 2.0)};
}

// A value as the WV nu^2 it stands for: adev^2 / 2, avar / 2, wv.
double as_wv(CurveQuantity q, double v) {
  switch (q) {
    case CurveQuantity::kAdev:
      return 0.5 * v * v;
    case CurveQuantity::kAvar:
      return 0.5 * v;
    case CurveQuantity::kWv:
      return v;
  }
  return v;
}

// A point's averaging time in seconds: tau itself (adev, avar) or half the Haar scale (wv).
double averaging_time(CurveQuantity q, double tau) { return q == CurveQuantity::kWv ? 0.5 * tau : tau; }

// The first problem with the lengths of the fields.
std::string size_problem(const GivenCurve& c) {
  const std::string head = c.source + ": " + (c.name.empty() ? std::string() : "curve '" + c.name + "': ");
  if (c.tau.empty()) return head + "found no point, expected a curve of tau and " + c.value_field.name;
  auto differs = [&](std::size_t n, bool optional) { return (!optional || n != 0) && n != c.tau.size(); };
  if (differs(c.value.size(), false) || differs(c.low.size(), true) || differs(c.high.size(), true) ||
      differs(c.edf.size(), true) || differs(c.line.size(), true))
    return head + "found fields of different lengths (" + std::to_string(c.tau.size()) + " taus, " +
           std::to_string(c.value.size()) + " values), expected one of each per point";
  if (c.low.empty() != c.high.empty())
    return head + "found " + (c.low.empty() ? c.high_field.name : c.low_field.name) + " without " +
           (c.low.empty() ? c.low_field.name : c.high_field.name) + ", expected both ends of each interval or neither";
  return {};
}

// The first problem of point k's tau, given the one before.
std::string tau_problem(const GivenCurve& c, std::size_t k) {
  const double t = c.tau[k];
  if (!(std::isfinite(t) && t > 0.0))
    return curve_place(c, k, c.tau_field) + "found " + num(t) + ", expected a positive finite tau in seconds";
  if (k == 0 || t > c.tau[k - 1]) return {};
  // A repeat names the point it repeats; a decrease the one it falls below.
  std::size_t j = k - 1;
  while (j > 0 && c.tau[j - 1] >= t) --j;
  const std::string other =
      c.line.empty() ? c.tau_field.name + "[" + std::to_string(j) + "]" : "line " + std::to_string(c.line[j]);
  if (t == c.tau[k - 1])
    return curve_place(c, k, c.tau_field) + "found tau " + num(t) + " s again (" + other +
           "), expected each tau once, increasing";
  return curve_place(c, k, c.tau_field) + "found tau " + num(t) + " s after " + num(c.tau[k - 1]) +
         " s, expected taus increasing";
}

// The first problem of point k's value, interval and edf.
std::string point_problem(const GivenCurve& c, std::size_t k) {
  const double v = c.value[k];
  const std::string what = to_string(c.quantity);
  if (!(std::isfinite(v) && v > 0.0))
    return curve_place(c, k, c.value_field) + "found " + num(v) + ", expected a positive finite " + what;
  const double w = as_wv(c.quantity, v);
  if (!(w >= kMinFittableWv && w <= kMaxFittableWv))
    return curve_place(c, k, c.value_field) + "found " + num(v) + " (a WV of " + num(w) + "), expected a " + what +
           " whose WV lies within " + num(kMinFittableWv) + " .. " + num(kMaxFittableWv) +
           " (give the curve in another unit)";
  if (!c.low.empty()) {
    const double lo = c.low[k], hi = c.high[k];
    if (!(std::isfinite(lo) && lo >= 0.0))
      return curve_place(c, k, c.low_field) + "found " + num(lo) + ", expected an interval's low end from 0";
    if (!std::isfinite(hi))
      return curve_place(c, k, c.high_field) + "found " + num(hi) + ", expected an interval's finite high end";
    if (!(lo <= v && v <= hi && lo < hi))
      return curve_place(c, k, c.low_field) + "found the interval " + num(lo) + " .. " + num(hi) + " for " + num(v) +
             ", expected low < high holding the value";
  }
  if (!c.edf.empty() && !(c.edf[k] > 0.0 && c.edf[k] <= kMaxCurveEdf))
    return curve_place(c, k, c.edf_field) + "found " + num(c.edf[k]) + ", expected degrees of freedom above 0, up to " +
           num(kMaxCurveEdf);
  return {};
}

// Point k's eta and WV interval from what the curve gives (NaN eta: nothing).
struct PointPrecision {
  double eta = kNan, low = kNan, high = kNan;
};

PointPrecision precision_of(const GivenCurve& c, std::size_t k, double nu2, double m, double record_samples,
                            const CurveFitOptions& o) {
  PointPrecision p;
  if (!c.edf.empty())
    p.eta = c.edf[k];
  else if (!c.low.empty())
    p.eta = interval_edf(as_wv(c.quantity, c.low[k]), as_wv(c.quantity, c.high[k]), o.confidence);
  else
    p.eta = std::max((record_samples - 2.0 * m + 1.0) / (2.0 * m), 1.0);  // wv_eta of N - 2m + 1 windows
  if (!c.low.empty()) {
    p.low = as_wv(c.quantity, c.low[k]);
    p.high = as_wv(c.quantity, c.high[k]);
  } else if (std::isfinite(p.eta)) {
    std::tie(p.low, p.high) = chi_square_interval(nu2, p.eta, o.fit.alpha);
  }
  return p;
}

CurveWeights weights_of(const GivenCurve& c, double record_seconds) {
  if (!c.edf.empty()) return CurveWeights::kEdf;
  if (!c.low.empty()) return CurveWeights::kIntervals;
  return record_seconds > 0.0 ? CurveWeights::kRecord : CurveWeights::kShortestRecord;
}

// m = T f as a whole number when it is one within kWholeScaleTolerance.
double samples_at(double seconds, double freq) {
  const double m = seconds * freq;
  const double whole = std::round(m);
  return std::abs(m - whole) <= kWholeScaleTolerance * m ? whole : m;
}

// Refuses a tau below one sample (two for a WV's scale) at freq, and a record shorter than
// the longest averaging window.
void check_scales(const GivenCurve& c, double freq, const CurveFitOptions& o) {
  const bool wv = c.quantity == CurveQuantity::kWv;
  const double m0 = samples_at(averaging_time(c.quantity, c.tau.front()), freq);
  if (m0 < 1.0)
    throw InputError(curve_place(c, 0, c.tau_field) + "found tau " + num(c.tau.front()) + " s, " +
                     num(wv ? 2 * m0 : m0) + " samples at " + num(freq) + " Hz, expected at least " +
                     (wv ? "2 samples (" : "one sample (") + num((wv ? 2.0 : 1.0) / freq) +
                     " s; give the rate of the data behind the curve: --freq)");
  const double window = 2.0 * averaging_time(c.quantity, c.tau.back());
  if (o.record_seconds > 0.0 && o.record_seconds < window)
    throw InputError("--record: found " + num(o.record_seconds) + " s, expected at least the longest window of " +
                     c.source + " (" + num(window) + " s: twice its longest averaging time)");
}

}  // namespace

const char* to_string(CurveQuantity q) {
  switch (q) {
    case CurveQuantity::kAdev:
      return "adev";
    case CurveQuantity::kAvar:
      return "avar";
    case CurveQuantity::kWv:
      return "wv";
  }
  return "?";
}

std::optional<CurveQuantity> parse_curve_quantity(const std::string& name) { return parse_among(name, kQuantities); }

std::vector<std::string> curve_quantity_names() { return names_among(kQuantities); }

const char* to_string(CurveWeights w) {
  switch (w) {
    case CurveWeights::kEdf:
      return "edf";
    case CurveWeights::kIntervals:
      return "intervals";
    case CurveWeights::kRecord:
      return "record";
    case CurveWeights::kShortestRecord:
      return "shortest-record";
  }
  return "?";
}

std::string curve_place(const GivenCurve& curve, std::size_t k, const CurveField& field) {
  if (k < curve.line.size()) {
    std::string out = curve.source + ":" + std::to_string(curve.line[k]) + ":";
    if (field.column > 0) out += std::to_string(field.column) + ":";
    return out + " ";
  }
  return curve.source + ": " + field.name + "[" + std::to_string(k) + "]: ";
}

std::string curve_problem(const GivenCurve& curve) {
  if (std::string why = size_problem(curve); !why.empty()) return why;
  for (std::size_t k = 0; k < curve.size(); ++k) {
    if (std::string why = tau_problem(curve, k); !why.empty()) return why;
    if (std::string why = point_problem(curve, k); !why.empty()) return why;
  }
  return {};
}

double curve_rate(const GivenCurve& curve) {
  if (curve.tau.empty() || !(curve.tau.front() > 0.0)) return 1.0;
  const double unit = curve.quantity == CurveQuantity::kWv ? 2.0 : 1.0;  // samples at the finest tau
  const double f0 = std::stod(significant(unit / curve.tau.front(), kCurveRateDigits));
  for (double t : curve.tau) {
    const double m = averaging_time(curve.quantity, t) * f0;
    if (std::abs(m - std::round(m)) > kWholeScaleTolerance * m) return kDigitisedFinestSamples * f0;
  }
  return f0;
}

std::string CurveFitOptions::Validate() const {
  if (!(record_seconds >= 0.0 && std::isfinite(record_seconds)))
    return "--record: found " + num(record_seconds) + ", expected a record length in seconds above 0";
  if (!(confidence > 0.0 && confidence < 1.0))
    return "--curve-confidence: found " + num(confidence) +
           ", expected a confidence level strictly between 0 and 1 (0.683 for +-1 sigma bars)";
  if (omega != OmegaKind::kModel && omega != OmegaKind::kDiag)
    return std::string("--omega: found '") + to_string(omega) +
           "', expected model or diag (a curve has no record to simulate or to take a covariance from)";
  return fit.Validate();
}

double interval_edf(double low, double high, double confidence) {
  if (!(low >= 0.0 && high > low && std::isfinite(high)))
    throw InvalidArgument("interval_edf: expected 0 <= low < high, got " + num(low) + " .. " + num(high));
  check_open_interval("interval_edf", "confidence", confidence, 0.0, 1.0);
  const double a = 1.0 - confidence;
  auto ratio = [a](double eta) {  // q(1 - a/2) / q(a/2): the interval's high / low at eta
    return chi_square_quantile(eta, 1.0 - a / 2.0) / chi_square_quantile(eta, a / 2.0);
  };
  const double target = low > 0.0 ? high / low : std::numeric_limits<double>::infinity();
  if (!(target < ratio(kMinCurveEdf))) return kMinCurveEdf;
  if (!(target > ratio(kMaxCurveEdf))) return kMaxCurveEdf;
  double lo = std::log(kMinCurveEdf), hi = std::log(kMaxCurveEdf);  // the ratio falls with eta
  for (int it = 0; it < 200 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ratio(std::exp(mid)) > target ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

WaveletVariance curve_wv(const GivenCurve& curve, double freq, const CurveFitOptions& options, CurveWeights* weights) {
  if (std::string why = options.Validate(); !why.empty()) throw InputError("curve fit: " + why);
  if (std::string why = curve_problem(curve); !why.empty()) throw InputError(why);
  check_positive("curve_wv", "freq", freq);
  check_scales(curve, freq, options);
  // The record's samples: given, or the shortest record reaching the longest window, 2 m_max.
  const double longest_window = 2.0 * samples_at(averaging_time(curve.quantity, curve.tau.back()), freq);
  const double record_samples = options.record_seconds > 0.0 ? options.record_seconds * freq : longest_window;
  WaveletVariance w;
  w.estimator = "curve";
  w.alpha = options.fit.alpha;
  for (std::size_t k = 0; k < curve.size(); ++k) {
    const double m = samples_at(averaging_time(curve.quantity, curve.tau[k]), freq);
    const double nu2 = as_wv(curve.quantity, curve.value[k]);
    const PointPrecision p = precision_of(curve, k, nu2, m, record_samples, options);
    w.tau.push_back(2.0 * m);
    w.wv.push_back(nu2);
    w.ci_low.push_back(p.low);
    w.ci_high.push_back(p.high);
    w.eta.push_back(p.eta);
    w.variance.push_back(2.0 * nu2 * nu2 / p.eta);
    w.coefficients.push_back(0);
    w.notes.emplace_back();
  }
  w.n = std::llround(std::ceil(record_samples));
  if (weights) *weights = weights_of(curve, options.record_seconds);
  return w;
}

std::vector<double> model_allan_variance(const Model& model, const Eigen::VectorXd& theta,
                                         std::span<const double> tau_seconds, double freq) {
  check_positive("model_allan_variance", "freq", freq);
  std::vector<double> scales(tau_seconds.size());
  for (std::size_t k = 0; k < scales.size(); ++k) scales[k] = 2.0 * samples_at(tau_seconds[k], freq);
  const Eigen::VectorXd nu = model.wv(theta, scales);
  std::vector<double> out(scales.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = 2.0 * nu(static_cast<Eigen::Index>(k));
  return out;
}

AllanDeviation curve_allan_deviation(const WaveletVariance& wv, double freq, const std::vector<bool>& keep) {
  AllanDeviation a;
  a.freq = freq;
  a.n = wv.n;
  a.alpha = wv.alpha;
  for (std::size_t k = 0; k < wv.tau.size(); ++k) {
    if (!keep.empty() && !keep[k]) continue;
    const double m = 0.5 * wv.tau[k];
    a.m.push_back(std::max<std::int64_t>(1, std::llround(m)));
    a.tau.push_back(m / freq);
    a.adev.push_back(std::sqrt(2.0 * wv.wv[k]));
    a.ci_low.push_back(std::sqrt(2.0 * wv.ci_low[k]));
    a.ci_high.push_back(std::sqrt(2.0 * wv.ci_high[k]));
    a.edf.push_back(wv.eta[k]);
  }
  return a;
}

}  // namespace gmwm
