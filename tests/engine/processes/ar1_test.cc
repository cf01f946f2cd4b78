#include <cmath>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gmwm/engine/check.h"
#include "high_precision_reference.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(Ar1Process, MatchesReferenceWaveletVariance) {
  const auto p = make_process("AR1");
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(
      wv_of(*p, std::vector<double>{0.9, 1.0}, tau),
      {0.26315789473684211, 0.3625, 0.5680840625, 0.83433445313871016, 1.0034787352015113, 0.90012117108309364}, 1e-12,
      "AR1(0.9, 1)");
  expect_all_relatively_near(
      wv_of(*p, std::vector<double>{0.5, 2.0}, tau),
      {0.66666666666666667, 0.625, 0.541015625, 0.37565040588378906, 0.21875063578045228, 0.11718750000242532}, 1e-12,
      "AR1(0.5, 2)");
  expect_all_relatively_near(
      wv_of(*p, std::vector<double>{-0.5, 1.0}, tau),
      {1, 0.1875, 0.0810546875, 0.034686088562011719, 0.015624964678863762, 0.0073784722220874823}, 1e-12,
      "AR1(-0.5, 1)");
}

TEST(Ar1Process, MatchesHighPrecisionValuesNearTheUnitRoot) {
  const auto p = make_process("AR1");
  expect_all_relatively_near(
      wv_of(*p, std::vector<double>{0.999995, 1e-6}, dyadic_scales(10)),
      {2.500006250015625e-7, 3.749993750000000e-7, 6.874934375312500e-7, 1.343716719221870e-6, 2.671728364198320e-6,
       5.335324222771941e-6, 1.066546245309715e-5, 2.132385402619981e-5, 4.262626967189660e-5, 8.517027709134398e-5},
      1e-10, "AR1(0.999995, 1e-6)");
}

TEST(Ar1Process, MatchesReferenceDerivatives) {
  const auto p = make_process("AR1");
  const auto tau = dyadic_scales(5);
  const std::vector<double> theta{0.9, 1.0};
  Eigen::MatrixXd jac(5, 2), hess(5, 4);
  p->wv_jacobian(theta, tau, jac);
  p->wv_hessian(theta, tau, hess);
  const double dphi[] = {-0.13850415512465374, 0.125, 1.082265625, 3.8124777921469766, 8.6751273840395974};
  const double d2phi[] = {0.14579384749963552, 0.0, 2.113125, 20.824038226065938, 96.940684814506211};
  const auto wv = wv_of(*p, theta, tau);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(jac(k, 0), dphi[k], 1e-12 * std::fabs(dphi[k])) << "tau = " << tau[k];
    EXPECT_NEAR(jac(k, 1), wv[static_cast<std::size_t>(k)], 1e-14) << "tau = " << tau[k];
    EXPECT_NEAR(hess(k, 0), d2phi[k], 1e-12 * std::fabs(d2phi[k]) + 1e-14) << "tau = " << tau[k];
    EXPECT_NEAR(hess(k, 1), dphi[k], 1e-12 * std::fabs(dphi[k])) << "tau = " << tau[k];
    EXPECT_EQ(hess(k, 3), 0.0);
  }
}

// Value, d/dphi and d2/dphi2 against 100-digit references for phi from -1 + 1e-6 to
// 1 - 1e-9 at every scale up to 2^30.
void expect_matches_reference(double phi, const Reference& ref, double tau, const std::string& tag) {
  const auto p = make_process("AR1");
  const std::vector<double> theta{phi, 1.0}, t{tau};
  Eigen::MatrixXd jac(1, 2), hess(1, 4);
  p->wv_jacobian(theta, t, jac);
  p->wv_hessian(theta, t, hess);
  const double v = wv_of(*p, theta, t)[0];
  const std::string what = tag + " tau = " + std::to_string(tau);
  EXPECT_NEAR(v, ref.value, 1e-10 * ref.value) << what;
  // Derivatives: relative to the size of the Taylor coefficients (d2 may vanish).
  const double size1 = std::fabs(ref.d1) + std::fabs(ref.value);
  const double size2 = std::fabs(ref.d2) + std::fabs(ref.d1) + std::fabs(ref.value);
  EXPECT_NEAR(jac(0, 0), ref.d1, 1e-10 * size1) << what << " d/dphi";
  EXPECT_NEAR(hess(0, 0), ref.d2, 1e-10 * size2) << what << " d2/dphi2";
}

