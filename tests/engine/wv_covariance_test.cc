// The model-based covariance of the empirical WV: exact values for white noise, and
// agreement with a Monte-Carlo covariance (fixed seed) for a sum of processes.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/gappy_wv.h"
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
void expect_matches_monte_carlo(const Model& m, const Eigen::MatrixXd& V, std::int64_t n, int R, std::uint64_t seed,
                                const WvEstimator& est = ClassicalWvEstimator()) {
  const int J = static_cast<int>(V.rows());
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

TEST(WvCovariance, FollowsTheCompleteWindowsOfARecordWithGaps) {
  // 5% of 2048 samples missing in six runs, leaving segments of 97 to 490 samples. The
  // simulated WVs are read through the same gaps (GappyWvEstimator), so the Monte Carlo is
  // the oracle of the scaled sums: they hold at every level whose windows are at most a
  // quarter of the typical segment (levels 1-6, windows up to 64 samples).
  const Model m = parse_model("AR1(phi=0.95,sigma2=0.1)+WN(sigma2=1)+RW(gamma2=1e-3)");
  const std::int64_t n = 2048;
  const int R = 4000;
  const std::vector<MissingRun> runs = {{100, 20}, {400, 5}, {700, 40}, {1200, 10}, {1500, 30}, {1900, 3}};
  const GappyWvEstimator est(runs);
  std::vector<double> wave(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < wave.size(); ++i) wave[i] = std::sin(0.1 * static_cast<double>(i));
  const WaveletVariance six = est.compute(wave.data(), n, 6, 0.05);
  ASSERT_EQ(six.levels(), 6);
  expect_matches_monte_carlo(m, model_wv_covariance(m, m.given_values(), six), n, R, 78, est);
  // Level 7 keeps 1078 of its 1921 windows; there a window is a quarter to all of a
  // segment, pairs of complete windows thin out with the lag faster than the first-order
  // share, and the scaled variance (1921 / 1078 = 1.78 times the regular record's) is
  // conservative: 20% above the Monte Carlo's, where the regular record's sums are 1.48
  // times too small.
  const WaveletVariance seven = est.compute(wave.data(), n, 7, 0.05);
  ASSERT_EQ(seven.coefficients[6], 1078);
  const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), seven);
  const Eigen::MatrixXd regular = model_wv_covariance(m, m.given_values(), n, 7);
  EXPECT_NEAR(V(6, 6) / regular(6, 6), 1921.0 / 1078.0, 1e-9);
  const Eigen::MatrixXd S = bootstrap_wv_covariance(m, m.given_values(), n, 7, R, 78, est);
  EXPECT_GT(V(6, 6), S(6, 6));
  EXPECT_LT(regular(6, 6), S(6, 6) / 1.4);
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

// Cov(nuhat_i, nuhat_j) = 2 sum_h n_ij(h) c_ij(h)^2 / (M_i M_j) for a zero-mean stationary
// Gaussian series with autocovariance gamma, summed lag by lag: c_ij(h) = sum_k sum_l
// h_i(k) h_j(l) gamma(h - l + k) with the Haar MODWT filters h_j(k) = +-1/tau_j.
// One entry (levels i, j; 0-based) of that covariance: the coarse levels of a long record
// alone, where the whole matrix would cost minutes.
long double lag_by_lag_entry(const std::function<double(long)>& gamma, long n, int i, int j) {
  auto filter = [](long tau) {
    std::vector<double> h(static_cast<std::size_t>(tau));
    for (long k = 0; k < tau; ++k)
      h[static_cast<std::size_t>(k)] = (k < tau / 2 ? 1.0 : -1.0) / static_cast<double>(tau);
    return h;
  };
  const long ti = 2L << i, tj = 2L << j, Mi = n - ti + 1, Mj = n - tj + 1;
  const auto hi = filter(ti), hj = filter(tj);
  // a(m) = sum_k h_i(k) gamma(m + k) for the m that c(h) reads: m = h - l.
  const long lo = -(Mj - 1) - tj, hi_m = Mi - 1;
  std::vector<long double> a(static_cast<std::size_t>(hi_m - lo + 1));
  for (long m = lo; m <= hi_m; ++m) {
    long double s = 0.0L;
    for (long k = 0; k < ti; ++k) s += hi[static_cast<std::size_t>(k)] * gamma(std::labs(m + k));
    a[static_cast<std::size_t>(m - lo)] = s;
  }
  long double sum = 0.0L;
  for (long h = -(Mj - 1); h <= Mi - 1; ++h) {
    // t in [ti - 1, n - 1] and t + h in [tj - 1, n - 1].
    const long count = std::min(n - 1, n - 1 - h) - std::max(ti - 1, tj - 1 - h) + 1;
    if (count <= 0) continue;
    long double c = 0.0L;
    for (long l = 0; l < tj; ++l) c += hj[static_cast<std::size_t>(l)] * a[static_cast<std::size_t>(h - l - lo)];
    sum += static_cast<long double>(count) * c * c;
  }
  return 2.0L * sum / (static_cast<long double>(Mi) * static_cast<long double>(Mj));
}

