// The robust WV (robust/src/robust_wv.cc): Fisher consistency at the Gaussian (Huber
// and bisquare) and the small-eta fallback, Monte-Carlo efficiency of the scale
// M-estimator against the spec's target, no root on heavily quantized data, robustness to isolated spikes, the
// robust CIs (eff x eta degrees of freedom), the estimator object and option checks.
// Seeds are fixed here; tolerances are derived in the comments from the estimators'
// asymptotic variances and the number of replicates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <tbb/parallel_for.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"
#include "robust_test_util.h"

namespace gmwm::robust {
namespace {

using namespace test_util;

#include "robust_test_util.h"

// Fisher consistency on Gaussian white noise.

struct LevelSummary {
  double truth = 0.0;           // sigma2 / tau_j
  double eta = 0.0;             // classical eta_j = max(M_j / tau_j, 1)
  double mean = 0.0, sd = 0.0;  // of the robust estimate over replicates
  double coverage = 0.0;        // share of robust CIs containing the truth
  double var_ratio = 0.0;       // Var(classical) / Var(robust) over replicates
  std::string note;             // of replicate 0
};

// Replicates of the Gaussian model `spec` (with values): robust and classical WVs.
std::vector<LevelSummary> consistency_study(const char* spec, RobustKind kind, double eff, std::int64_t n,
                                            int replicates, std::uint64_t seed) {
  const Model model = parse_model(spec);
  const Eigen::VectorXd theta = model.given_values();
  RobustWvOptions o;
  o.estimator = kind;
  o.efficiency = eff;
  std::vector<WaveletVariance> rob(static_cast<std::size_t>(replicates)), cla(rob.size());
  // Replicate r draws from stream r only: the result does not depend on the thread count.
  tbb::parallel_for(0, replicates, [&](int r) {
    const auto x = simulate(model, theta, n, seed, static_cast<std::uint64_t>(r));
    rob[static_cast<std::size_t>(r)] = robust_wv(x.data(), n, o);
    cla[static_cast<std::size_t>(r)] = classical_wv(x.data(), n);
  });
  std::vector<LevelSummary> out(rob[0].wv.size());
  const Eigen::VectorXd truth = model.wv(theta, rob[0].tau);
  for (std::size_t j = 0; j < out.size(); ++j) {
    LevelSummary& s = out[j];
    s.truth = truth(static_cast<Eigen::Index>(j));
    s.eta = cla[0].eta[j];
    s.note = rob[0].notes[j];
    double sr = 0, sr2 = 0, sc = 0, sc2 = 0, cover = 0;
    for (std::size_t r = 0; r < rob.size(); ++r) {
      const double v = rob[r].wv[j], c = cla[r].wv[j];
      sr += v;
      sr2 += v * v;
      sc += c;
      sc2 += c * c;
      cover += rob[r].ci_low[j] <= s.truth && s.truth <= rob[r].ci_high[j];
    }
    const double R = replicates;
    s.mean = sr / R;
    s.sd = std::sqrt((sr2 - R * s.mean * s.mean) / (R - 1));
    const double cmean = sc / R, csd2 = (sc2 - R * cmean * cmean) / (R - 1);
    s.var_ratio = csd2 / (s.sd * s.sd);
    s.coverage = cover / R;
  }
  return out;
}

// N = 24000 puts eta at 11999.5, 5999.25, ..., 45.9 (levels 1-9: the spec's criterion
// levels, eta >= 30), 22.4 and 10.7 (levels 10-11: robust, below 30) and 4.9, 1.9, 1
// (levels 12-14: classical fallback below kRobustMinEta = 10).
constexpr std::int64_t kConsistencyN = 24000;
// 2000 replicates, chosen from the nominal variance of the robust estimate,
// 2 nu^4 / (eff eta): its Monte-Carlo standard error at eta = 46 (level 9) is
// sqrt(2 / (0.6 x 46)) / sqrt(2000) = 0.6% of the truth, so three of them resolve a
// bias of ~2%. (eta is conservative for white noise: the measured standard error is
// about half that.)
constexpr int kConsistencyReplicates = 2000;

void print_study(const char* label, const std::vector<LevelSummary>& s) {
  for (std::size_t j = 0; j < s.size(); ++j)
    std::printf("[ %s ] level %2zu eta %8.2f mean/truth - 1 %+.4f (%.2f MC se) var ratio %.3f coverage %.3f%s\n", label,
                j + 1, s[j].eta, s[j].mean / s[j].truth - 1.0,
                (s[j].mean - s[j].truth) / (s[j].sd / std::sqrt(static_cast<double>(kConsistencyReplicates))),
                s[j].var_ratio, s[j].coverage, s[j].note.empty() ? "" : " (classical fallback)");
}

// The three tests on the Huber study share one run (1.6 s on 2 cores).
const std::vector<LevelSummary>& huber_study() {
  static const auto s =
      consistency_study("WN(sigma2=1)", RobustKind::kHuber, 0.6, kConsistencyN, kConsistencyReplicates, 3101);
  return s;
}

// |mean - truth| <= 3 Monte-Carlo standard errors (the replicates' sd / sqrt(R)) at every
// level with eta >= 30 (issue 3). Without the small-sample correction
// (robust/src/small_sample.h) the Huber estimate is biased by about +0.35 / eta on these
// levels (4000 replicates; with this seed +1.34% at eta 45.9, 4.4 standard errors): this
// check fails without it.
void expect_fisher_consistent(const std::vector<LevelSummary>& s) {
  int checked = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s[j].eta < 30.0) continue;
    ++checked;
    const double se = s[j].sd / std::sqrt(static_cast<double>(kConsistencyReplicates));
    EXPECT_LE(std::abs(s[j].mean - s[j].truth), 3.0 * se)
        << "level " << j + 1 << " (eta " << s[j].eta << "): mean/truth - 1 = " << s[j].mean / s[j].truth - 1.0 << ", "
        << (s[j].mean - s[j].truth) / se << " Monte-Carlo standard errors";
  }
  EXPECT_EQ(checked, 9);
}

