// Monte Carlo checks of the classical WV: CI coverage and unbiasedness for every
// process, with seeds fixed here before looking at results. Tolerances: 3 Monte-Carlo
// standard errors (sd / sqrt(R), sd from the model-based Var(nuhat)) for means; coverage is asserted >= the nominal 95%,
// the eta-based interval being known to be conservative (docs/statistics.md section 5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm {
namespace {

struct Stats {
  std::vector<double> mean, sd, coverage, eta;
  std::vector<double> truth;
  std::vector<double> theory_sd;  // sqrt(Var(nuhat_j)) from the model-based covariance
};

Stats run(const std::string& spec, std::int64_t n, int replicates, std::uint64_t seed) {
  const Model m = parse_model(spec);
  const Eigen::VectorXd theta = m.given_values();
  std::vector<WaveletVariance> w(static_cast<std::size_t>(replicates));
  tbb::parallel_for(0, replicates, [&](int r) {
    const auto x = simulate(m, theta, n, seed, static_cast<std::uint64_t>(r));
    w[static_cast<std::size_t>(r)] = classical_wv(x.data(), n);
  });
  Stats s;
  const int J = w[0].levels();
  const Eigen::VectorXd nu = m.wv(theta, w[0].tau);
  const Eigen::MatrixXd V = model_wv_covariance(m, theta, n, J);
  for (int j = 0; j < J; ++j) {
    double sum = 0, sum2 = 0, cover = 0;
    for (const auto& wr : w) {
      const double v = wr.wv[static_cast<std::size_t>(j)];
      sum += v;
      sum2 += v * v;
      cover +=
          (wr.ci_low[static_cast<std::size_t>(j)] <= nu(j) && nu(j) <= wr.ci_high[static_cast<std::size_t>(j)]) ? 1 : 0;
    }
    const double mean = sum / replicates;
    s.mean.push_back(mean);
    s.sd.push_back(std::sqrt(std::max(0.0, sum2 / replicates - mean * mean) * replicates / (replicates - 1)));
    s.coverage.push_back(cover / replicates);
    s.eta.push_back(w[0].eta[static_cast<std::size_t>(j)]);
    s.truth.push_back(nu(j));
    s.theory_sd.push_back(std::sqrt(V(j, j)));
  }
  return s;
}

void expect_unbiased(const std::string& spec, std::uint64_t seed) {
  // 4000 replicates: with 400 the AR1 case sat at 3.2 MC standard errors at level 6 by
  // chance (a 4000-replicate run of the same seed shows no bias), see the issue notes.
  constexpr int kReplicates = 4000;
  const Stats s = run(spec, 4096, kReplicates, seed);
  int checked = 0;
  for (std::size_t j = 0; j < s.mean.size(); ++j) {
    if (s.eta[j] < 30) continue;
    ++checked;
    // Monte-Carlo standard error of the mean from the exact variance of the WV (the
    // sample sd of a skewed statistic is itself noisy at coarse levels).
    const double se = s.theory_sd[j] / std::sqrt(static_cast<double>(kReplicates));
    EXPECT_LE(std::abs(s.mean[j] - s.truth[j]), 3.0 * se)
        << spec << " level " << j + 1 << ": mean " << s.mean[j] << " truth " << s.truth[j] << " se " << se;
  }
  EXPECT_GE(checked, 5);
}

TEST(WvMonteCarlo, MeanEmpiricalWvOfWhiteNoiseMatchesTheory) { expect_unbiased("WN(sigma2=2)", 101); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfAr1MatchesTheory) { expect_unbiased("AR1(phi=0.9,sigma2=1)", 102); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfRandomWalkMatchesTheory) { expect_unbiased("RW(gamma2=0.01)", 103); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfQuantizationNoiseMatchesTheory) { expect_unbiased("QN(Q2=0.5)", 104); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfMa1MatchesTheory) { expect_unbiased("MA1(theta=0.5,sigma2=1)", 105); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfASinusoidMatchesTheory) { expect_unbiased("SIN(A2=1,f=0.013)+WN(sigma2=1)", 106); }
TEST(WvMonteCarlo, MeanEmpiricalWvOfASumMatchesTheory) {
  expect_unbiased("AR1(phi=0.99,sigma2=0.01)+WN(sigma2=1)+RW(gamma2=1e-4)", 107);
}

TEST(WvMonteCarlo, DriftWvIsDeterministicAndMatchesItsFormula) {
  const Model m = parse_model("DR(omega=0.003)");
  const auto x = simulate(m, m.given_values(), 5000, 1);
  const WaveletVariance w = classical_wv(x.data(), 5000);
  const Eigen::VectorXd nu = m.wv(m.given_values(), w.tau);
  for (int j = 0; j < w.levels(); ++j) EXPECT_NEAR(w.wv[static_cast<std::size_t>(j)] / nu(j), 1.0, 1e-12) << j;
}

void expect_coverage(const std::string& spec, std::uint64_t seed) {
  constexpr int kReplicates = 1000;
  const Stats s = run(spec, 4096, kReplicates, seed);
  std::string record;
  for (std::size_t j = 0; j < 6; ++j) {
    EXPECT_GE(s.coverage[j], 0.95) << spec << " level " << j + 1;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.3f", j ? "," : "", s.coverage[j]);
    record += buf;
  }
  ::testing::Test::RecordProperty("coverage_levels_1_to_6", record);
  std::printf("[ coverage ] %s: %s\n", spec.c_str(), record.c_str());
}

TEST(WvMonteCarlo, ChiSquareCiCoversTheTrueWvOfWhiteNoiseAtLeast95Percent) { expect_coverage("WN(sigma2=1)", 201); }
TEST(WvMonteCarlo, ChiSquareCiCoversTheTrueWvOfAr1AtLeast95Percent) { expect_coverage("AR1(phi=0.9,sigma2=1)", 202); }

}  // namespace
}  // namespace gmwm
