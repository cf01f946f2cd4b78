#include <cmath>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

std::unique_ptr<Process> arma(long p, long q) { return make_process("ARMA", {{"p", p}, {"q", q}}); }

TEST(ArmaProcess, NeedsWholeScalesAndRefusesOthersNamingTheScale) {
  // Its WV sums the autocovariance over whole lags (docs/statistics.md section 3): a scale
  // between even whole numbers is refused, and the process says so (a curve study refuses
  // such taus before fitting, pipeline/curve_study.h).
  const auto p = make_process("ARMA", {{"p", 1}, {"q", 1}});
  EXPECT_TRUE(p->needs_whole_scales());
  std::vector<double> out(1);
  try {
    p->wv(std::vector<double>{0.5, 0.2, 1.0}, std::vector<double>{3.0}, out);
    FAIL() << "an odd scale was taken";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("an even integer"), std::string::npos) << e.what();
  }
}

TEST(ArmaProcess, NamesItsStructureAndParameters) {
  const auto p = arma(2, 1);
  EXPECT_EQ(p->name(), "ARMA");
  EXPECT_EQ(p->structure(), "p=2,q=1");
  EXPECT_EQ(p->canonical_rank(), 45);
  ASSERT_EQ(p->size(), 4);
  EXPECT_EQ(p->parameters()[0].name, "phi1");
  EXPECT_EQ(p->parameters()[1].name, "phi2");
  EXPECT_EQ(p->parameters()[2].name, "theta1");
  EXPECT_EQ(p->parameters()[3].name, "sigma2");
}

TEST(ArmaProcess, WithOrdersOneOneEqualsArma11) {
  const auto generic = arma(1, 1);
  const auto closed = make_process("ARMA11");
  const auto tau = dyadic_scales(12);
  for (auto [phi, th] : {std::pair{0.6, 0.3}, {-0.7, 0.5}, {0.99, -0.4}, {0.2, 0.9}}) {
    const std::vector<double> theta{phi, th, 1.7};
    const std::string tag = "phi = " + std::to_string(phi) + ", theta = " + std::to_string(th);
    expect_all_relatively_near(wv_of(*generic, theta, tau), wv_of(*closed, theta, tau), 1e-12,
                               "ARMA(1,1) vs ARMA11, " + tag);
    Eigen::MatrixXd jg(12, 3), jc(12, 3), hg(12, 9), hc(12, 9);
    generic->wv_jacobian(theta, tau, jg);
    closed->wv_jacobian(theta, tau, jc);
    generic->wv_hessian(theta, tau, hg);
    closed->wv_hessian(theta, tau, hc);
    EXPECT_LE((jg - jc).cwiseAbs().maxCoeff(), 1e-11 * jc.cwiseAbs().maxCoeff()) << tag;
    EXPECT_LE((hg - hc).cwiseAbs().maxCoeff(), 1e-10 * hc.cwiseAbs().maxCoeff()) << tag;
  }
}

TEST(ArmaProcess, WithOrdersOneZeroEqualsAr1EvenNearTheUnitRoot) {
  const auto generic = arma(1, 0);
  const auto ar1 = make_process("AR1");
  const auto tau = dyadic_scales(14);
  for (double phi : {0.9, -0.5, 0.0, 0.999995}) {
    const std::vector<double> theta{phi, 2.0};
    const double tol = phi > 0.99 ? 1e-10 : 1e-12;
    expect_all_relatively_near(wv_of(*generic, theta, tau), wv_of(*ar1, theta, tau), tol,
                               "ARMA(1,0) vs AR1, phi = " + std::to_string(phi));
  }
}

TEST(ArmaProcess, WithOrdersZeroOneEqualsMa1) {
  const auto generic = arma(0, 1);
  const auto ma1 = make_process("MA1");
  const auto tau = dyadic_scales(10);
  const std::vector<double> theta{-0.45, 0.8};
  expect_all_relatively_near(wv_of(*generic, theta, tau), wv_of(*ma1, theta, tau), 1e-12, "ARMA(0,1) vs MA1");
}

TEST(ArmaProcess, AutocovarianceMatchesALongMovingAverageSum) {
  // Roots of modulus <= 0.8: 3000 psi weights leave a truncation error below 1e-280.
  const auto p = arma(2, 2);
  const std::vector<double> theta{0.5, -0.3, 0.4, 0.2, 1.3};
  std::vector<double> g(12);
  p->generalized_autocovariance(theta, g);
  std::vector<double> psi{1.0};
  for (std::size_t j = 1; j < 3000; ++j) {
    double x = j <= 2 ? theta[1 + j] : 0.0;
    x += theta[0] * psi[j - 1] + (j >= 2 ? theta[1] * psi[j - 2] : 0.0);
    psi.push_back(x);
  }
  for (std::size_t h = 0; h < g.size(); ++h) {
    double s = 0.0;
    for (std::size_t j = 0; j + h < psi.size(); ++j) s += psi[j] * psi[j + h];
    EXPECT_NEAR(g[h], 1.3 * s, 1e-13 * 1.3 * psi[0]) << "h = " << h;
  }
}