TEST(Ar1Process, IsAccurateWithDerivativesUpToPhiOneMinus1e9AtAllScales) {
  for (double d : {1e-9, 1e-7, 5e-6, 1e-4, 0.01, 0.3, 0.5, 0.7}) {
    const double phi = 1.0 - d;
    for (int j = 1; j <= 30; ++j)
      expect_matches_reference(phi, ar1_reference(phi, j), std::ldexp(1.0, j), "phi = 1 - " + std::to_string(d));
  }
}

TEST(Ar1Process, IsAccurateWithDerivativesForNegativeAndSmallPhi) {
  for (double phi : {0.2, 0.0, -0.3, -0.5, -0.9, -0.999, -0.999999}) {
    for (int j = 1; j <= 30; ++j)
      expect_matches_reference(phi, ar1_reference(phi, j), std::ldexp(1.0, j), "phi = " + std::to_string(phi));
  }
}

TEST(Ar1Process, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("AR1");
  const auto tau = dyadic_scales(12);
  for (double phi : {0.9, 0.3, 0.0, -0.5, 0.999, -0.999, 1.0 - 1e-6, -1.0 + 1e-6})
    expect_derivatives_match_finite_differences(*p, {phi, 0.7}, tau);
}

TEST(Ar1Process, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("AR1");
  const auto tau = dyadic_scales(6);
  for (double phi : {0.9, 0.4, -0.6}) {
    const std::vector<double> theta{phi, 0.5};
    expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-10,
                               "AR1 from g, phi = " + std::to_string(phi));
  }
}

TEST(Ar1Process, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("AR1");
  expect_simulated_moments_match(*p, std::vector<double>{0.8, 0.5}, {.seed = 104});
  expect_simulated_moments_match(*p, std::vector<double>{-0.6, 2.0}, {.seed = 105});
}

TEST(Ar1Process, SimulationStartsFromTheStationaryDistribution) {
  const auto p = make_process("AR1");
  expect_first_sample_is_stationary(*p, std::vector<double>{0.99, 1.0}, 20000, 106);
}

TEST(Ar1Process, InitialGuessPlacesTheBumpAtTheHint) {
  const auto p = make_process("AR1");
  const auto tau = dyadic_scales(14);
  const std::vector<double> truth{0.99, 1e-4};
  const auto wv = wv_of(*p, truth, tau);
  const auto guess = p->initial_guess({tau, wv, 3.79 / (1.0 - 0.99)});
  ASSERT_EQ(p->validate(guess), "");
  EXPECT_NEAR(guess[0], 0.99, 1e-12);
  EXPECT_NEAR(guess[1], 1e-4, 1e-12);
  // Without a hint, the bump of the data is used.
  const auto unhinted = p->initial_guess({tau, wv, 0.0});
  ASSERT_EQ(p->validate(unhinted), "");
  EXPECT_GT(unhinted[0], 0.9);
  EXPECT_EQ(p->validate(p->initial_guess({})), "");
}

TEST(Ar1Process, SortsByPhiAndRanksFirst) {
  const auto p = make_process("AR1");
  EXPECT_EQ(p->sort_key(), 0);
  EXPECT_EQ(p->canonical_rank(), 10);
  EXPECT_EQ(p->parameters().at(0).name, "phi");
  EXPECT_EQ(p->parameters().at(1).name, "sigma2");
}

TEST(Ar1Process, RejectsPhiOutsideTheUnitIntervalNamingIt) {
  const auto p = make_process("AR1");
  const std::string why = p->validate(std::vector<double>{1.0, 1.0});
  EXPECT_NE(why.find("phi"), std::string::npos) << why;
  EXPECT_NE(p->validate(std::vector<double>{0.5, 0.0}).find("sigma2"), std::string::npos);
}

