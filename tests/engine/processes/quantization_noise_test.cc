#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(QuantizationNoiseProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("QN");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)),
                             {1.5, 0.375, 0.09375, 0.0234375, 0.005859375, 0.00146484375},
                             1e-15, "QN(1)");
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
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10,
                             "QN from g");
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

}  // namespace
}  // namespace gmwm::test
