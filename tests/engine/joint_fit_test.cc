// The multi-signal (joint) GMWM fit over replicates of different lengths: the joint
// estimate, its objective as the sum of the replicates' terms, AGMWM beside it, the
// sandwich over the stacked WV, and the error paths. Seeds are fixed here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "counting_estimator.h"
#include "test_support.h"

namespace gmwm {
namespace {

constexpr const char* kTruth = "AR1(phi=0.99,sigma2=1e-4)+WN(sigma2=1e-2)+RW(gamma2=1e-8)";

std::vector<WaveletVariance> replicates(const std::string& spec, const std::vector<int>& log2n, std::uint64_t seed) {
  return test::simulated_replicates(spec, log2n, seed);
}

TEST(JointFit, RecoversASharedModelFromReplicatesOfDifferentLengths) {
  const auto wvs = replicates(kTruth, {14, 15, 16}, 301);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("AR1+WN+RW"));
  ASSERT_EQ(r.joint.status, FitStatus::kConverged) << r.joint.message;
  ASSERT_EQ(r.singles.size(), 3u);
  EXPECT_EQ(r.levels, (std::vector<int>{14, 15, 16}));
  const Eigen::VectorXd truth = parse_model(kTruth).given_values();
  // Within 4 sandwich standard errors of the truth, parameter by parameter (p = 4).
  for (Eigen::Index i = 0; i < truth.size(); ++i) {
    ASSERT_GT(r.joint.se(i), 0.0) << i;
    EXPECT_LT(std::abs(r.joint.theta(i) - truth(i)), 4.0 * r.joint.se(i)) << "parameter " << i;
  }
  // df = sum_k J_k - p.
  EXPECT_EQ(r.joint.gof.df, 14 + 15 + 16 - 4);
}

TEST(JointFit, ItsObjectiveIsTheSumOfTheReplicatesTermsAndNoStartBeatsIt) {
  const auto wvs = replicates(kTruth, {14, 16}, 302);
  const Model model = parse_model("AR1+WN+RW");
  const JointFitResult r = fit_gmwm_joint(wvs, model);
  ASSERT_NE(r.joint.status, FitStatus::kFailed);
  ASSERT_EQ(r.objective_share.size(), 2u);
  // Each term recomputed from its own WV and its own (diagonal, model-based) Omega_k.
  ASSERT_EQ(r.omegas.size(), 2u);
  double sum = 0.0;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::MatrixXd& block = r.omegas[k];
    ASSERT_EQ(block.rows(), wvs[k].levels());
    EXPECT_TRUE(block.isDiagonal()) << k;
    EXPECT_GT(block.diagonal().minCoeff(), 0.0) << k;
    const double term = gmwm_objective(wvs[k], r.joint.model, r.joint.theta, block);
    EXPECT_NEAR(r.objective_share[k] / term, 1.0, 1e-10);
    sum += term;
  }
  EXPECT_NEAR(r.joint.objective / sum, 1.0, 1e-10);
  // The joint minimum is at or below the joint objective at AGMWM and at every single
  // estimate (it starts from all of them).
  const WaveletVariance stacked = stack_wv(wvs);
  const Eigen::MatrixXd omega = block_diagonal(r.omegas);
  EXPECT_LE(r.joint.objective, gmwm_objective(stacked, r.joint.model, r.agmwm, omega) * (1 + 1e-12));
  for (const auto& s : r.singles)
    EXPECT_LE(r.joint.objective, gmwm_objective(stacked, r.joint.model, s.theta, omega) * (1 + 1e-12));
}

TEST(JointFit, AgmwmIsTheMeanOfTheSingleEstimatesWithItsStandardError) {
  const auto wvs = replicates(kTruth, {14, 14, 15}, 303);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("AR1+WN+RW"));
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(4);
  for (const auto& s : r.singles) mean += s.theta / 3.0;
  EXPECT_TRUE(r.agmwm.isApprox(mean, 1e-12));
  Eigen::VectorXd ss = Eigen::VectorXd::Zero(4);
  for (const auto& s : r.singles) ss += (s.theta - mean).cwiseAbs2();
  EXPECT_TRUE(r.agmwm_se.isApprox((ss / 2.0 / 3.0).cwiseSqrt(), 1e-10));
}