TEST(RobustWvConsistency, HuberMeanIsWithinThreeMonteCarloErrorsOfTheTruthAtEveryLevelWithEtaAtLeast30) {
  const auto& s = huber_study();
  print_study("huber 0.6", s);
  expect_fisher_consistent(s);
}

TEST(RobustWvConsistency, HuberMeanIsWithinThreeMonteCarloErrorsOnARandomWalkPlusWhiteNoise) {
  // The coarse levels of WN + RW (crossover at tau ~ 110) are random-walk dominated:
  // their coefficients are correlated differently from white noise's, and the
  // correction estimates the long-run covariances from the data rather than assuming
  // one structure. Uncorrected, levels 7-9 are biased by +0.55%, +0.86%, +1.57% here
  // (3.2 to 3.9 Monte-Carlo standard errors, this seed): the check fails without it.
  const auto s = consistency_study("WN(sigma2=1)+RW(gamma2=1e-3)", RobustKind::kHuber, 0.6, kConsistencyN,
                                   kConsistencyReplicates, 3103);
  print_study("huber 0.6, WN+RW", s);
  expect_fisher_consistent(s);
}

TEST(RobustWvConsistency, HuberStaysWithinTenPercentAtCoarseRobustLevelsAndFallsBackBelowEtaTen) {
  // Levels with 10 <= eta < 30 are estimated robustly but carry the estimator's
  // small-sample bias (spec section 2: +8% in the median at eta = 7, shrinking like
  // 1 / eta); the mean relative error over them must stay within 10%. Below eta = 10
  // the classical estimate is used and the note says so.
  const auto& s = huber_study();
  double rel = 0.0;
  int robust_coarse = 0, fallback = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s[j].eta >= 30.0) continue;
    if (s[j].eta >= kRobustMinEta) {
      EXPECT_TRUE(s[j].note.empty()) << "level " << j + 1 << ": " << s[j].note;
      rel += s[j].mean / s[j].truth - 1.0;
      ++robust_coarse;
    } else {
      ++fallback;
      EXPECT_EQ(s[j].note.rfind("classical estimate", 0), 0u) << "level " << j + 1 << ": " << s[j].note;
      EXPECT_NE(s[j].note.find("eta"), std::string::npos) << s[j].note;
    }
  }
  ASSERT_EQ(robust_coarse, 2);
  EXPECT_EQ(fallback, 3);
  std::printf("[ huber 0.6 ] mean relative error over the levels with 10 <= eta < 30: %+.4f\n", rel / robust_coarse);
  EXPECT_LE(std::abs(rel / robust_coarse), 0.10);
}

