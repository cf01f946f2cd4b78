#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(WhiteNoiseProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("WN");
  const std::vector<double> theta{1.0};
  expect_all_relatively_near(wv_of(*p, theta, dyadic_scales(6)), {0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625}, 1e-15,
                             "WN(1)");
}

TEST(WhiteNoiseProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("WN");
  const std::vector<double> theta{0.7};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-12, "WN from g");
}

TEST(WhiteNoiseProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("WN");
  expect_derivatives_match_finite_differences(*p, {0.3}, dyadic_scales(8));
}

TEST(WhiteNoiseProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("WN");
  expect_simulated_moments_match(*p, std::vector<double>{2.0}, {.seed = 101});
}

TEST(WhiteNoiseProcess, PhysicalNoiseDensityOfTheEurocAdis16448Gyro) {
  // EuRoC ADIS16448 gyro: sigma2 = 5.7583e-06 (rad/s)^2 per sample at f = 200 Hz.
  // N = sqrt(5.7583e-06 / 200) = sqrt(2.87915e-08) = 1.6968058e-04 rad/s/sqrt(Hz);
  // in deg/sqrt(h): 1.6968058e-04 * (180 / pi) * 60 = 0.58331887.
  const auto p = make_process("WN");
  const std::vector<double> theta{5.7583e-06};
  const auto q = p->physical(theta, 200.0);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].name, "noise density");
  EXPECT_NEAR(q[0].value, 1.6968058227151392e-04, 1e-12 * 1.7e-04);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "rad/s"), "rad/s/sqrt(Hz)");
  EXPECT_NE(q[0].convention.find("N = sqrt(sigma2 / f)"), std::string::npos);
  EXPECT_NEAR(q[0].value * 180.0 / std::numbers::pi * 60.0, 0.5833188737688052, 1e-12);
  // The derivation: AVAR(T) = 2 WV(tau = 2m), m = T f samples, equals N^2 / T.
  const double m = 64.0, T = m / 200.0;
  const std::vector<double> tau{2.0 * m};
  EXPECT_NEAR(2.0 * wv_of(*p, theta, tau)[0], q[0].value * q[0].value / T, 1e-12 * 3.6e-10);
}

}  // namespace
}  // namespace gmwm::test