TEST(JointFit, OneReplicateGivesTheSingleSignalFitUnderTheSameWeights) {
  const auto wvs = replicates(kTruth, {15}, 304);
  const Model model = parse_model("AR1+WN+RW");
  const JointFitResult r = fit_gmwm_joint(wvs, model);
  ASSERT_EQ(r.singles.size(), 1u);
  FitOptions o;
  o.omega_matrix = r.joint.omega;
  o.starts = {r.singles[0].theta};
  const FitResult single = fit_gmwm(wvs[0], model, o);
  EXPECT_NEAR(r.joint.objective / single.objective, 1.0, 1e-6);
  for (Eigen::Index i = 0; i < 4; ++i) EXPECT_NEAR(r.joint.theta(i) / single.theta(i), 1.0, 1e-3) << i;
  EXPECT_TRUE(std::isnan(r.agmwm_se(0)));
}

TEST(JointFit, DoesNotFavourTheReplicateWhoseCoarseWvCameOutLowest) {
  // Six replicates of a resolved random walk, 40 data sets. Under each replicate's own
  // data-based weights 1 / nuhat_kj^2 the joint RW came out low (the lowest replicate at
  // each coarse level weighs most); under model-based weights its mean relative error is
  // within 3 Monte-Carlo standard errors of AGMWM's (which has no cross-replicate weighting).
  constexpr int kSets = 40;
  const Model model = parse_model("WN+RW");
  const double truth = 1e-7;
  double sum_joint = 0.0, sum_agmwm = 0.0, ss = 0.0;
  for (int i = 0; i < kSets; ++i) {
    const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-7)", {13, 13, 14, 14, 15, 15}, 1000 + i);
    const JointFitResult r = fit_gmwm_joint(wvs, model);
    const double d = (r.joint.theta(1) - r.agmwm(1)) / truth;
    sum_joint += r.joint.theta(1) / truth;
    sum_agmwm += r.agmwm(1) / truth;
    ss += d * d;
  }
  const double mean_diff = (sum_joint - sum_agmwm) / kSets;
  const double se = std::sqrt(ss / kSets / kSets);
  EXPECT_GT(mean_diff, -3.0 * se) << "joint " << sum_joint / kSets << ", AGMWM " << sum_agmwm / kSets;
}

TEST(JointFit, TheModelBasedOmegaWeighsEachReplicateByItsOwnCovariance) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {13, 15}, 305);
  FitOptions o;
  o.omega = OmegaKind::kFull;
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"), o);
  ASSERT_NE(r.joint.status, FitStatus::kFailed) << r.joint.message;
  EXPECT_EQ(r.joint.gof.method, "chi-square");
  // Each replicate its own V_k^-1 (full: the levels' correlation weighed), nothing between
  // the replicates' levels: the reduced problem's weight is their sum on the common levels.
  ASSERT_EQ(r.omegas.size(), 2u);
  ASSERT_EQ(r.omegas[0].rows(), 13);
  ASSERT_EQ(r.omegas[1].rows(), 15);
  EXPECT_FALSE(r.omegas[0].isDiagonal(1e-6));
  Eigen::MatrixXd w = r.omegas[1];
  w.topLeftCorner(13, 13) += r.omegas[0];
  EXPECT_TRUE(r.joint.omega.isApprox(w, 1e-12));
}

TEST(JointFit, RejectsNoReplicateABootstrapOmegaAndAReplicateTooShortForTheModel) {
  const Model model = parse_model("AR1+WN+RW");
  std::vector<WaveletVariance> none;
  try {
    fit_gmwm_joint(none, model);
    FAIL() << "no replicate accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "joint fit: no replicate given");
  }
  const auto wvs = replicates(kTruth, {12, 4}, 306);
  try {
    fit_gmwm_joint(wvs, parse_model("2*AR1+WN+RW"));
    FAIL() << "a 16-sample replicate (4 levels) accepted for a 6-parameter model";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("replicate 2: ", 0), 0u) << e.what();
  }
  FitOptions o;
  o.omega = OmegaKind::kBootstrap;
  EXPECT_THROW(fit_gmwm_joint(replicates(kTruth, {12}, 307), model, o), InputError);
}

