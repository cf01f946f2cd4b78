// detect_repeated_samples (issue 47, item 2): held and interpolated samples found on
// RealSense-like records (an accelerometer at 200 or 250 Hz put on a 400 Hz gyroscope's
// stamps by copying or by linear interpolation, at a random phase, rounded or not), never on
// natural records (rounded as coarsely as one quantum of step noise, or filtered far below
// their rate), and the fine scales' shortfall against the exact Haar filter sums.
#include "gmwm/engine/repeated_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

// A measured series at its own rate: AR1 + WN + RW, rounded to `quantum` (0: not rounded).
std::vector<double> measured(std::int64_t n, std::uint64_t seed, double quantum) {
  const Model m =
      parse_model("AR1(phi=0.99, sigma2=1e-4) + WN(sigma2=1) + RW(gamma2=1e-6)", ProcessContext{200.0, true});
  std::vector<double> x = simulate(m, m.given_values(), n, seed);
  if (quantum > 0.0)
    for (double& v : x) v = quantum * std::round(v / quantum);
  return x;
}

enum class Fill { kCopy, kLinear };

// The measured series on stamps `per` times as dense (out_rate / in_rate), starting at
// `phase` (0..1) of a measurement: each output copies the last measurement or joins the
// two around it with a straight line.
std::vector<double> on_faster_stamps(const std::vector<double>& a, double per, double phase, Fill fill) {
  std::vector<double> y;
  for (std::int64_t t = 0;; ++t) {
    const double u = static_cast<double>(t) / per + phase;
    const auto k = static_cast<std::size_t>(std::floor(u));
    if (k + 1 >= a.size()) break;
    const double f = u - std::floor(u);
    y.push_back(fill == Fill::kCopy ? a[k] : a[k] + f * (a[k + 1] - a[k]));
  }
  return y;
}

RepeatedSamples detect(const std::vector<double>& y) {
  return detect_repeated_samples(y.data(), static_cast<std::int64_t>(y.size()));
}

// The 50 cases: seed, phase, and rounding (none, or a quantum of 1/1.5 of the step noise).
struct Case {
  std::vector<double> measured;
  double phase;
};
Case realsense_case(int i) {
  Rng rng(1000 + static_cast<std::uint64_t>(i));
  boost::random::uniform_real_distribution<double> unit(0.0, 1.0);
  const double quantum = i % 2 == 0 ? 0.0 : 0.66;
  return {measured(1 << 15, 77 + static_cast<std::uint64_t>(i), quantum), unit(rng)};
}

TEST(RepeatedSamples, HeldSamplesOf200HzOn400HzStampsAreFoundInEachOfFiftyRecords) {
  for (int i = 0; i < 50; ++i) {
    const Case c = realsense_case(i);
    const RepeatedSamples r = detect(on_faster_stamps(c.measured, 2.0, c.phase, Fill::kCopy));
    SCOPED_TRACE(i);
    ASSERT_TRUE(r.held());
    EXPECT_FALSE(r.interpolated());
    // Half the samples copy the one before: the estimate within 4 binomial sd of 2^16 steps
    // and the rounding model's error (0.02, the ADIS units).
    EXPECT_NEAR(r.held_share, 0.5, 0.03);
    EXPECT_NEAR(r.samples_per_measurement, 2.0, 0.15);
    EXPECT_EQ(r.first, 0);
  }
}

TEST(RepeatedSamples, InterpolatedSamplesOf200HzOn400HzStampsAreFoundInEachOfFiftyRecords) {
  for (int i = 0; i < 50; ++i) {
    const Case c = realsense_case(i);
    const RepeatedSamples r = detect(on_faster_stamps(c.measured, 2.0, c.phase, Fill::kLinear));
    SCOPED_TRACE(i);
    ASSERT_TRUE(r.interpolated());
    EXPECT_FALSE(r.held());
    EXPECT_EQ(r.period, 2);
    EXPECT_GE(r.samples_per_measurement, 2.0);
  }
}

