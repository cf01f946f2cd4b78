// Selection over replicates (cross-validated WVIC): the splits, the held-out losses, the
// chosen and recommended models on replicates of a known truth, and the error paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "counting_estimator.h"
#include "test_support.h"
#include "gmwm/selection/replicate_select.h"

namespace gmwm::selection {
namespace {

std::vector<WaveletVariance> replicates(const std::string& spec, const std::vector<int>& log2n, std::uint64_t seed) {
  return test::simulated_replicates(spec, log2n, seed);
}

TEST(ReplicateSelect, RecommendsTheTruthFromThreeReplicatesOfWhiteNoiseAndRandomWalk) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", {13, 14, 15}, 401);
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("AR1+WN+RW"));
  EXPECT_EQ(r.training, (std::vector<std::vector<int>>{{0, 1}, {0, 2}, {1, 2}}));
  ASSERT_EQ(r.ranking.size(), 7u);  // every sub-model of AR1+WN+RW
  EXPECT_EQ(r.recommended, "WN+RW");
  EXPECT_EQ(r.chosen, r.ranking.front().model);
  EXPECT_TRUE(r.ranking.front().equivalent);
  for (const auto& c : r.ranking) {
    ASSERT_EQ(c.split_loss.size(), 3u) << c.model;
    EXPECT_NEAR(c.cv_wvic, (c.split_loss[0] + c.split_loss[1] + c.split_loss[2]) / 3.0, 1e-9 * std::abs(c.cv_wvic));
  }
  // A model without the random walk misses the coarse levels of the held-out replicates.
  for (const auto& c : r.ranking)
    if (c.model == "WN") {
      EXPECT_FALSE(c.equivalent);
      EXPECT_GT(c.cv_wvic, r.ranking.front().cv_wvic);
    }
}

TEST(ReplicateSelect, FourReplicatesGiveSixSplitsOfTwo) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", {12, 12, 13, 13}, 402);
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("WN+RW"));
  EXPECT_EQ(r.training.size(), 6u);
  EXPECT_EQ(r.training.back(), (std::vector<int>{2, 3}));
  for (const auto& c : r.ranking) EXPECT_EQ(c.split_loss.size(), 6u);
}

TEST(ReplicateSelect, GivesTheSameResultWhateverTheThreadCountAndForEveryAxisAtOnce) {
  const std::vector<std::vector<WaveletVariance>> axes = {
      replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", {12, 13, 13}, 404),
      replicates("AR1(phi=0.9,sigma2=1e-2)+WN(sigma2=1e-2)", {12, 12, 13}, 405)};
  const Model maximal = parse_model("AR1+WN+RW");
  const std::vector<ReplicateSelection> many = select_by_replicates(axes, maximal);
  ReplicateSelection single;
  {
    oneapi::tbb::global_control one(oneapi::tbb::global_control::max_allowed_parallelism, 1);
    single = select_by_replicates(axes[1], maximal);
  }
  ASSERT_EQ(many.size(), 2u);
  EXPECT_EQ(many[1].chosen, single.chosen);
  EXPECT_EQ(many[1].recommended, single.recommended);
  ASSERT_EQ(many[1].ranking.size(), single.ranking.size());
  for (std::size_t i = 0; i < single.ranking.size(); ++i) {
    EXPECT_EQ(many[1].ranking[i].model, single.ranking[i].model);
    EXPECT_EQ(many[1].ranking[i].split_loss, single.ranking[i].split_loss);  // bit for bit
    EXPECT_EQ(many[1].ranking[i].analytic_wvic, single.ranking[i].analytic_wvic);
    EXPECT_EQ(many[1].ranking[i].p_not_worse, single.ranking[i].p_not_worse);
  }
  EXPECT_EQ(many[0].recommended, "WN+RW");
}