TEST(JointFit, TheReplicateTestAcceptsASharedThetaAndRejectsAReplicateWhoseNoiseDiffers) {
  ReplicateTestOptions o;
  o.bootstrap = 39;
  o.seed = 7;
  const Model model = parse_model("WN+RW");
  // Shared: three replicates of one WN+RW.
  const auto same = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {13, 14, 14}, 308);
  const ReplicateTest a = replicate_test(same, fit_gmwm_joint(same, model), o);
  EXPECT_EQ(a.draws, 39);
  EXPECT_GE(a.heterogeneity, 0.0);
  EXPECT_GT(a.heterogeneity_p, 0.05);
  // One replicate with twice the white noise: its own fit is far from the others'.
  auto differ = same;
  differ[2] = replicates("WN(sigma2=2e-2)+RW(gamma2=1e-8)", {14}, 309)[0];
  const ReplicateTest b = replicate_test(differ, fit_gmwm_joint(differ, model), o);
  EXPECT_LE(b.heterogeneity_p, 1.0 / 40.0 + 1e-12);  // above every bootstrap draw
  EXPECT_LE(b.p_value, 0.05);
  ASSERT_EQ(b.own_minimum.size(), 3u);
  EXPECT_GT(b.heterogeneity, a.heterogeneity);
}

TEST(JointFit, TheReplicateTestIsTheSameWhateverTheThreadCount) {
  ReplicateTestOptions o;
  o.bootstrap = 19;
  o.seed = 8;
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {12, 13}, 310);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  const ReplicateTest many = replicate_test(wvs, r, o);
  oneapi::tbb::global_control one(oneapi::tbb::global_control::max_allowed_parallelism, 1);
  const ReplicateTest single = replicate_test(wvs, r, o);
  EXPECT_EQ(many.p_value, single.p_value);
  EXPECT_EQ(many.heterogeneity_p, single.heterogeneity_p);
  EXPECT_EQ(many.statistic, single.statistic);
}

TEST(JointFit, TheReplicateBootstrapFitsEveryDistinctResampleOfThreeReplicates) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {13, 14, 15}, 312);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  const ReplicateBootstrap b = replicate_bootstrap(wvs, r);
  EXPECT_TRUE(b.exhaustive);
  EXPECT_EQ(b.draws, 10);  // C(5, 3) multisets of 3 replicates
  for (Eigen::Index i = 0; i < 2; ++i) {
    ASSERT_TRUE(std::isfinite(b.ci_low(i)) && std::isfinite(b.ci_high(i))) << i;
    EXPECT_LE(b.ci_low(i), b.ci_high(i));
  }
  // The white noise is pinned by the finest levels of all three: its interval holds the joint estimate.
  EXPECT_LE(b.ci_low(0), r.joint.theta(0));
  EXPECT_GE(b.ci_high(0), r.joint.theta(0));
}

TEST(JointFit, TheReplicateTIntervalWidensThePercentileOneByStudentsTAndTheBootstrapVarianceCorrection) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {13, 14, 15}, 314);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  const ReplicateBootstrap b = replicate_bootstrap(wvs, r);
  for (Eigen::Index i = 0; i < 2; ++i) {
    ASSERT_TRUE(b.percentile_low.allFinite() && b.se.allFinite());
    // The percentile interval stays within the range of the resampled fits; the replicate-t
    // one (t_{2, 0.975} = 4.30, x sqrt(3/2)) reaches beyond it on both sides.
    EXPECT_LT(b.ci_low(i), b.percentile_low(i)) << i;
    EXPECT_GT(b.ci_high(i), b.percentile_high(i)) << i;
    EXPECT_LT(b.ci_low(i), r.joint.theta(i));
    EXPECT_GT(b.ci_high(i), r.joint.theta(i));
    // Built on the log scale for a variance: the estimate is the geometric centre.
    EXPECT_NEAR(std::log(b.ci_low(i)) + std::log(b.ci_high(i)), 2.0 * std::log(r.joint.theta(i)), 1e-9);
    EXPECT_GT(b.se(i), 0.0);
  }
}