// The closed form of docs/statistics.md section 3 at a real half-scale m in long double, written
// in a = phi^m (phi^tau = a^2), with a continued as |phi|^m cos(pi m) for a negative phi.
long double ar1_closed_form(long double phi, long double m) {
  const long double pi = 3.141592653589793238462643383279502884L;
  const long double a = std::pow(std::fabs(phi), m) * (phi < 0 ? std::cos(pi * m) : 1.0L);
  const long double tau = 2.0L * m;
  return ((phi * phi - 1.0L) * tau + 2.0L * phi * (a * a - 4.0L * a + 3.0L)) /
         ((phi - 1.0L) * (phi - 1.0L) * (phi - 1.0L) * (phi + 1.0L) * tau * tau);
}

TEST(Ar1Process, TakesScalesBetweenWholeNumbersOfSamplesAsItsClosedFormContinued) {
  // An averaging time of m samples, m not whole (a digitised curve's tau, curve.h): the
  // closed form in m, as at every whole m; for phi < 0 written in a = phi^m, continued as
  // |phi|^m cos(pi m). Against the naive form in long double (no cancellation to speak of
  // at these phi): 1e-12.
  const auto p = make_process("AR1");
  const std::vector<double> tau{2.5, 3.0, 5.5, 13.7, 101.3};
  for (double phi : {0.3, 0.6, 0.9, 0.99, -0.3, -0.6}) {
    std::vector<double> expected;
    for (double t : tau) expected.push_back(static_cast<double>(ar1_closed_form(phi, 0.5L * t)));
    expect_all_relatively_near(wv_of(*p, std::vector<double>{phi, 1.0}, tau), expected, 1e-12,
                               "AR1(" + std::to_string(phi) + ", 1) at non-whole m");
    expect_derivatives_match_finite_differences(*p, {phi, 1.0}, tau);
  }
}

TEST(Ar1Process, RefusesScalesBelowTwoSamplesOrNotFinite) {
  const auto p = make_process("AR1");
  std::vector<double> out(1);
  EXPECT_THROW(p->wv(std::vector<double>{0.5, 1.0}, std::vector<double>{1.0}, out), InvalidArgument);
  EXPECT_THROW(p->wv(std::vector<double>{0.5, 1.0}, std::vector<double>{INFINITY}, out), InvalidArgument);
  EXPECT_THROW(p->wv(std::vector<double>{0.5, 1.0}, std::vector<double>{NAN}, out), InvalidArgument);
  EXPECT_FALSE(p->needs_whole_scales());
}

TEST(Ar1Process, PhysicalCorrelationTimeAndStationarySigma) {
  // phi = 0.99, sigma2 = 1e-4 at f = 100 Hz:
  //   T = -1 / (100 ln 0.99) = -1 / (100 * -0.01005033585) = 0.99499162 s,
  //   sigma = sqrt(1e-4 / (1 - 0.9801)) = sqrt(1e-4 / 0.0199) = 0.07088812 U.
  const auto p = make_process("AR1");
  const auto q = p->physical(std::vector<double>{0.99, 1e-4}, 100.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "correlation time");
  EXPECT_NEAR(q[0].value, 0.9949916247342208, 1e-12);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "deg/s"), "s");
  EXPECT_EQ(q[1].name, "stationary sigma");
  EXPECT_NEAR(q[1].value, 0.07088812050083354, 1e-14);
  EXPECT_EQ(render_unit(q[1].unit_pattern, "deg/s"), "deg/s");
  // The autocovariance decays as exp(-lag / T): g(50) / g(0) = exp(-0.5 / T).
  std::vector<double> g(51);
  p->generalized_autocovariance(std::vector<double>{0.99, 1e-4}, g);
  EXPECT_NEAR(g[50] / g[0], std::exp(-0.5 / q[0].value), 1e-13);
  // phi < 0: the envelope's time, -1 / (100 ln 0.5) = 1 / (100 ln 2) = 0.0144269504 s;
  // phi = 0: 0; |phi| -> 1 stays accurate: phi = 1 - 1e-12 gives 1e12 / 100 s.
  EXPECT_NEAR(p->physical(std::vector<double>{-0.5, 1.0}, 100.0)[0].value, 0.014426950408889633, 1e-15);
  EXPECT_EQ(p->physical(std::vector<double>{0.0, 1.0}, 100.0)[0].value, 0.0);
  EXPECT_NEAR(p->physical(std::vector<double>{1.0 - 1e-12, 1.0}, 100.0)[0].value / 1e10, 1.0, 1e-4);
}

}  // namespace
}  // namespace gmwm::test
