#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(WhiteNoiseProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("WN");
  const std::vector<double> theta{1.0};
  expect_all_relatively_near(wv_of(*p, theta, dyadic_scales(6)),
                             {0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625}, 1e-15, "WN(1)");
}

TEST(WhiteNoiseProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("WN");
  const std::vector<double> theta{0.7};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-12,
                             "WN from g");
}

TEST(WhiteNoiseProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("WN");
  expect_derivatives_match_finite_differences(*p, {0.3}, dyadic_scales(8));
}

TEST(WhiteNoiseProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("WN");
  expect_simulated_moments_match(*p, std::vector<double>{2.0}, {.seed = 101});
}

}  // namespace
}  // namespace gmwm::test
