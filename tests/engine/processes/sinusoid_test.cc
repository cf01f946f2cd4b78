#include <cmath>

#include <boost/math/special_functions/sin_pi.hpp>
#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

double direct_sin_wv(double a2, double f, double tau) {
  const double pi = 3.14159265358979323846;
  const double s = std::sin(pi * f * tau / 2.0), d = std::sin(pi * f);
  return 0.5 * a2 * s * s * s * s / ((tau / 2.0) * (tau / 2.0) * d * d);
}

TEST(SinusoidProcess, MatchesTheClosedForm) {
  const auto p = make_process("SIN");
  const auto tau = dyadic_scales(10);
  for (double f : {0.01, 0.1234, 0.3, 0.49}) {
    std::vector<double> expected;
    for (double t : tau) expected.push_back(direct_sin_wv(2.0, f, t));
    expect_all_relatively_near(wv_of(*p, std::vector<double>{2.0, f}, tau), expected, 1e-10, "SIN(2, f)");
  }
}

TEST(SinusoidProcess, KeepsFullAccuracyAtCoarseScalesWithoutLongDoubleTrigonometry) {
  // The angles are reduced exactly and evaluated in double (long-double sinl/cosl were 30%
  // of a gap run): against the closed form with Boost's long-double-promoted sin_pi, within
  // 1e-14 relative up to tau = 2^40 samples, where pi f tau / 2 is ~1e11 radians.
  const auto p = make_process("SIN");
  const auto tau = dyadic_scales(40);
  for (double f : {1e-7, 0.01, 0.1234, 0.3, 0.49}) {
    std::vector<double> expected;
    for (double t : tau) {
      const long double s = boost::math::sin_pi(static_cast<long double>(f) * t / 2.0L),
                        d = boost::math::sin_pi(static_cast<long double>(f));
      expected.push_back(static_cast<double>(0.5L * 2.0L * s * s * s * s / ((t / 2.0L) * (t / 2.0L) * d * d)));
    }
    expect_all_relatively_near(wv_of(*p, std::vector<double>{2.0, f}, tau), expected, 1e-14, "SIN(2, f), coarse");
  }
}

TEST(SinusoidProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("SIN");
  for (double f : {0.01, 0.1234, 0.3}) expect_derivatives_match_finite_differences(*p, {0.7, f}, dyadic_scales(8));
}

TEST(SinusoidProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("SIN");
  const auto tau = dyadic_scales(6);
  for (double f : {0.02, 0.17, 0.41}) {
    const std::vector<double> theta{1.5, f};
    expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "SIN from g");
  }
}

TEST(SinusoidProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("SIN");
  expect_simulated_moments_match(*p, std::vector<double>{2.0, 0.07}, {.length = 64, .seed = 501});
}

TEST(SinusoidProcess, ShowsTheFrequencyInHertzWhenTheRateIsKnown) {
  const auto known = make_process("SIN", {}, {200.0, true});
  EXPECT_DOUBLE_EQ(known->to_display(1, 0.05), 10.0);
  EXPECT_DOUBLE_EQ(known->from_display(1, 10.0), 0.05);
  EXPECT_DOUBLE_EQ(known->to_display(0, 0.05), 0.05);
  const auto unknown = make_process("SIN");
  EXPECT_DOUBLE_EQ(unknown->to_display(1, 0.05), 0.05);
}

TEST(SinusoidProcess, InitialGuessTakesTheFrequencyFromTheHint) {
  const auto p = make_process("SIN");
  EXPECT_EQ(p->canonical_rank(), 90);
  const auto tau = dyadic_scales(10);
  const auto wv = wv_of(*p, std::vector<double>{1.0, 1.0 / 32.0}, tau);
  const auto guess = p->initial_guess({tau, wv, 32.0});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(guess[1], 1.0 / 32.0, 1e-15);
  EXPECT_NEAR(guess[0], 1.0, 1e-12);
  EXPECT_EQ(p->validate(p->initial_guess({tau, wv, 1.5})), "");  // f clamped below 1/2
  EXPECT_EQ(p->validate(p->initial_guess({})), "");
}

TEST(SinusoidProcess, RejectsFrequenciesOutsideNyquistNamingF) {
  const auto p = make_process("SIN");
  EXPECT_NE(p->validate(std::vector<double>{1.0, 0.5}).find("f "), std::string::npos);
  EXPECT_NE(p->validate(std::vector<double>{0.0, 0.1}).find("A2"), std::string::npos);
}

TEST(SinusoidProcess, PhysicalAmplitudeAndFrequency) {
  // A2 = 2.25, f = 0.05 cycles/sample at 200 Hz: A = sqrt(2.25) = 1.5 U, F = 0.05 * 200 = 10 Hz.
  const auto p = make_process("SIN");
  const auto q = p->physical(std::vector<double>{2.25, 0.05}, 200.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "amplitude");
  EXPECT_DOUBLE_EQ(q[0].value, 1.5);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "m/s^2"), "m/s^2");
  EXPECT_EQ(q[1].name, "frequency");
  EXPECT_DOUBLE_EQ(q[1].value, 10.0);
  EXPECT_EQ(render_unit(q[1].unit_pattern, "m/s^2"), "Hz");
}

}  // namespace
}  // namespace gmwm::test
