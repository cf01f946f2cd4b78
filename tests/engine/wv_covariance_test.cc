// The model-based covariance of the empirical WV: exact values for white noise, and
// agreement with a Monte-Carlo covariance (fixed seed) for a sum of processes.
#include <gtest/gtest.h>

#include <cmath>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/wv_covariance.h"

#include <Eigen/Dense>

namespace gmwm {
namespace {

ProcessContext one_hz() {
  ProcessContext c;
  c.freq = 1.0;
  c.freq_known = true;
  return c;
}

// V against the sample covariance of R simulated WVs (seed fixed by the caller).
void expect_matches_monte_carlo(const Model& m, const Eigen::MatrixXd& V, std::int64_t n, int R,
                                std::uint64_t seed) {
  const int J = static_cast<int>(V.rows());
  ClassicalWvEstimator est;
  const Eigen::MatrixXd S = bootstrap_wv_covariance(m, m.given_values(), n, J, R, seed, est);
  // A sample variance has relative sd sqrt(2/(R-1)) (Gaussian approximation; the WV's
  // skewness at coarse levels makes it a little larger): allow 4 of them.
  const double tol = 4.0 * std::sqrt(2.0 / (R - 1)) * 1.25;
  for (int j = 0; j < J; ++j) EXPECT_NEAR(S(j, j) / V(j, j), 1.0, tol) << "level " << j + 1;
  // Correlations between neighbouring levels: sd ~ (1 - rho^2)/sqrt(R).
  for (int j = 0; j + 1 < J; ++j) {
    const double rv = V(j, j + 1) / std::sqrt(V(j, j) * V(j + 1, j + 1));
    const double rs = S(j, j + 1) / std::sqrt(S(j, j) * S(j + 1, j + 1));
    EXPECT_NEAR(rs, rv, 4.0 / std::sqrt(static_cast<double>(R)) + 0.01) << "levels " << j + 1 << "," << j + 2;
  }
}

TEST(WvCovariance, WhiteNoiseLevelOneVarianceMatchesTheExactSum) {
  // W_1 = (x_t - x_{t-1})/2: c(0) = s2/2, c(+-1) = -s2/4, so with M = N - 1,
  // Var = 2/M^2 (M s2^2/4 + 2 (M - 1) s2^2/16).
  const Model m = parse_model("WN(sigma2=3)");
  const std::int64_t n = 1000;
  const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), n, 5);
  const double M = static_cast<double>(n - 1), s4 = 9.0;
  EXPECT_NEAR(V(0, 0) / (2.0 / (M * M) * (M * s4 / 4 + 2 * (M - 1) * s4 / 16)), 1.0, 1e-12);
  EXPECT_NEAR((V - V.transpose()).norm(), 0.0, 1e-18);
}

TEST(WvCovariance, UsesTheExactSumAtTheCoarsestLevelWithOneCoefficient) {
  // A single coefficient: Var(W^2) = 2 Var(W)^2 = 2 nu^4.
  const Model m = parse_model("WN(sigma2=1)");
  const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), 1024, 10);
  const double nu = 1.0 / 1024.0;
  EXPECT_NEAR(V(9, 9) / (2 * nu * nu), 1.0, 1e-10);
}

TEST(WvCovariance, AgreesWithMonteCarloForASumOfProcesses) {
  const Model m = parse_model("AR1(phi=0.95,sigma2=0.1)+WN(sigma2=1)+RW(gamma2=1e-3)");
  const std::int64_t n = 2048;
  const int J = 8, R = 4000;
  const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), n, J);
  expect_matches_monte_carlo(m, V, n, R, 77);
}

TEST(WvCovariance, IncludesTheDriftTimesNoiseTermAndAgreesWithMonteCarlo) {
  // With DR the Haar coefficients are d_j + S_{j,t}, d_j = omega tau_j / 4, and
  // Cov(nuhat) gains 4 d_i d_j Cov(mean S_i, mean S_j), which dominates the coarse
  // levels here (the published simulation study's model, shorter series).
  const Model m = parse_model("GM(beta=0.05,sigma2_gm=16)+WN(sigma2=4)+DR(omega=0.005)", one_hz());
  const std::int64_t n = 2048;
  const int J = 11, R = 4000;
  const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), n, J);
  const Model no_drift = parse_model("GM(beta=0.05,sigma2_gm=16)+WN(sigma2=4)", one_hz());
  const Eigen::MatrixXd V0 = model_wv_covariance(no_drift, no_drift.given_values(), n, J);
  EXPECT_GT(V(J - 1, J - 1), 10.0 * V0(J - 1, J - 1)) << "the drift term is missing";
  expect_matches_monte_carlo(m, V, n, R, 78);
}

TEST(WvCovariance, IsFastForAMillionSamples) {
  const Model m = parse_model("3*AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=1e-4)+RW(gamma2=1e-10)+QN(Q2=1e-6)");
  Eigen::VectorXd theta = m.given_values();
  theta(0) = 0.9; theta(2) = 0.999; theta(4) = 0.99999;
  const Eigen::MatrixXd V = model_wv_covariance(m, theta, 1000000, 19);
  for (int j = 0; j < 19; ++j) EXPECT_GT(V(j, j), 0.0) << j;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(V);
  EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * es.eigenvalues().maxCoeff());
}

}  // namespace
}  // namespace gmwm