TEST(RepeatedSamples, TheRatesOfOtherRealSenseModesAreFoundToo) {
  const std::vector<double> a = measured(1 << 15, 5, 0.0);
  // 250 Hz on 400 Hz: 3 of every 8 samples held, or a linear pattern every 8 samples.
  const RepeatedSamples copy = detect(on_faster_stamps(a, 1.6, 0.3, Fill::kCopy));
  EXPECT_TRUE(copy.held());
  EXPECT_NEAR(copy.held_share, 3.0 / 8.0, 0.01);
  const RepeatedSamples linear = detect(on_faster_stamps(a, 1.6, 0.3, Fill::kLinear));
  EXPECT_TRUE(linear.interpolated());
  EXPECT_EQ(linear.period, 8);
  // 63 Hz on 200 Hz (3.17 samples a measurement): three samples on one line, no period.
  const RepeatedSamples slow = detect(on_faster_stamps(a, 200.0 / 63.0, 0.3, Fill::kLinear));
  EXPECT_TRUE(slow.interpolated());
  EXPECT_EQ(slow.period, 1);
  EXPECT_GE(slow.samples_per_measurement, 200.0 / 63.0);
}

TEST(RepeatedSamples, NaturalRecordsRoundedDownToAQuantumOfStepNoiseAreNotFlagged) {
  // Step noise of sqrt(2) (WN of variance 1): quanta from 1/20 to 2 of it, and none.
  for (const double quantum : {0.0, 0.07, 0.5, 1.0, 1.4, 2.0}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const RepeatedSamples r = detect(measured(1 << 16, seed, quantum));
      SCOPED_TRACE(quantum);
      EXPECT_FALSE(r.detected()) << r.held_share << " " << r.interpolated_share;
      EXPECT_LT(r.held_share, 0.02);
    }
  }
}

TEST(RepeatedSamples, ASignalFilteredFarBelowItsRateIsNotCalledInterpolated) {
  // White noise through four passes of a 0.02 exponential smoother: smooth at every sample.
  std::vector<double> x = measured(1 << 15, 9, 0.0);
  for (int pass = 0; pass < 4; ++pass)
    for (std::size_t t = 1; t < x.size(); ++t) x[t] = 0.98 * x[t - 1] + 0.02 * x[t];
  const RepeatedSamples r = detect(x);
  EXPECT_FALSE(r.detected()) << r.interpolated_share;
}

TEST(RepeatedSamples, TheFineScalesShortfallIsTheExactFilterSum) {
  // p = 2 held: at tau = 2 each window sees one measurement twice (phase 0, 0 variance) or
  // two halves of two (phase 1, 1/2 of the measured WV's): 1 - 1/4 = 0.75.
  EXPECT_NEAR(repetition_wv_shortfall(2, 2, false), 0.75, 1e-12);
  // p = 2 linear at tau = 2: 1 - 1/8.
  EXPECT_NEAR(repetition_wv_shortfall(2, 2, true), 0.875, 1e-12);
  EXPECT_EQ(repetition_wv_shortfall(1, 64, false), 0.0);
  // Against the WV of a simulated held white noise at tau = 8: within its sampling error.
  Rng rng(3);
  std::vector<double> e(1 << 20);
  rng.unit_normals(e.data(), e.size());
  std::vector<double> held(2 * e.size());
  for (std::size_t t = 0; t < held.size(); ++t) held[t] = e[t / 2];
  const WaveletVariance wv = classical_wv(held.data(), static_cast<std::int64_t>(held.size()), WvOptions{.levels = 4});
  const double measured_wv = 2.0 / 8.0;  // variance 1 a measurement, tau = 8 samples = 4 measurements
  EXPECT_NEAR(1.0 - wv.wv[2] / measured_wv, repetition_wv_shortfall(2, 8, false), 0.01);
  // The decay c p / tau: affected up to tau = 32 samples for p = 2 held (0.047 at 32).
  EXPECT_GT(repetition_wv_shortfall(2, 16, false), RepeatedSamples::kAffectedWvBias);
  EXPECT_LT(repetition_wv_shortfall(2, 32, false), RepeatedSamples::kAffectedWvBias);
}

TEST(RepeatedSamples, TheSentenceSaysTheShareWhereAndTheScalesToReadAbove) {
  const std::vector<double> a = measured(1 << 14, 5, 0.0);
  const RepeatedSamples r = detect(on_faster_stamps(a, 2.0, 0.0, Fill::kCopy));
  const std::string text = repeated_samples_text(r, "accel_x", 400.0);
  EXPECT_EQ(text.rfind("accel_x: 50", 0), 0u) << text;
  EXPECT_NE(text.find("copy the one before (held"), std::string::npos) << text;
  EXPECT_NE(text.find("from sample 0 to "), std::string::npos) << text;
  EXPECT_NE(text.find("the WV below tau = 32 samples (0.08 s) is smoothed (levels 1-4): read N above it"),
            std::string::npos)
      << text;
  EXPECT_EQ(repeated_samples_text(detect(a), "accel_x", 400.0), "");
}

}  // namespace
}  // namespace gmwm