TEST(RobustWvConsistency, HuberCisCoverTheWhiteNoiseWvAtLeastAtTheNominalRate) {
  // Coverage of the eff x eta chi-square CI at the criterion levels (eta >= 30): the
  // binomial standard error at 95% and 2000 replicates is 0.49%, so the bound is the
  // nominal 95% less three of them (eta is conservative for white noise, so the CIs
  // over-cover; the check is that the robust estimate's bias does not spoil them).
  const auto& s = huber_study();
  const double bound = 0.95 - 3.0 * std::sqrt(0.95 * 0.05 / kConsistencyReplicates);
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s[j].eta >= 30.0) {
      EXPECT_GE(s[j].coverage, bound) << "level " << j + 1;
    }
  }
}

TEST(RobustWvConsistency, BisquareMeanIsWithinThreeMonteCarloErrorsOfTheTruthAtEveryLevelWithEtaAtLeast30) {
  const auto s =
      consistency_study("WN(sigma2=1)", RobustKind::kBisquare, 0.6, kConsistencyN, kConsistencyReplicates, 3102);
  print_study("bisquare 0.6", s);
  expect_fisher_consistent(s);
}

// ---------------------------------------------------------------------------------
// Monte-Carlo efficiency on i.i.d. Gaussian samples.

// R replicates of n i.i.d. N(0, 1): the classical scale (mean of squares: the efficient
// estimator when the mean is known, as for wavelet coefficients) and solve_scale at
// each tuning. Efficiency = Var(classical) / Var(robust).
//
// Tolerance: a regular asymptotically linear estimator T of the scale satisfies
// T = S + E with S the efficient estimator and E uncorrelated with S, Var(E) =
// Var(S) (1/eff - 1). The delta method then gives, for Gaussian-like sampling
// distributions, sd(log(Var^(S) / Var^(T))) = sqrt(4 (1 - eff) / R). With R = 20000 this
// is 0.0089 at eff 0.6 and 0.0045 at 0.9, i.e. 0.0054 and 0.0040 on the efficiency:
// +-0.03 is more than 5 standard errors, and the O(1/n) finite-sample change of the
// efficiency at n = 1000 is ~1e-3.
TEST(RobustScaleEfficiency, MonteCarloEfficiencyOnGaussianDataMatchesTheTarget) {
  constexpr int kReplicates = 20000;
  constexpr int kN = 1000;
  const std::vector<Tuning> tunings = {tune(RobustKind::kHuber, 0.6), tune(RobustKind::kHuber, 0.9),
                                       tune(RobustKind::kBisquare, 0.6), tune(RobustKind::kBisquare, 0.9)};
  const std::size_t K = tunings.size();
  std::vector<double> classical(kReplicates), robust(kReplicates * K);
  std::vector<int> rooted(kReplicates * K);
  tbb::parallel_for(0, kReplicates, [&](int r) {
    Rng g = make_stream(4201, {static_cast<std::uint64_t>(r)});
    boost::random::normal_distribution<double> normal;
    std::vector<double> w(kN);
    for (double& v : w) v = normal(g);
    const double c = mean_of_squares(w);
    classical[static_cast<std::size_t>(r)] = c;
    for (std::size_t k = 0; k < K; ++k) {
      const ScaleSolution s = solve_scale(w, tunings[k], c);
      robust[static_cast<std::size_t>(r) * K + k] = s.scale;
      rooted[static_cast<std::size_t>(r) * K + k] = s.has_root;
    }
  });
  auto variance = [](const std::vector<double>& v, std::size_t stride, std::size_t offset) {
    double s = 0.0, s2 = 0.0;
    const double R = static_cast<double>(v.size() / stride);
    for (std::size_t i = offset; i < v.size(); i += stride) s += v[i];
    const double m = s / R;
    for (std::size_t i = offset; i < v.size(); i += stride) s2 += (v[i] - m) * (v[i] - m);
    return s2 / (R - 1.0);
  };
  const double var_classical = variance(classical, 1, 0);
  for (std::size_t k = 0; k < K; ++k) {
    int roots = 0;
    for (int r = 0; r < kReplicates; ++r) roots += rooted[static_cast<std::size_t>(r) * K + k];
    ASSERT_EQ(roots, kReplicates) << to_string(tunings[k].kind);
    const double eff = var_classical / variance(robust, K, k);
    const double se = tunings[k].efficiency * std::sqrt(4.0 * (1.0 - tunings[k].efficiency) / kReplicates);
    std::printf("[ efficiency ] %-8s target %.2f measured %.4f (theory se %.4f)\n", to_string(tunings[k].kind),
                tunings[k].efficiency, eff, se);
    EXPECT_NEAR(eff, tunings[k].efficiency, 0.03) << to_string(tunings[k].kind);
  }
}

