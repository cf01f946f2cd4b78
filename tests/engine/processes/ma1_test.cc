#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(Ma1Process, MatchesReferenceWaveletVarianceAndDerivative) {
  const auto p = make_process("MA1");
  const std::vector<double> theta{0.5, 1.0};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_of(*p, theta, tau), {0.375, 0.375, 0.234375, 0.12890625, 0.0673828125, 0.034423828125},
                             1e-12, "MA1(0.5, 1)");
  Eigen::MatrixXd jac(6, 2);
  p->wv_jacobian(theta, tau, jac);
  const double expected[] = {0, 0.375, 0.28125, 0.1640625, 0.087890625};
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(jac(k, 0), expected[k], 1e-15) << "tau = " << tau[k];
}

TEST(Ma1Process, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("MA1");
  for (double theta : {0.5, -0.7, 0.0, 0.99})
    expect_derivatives_match_finite_differences(*p, {theta, 0.3}, dyadic_scales(10));
}

TEST(Ma1Process, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("MA1");
  const std::vector<double> theta{-0.4, 2.0};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "MA1 from g");
}

TEST(Ma1Process, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("MA1");
  expect_simulated_moments_match(*p, std::vector<double>{0.6, 1.5}, {.seed = 301});
  expect_first_sample_is_stationary(*p, std::vector<double>{0.9, 1.0}, 20000, 302);
}

TEST(Ma1Process, InitialGuessIsValidAndMatchesTheHintedLevel) {
  const auto p = make_process("MA1");
  const auto tau = dyadic_scales(8);
  const auto wv = wv_of(*p, std::vector<double>{0.3, 2.0}, tau);
  const auto guess = p->initial_guess({tau, wv, 8.0});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(wv_of(*p, guess, std::vector<double>{8.0})[0], wv[2], 1e-12 * wv[2]);
}

TEST(Ma1Process, RejectsANonInvertibleThetaNamingIt) {
  const auto p = make_process("MA1");
  EXPECT_EQ(p->canonical_rank(), 30);
  EXPECT_NE(p->validate(std::vector<double>{1.0, 1.0}).find("theta"), std::string::npos);
}

TEST(Ma1Process, PhysicalQuantitiesAreTheDiscreteParameters) {
  // No standard physical counterpart: the default reports theta and sigma2 unchanged.
  const auto p = make_process("MA1");
  const auto q = p->physical(std::vector<double>{-0.3, 2.5}, 100.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "theta");
  EXPECT_EQ(q[0].value, -0.3);
  EXPECT_EQ(q[1].name, "sigma2");
  EXPECT_EQ(q[1].value, 2.5);
  for (const auto& x : q) {
    EXPECT_EQ(x.unit_pattern, "");
    EXPECT_NE(x.convention.find("discrete"), std::string::npos);
  }
}

}  // namespace
}  // namespace gmwm::test
