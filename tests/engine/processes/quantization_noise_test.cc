#include <string>

#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(QuantizationNoiseProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("QN");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)),
                             {1.5, 0.375, 0.09375, 0.0234375, 0.005859375, 0.00146484375}, 1e-15, "QN(1)");
}

TEST(QuantizationNoiseProcess, IsLinearAndRanksAfterWhiteNoise) {
  const auto p = make_process("QN");
  EXPECT_TRUE(p->linear());
  EXPECT_FALSE(p->deterministic());
  EXPECT_EQ(p->canonical_rank(), 60);
  EXPECT_EQ(p->parameters().at(0).name, "Q2");
}

TEST(QuantizationNoiseProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("QN");
  const std::vector<double> theta{0.4};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "QN from g");
}

TEST(QuantizationNoiseProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("QN");
  expect_derivatives_match_finite_differences(*p, {2.5}, dyadic_scales(8));
}

TEST(QuantizationNoiseProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("QN");
  expect_simulated_moments_match(*p, std::vector<double>{0.3}, {.seed = 102});
}

TEST(QuantizationNoiseProcess, InitialGuessExplainsTheFinestScale) {
  const auto p = make_process("QN");
  const auto tau = dyadic_scales(6);
  const auto wv = wv_of(*p, std::vector<double>{0.25}, tau);
  const auto guess = p->initial_guess({tau, wv, 0.0});
  EXPECT_NEAR(guess.at(0), 0.25, 1e-14);
  EXPECT_EQ(p->validate(guess), "");
}

TEST(QuantizationNoiseProcess, RejectsNonPositiveQ2NamingIt) {
  const auto p = make_process("QN");
  EXPECT_NE(p->validate(std::vector<double>{-1.0}).find("Q2"), std::string::npos);
}

TEST(QuantizationNoiseProcess, PhysicalQuantizationCoefficientInUnitSeconds) {
  // Q2 = 4e-6 (deg/s)^2 per sample at f = 100 Hz: Q = sqrt(4e-6) / 100 = 2e-3 / 100
  // = 2e-5 deg (U*s with U = deg/s).
  const auto p = make_process("QN");
  const std::vector<double> theta{4e-6};
  const auto q = p->physical(theta, 100.0);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].name, "quantization");
  EXPECT_NEAR(q[0].value, 2e-5, 1e-12 * 2e-5);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "deg/s"), "deg");
  EXPECT_EQ(render_unit(q[0].unit_pattern, "g"), "g*s");
  // The derivation: AVAR(T) = 2 WV(2m) = 12 Q2 / (2m)^2 equals 3 Q^2 / T^2, T = m / f.
  for (double m : {1.0, 8.0, 512.0}) {
    const double T = m / 100.0;
    const std::vector<double> tau{2.0 * m};
    EXPECT_NEAR(2.0 * wv_of(*p, theta, tau)[0] / (3.0 * q[0].value * q[0].value / (T * T)), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace gmwm::test