// ---------------------------------------------------------------------------------
// The root finder.

TEST(RobustWv, HeavilyQuantizedSeriesGivesNoRootAtLevelOneNeverANumber) {
  // round(0.3 Z): 90% of the samples are 0, ~82% of the level-1 coefficients are
  // exactly 0, far above the 56.7% limit.
  constexpr std::int64_t n = 1 << 14;
  auto x = white_noise(n, 5201, 0);
  for (double& v : x) v = std::round(0.3 * v);
  const WaveletVariance w = robust_wv(x.data(), n);
  EXPECT_TRUE(std::isnan(w.wv[0])) << w.wv[0];
  EXPECT_TRUE(std::isnan(w.ci_low[0]) && std::isnan(w.ci_high[0]) && std::isnan(w.variance[0]));
  EXPECT_EQ(w.notes[0].rfind("no root", 0), 0u) << w.notes[0];
  for (int j = 0; j < w.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j);
    if (std::isnan(w.wv[i])) {
      EXPECT_EQ(w.notes[i].rfind("no root", 0), 0u) << j + 1 << ": " << w.notes[i];
    } else {
      EXPECT_TRUE(w.wv[i] > 0.0 && std::isfinite(w.wv[i])) << j + 1 << ": " << w.wv[i];
    }
  }
  // The same through the multi-series entry point.
  const auto many = robust_wv(std::vector<std::span<const double>>{x});
  EXPECT_TRUE(std::isnan(many[0].wv[0]));
  EXPECT_EQ(many[0].notes[0], w.notes[0]);
}

// ---------------------------------------------------------------------------------
// Robustness to isolated spikes.