TEST(ArmaProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto tau = dyadic_scales(6);
  const auto p = arma(2, 1);
  for (const std::vector<double>& theta :
       {std::vector<double>{0.5, -0.3, 0.4, 1.3}, {1.2, -0.5, -0.6, 0.5}, {-0.2, 0.6, 0.9, 2.0}})
    expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10,
                               "ARMA(2,1) from g");
}

TEST(ArmaProcess, DerivativesMatchFiniteDifferences) {
  expect_derivatives_match_finite_differences(*arma(2, 1), {0.5, -0.3, 0.4, 1.3}, dyadic_scales(10));
  expect_derivatives_match_finite_differences(*arma(2, 2), {1.2, -0.5, -0.6, 0.3, 0.5}, dyadic_scales(10));
  expect_derivatives_match_finite_differences(*arma(1, 2), {0.95, 0.3, -0.2, 1.0}, dyadic_scales(10));
  expect_derivatives_match_finite_differences(*arma(0, 3), {0.3, -0.2, 0.1, 1.0}, dyadic_scales(8));
}

TEST(ArmaProcess, RejectsNonStationaryAndNonInvertiblePolynomialsNamingTheParameters) {
  const auto p = arma(2, 1);
  const std::string ar = p->validate(std::vector<double>{0.5, 0.6, 0.1, 1.0});
  EXPECT_NE(ar.find("phi1..phi2"), std::string::npos) << ar;
  EXPECT_NE(ar.find("stationary"), std::string::npos) << ar;
  const std::string ma = p->validate(std::vector<double>{0.5, 0.1, 1.5, 1.0});
  EXPECT_NE(ma.find("theta1"), std::string::npos) << ma;
  EXPECT_NE(ma.find("invertible"), std::string::npos) << ma;
  EXPECT_EQ(p->validate(std::vector<double>{1.2, -0.5, -0.6, 0.5}), "");
  EXPECT_NE(p->validate(std::vector<double>{0.1, 0.1, 0.1, -1.0}).find("sigma2"), std::string::npos);
  EXPECT_NE(p->validate(std::vector<double>{0.1, 0.1, 1.0}), "");  // wrong size
}

TEST(ArmaProcess, RegistryRejectsBadStructureWithClearMessages) {
  auto message = [](const std::map<std::string, long>& s) {
    try {
      make_process("ARMA", s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({{"p", 1}}).find("q is missing"), std::string::npos);
  EXPECT_NE(message({{"p", -1}, {"q", 1}}).find("p must be"), std::string::npos);
  EXPECT_NE(message({{"p", 1}, {"q", 99}}).find("q must be"), std::string::npos);
  EXPECT_NE(message({{"p", 0}, {"q", 0}}).find("WN"), std::string::npos);
  EXPECT_NE(message({{"p", 1}, {"q", 0}, {"r", 2}}).find("'r'"), std::string::npos);
}

TEST(ArmaProcess, SimulatedMomentsMatchTheAutocovariance) {
  expect_simulated_moments_match(*arma(2, 1), std::vector<double>{1.2, -0.5, -0.6, 0.5}, {.seed = 601});
  expect_simulated_moments_match(*arma(0, 2), std::vector<double>{0.5, 0.4, 1.0}, {.seed = 602});
}

TEST(ArmaProcess, SimulationStartsFromTheStationaryDistribution) {
  expect_first_sample_is_stationary(*arma(2, 1), std::vector<double>{1.5, -0.56, 0.5, 1.0}, 20000, 603);
  expect_first_sample_is_stationary(*arma(1, 2), std::vector<double>{0.99, 0.5, 0.3, 1.0}, 20000, 604);
}

TEST(ArmaProcess, InitialGuessIsValidAndMatchesTheHintedLevel) {
  const auto p = arma(2, 1);
  const auto tau = dyadic_scales(12);
  const auto wv = wv_of(*p, std::vector<double>{1.2, -0.5, -0.6, 0.5}, tau);
  const auto guess = p->initial_guess({tau, wv, 16.0});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(wv_of(*p, guess, std::vector<double>{16.0})[0], wv[3], 1e-10 * wv[3]);
  const auto ma2 = arma(0, 2);
  EXPECT_EQ(ma2->validate(ma2->initial_guess({tau, wv, 0.0})), "");
  EXPECT_EQ(p->validate(p->initial_guess({})), "");
}

TEST(ArmaProcess, PhysicalQuantitiesAreTheDiscreteParameters) {
  const auto p = arma(2, 1);
  const auto q = p->physical(std::vector<double>{0.5, -0.2, 0.3, 1.5}, 10.0);
  ASSERT_EQ(q.size(), 4u);
  const char* names[] = {"phi1", "phi2", "theta1", "sigma2"};
  const double values[] = {0.5, -0.2, 0.3, 1.5};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(q[k].name, names[k]);
    EXPECT_EQ(q[k].value, values[k]);
    EXPECT_EQ(q[k].unit_pattern, "");
  }
}

}  // namespace
}  // namespace gmwm::test
