#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(RandomWalkProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("RW");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)),
                             {0.25, 0.375, 0.6875, 1.34375, 2.671875, 5.3359375}, 1e-15, "RW(1)");
}

TEST(RandomWalkProcess, IsLinearAndRanksAfterQuantizationNoise) {
  const auto p = make_process("RW");
  EXPECT_TRUE(p->linear());
  EXPECT_EQ(p->canonical_rank(), 70);
  EXPECT_EQ(p->parameters().at(0).name, "gamma2");
}

TEST(RandomWalkProcess, GeneralizedAutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("RW");
  const std::vector<double> theta{0.01};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "RW from g");
}

TEST(RandomWalkProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("RW");
  expect_derivatives_match_finite_differences(*p, {1e-4}, dyadic_scales(10));
}

TEST(RandomWalkProcess, SimulatedIncrementsMatchTheGeneralizedAutocovariance) {
  const auto p = make_process("RW");
  expect_simulated_moments_match(*p, std::vector<double>{0.5}, {.seed = 103, .stationary = false});
}

TEST(RandomWalkProcess, InitialGuessExplainsTheCoarsestScale) {
  const auto p = make_process("RW");
  const auto tau = dyadic_scales(12);
  const auto wv = wv_of(*p, std::vector<double>{3e-5}, tau);
  const auto guess = p->initial_guess({tau, wv, 0.0});
  EXPECT_NEAR(guess.at(0), 3e-5, 1e-18);
  EXPECT_EQ(p->validate(guess), "");
}

TEST(RandomWalkProcess, RejectsNonPositiveGamma2NamingIt) {
  const auto p = make_process("RW");
  EXPECT_NE(p->validate(std::vector<double>{0.0}).find("gamma2"), std::string::npos);
  EXPECT_NE(p->validate(std::vector<double>{NAN}).find("gamma2"), std::string::npos);
}

TEST(RandomWalkProcess, PhysicalRandomWalkDensity) {
  // gamma2 = 2e-10 (rad/s)^2 per sample at f = 200 Hz: K = sqrt(2e-10 * 200) = sqrt(4e-8)
  // = 2e-4 rad/s^2/sqrt(Hz) (Kalibr's gyroscope_random_walk unit).
  const auto p = make_process("RW");
  const std::vector<double> theta{2e-10};
  const auto q = p->physical(theta, 200.0);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].name, "random walk");
  EXPECT_NEAR(q[0].value, 2e-4, 1e-12 * 2e-4);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "rad/s"), "rad/s^2/sqrt(Hz)");
  // The derivation: AVAR(T) = 2 WV(2m) = gamma2 (4 m^2 + 2) / (12 m) -> K^2 T / 3 with
  // T = m / f, up to a relative 1 / (2 m^2).
  const double m = 1024.0, T = m / 200.0;
  const std::vector<double> tau{2.0 * m};
  EXPECT_NEAR(2.0 * wv_of(*p, theta, tau)[0] / (q[0].value * q[0].value * T / 3.0), 1.0, 1e-6);
}

TEST(RandomWalkProcess, SumMomentsAreTheClosedFormOfAWalkStartedAtZero) {
  // x_t = e_1 + ... + e_t: Var(x_1 + ... + x_K) = gamma2 (1^2 + ... + K^2):
  // K = 1: gamma2; K = 2: 5 gamma2; K = 3: 14 gamma2; K = 10: 385 gamma2.
  const auto p = make_process("RW");
  const std::vector<std::int64_t> counts{1, 2, 3, 10};
  const auto m = p->sum_moments(std::vector<double>{0.5}, counts);
  ASSERT_EQ(m.size(), 4u);
  const double expected[] = {0.5, 2.5, 7.0, 192.5};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(m[k].variance, expected[k]) << "K = " << counts[k];
    EXPECT_EQ(m[k].mean, 0.0);
  }
}

}  // namespace
}  // namespace gmwm::test
