#include <cmath>

#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(RandomWalkProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("RW");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)),
                             {0.25, 0.375, 0.6875, 1.34375, 2.671875, 5.3359375}, 1e-15,
                             "RW(1)");
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
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10,
                             "RW from g");
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

}  // namespace
}  // namespace gmwm::test
