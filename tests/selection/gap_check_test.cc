// The withheld-effect self-check's oracle figures (issue 14, item 7).
#include <gtest/gtest.h>

#include <cmath>

#include "gmwm/engine/error.h"
#include "gmwm/selection/gap_check.h"

namespace gmwm::selection {
namespace {

// z_0.95 + z_0.90: a one-sided 5% test of a normal mean has 90% power when the mean is
// this many standard deviations from zero.
constexpr double kZ95PlusZ90 = 1.6448536269514722 + 1.2815515655446004;

GapCheckOptions one_case(GapEffect family, double strength) {
  GapCheckOptions o;
  o.cases = 1;
  o.strengths = {strength};
  o.families = {family};
  o.n = std::int64_t{1} << 12;
  o.replicates = 20;
  o.null_side = false;
  o.seed = 11;
  return o;
}

TEST(GapCheck, TheOraclesStrengthAtNinetyPercentPowerInvertsItsNoncentrality) {
  const GapCheckResult r = run_gap_check(one_case(GapEffect::kQN, 4.0));
  ASSERT_EQ(r.cases.size(), 1u);
  const double nc = r.cases[0].oracle_nc;
  ASSERT_TRUE(std::isfinite(nc) && nc > 0.0);
  const GapCheckFamily& f = r.families.at("QN");
  // One case: Phi(s sqrt(nc) - z_0.95) = 0.9 at s = (z_0.95 + z_0.90) / sqrt(nc).
  EXPECT_NEAR(f.oracle_strength_90 * std::sqrt(nc), kZ95PlusZ90, 1e-8);
  EXPECT_NEAR(f.oracle_ratio, f.strength_90 / f.oracle_strength_90, 1e-12);
}

TEST(GapCheck, APowerCurveThatStartsAboveNinetyPercentGivesAnUpperBound) {
  // One strength: either 100% correct (the 90% strength is at most it) or 0% (beyond it).
  const GapCheckResult r = run_gap_check(one_case(GapEffect::kSin, 8.0));
  const GapCheckFamily& f = r.families.at("SIN");
  EXPECT_DOUBLE_EQ(f.strength_90, 8.0);
  EXPECT_EQ(f.crossing, f.correct == 1 ? Crossing::kAtMost : Crossing::kBeyond);
}

TEST(GapCheck, TheNullSideHasNoOracleFigure) {
  GapCheckOptions o = one_case(GapEffect::kQN, 2.0);
  o.null_side = true;
  const GapCheckResult r = run_gap_check(o);
  const GapCheckFamily& none = r.families.at("none");
  EXPECT_TRUE(std::isnan(none.oracle_strength_90));
  for (const auto& c : r.cases)
    if (c.truth == GapEffect::kNone) {
      EXPECT_TRUE(std::isnan(c.oracle_nc));
    }
}

}  // namespace
}  // namespace gmwm::selection