TEST(ReplicateSelect, PutsTheBootstrapWvicOfTheJointFitBesideTheAnalyticOne) {
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", {12, 13, 13}, 406);
  ReplicateSelectOptions o;
  o.select.optimism = OptimismMethod::kBoth;
  o.select.bootstrap_replicates = 40;
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("AR1+WN+RW"), o);
  EXPECT_FALSE(r.chosen_bootstrap.empty());
  std::vector<int> ranks;
  for (const auto& c : r.ranking) {
    if (c.model == "AR1+WN+RW") continue;  // the maximal model may sit at the boundary
    ASSERT_TRUE(std::isfinite(c.bootstrap_wvic)) << c.model;
    // The bootstrap optimism estimates the analytic one: 2 tr(...) = 2p when the model holds
    // (Monte-Carlo s.e. from 40 draws); both are positive penalties on the same objective.
    EXPECT_GT(c.bootstrap_wvic, c.objective) << c.model;
    ranks.push_back(c.rank_bootstrap);
  }
  std::sort(ranks.begin(), ranks.end());
  EXPECT_EQ(ranks.front(), 1);
  // At the truth WN+RW both estimate the same optimism: within 4 Monte-Carlo s.e. of the
  // 40 draws, plus the analytic formula's own first-order error (a quarter of it).
  for (const auto& c : r.ranking)
    if (c.model == "WN+RW") {
      const double analytic = c.analytic_wvic - c.objective, boot = c.bootstrap_wvic - c.objective;
      EXPECT_NEAR(boot, analytic, 4.0 * c.bootstrap_se + 0.25 * analytic) << c.bootstrap_se;
    }
  // Without the request: none.
  const ReplicateSelection plain = select_by_replicates(wvs, parse_model("AR1+WN+RW"));
  EXPECT_TRUE(plain.chosen_bootstrap.empty());
  EXPECT_TRUE(std::isnan(plain.ranking.front().bootstrap_wvic));
  EXPECT_EQ(plain.ranking.front().rank_bootstrap, 0);
}

TEST(ReplicateSelect, TheBootstrapWvicReadsEachReplicatesDrawsThroughItsOwnEstimator) {
  // Two units with their own gaps: every bootstrap draw of the joint fit simulates both and
  // reads each through its own estimator; a list of another length is refused.
  const Model truth = parse_model("WN(sigma2=1e-2)+RW(gamma2=1e-6)");
  constexpr std::int64_t kGrid = 1 << 13;
  const GappyWvEstimator a({{700, 90}}), b({{2000, 15}, {6000, 400}});
  std::vector<WaveletVariance> wvs;
  for (const auto& [e, seed] : std::vector<std::pair<const GappyWvEstimator*, std::uint64_t>>{{&a, 408}, {&b, 409}}) {
    const std::vector<double> x = simulate(truth, truth.given_values(), kGrid, seed);
    wvs.push_back(e->compute(x.data(), kGrid, 9, 0.05));
  }
  const test::CountingEstimator ca(a), cb(b);
  ReplicateSelectOptions o;
  o.select.optimism = OptimismMethod::kBoth;
  o.select.bootstrap_replicates = 20;
  o.estimators = {&ca, &cb};
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("WN+RW"), o);
  EXPECT_FALSE(r.chosen_bootstrap.empty());
  EXPECT_GE(ca.calls(), 20);
  EXPECT_EQ(ca.calls(), cb.calls());
  o.estimators = {&ca, &cb, &cb};
  try {
    select_by_replicates(wvs, parse_model("WN+RW"), o);
    FAIL() << "three estimators for two replicates accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "select by replicates: 3 estimators for 2 replicates (one per replicate, or none)");
  }
}

TEST(ReplicateSelect, SaysWhenNoCandidateDescribesTheRecordings) {
  const auto wvs = replicates("AR1(phi=0.9,sigma2=1e-2)+RW(gamma2=1e-6)", {13, 13, 14}, 407);
  EXPECT_TRUE(select_by_replicates(wvs, parse_model("WN+QN")).all_rejected);
  EXPECT_FALSE(select_by_replicates(wvs, parse_model("AR1+WN+RW")).all_rejected);
}

TEST(ReplicateSelect, NeedsAtLeastTwoReplicates) {
  const auto wvs = replicates("WN(sigma2=1e-2)", {12}, 403);
  try {
    select_by_replicates(wvs, parse_model("WN+RW"));
    FAIL() << "one replicate accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "select by replicates: the replicate-based optimism needs at least 2 replicates, got 1");
  }
}

}  // namespace
}  // namespace gmwm::selection
