#include <cmath>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "high_precision_reference.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(Arma11Process, MatchesReferenceWaveletVarianceAndDerivatives) {
  const auto p = make_process("ARMA11");
  const std::vector<double> theta{0.6, 0.3, 1.0};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(
      wv_of(*p, theta, tau),
      {0.303125, 0.45025, 0.5105906, 0.422504462113024, 0.26933285375533497, 0.14984703225175818}, 1e-12,
      "ARMA11(0.6, 0.3, 1)");
  Eigen::MatrixXd jac(6, 3);
  p->wv_jacobian(theta, tau, jac);
  EXPECT_NEAR(jac(0, 0), -0.095703125, 1e-14);
  EXPECT_NEAR(jac(0, 1), 0.0625, 1e-14);
  EXPECT_NEAR(jac(1, 0), 0.25625, 1e-14);
  EXPECT_NEAR(jac(1, 1), 0.515, 1e-14);
}

TEST(Arma11Process, ReducesToTheAr1WhenThetaIsZero) {
  const auto arma = make_process("ARMA11");
  const auto ar1 = make_process("AR1");
  const auto tau = dyadic_scales(20);
  for (double phi : {0.999995, 0.9, -0.5, -0.999})
    expect_all_relatively_near(wv_of(*arma, std::vector<double>{phi, 0.0, 2.0}, tau),
                               wv_of(*ar1, std::vector<double>{phi, 2.0}, tau), 1e-13,
                               "ARMA11 vs AR1, phi = " + std::to_string(phi));
}

TEST(Arma11Process, IsAccurateWithDerivativesNearTheUnitRoot) {
  const auto p = make_process("ARMA11");
  for (double phi : {1.0 - 1e-8, 0.999995, 0.99, 0.6, 0.2, -0.7, -0.999999}) {
    for (double th : {0.3, -0.8}) {
      for (int j = 1; j <= 30; ++j) {
        const std::vector<double> theta{phi, th, 1.0}, t{std::ldexp(1.0, j)};
        Eigen::MatrixXd jac(1, 3), hess(1, 9);
        p->wv_jacobian(theta, t, jac);
        p->wv_hessian(theta, t, hess);
        const std::string what =
            "phi = " + std::to_string(phi) + ", theta = " + std::to_string(th) + ", j = " + std::to_string(j);
        for (int wrt = 0; wrt < 2; ++wrt) {
          const Reference ref = arma11_reference(phi, th, j, wrt);
          const double size1 = std::fabs(ref.d1) + std::fabs(ref.value);
          const double size2 = std::fabs(ref.d2) + size1;
          if (wrt == 0) {
            EXPECT_NEAR(wv_of(*p, theta, t)[0], ref.value, 1e-10 * ref.value) << what;
          }
          EXPECT_NEAR(jac(0, wrt), ref.d1, 1e-10 * size1) << what << " first derivative " << wrt;
          EXPECT_NEAR(hess(0, 4 * wrt), ref.d2, 1e-10 * size2) << what << " second derivative " << wrt;
        }
      }
    }
  }
}

TEST(Arma11Process, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("ARMA11");
  for (auto [phi, th] : {std::pair{0.6, 0.3}, {-0.5, 0.4}, {0.999, -0.5}, {0.3, -0.95}})
    expect_derivatives_match_finite_differences(*p, {phi, th, 0.8}, dyadic_scales(12));
}

TEST(Arma11Process, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("ARMA11");
  const auto tau = dyadic_scales(6);
  for (auto [phi, th] : {std::pair{0.6, 0.3}, {-0.7, 0.5}}) {
    const std::vector<double> theta{phi, th, 1.3};
    expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10, "ARMA11 from g");
  }
}

TEST(Arma11Process, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("ARMA11");
  expect_simulated_moments_match(*p, std::vector<double>{0.7, -0.3, 1.0}, {.seed = 401});
  expect_first_sample_is_stationary(*p, std::vector<double>{0.98, 0.5, 1.0}, 20000, 402);
}

TEST(Arma11Process, InitialGuessIsValid) {
  const auto p = make_process("ARMA11");
  EXPECT_EQ(p->canonical_rank(), 40);
  const auto tau = dyadic_scales(12);
  const auto wv = wv_of(*p, std::vector<double>{0.95, 0.2, 1.0}, tau);
  const auto guess = p->initial_guess({tau, wv, 3.79 / 0.05});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(guess[0], 0.95, 1e-12);
  EXPECT_NE(p->validate(std::vector<double>{0.5, -1.5, 1.0}).find("theta"), std::string::npos);
}

TEST(Arma11Process, PhysicalQuantitiesAreTheDiscreteParameters) {
  const auto p = make_process("ARMA11");
  const auto q = p->physical(std::vector<double>{0.9, 0.2, 0.01}, 50.0);
  ASSERT_EQ(q.size(), 3u);
  const char* names[] = {"phi", "theta", "sigma2"};
  const double values[] = {0.9, 0.2, 0.01};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(q[k].name, names[k]);
    EXPECT_EQ(q[k].value, values[k]);
    EXPECT_EQ(q[k].unit_pattern, "");
  }
}

}  // namespace
}  // namespace gmwm::test
