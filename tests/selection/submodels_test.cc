// Sub-model enumeration (selection/src/submodels.cc): the counts of docs/statistics.md
// section 6, the order (by size, parents first), the parent links, interchangeable slots,
// the common super-model of the non-nested mode, and the error paths.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/selection/submodels.h"

namespace gmwm::selection {
namespace {

TEST(SubModels, CountsMatchTheSpecForTheUsualMaximalModels) {
  EXPECT_EQ(enumerate_submodels(parse_model("3*AR1+WN+RW+QN+DR")).models.size(), 63u);  // 4 x 2^4 - 1
  EXPECT_EQ(enumerate_submodels(parse_model("4*AR1+WN+RW")).models.size(), 19u);        // 5 x 2 x 2 - 1
  EXPECT_EQ(enumerate_submodels(parse_model("WN")).models.size(), 1u);
}

TEST(SubModels, AreDistinctOrderedBySizeAndEndWithTheMaximalModel) {
  const SubModelSet set = enumerate_submodels(parse_model("3*AR1+WN+RW+QN+DR"));
  std::set<std::string> names;
  int previous = 0;
  for (const auto& m : set.models) {
    EXPECT_TRUE(names.insert(m.model.to_string()).second) << "duplicate " << m.model.to_string();
    EXPECT_GE(m.size, previous);
    EXPECT_EQ(m.size, m.model.num_components());
    previous = m.size;
  }
  EXPECT_EQ(set.models.back().model.to_string(), "3*AR1+WN+QN+RW+DR");
  EXPECT_EQ(set.models.front().model.to_string(), "AR1");  // more of an earlier process first
  // AR1 slots are interchangeable: 2*AR1 appears once, not three times.
  EXPECT_EQ(names.count("2*AR1"), 1u);
}

TEST(SubModels, ParentsHaveOneComponentFewerAndComeFirst) {
  const SubModelSet set = enumerate_submodels(parse_model("2*AR1+WN+RW"));
  for (std::size_t i = 0; i < set.models.size(); ++i) {
    const auto& m = set.models[i];
    // a model with k distinct processes has k parents (one per process it can lose),
    // except single-component models, which have none
    int distinct = 0;
    for (int c : m.counts) distinct += c > 0;
    EXPECT_EQ(static_cast<int>(m.parents.size()), m.size == 1 ? 0 : distinct) << m.model.to_string();
    for (int p : m.parents) {
      EXPECT_LT(p, static_cast<int>(i));
      EXPECT_EQ(set.models[static_cast<std::size_t>(p)].size, m.size - 1);
    }
  }
  const int full = set.find({2, 1, 1});
  ASSERT_EQ(full, static_cast<int>(set.models.size()) - 1);
  std::set<std::string> removed;
  for (int p : set.models.back().parents) removed.insert(difference(set, full, p));
  EXPECT_EQ(removed, (std::set<std::string>{"AR1", "WN", "RW"}));
  EXPECT_EQ(set.find({3, 0, 0}), -1);
}

TEST(SubModels, KeepTheGivenStartingValuesOfTheMaximalModel) {
  const SubModelSet set = enumerate_submodels(parse_model("AR1(phi=0.9,sigma2=1)+WN(sigma2=2)"));
  ASSERT_EQ(set.models.size(), 3u);
  const int wn = set.find({0, 1});
  ASSERT_GE(wn, 0);
  EXPECT_EQ(set.models[static_cast<std::size_t>(wn)].model.given_values()(0), 2.0);
}

TEST(CommonSuperModel, TakesTheLargestNumberOfSlotsOfEachProcess) {
  const Model m = common_supermodel({parse_model("2*AR1+WN"), parse_model("AR1+RW+QN"), parse_model("WN+DR")});
  EXPECT_EQ(m.to_string(), "2*AR1+WN+QN+RW+DR");
  EXPECT_EQ(common_supermodel({parse_model("WN")}).to_string(), "WN");
}

TEST(SubModels, RejectEmptyInputsWithAClearMessage) {
  try {
    common_supermodel({});
    FAIL() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("no models given"), std::string::npos) << e.what();
  }
  EXPECT_THROW(enumerate_submodels(Model{}), InvalidArgument);
}

}  // namespace
}  // namespace gmwm::selection