Eigen::MatrixXd lag_by_lag_covariance(const std::function<double(long)>& gamma, long n, int J) {
  Eigen::MatrixXd V(J, J);
  for (int i = 0; i < J; ++i)
    for (int j = 0; j < J; ++j) V(i, j) = static_cast<double>(lag_by_lag_entry(gamma, n, i, j));
  return V;
}

// Largest |V_ij - ref_ij| / sqrt(ref_ii ref_jj).
double worst_relative_error(const Eigen::MatrixXd& V, const Eigen::MatrixXd& ref) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (Eigen::Index j = 0; j < V.cols(); ++j)
      worst = std::max(worst, std::abs(V(i, j) - ref(i, j)) / std::sqrt(ref(i, i) * ref(j, j)));
  return worst;
}

TEST(WvCovariance, AgreesWithTheLagByLagSumForAr1sOfShortAndLongMemory) {
  // Supports from ~20 to ~1400 lags: long stretches of lags go through the corrected
  // Simpson rule (alone within 1e-8 of the lag-by-lag sum over the same tables). The
  // bound is set by the tables' tail cut (kTailTolerance = 1e-6 on |Delta^2 g|): with the
  // last slope continued as a line it was 5.9e-7 (phi 0.5), 4.3e-7 (0.9), 1.5e-7 (0.99);
  // with the AR1's geometric remainder continued too, the rule's own error is left.
  constexpr double kCovarianceAccuracy = 1e-6;
  const long n = 4096;
  const int J = 6;
  for (const double phi : {0.5, 0.9, 0.99}) {
    const Model m = parse_model("AR1(phi=" + std::to_string(phi) + ",sigma2=2)+WN(sigma2=0.1)", one_hz());
    const auto gamma = [&](long k) {
      return 2.0 / (1.0 - phi * phi) * std::pow(phi, static_cast<double>(k)) + (k == 0 ? 0.1 : 0.0);
    };
    const double err =
        worst_relative_error(model_wv_covariance(m, m.given_values(), n, J), lag_by_lag_covariance(gamma, n, J));
    EXPECT_LT(err, kCovarianceAccuracy) << "phi " << phi;
  }
}

TEST(WvCovariance, TheCoarsestLevelOfAnAr1HasTheExactVarianceOfItsSingleCoefficient) {
  // One Haar coefficient at the last level of 2^J samples: Var(nuhat_J) = 2 nu_J^2 exactly.
  // The tables' tail once continued an AR1's residual slope over the whole record: V_JJ came
  // out 3351 (phi 0.5), 3.1e5 (0.9), 1.2e4 (0.99) and 155 (0.999) times that at 2^18. Now
  // within 4e-9 (phi <= 0.99) and 1.5e-6 (0.999: the remainder's ratio rho = phi is read off
  // second differences of ~1e-9 g(0), and (1 - rho)^2 scales its error), the 1e-6 order of
  // the tables' tail cut (kTailTolerance).
  constexpr double kSingleCoefficientAccuracy = 1e-5;
  const std::int64_t n = std::int64_t{1} << 18;
  for (const double phi : {0.5, 0.9, 0.99, 0.999}) {
    const Model m = parse_model("AR1(phi=" + std::to_string(phi) + ",sigma2=1)", one_hz());
    const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), n, 18);
    const double nu = m.wv(m.given_values(), std::vector<double>{std::ldexp(1.0, 18)})(0);
    EXPECT_NEAR(V(17, 17) / (2.0 * nu * nu), 1.0, kSingleCoefficientAccuracy) << "phi " << phi;
  }
}

