// The three-cornered hat (three_cornered_hat.h): the pairs' checks -> each factor's separated
// variances -> each one's score interval from the pairs' degrees of freedom.
#include "gmwm/stability/three_cornered_hat.h"

#include <algorithm>
#include <array>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::stability {
namespace {

// The score interval is given where the pairs keep at least this many z^2 degrees of freedom
// (z the normal quantile of the confidence: 4 at 68.27%, 15.4 at 95%), its quadratic's
// leading coefficient 1 - 2 z^2 / nu then at least 1/2. Below it the set of variances is
// unbounded above (nu <= 2 z^2) or given for some records only, and those covered the truth
// 45-89% of the time at 95% (tools/bench/bench_three_cornered_hat.cc, 1000 records of three
// sensors: tools/bench/RESULTS.md); above it 92-98% at 95% and 63-80% at 68.27% (every m but
// TOTDEV's 1 and 2, whose pairs' edf run high: docs/stability.md, "Three-cornered hat").
constexpr double kMinEdfPerZSquared = 4.0;

constexpr std::array<std::string_view, kHatSensors> kPairNames = {"A - B", "B - C", "C - A"};

// The pair opposite each sensor (the one it is not in): B - C for A, C - A for B, A - B for C.
constexpr std::array<std::size_t, kHatSensors> kOppositePair = {1, 2, 0};

std::string pair_name(std::size_t k) { return std::string(kPairNames[k]); }

std::string factor_list(const std::vector<std::int64_t>& m) {
  std::string out;
  for (std::size_t i = 0; i < m.size() && i < 6; ++i) out += (i ? ", " : "") + std::to_string(m[i]);
  return out + (m.size() > 6 ? ", ..." : "");
}

void check_pair_values(const DeviationCurve& c, std::size_t k) {
  if (c.tau.size() != c.m.size() || c.value.size() != c.m.size() || c.terms.size() != c.m.size())
    throw InputError("three-cornered hat: " + pair_name(k) + "'s curve holds " + std::to_string(c.m.size()) +
                     " factors, " + std::to_string(c.value.size()) + " values and " + std::to_string(c.terms.size()) +
                     " term counts, expected one of each per factor");
  for (std::size_t i = 0; i < c.m.size(); ++i)
    if (!(c.value[i] >= 0.0) || !std::isfinite(c.value[i]))
      throw InputError("three-cornered hat: " + pair_name(k) + "'s deviation at m = " + std::to_string(c.m[i]) +
                       " is " + significant(c.value[i], 6) + ", expected a finite deviation >= 0");
}

// One kind, one tau0, the same factors and terms: three differences of one record.
void check_pair_agrees(const DeviationCurve& c, const DeviationCurve& first, std::size_t k) {
  const std::string who = "three-cornered hat: " + pair_name(0) + " and " + pair_name(k);
  if (c.kind != first.kind)
    throw InputError(who + " are of different kinds (" + std::string(deviation_name(first.kind)) + ", " +
                     std::string(deviation_name(c.kind)) + ")");
  if (c.tau0 != first.tau0)
    throw InputError(who + " have different sampling periods (" + significant(first.tau0, 9) + " s, " +
                     significant(c.tau0, 9) + " s)");
  if (c.m != first.m)
    throw InputError(who + " have different averaging factors (" + factor_list(first.m) + "; " + factor_list(c.m) +
                     ")");
  for (std::size_t i = 0; i < c.m.size(); ++i)
    if (c.terms[i] != first.terms[i])
      throw InputError(who + " averaged " + std::to_string(first.terms[i]) + " and " + std::to_string(c.terms[i]) +
                       " terms at m = " + std::to_string(c.m[i]) +
                       ": records of different lengths; the hat reads three sensors recorded together");
}

void check_pairs(std::span<const DeviationCurve> pairs) {
  if (pairs.size() != kHatSensors)
    throw InputError("three-cornered hat: expected the three pairwise curves A - B, B - C, C - A, found " +
                     std::to_string(pairs.size()));
  if (!separable(pairs[0].kind))
    throw InputError("three-cornered hat: " + std::string(deviation_name(pairs[0].kind)) +
                     " is a maximum, not a variance: the hat separates every kind but mtie");
  for (std::size_t k = 0; k < kHatSensors; ++k) {
    check_pair_values(pairs[k], k);
    if (k > 0) check_pair_agrees(pairs[k], pairs[0], k);
  }
}

void check_intervals(std::span<const DeviationIntervals> intervals, std::span<const DeviationCurve> pairs) {
  if (intervals.empty()) return;
  if (intervals.size() != kHatSensors)
    throw InputError("three-cornered hat: expected the three pairs' intervals or none, found " +
                     std::to_string(intervals.size()));
  for (std::size_t k = 0; k < kHatSensors; ++k) {
    if (intervals[k].edf.size() != pairs[k].m.size())
      throw InputError("three-cornered hat: " + pair_name(k) + "'s intervals hold " +
                       std::to_string(intervals[k].edf.size()) + " degrees of freedom for " +
                       std::to_string(pairs[k].m.size()) + " factors");
    if (intervals[k].options.confidence != intervals[0].options.confidence)
      throw InputError("three-cornered hat: " + pair_name(k) + "'s intervals are at confidence " +
                       significant(intervals[k].options.confidence, 6) + ", " + pair_name(0) + "'s at " +
                       significant(intervals[0].options.confidence, 6));
  }
}

// The smallest of the three pairs' degrees of freedom at factor i; NaN where one has none.
double smallest_edf(std::span<const DeviationIntervals> intervals, std::size_t i) {
  if (intervals.empty()) return NAN;
  double edf = INFINITY;
  for (const DeviationIntervals& ci : intervals) {
    if (!(ci.edf[i] > 0.0)) return NAN;
    edf = std::min(edf, ci.edf[i]);
  }
  return edf;
}

void resize(HatSensor& s, std::size_t n) {
  s.variance.assign(n, NAN);
  s.value.assign(n, NAN);
  s.negative.assign(n, false);
  s.low.assign(n, NAN);
  s.high.assign(n, NAN);
}

// Sensor s's estimate at factor i, and its interval where the pairs have degrees of freedom.
// The variances come on the scale of the pairs' largest deviation (`scale`): a deviation of
// 1e160 squared would overflow.
void separate(HatSensor& sensor, std::size_t s, std::size_t i, const std::array<double, kHatSensors>& variance,
              const std::array<double, kHatSensors>& pair_variance, double scale, double edf, double confidence) {
  const double v = variance[s];
  sensor.variance[i] = v * scale * scale;
  sensor.negative[i] = v < 0.0;
  sensor.value[i] = v < 0.0 ? NAN : std::sqrt(v) * scale;
  if (!std::isfinite(edf)) return;
  const double b = std::max(variance[(s + 1) % kHatSensors], 0.0);
  const double c = std::max(variance[(s + 2) % kHatSensors], 0.0);
  const VarianceInterval ci = separated_variance_interval(v, pair_variance[kOppositePair[s]], b * c, edf, confidence);
  sensor.low[i] = std::sqrt(ci.low) * scale;  // NaN stays NaN
  sensor.high[i] = std::sqrt(ci.high) * scale;
}

}  // namespace

