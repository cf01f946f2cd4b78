// The selection over replicates as a reader sees it (report/src/replicate_rows.h, used by the
// HTML page and the terminal): each effective model once, at its best-ranked candidate, with
// the candidates that fell onto it, the chosen and recommended marks kept.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../../report/src/replicate_rows.h"

namespace gmwm::report {
namespace {

selection::CvCandidate candidate(const std::string& model, const std::string& effective, int rank, double cv) {
  selection::CvCandidate c;
  c.model = model;
  c.effective = effective;
  c.rank = rank;
  c.cv_wvic = cv;
  return c;
}

TEST(FoldByEffective, ListsEachEffectiveModelOnceAtItsBestCandidateWithTheOthersBelowIt) {
  selection::ReplicateSelection s;
  s.ranking = {candidate("2*AR1+WN", "AR1+WN", 1, 10.0), candidate("AR1+WN", "AR1+WN", 2, 10.5),
               candidate("AR1+WN+RW", "AR1+WN+RW", 3, 11.0), candidate("3*AR1+WN", "AR1+WN", 4, 12.0),
               candidate("WN", "WN", 5, 50.0)};
  s.chosen = "2*AR1+WN";
  s.recommended = "AR1+WN";
  const std::vector<detail::FoldedRow> rows = detail::fold_by_effective(s);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].best->model, "2*AR1+WN");
  ASSERT_EQ(rows[0].others.size(), 2u);
  EXPECT_EQ(rows[0].others[0]->model, "AR1+WN");
  EXPECT_EQ(rows[0].others[1]->model, "3*AR1+WN");
  EXPECT_TRUE(rows[0].chosen);
  EXPECT_TRUE(rows[0].recommended);  // AR1+WN, a member of the first row
  EXPECT_FALSE(rows[1].chosen || rows[1].recommended);
  EXPECT_EQ(detail::folded_name(rows[0]), "AR1+WN (best as 2*AR1+WN)");
  EXPECT_EQ(detail::folded_name(rows[1]), "AR1+WN+RW");
  EXPECT_EQ(rows[2].best->model, "WN");
}

TEST(FoldByEffective, KeepsACandidateWithoutAnEffectiveModelAsItsOwnRow) {
  selection::ReplicateSelection s;
  s.ranking = {candidate("WN+RW", "", 1, 3.0), candidate("WN", "", 2, 4.0)};
  const std::vector<detail::FoldedRow> rows = detail::fold_by_effective(s);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(detail::folded_name(rows[0]), "WN+RW");
}

}  // namespace
}  // namespace gmwm::report