TEST(JointFit, TheReplicateBootstrapGivesNoIntervalForACollapsedComponent) {
  // White noise only, fitted with WN+RW: the RW collapses in the joint fit, and the
  // resamples cannot say how uncertain a collapsed value is.
  const auto wvs = replicates("WN(sigma2=1e-2)", {12, 13, 14}, 316);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  ASSERT_EQ(r.joint.interval.size(), 2u);
  if (r.joint.interval[1] != IntervalKind::kBoundary && r.joint.interval[1] != IntervalKind::kNotIdentified)
    GTEST_SKIP() << "the RW did not collapse in this draw: " << to_string(r.joint.interval[1]);
  const ReplicateBootstrap b = replicate_bootstrap(wvs, r);
  EXPECT_TRUE(std::isfinite(b.ci_low(0)) && std::isfinite(b.ci_high(0)));
  EXPECT_TRUE(std::isnan(b.ci_low(1)) && std::isnan(b.ci_high(1)));
}

TEST(JointFit, TheReplicateBootstrapNeedsTwoReplicates) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {12}, 315);
  try {
    replicate_bootstrap(wvs, fit_gmwm_joint(wvs, parse_model("WN+RW")));
    FAIL() << "one replicate accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "replicate bootstrap: needs at least 2 replicates, got 1");
  }
}

TEST(JointFit, TheReplicateBootstrapDrawsResamplesWhenThereAreTooManyAndRepeatsWithTheSeed) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {12, 12, 12, 13, 13, 13}, 313);
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  const ReplicateBootstrap a = replicate_bootstrap(wvs, r, 0.05, 40, 5);
  EXPECT_FALSE(a.exhaustive);  // C(11, 6) = 462 > 40
  EXPECT_EQ(a.draws, 40);
  const ReplicateBootstrap b = replicate_bootstrap(wvs, r, 0.05, 40, 5);
  EXPECT_EQ(a.ci_low, b.ci_low);
  EXPECT_EQ(a.ci_high, b.ci_high);
}

TEST(JointFit, TheReplicateTestReadsEachReplicatesDrawsThroughItsOwnEstimator) {
  // Two units with their own gaps: each WV reads its own complete windows, and every
  // bootstrap draw of replicate k is read through replicate k's gaps (its estimator).
  const Model truth = parse_model("WN(sigma2=1e-2)+RW(gamma2=1e-8)");
  constexpr std::int64_t kGrid = 1 << 13;
  const GappyWvEstimator a({{1000, 40}, {5000, 300}}), b({{3000, 200}});
  std::vector<WaveletVariance> wvs;
  for (const auto& [e, seed] : std::vector<std::pair<const GappyWvEstimator*, std::uint64_t>>{{&a, 312}, {&b, 313}}) {
    const std::vector<double> x = simulate(truth, truth.given_values(), kGrid, seed);
    wvs.push_back(e->compute(x.data(), kGrid, 9, 0.05));
  }
  ASSERT_NE(wvs[0].coefficients, wvs[1].coefficients);  // each read its own windows
  const test::CountingEstimator ca(a), cb(b);
  ReplicateTestOptions o;
  o.bootstrap = 19;
  o.seed = 9;
  o.estimators = {&ca, &cb};
  const JointFitResult r = fit_gmwm_joint(wvs, parse_model("WN+RW"));
  const ReplicateTest t = replicate_test(wvs, r, o);
  EXPECT_EQ(t.draws, 19);
  EXPECT_EQ(ca.calls(), 19);
  EXPECT_EQ(cb.calls(), 19);
  // Null entries take the common estimator; a list of another length is refused.
  o.estimators = {&ca, nullptr};
  o.estimator = &cb;
  replicate_test(wvs, r, o);
  EXPECT_EQ(ca.calls(), 38);
  EXPECT_EQ(cb.calls(), 38);
  o.estimators = {&ca};
  try {
    replicate_test(wvs, r, o);
    FAIL() << "one estimator for two replicates accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "replicate test: 1 estimators for 2 replicates (one per replicate, or none)");
  }
}

TEST(JointFit, TheReplicateTestNeedsAtLeastNineteenDraws) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-8)", {12}, 311);
  ReplicateTestOptions o;
  o.bootstrap = 10;
  try {
    replicate_test(wvs, fit_gmwm_joint(wvs, parse_model("WN+RW")), o);
    FAIL() << "10 draws accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "replicate test: bootstrap must be at least 19 (a p-value of 0.05 needs 19 draws), got 10");
  }
}

}  // namespace
}  // namespace gmwm
