// The withheld-effect self-check's oracle figures (issue 14, item 7).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Cholesky>

#include "gmwm/engine/error.h"
#include "gmwm/gap/gap_check.h"

namespace gmwm::gap {
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
  o.replicates = 40;
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

TEST(GapCheck, TheDriftsOracleIsTheGlsTestOnTheSeriesWithTheBasesExactCovariance) {
  GapCheckOptions o = one_case(GapEffect::kDR, 4.0);
  o.n = 1024;
  const GapCheckResult r = run_gap_check(o);
  ASSERT_EQ(r.cases.size(), 1u);
  const GapCheckCase& c = r.cases[0];
  ASSERT_TRUE(c.oracle_time_domain);
  // omega at strength 1 from the injected DR(omega=...), omega growing as sqrt(strength).
  const auto at = c.injected.find("omega=");
  ASSERT_NE(at, std::string::npos) << c.injected;
  const double omega1 = std::stod(c.injected.substr(at + 6)) / 2.0;
  // Dense: Sigma_x = sigma2 I + gamma2 (min(s, t) + 1) (the RW's first step included).
  const double sigma2 = 1e-4, gamma2 = 1e-10;
  const Eigen::Index n = o.n;
  Eigen::MatrixXd S(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      S(i, j) = gamma2 * static_cast<double>(std::min(i, j) + 1) + (i == j ? sigma2 : 0.0);
  Eigen::VectorXd m(n);
  for (Eigen::Index t = 0; t < n; ++t) m(t) = omega1 * static_cast<double>(t);
  const double dense = m.dot(S.ldlt().solve(m));
  EXPECT_NEAR(c.oracle_nc / dense, 1.0, 1e-8);
  // Its power Phi(sqrt(s nc) - z_0.95) is 90% where s nc = (z_0.95 + z_0.90)^2.
  const GapCheckFamily& f = r.families.at("DR");
  EXPECT_NEAR(f.oracle_strength_90 * c.oracle_nc, kZ95PlusZ90 * kZ95PlusZ90, 1e-6);
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
}  // namespace gmwm::gap