// The scale s (in units of the clean variance) solving the estimating equation at a
// Gaussian contaminated by a share eps of gross outliers (spec section 2):
//   (1 - eps) E[chi(Z^2 / s)] + eps chi(inf) = a,
// chi(inf) = c^2 for Huber (clipped), 0 for bisquare (rejected). E[.] by Gauss-Kronrod
// on [0, c sqrt(s)] and beyond (chi has a kink there), s by bisection on [0.3, 3].
double outlier_scale(const Tuning& t, double eps) {
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  auto lhs = [&](double s) {
    auto f = [&](double z) {
      return 2.0 * chi(t.kind, t.c, z * z / s) * std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    };
    const double k = t.c * std::sqrt(s);
    const double tail = t.kind == RobustKind::kHuber ? t.c * t.c : 0.0;
    return (1.0 - eps) * (GK::integrate(f, 0.0, k, 15, 1e-13) + GK::integrate(f, k, 40.0, 15, 1e-13)) + eps * tail -
           t.a;
  };
  double lo = 0.3, hi = 3.0;  // lhs > 0 at lo, < 0 at hi for eps <= 10%
  for (int i = 0; i < 60; ++i) (lhs(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

TEST(RobustWv, OutlierBiasPredictionMatchesTheSpecFigures) {
  // Sanity of the helper: eps = 0 gives back the consistent scale 1, and Huber's bias
  // grows with eps while staying bounded (the spec: bounded whatever the outliers' size).
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare})
    EXPECT_NEAR(outlier_scale(tune(kind, 0.6), 0.0), 1.0, 1e-9) << to_string(kind);
  const Tuning h = tune(RobustKind::kHuber, 0.6);
  EXPECT_GT(outlier_scale(h, 0.04), outlier_scale(h, 0.02));
  EXPECT_LT(outlier_scale(h, 0.02), 1.10);
}

TEST(RobustWv, IsolatedSpikesBarelyMoveTheRobustLevelOneWvEvenWithoutTheSpikeScreen) {
  // 1% isolated spikes of +-20 sd (one per block of 100 samples, away from the block
  // edges, so never adjacent) on unit WN. Each spike puts two level-1 coefficients at
  // ~+-10, i.e. eps = 2% gross outliers: the classical WV (0.5) gains ~eps x 100 = 2
  // (+400%), while the robust ones move as outlier_scale predicts (Huber +5.6% at eff
  // 0.6, bisquare -4%). Median over 20 replicates of the spiky / clean ratio, same seeds.
  constexpr std::int64_t n = 1 << 14;
  constexpr int kReplicates = 20;
  std::vector<double> huber(kReplicates), bisquare(kReplicates), classical(kReplicates);
  RobustWvOptions hb, bs;
  bs.estimator = RobustKind::kBisquare;
  hb.levels = bs.levels = 3;
  hb.screen_spikes = bs.screen_spikes = false;  // the estimator's own bounded influence
  tbb::parallel_for(0, kReplicates, [&](int r) {
    const auto clean = white_noise(n, 5301, static_cast<std::uint64_t>(r));
    auto spiky = clean;
    Rng g = make_stream(5302, {static_cast<std::uint64_t>(r)});
    boost::random::uniform_int_distribution<int> where(10, 89), sign(0, 1);
    for (std::int64_t b = 0; b + 100 <= n; b += 100)
      spiky[static_cast<std::size_t>(b + where(g))] += sign(g) ? 20.0 : -20.0;
    const auto i = static_cast<std::size_t>(r);
    huber[i] = robust_wv(spiky.data(), n, hb).wv[0] / robust_wv(clean.data(), n, hb).wv[0];
    bisquare[i] = robust_wv(spiky.data(), n, bs).wv[0] / robust_wv(clean.data(), n, bs).wv[0];
    classical[i] = classical_wv(spiky.data(), n).wv[0] / classical_wv(clean.data(), n).wv[0];
  });
  const double ph = outlier_scale(tune(RobustKind::kHuber, 0.6), 0.02);
  const double pb = outlier_scale(tune(RobustKind::kBisquare, 0.6), 0.02);
  std::printf(
      "[ spikes ] level-1 spiky/clean medians: huber %.4f (predicted %.4f), bisquare %.4f (predicted %.4f), "
      "classical %.3f\n",
      median(huber), ph, median(bisquare), pb, median(classical));
  EXPECT_NEAR(median(huber), 1.0, 0.10);
  EXPECT_NEAR(median(bisquare), 1.0, 0.10);
  EXPECT_GT(median(classical), 1.30);
  // And as predicted: the level-1 coefficients are not independent (MA(1), correlation
  // -1/2), but the marginal argument holds; 2% leaves room for the 20-replicate median.
  EXPECT_NEAR(median(huber), ph, 0.02);
  EXPECT_NEAR(median(bisquare), pb, 0.02);
}

TEST(RobustWv, EnormousSpikesLeaveTheRobustWvFiniteAndBoundedEvenWithoutTheSpikeScreen) {
  // 1% isolated spikes of 1e4 sd: the classical WV is ~1e6 times the robust one. A spike
  // makes tau_j gross coefficients at level j (eps_j = tau_j / 100); the robust ratio
  // spiky / clean must be finite and close to outlier_scale(eps_j) (Huber: +6%, +12%,
  // +27% at levels 1-3; bisquare -4%, -8%, -17%), since the outliers' size does not
  // matter. Regressions: solve_scale, started from the classical value, took one
  // unbounded Newton step past its 2^-300 guard and reported "no root" at every level;
  // bisquare at level 3 then collapsed onto the spikes' own hump (g < 0) and gave up.
  constexpr std::int64_t n = 1 << 14;
  const auto clean = white_noise(n, 5311, 0);
  auto spiky = clean;
  for (std::int64_t b = 50; b < n; b += 100) spiky[static_cast<std::size_t>(b)] += (b / 100) % 2 ? 1e4 : -1e4;
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    RobustWvOptions o;
    o.estimator = kind;
    o.screen_spikes = false;  // the estimator's own bounded influence (spike_screen_test.cc: with it)
    const WaveletVariance r = robust_wv(spiky.data(), n, o), c = robust_wv(clean.data(), n, o);
    const WaveletVariance cs = classical_wv(spiky.data(), n);
    for (int j = 0; j < 3; ++j) {
      const auto i = static_cast<std::size_t>(j);
      const double predicted = outlier_scale(tune(kind, 0.6), r.tau[i] / 100.0);
      std::printf("[ huge spikes ] %-8s level %d: robust spiky/clean %.4f (predicted %.4f), classical %.3g\n",
                  to_string(kind), j + 1, r.wv[i] / c.wv[i], predicted, cs.wv[i] / c.wv[i]);
      EXPECT_TRUE(r.notes[i].empty()) << to_string(kind) << " level " << j + 1 << ": " << r.notes[i];
      EXPECT_NEAR(r.wv[i] / c.wv[i], predicted, 0.05) << to_string(kind) << " level " << j + 1;
    }
  }
}