TEST(WvCovariance, SumsThePolynomialStretchesOfARandomWalkExactly) {
  // Between breakpoints n(h) c(h)^2 of WN + RW is a polynomial of degree 7 in h (the random
  // walk's structure function is cubic), which the stretch rule sums exactly (issue 44):
  // only round-off is left. The earlier rule (error O(s^6 f^(6)), exact to degree 5) was
  // 9.4e-9 off at N = 1e6. The walk's generalized autocovariance -gamma2 |k| / 2 serves the
  // lag-by-lag sum, since the Haar filters sum to zero.
  constexpr double kRoundOff = 1e-12;
  const long n = 4096;
  const int J = 8;
  const Model m = parse_model("WN(sigma2=1)+RW(gamma2=1e-3)", one_hz());
  const auto gamma = [](long k) { return -1e-3 * static_cast<double>(k) / 2.0 + (k == 0 ? 1.0 : 0.0); };
  const double err =
      worst_relative_error(model_wv_covariance(m, m.given_values(), n, J), lag_by_lag_covariance(gamma, n, J));
  std::printf("[ wv covariance ] WN + RW against the lag-by-lag sum: %.3g\n", err);
  EXPECT_LT(err, kRoundOff);
}

TEST(WvCovariance, AgreesWithTheLagByLagSumAtTheCoarsestLevelsOfARecord) {
  // Levels 10-12 of 2^12 samples, where the lags reach the record's length: the tables' tail
  // (a line plus the AR1's geometric remainder) against the exact sum. Measured <= 2.9e-8.
  constexpr double kCoarseAccuracy = 1e-7;
  const long n = 4096;
  for (const double phi : {0.5, 0.9, 0.99, 0.999}) {
    const Model m = parse_model("AR1(phi=" + std::to_string(phi) + ",sigma2=2)+WN(sigma2=0.1)", one_hz());
    const auto gamma = [&](long k) {
      return 2.0 / (1.0 - phi * phi) * std::pow(phi, static_cast<double>(k)) + (k == 0 ? 0.1 : 0.0);
    };
    const Eigen::MatrixXd V = model_wv_covariance(m, m.given_values(), n, 12);
    for (int j = 9; j < 12; ++j) {
      const long double exact = lag_by_lag_entry(gamma, n, j, j);
      EXPECT_LT(std::abs(static_cast<double>((V(j, j) - exact) / exact)), kCoarseAccuracy)
          << "phi " << phi << ", level " << j + 1;
    }
  }
}

TEST(WvCovariance, IgnoresACollapsedComponentBelowItsNegligibleShare) {
  // A WN at 1e-17 beside an AR1 of variance ~1 (a maximal model's collapsed term) moves V
  // by at most ~1e-17 relative: the result equals the AR1's alone to 1e-10.
  const Model with = parse_model("AR1(phi=0.999,sigma2=1e-3)+WN(sigma2=1e-17)+QN(Q2=1e-20)", one_hz());
  const Model without = parse_model("AR1(phi=0.999,sigma2=1e-3)", one_hz());
  const Eigen::MatrixXd a = model_wv_covariance(with, with.given_values(), 100000, 14);
  const Eigen::MatrixXd b = model_wv_covariance(without, without.given_values(), 100000, 14);
  for (int i = 0; i < 14; ++i)
    for (int j = 0; j < 14; ++j) EXPECT_NEAR(a(i, j) / b(i, j), 1.0, 1e-10) << i << "," << j;
  // A visible WN is kept: it changes the finest level's variance by far more than that.
  const Model visible = parse_model("AR1(phi=0.999,sigma2=1e-3)+WN(sigma2=1e-3)", one_hz());
  EXPECT_GT(model_wv_covariance(visible, visible.given_values(), 100000, 14)(0, 0), 1.5 * b(0, 0));
}

TEST(WvCovariance, IsFastForAMillionSamples) {
  const Model m = parse_model("3*AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=1e-4)+RW(gamma2=1e-10)+QN(Q2=1e-6)");
  Eigen::VectorXd theta = m.given_values();
  theta(0) = 0.9;
  theta(2) = 0.999;
  theta(4) = 0.99999;
  const Eigen::MatrixXd V = model_wv_covariance(m, theta, 1000000, 19);
  for (int j = 0; j < 19; ++j) EXPECT_GT(V(j, j), 0.0) << j;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(V);
  EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * es.eigenvalues().maxCoeff());
}

}  // namespace
}  // namespace gmwm
