#include <cmath>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gmwm/engine/error.h"
#include "high_precision_reference.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

ProcessContext at_rate(double hz) { return {hz, true}; }

TEST(GaussMarkovProcess, EqualsTheAr1WithTheReferenceConversionAt100Hz) {
  const auto gm = make_process("GM", {}, at_rate(100.0));
  const auto ar1 = make_process("AR1");
  const auto tau = dyadic_scales(14);
  expect_all_relatively_near(wv_of(*gm, std::vector<double>{2.0, 3.0}, tau),
                             wv_of(*ar1, std::vector<double>{0.9801986733067553, 0.11763168254303047}, tau), 1e-12,
                             "GM(2, 3) at 100 Hz vs AR1");
}

TEST(GaussMarkovProcess, EqualsTheAr1WithTheReferenceConversionAt1Hz) {
  const auto gm = make_process("GM", {}, at_rate(1.0));
  const auto ar1 = make_process("AR1");
  const auto tau = dyadic_scales(10);
  expect_all_relatively_near(wv_of(*gm, std::vector<double>{0.10536051565782628, 5.263157894736843}, tau),
                             wv_of(*ar1, std::vector<double>{0.9, 1.0}, tau), 1e-12, "GM at 1 Hz vs AR1(0.9, 1)");
}

TEST(GaussMarkovProcess, IsAccurateWithDerivativesForLongCorrelationTimes) {
  // beta / f from 1e-9 (phi = 1 - 1e-9, formed without rounding through L = beta/f) to 3.
  for (double beta : {1e-7, 1e-4, 0.05, 2.0, 300.0}) {
    const double freq = 100.0, s2 = 3.0;
    const auto p = make_process("GM", {}, at_rate(freq));
    for (int j = 1; j <= 30; j += 1) {
      const std::vector<double> theta{beta, s2}, t{std::ldexp(1.0, j)};
      const Reference ref = gm_reference(beta, freq, s2, j);
      Eigen::MatrixXd jac(1, 2), hess(1, 4);
      p->wv_jacobian(theta, t, jac);
      p->wv_hessian(theta, t, hess);
      const std::string what = "beta = " + std::to_string(beta) + ", j = " + std::to_string(j);
      EXPECT_NEAR(wv_of(*p, theta, t)[0], ref.value, 1e-10 * ref.value) << what;
      const double size1 = std::fabs(ref.d1) + std::fabs(ref.value) / beta;
      const double size2 = std::fabs(ref.d2) + size1 / beta;
      EXPECT_NEAR(jac(0, 0), ref.d1, 1e-10 * size1) << what << " d/dbeta";
      EXPECT_NEAR(hess(0, 0), ref.d2, 1e-10 * size2) << what << " d2/dbeta2";
      EXPECT_NEAR(jac(0, 1), ref.value / s2, 1e-12 * ref.value / s2) << what << " d/dsigma2_gm";
      EXPECT_NEAR(hess(0, 1), ref.d1 / s2, 1e-10 * size1 / s2) << what << " d2/dbeta dsigma2_gm";
    }
  }
}

TEST(GaussMarkovProcess, DerivativesMatchFiniteDifferences) {
  for (double beta : {2.0, 1e-3, 150.0}) {
    const auto p = make_process("GM", {}, at_rate(100.0));
    expect_derivatives_match_finite_differences(*p, {beta, 0.4}, dyadic_scales(12));
  }
}

TEST(GaussMarkovProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("GM", {}, at_rate(10.0));
  const std::vector<double> theta{1.5, 0.2};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "GM from g");
}

TEST(GaussMarkovProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("GM", {}, at_rate(10.0));
  expect_simulated_moments_match(*p, std::vector<double>{1.5, 0.2}, {.seed = 201});
  expect_first_sample_is_stationary(*p, std::vector<double>{0.05, 2.0}, 20000, 202);
}

TEST(GaussMarkovProcess, InitialGuessRecoversTheCorrelationTime) {
  const double freq = 50.0, beta = 0.5;
  const auto p = make_process("GM", {}, at_rate(freq));
  const auto tau = dyadic_scales(16);
  const auto wv = wv_of(*p, std::vector<double>{beta, 2.0}, tau);
  const double phi = std::exp(-beta / freq);
  const auto guess = p->initial_guess({tau, wv, 3.79 / (1.0 - phi)});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(guess[0], beta, 1e-9 * beta);
  EXPECT_NEAR(guess[1], 2.0, 1e-9);
  EXPECT_EQ(p->validate(p->initial_guess({})), "");
}

TEST(GaussMarkovProcess, RanksAfterAr1AndNamesItsParameters) {
  const auto p = make_process("GM");
  EXPECT_EQ(p->canonical_rank(), 20);
  EXPECT_EQ(p->sort_key(), -1);
  EXPECT_EQ(p->parameters().at(0).name, "beta");
  EXPECT_EQ(p->parameters().at(1).name, "sigma2_gm");
  EXPECT_NE(p->validate(std::vector<double>{-1.0, 1.0}).find("beta"), std::string::npos);
}

TEST(GaussMarkovProcess, RefusesANonPositiveSamplingRate) {
  EXPECT_THROW(make_process("GM", {}, {0.0, true}), InputError);
}

TEST(GaussMarkovProcess, PhysicalQuantitiesAreItsParametersAndMatchTheAr1s) {
  // beta = 2 /s, sigma2_gm = 3 at 100 Hz: T = 1 / 2 = 0.5 s, sigma = sqrt(3) = 1.7320508 U.
  const auto gm = make_process("GM", {}, at_rate(100.0));
  const auto q = gm->physical(std::vector<double>{2.0, 3.0}, 100.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "correlation time");
  EXPECT_DOUBLE_EQ(q[0].value, 0.5);
  EXPECT_EQ(q[1].name, "stationary sigma");
  EXPECT_DOUBLE_EQ(q[1].value, 1.7320508075688772);
  // The equivalent AR1 (phi = exp(-0.02), sigma2 = 3 (1 - exp(-0.04))) reads the same.
  const auto ar1 = make_process("AR1")->physical(std::vector<double>{0.9801986733067553, 0.11763168254303047}, 100.0);
  EXPECT_NEAR(ar1[0].value, q[0].value, 1e-12);
  EXPECT_NEAR(ar1[1].value, q[1].value, 1e-12);
  EXPECT_EQ(ar1[0].unit_pattern, q[0].unit_pattern);
  EXPECT_EQ(ar1[1].unit_pattern, q[1].unit_pattern);
}

}  // namespace
}  // namespace gmwm::test