// ---------------------------------------------------------------------------------
// Robust CIs, the estimator object, options.

TEST(RobustWv, CisUseEfficiencyTimesEtaDegreesOfFreedomAndAreWiderThanClassical) {
  constexpr std::int64_t n = 1 << 14;
  const auto x = white_noise(n, 5401, 0);
  const WaveletVariance c = classical_wv(x.data(), n);
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double eff : {0.6, 0.9}) {
      RobustWvOptions o;
      o.estimator = kind;
      o.efficiency = eff;
      const WaveletVariance w = robust_wv(x.data(), n, o);
      EXPECT_EQ(w.estimator, to_string(kind));
      ASSERT_TRUE(w.efficiency.has_value());
      EXPECT_EQ(*w.efficiency, eff);
      ASSERT_EQ(w.levels(), c.levels());
      int robust_levels = 0;
      for (std::size_t j = 0; j < w.wv.size(); ++j) {
        EXPECT_EQ(w.tau[j], c.tau[j]);
        EXPECT_EQ(w.coefficients[j], c.coefficients[j]);
        if (c.eta[j] < kRobustMinEta) {  // classical fallback: everything as classical
          EXPECT_FALSE(w.notes[j].empty());
          EXPECT_EQ(w.wv[j], c.wv[j]);
          EXPECT_EQ(w.eta[j], c.eta[j]);
          EXPECT_EQ(w.ci_low[j], c.ci_low[j]);
          EXPECT_EQ(w.ci_high[j], c.ci_high[j]);
          continue;
        }
        ++robust_levels;
        EXPECT_TRUE(w.notes[j].empty()) << w.notes[j];
        EXPECT_DOUBLE_EQ(w.eta[j], eff * c.eta[j]) << j + 1;
        EXPECT_DOUBLE_EQ(w.variance[j], 2.0 * w.wv[j] * w.wv[j] / w.eta[j]) << j + 1;
        const auto ci = chi_square_ci(w.wv[j], eff * c.eta[j], w.alpha);
        EXPECT_DOUBLE_EQ(w.ci_low[j], ci.first) << j + 1;
        EXPECT_DOUBLE_EQ(w.ci_high[j], ci.second) << j + 1;
        EXPECT_LT(w.ci_low[j], w.wv[j]) << j + 1;
        EXPECT_GT(w.ci_high[j], w.wv[j]) << j + 1;
        // Wider, both absolutely and relative to the estimate (fewer degrees of freedom).
        EXPECT_GT(w.ci_high[j] - w.ci_low[j], c.ci_high[j] - c.ci_low[j]) << j + 1;
        EXPECT_GT((w.ci_high[j] - w.ci_low[j]) / w.wv[j], (c.ci_high[j] - c.ci_low[j]) / c.wv[j]) << j + 1;
      }
      EXPECT_EQ(robust_levels, 10);  // eta >= 10 at levels 1-10 for N = 2^14
    }
  }
}

TEST(RobustWv, EstimatorObjectComputesTheSameAsTheFunction) {
  constexpr std::int64_t n = 5000;
  const auto x = white_noise(n, 5501, 0);
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    RobustWvOptions o;
    o.estimator = kind;
    o.efficiency = 0.8;
    const RobustWvEstimator est(o);
    EXPECT_EQ(est.name(), to_string(kind));
    o.levels = 7;
    o.alpha = 0.1;
    const WaveletVariance a = est.compute(x.data(), n, 7, 0.1), b = robust_wv(x.data(), n, o);
    ASSERT_EQ(a.levels(), 7);
    EXPECT_EQ(a.wv, b.wv);
    EXPECT_EQ(a.ci_low, b.ci_low);
    EXPECT_EQ(a.ci_high, b.ci_high);
    EXPECT_EQ(a.eta, b.eta);
    EXPECT_EQ(a.notes, b.notes);
    EXPECT_EQ(a.alpha, 0.1);
    EXPECT_EQ(a.estimator, to_string(kind));
  }
  EXPECT_EQ(RobustWvEstimator(RobustWvOptions{}).name(), "huber");
  RobustWvOptions bad;
  bad.efficiency = 1.0;
  EXPECT_THROW(RobustWvEstimator{bad}, InvalidArgument);
}

