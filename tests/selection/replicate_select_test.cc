// Selection over replicates (cross-validated WVIC): the splits, the held-out losses, the
// chosen and recommended models on replicates of a known truth, and the error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
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