bool separable(DeviationKind kind) { return kind != DeviationKind::kMtie; }

std::array<double, kHatSensors> separated_variances(double ab, double bc, double ca) {
  return {(ab + ca - bc) / 2.0, (ab + bc - ca) / 2.0, (bc + ca - ab) / 2.0};
}

double separated_variance_variance(double own, double others_sum, double others_product, double edf) {
  return (2.0 * own * own + own * others_sum + others_product) / edf;
}

VarianceInterval separated_variance_interval(double estimate, double others_sum, double others_product, double edf,
                                             double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError("confidence: found " + significant(confidence, 6) + ", expected a number between 0 and 1");
  if (!(edf > 0.0) || !std::isfinite(edf))
    throw InputError("edf: found " + significant(edf, 6) + ", expected a positive number of degrees of freedom");
  if (!(others_sum >= 0.0) || !std::isfinite(others_sum) || !(others_product >= 0.0) ||
      !std::isfinite(others_product) || !std::isfinite(estimate))
    throw InputError("three-cornered hat: found the estimate " + significant(estimate, 6) + ", the others' sum " +
                     significant(others_sum, 6) + " and product " + significant(others_product, 6) +
                     ", expected finite numbers, the sum and product >= 0");
  const double z = boost::math::quantile(boost::math::normal_distribution<double>(), (1.0 + confidence) / 2.0);
  if (edf < kMinEdfPerZSquared * z * z) return {};  // too few degrees of freedom for the rule
  const double k = z * z / edf;
  // (estimate - a)^2 <= k (2 a^2 + a S + P), read on the scale of its largest term (variances
  // of 1e-200 would underflow squared): c2 a^2 + c1 a + c0 <= 0.
  const double scale = std::max({std::abs(estimate), others_sum, std::sqrt(others_product)});
  if (!(scale > 0.0)) return {0.0, 0.0};  // every pair's deviation 0
  const double e = estimate / scale, sum = others_sum / scale, product = others_product / (scale * scale);
  const double c2 = 1.0 - 2.0 * k, c1 = -(2.0 * e + k * sum), c0 = e * e - k * product;
  if (!(c2 > 0.0)) return {};  // unbounded above (not reached: edf >= 4 z^2 keeps c2 >= 1/2)
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc < 0.0) return {};  // no a fits
  // The roots without cancellation: q = -(c1 + sign(c1) sqrt(disc)) / 2, roots q / c2 and c0 / q.
  const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
  double low = q / c2, high = q != 0.0 ? c0 / q : low;
  if (low > high) std::swap(low, high);
  if (high < 0.0) return {};
  return {std::max(low, 0.0) * scale, high * scale};
}

ThreeCorneredHat three_cornered_hat(std::span<const DeviationCurve> pairs,
                                    std::span<const DeviationIntervals> intervals) {
  check_pairs(pairs);
  check_intervals(intervals, pairs);
  ThreeCorneredHat hat;
  hat.kind = pairs[0].kind;
  hat.tau0 = pairs[0].tau0;
  hat.m = pairs[0].m;
  hat.tau = pairs[0].tau;
  const std::size_t n = hat.m.size();
  hat.edf.assign(n, NAN);
  hat.confidence = intervals.empty() ? NAN : intervals[0].options.confidence;
  for (HatSensor& s : hat.sensors) resize(s, n);
  for (std::size_t i = 0; i < n; ++i) {
    double scale = std::max({pairs[0].value[i], pairs[1].value[i], pairs[2].value[i]});
    if (!(scale > 0.0)) scale = 1.0;
    std::array<double, kHatSensors> pair_variance{};
    for (std::size_t k = 0; k < kHatSensors; ++k) pair_variance[k] = std::pow(pairs[k].value[i] / scale, 2);
    const auto variance = separated_variances(pair_variance[0], pair_variance[1], pair_variance[2]);
    hat.edf[i] = smallest_edf(intervals, i);
    for (std::size_t s = 0; s < kHatSensors; ++s)
      separate(hat.sensors[s], s, i, variance, pair_variance, scale, hat.edf[i], hat.confidence);
  }
  return hat;
}

}  // namespace gmwm::stability