TEST(RobustWv, ManySeriesGiveTheSameAsOneAtATime) {
  // The multi-series entry point runs series x levels in parallel: same numbers.
  std::vector<std::vector<double>> xs;
  for (std::uint64_t k = 0; k < 3; ++k) xs.push_back(white_noise(3000 + 1000 * static_cast<std::int64_t>(k), 5601, k));
  RobustWvOptions o;
  o.estimator = RobustKind::kBisquare;
  std::vector<std::span<const double>> spans(xs.begin(), xs.end());
  const auto many = robust_wv(spans, o);
  ASSERT_EQ(many.size(), 3u);
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const auto one = robust_wv(xs[k].data(), static_cast<std::int64_t>(xs[k].size()), o);
    EXPECT_EQ(many[k].wv, one.wv) << k;
    EXPECT_EQ(many[k].notes, one.notes) << k;
  }
}

TEST(RobustWv, ReusingTheClassicalTransformsGivesTheSameNumbersAndScreenedSeriesGetTheirOwn) {
  // The studies hand the classical WV's transforms to the robust WV (issue 44): a series
  // whose screen replaces nothing is read from them, a screened one (spikes) is transformed
  // again from its cleaned copy; both give what the transforming form gives, to the bit.
  std::vector<std::vector<double>> xs;
  for (std::uint64_t k = 0; k < 2; ++k) xs.push_back(white_noise(4096, 5611, k));
  for (std::size_t t = 1000; t < 4000; t += 700) xs[1][t] += 500.0;  // isolated spikes: screened
  RobustWvOptions o;
  o.estimator = RobustKind::kBisquare;
  const std::vector<std::span<const double>> spans(xs.begin(), xs.end());
  const auto transforms = haar_transforms(spans);
  const auto reused = robust_wv(spans, o, transforms);
  const auto own = robust_wv(spans, o);
  ASSERT_EQ(reused.size(), 2u);
  EXPECT_TRUE(reused[0].replaced.empty());
  EXPECT_FALSE(reused[1].replaced.empty()) << "the spikes were not screened: the test lost its second case";
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(reused[k].wv, own[k].wv) << k;
    EXPECT_EQ(reused[k].ci_low, own[k].ci_low) << k;
    EXPECT_EQ(reused[k].replaced, own[k].replaced) << k;
  }
  // One transform per series, each of its series' length.
  std::vector<std::unique_ptr<HaarModwt>> one;
  one.push_back(std::make_unique<HaarModwt>(xs[0].data(), static_cast<std::int64_t>(xs[0].size())));
  try {
    (void)robust_wv(spans, o, one);
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("transforms"), std::string::npos) << e.what();
  }
}

TEST(RobustWvOptions, ValidateNamesTheOffendingOption) {
  EXPECT_EQ(RobustWvOptions{}.Validate(), "");
  auto message = [](auto edit) {
    RobustWvOptions o;
    edit(o);
    return o.Validate();
  };
  for (double e : {0.0, 1.0, -0.1, 1.5}) {
    const std::string m = message([&](RobustWvOptions& o) { o.efficiency = e; });
    EXPECT_NE(m.find("efficiency"), std::string::npos) << e << ": " << m;
  }
  for (double a : {0.0, 1.0}) {
    const std::string m = message([&](RobustWvOptions& o) { o.alpha = a; });
    EXPECT_NE(m.find("alpha"), std::string::npos) << a << ": " << m;
  }
  EXPECT_NE(message([](RobustWvOptions& o) { o.levels = -1; }).find("levels"), std::string::npos);
}

TEST(RobustWv, RejectsInvalidOptionsAndShortSeries) {
  const auto x = white_noise(100, 5701, 0);
  RobustWvOptions o;
  o.efficiency = 0.0;
  try {
    (void)robust_wv(x.data(), 100, o);
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("efficiency"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)robust_wv(x.data(), 15), InvalidArgument);
  EXPECT_NO_THROW((void)robust_wv(x.data(), 16));
}

}  // namespace
}  // namespace gmwm::robust
