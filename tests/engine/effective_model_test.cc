// The effective form's reduction test (effective_model.h): its statistic's null simulated
// under the covariance it is given (its thresholds against the closed forms where they
// exist), and collapsed components removed without a test (issue 27, mechanisms a and b).
// The statistic depends on the model, the WV's length and the covariance only; the
// threshold's draws are seeded, so these cases are fixed.
#include <gtest/gtest.h>

#include <string>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/effective_model.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm {
namespace {

constexpr std::int64_t kN = 1 << 17;
// A fast AR1, a slow one the data at 2^17 resolve only just, and a white noise (the
// independent selection study's truth in issue 27).
constexpr const char* kTruth = "AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=1e-5)+WN(sigma2=1)";

WaveletVariance wv_of_length(std::int64_t n) {
  const Model m = parse_model("WN(sigma2=1)");
  const auto x = simulate(m, m.given_values(), n, 2711, 0);
  return classical_wv(x.data(), n);
}

bool has_slow_ar1(const EffectiveModel& e) {
  for (int k = 0; k < e.model.num_components(); ++k)
    if (e.model.components()[static_cast<std::size_t>(k)].process->name() == "AR1" && e.theta(e.model.offset(k)) > 0.99)
      return true;
  return false;
}

Eigen::MatrixXd diagonal_of(const Eigen::MatrixXd& v) { return Eigen::MatrixXd(v.diagonal().asDiagonal()); }

// The 95% quantile of the test's null, one shape, independent levels, one-sided (a
// variance the fit collapses rather than make negative): (z_0.95)^2 = 1.6449^2.
constexpr double kOneSidedQuantile = 1.6448536269514722 * 1.6448536269514722;
// Monte-Carlo standard error of a 95% quantile from the test's 2000 draws: sqrt(0.05 x
// 0.95 / 2000) / f(q), f the density of (Z)+^2 at q, phi(1.645) / (2 x 1.645) = 0.0313.
constexpr double kQuantileSe = 0.00487 / 0.0313;

TEST(EffectiveModel, TestsAFixedShapeAtTheOneSidedNormalQuantileWhenLevelsAreIndependent) {
  // Dropping a RW (one shape, gamma2 >= 0) from WN+RW with a diagonal covariance: the
  // statistic is (Z)+^2 under the null, so the simulated threshold is z_0.95^2.
  const WaveletVariance wv = wv_of_length(kN);
  const Model m = parse_model("WN(sigma2=1)+RW(gamma2=1e-9)");
  EffectiveOptions o;
  o.covariance = diagonal_of(model_wv_covariance(m, m.given_values(), kN, wv.levels()));
  const EffectiveModel e = effective_model(wv, m, m.given_values(), o);
  ASSERT_EQ(e.model.to_string(), "WN") << "the RW must be small enough to drop";
  EXPECT_EQ(e.tested_parameters, 1);
  EXPECT_NEAR(e.threshold, kOneSidedQuantile, 4.0 * kQuantileSe);
  EXPECT_LE(e.statistic, e.threshold);
}

TEST(EffectiveModel, TestsAnAr1OverEveryCorrelationTimeTheFitCouldHaveChosen) {
  // Dropping a slow AR1 tests the largest excess over its shapes (phi is not identified
  // once its variance is 0): the threshold lies above one shape's and below the
  // Bonferroni bound over the grid's shapes, z_(1 - 0.05 / G)^2 with G <= 100.
  const WaveletVariance wv = wv_of_length(kN);
  const Model m = parse_model("AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=1e-6)+WN(sigma2=1)");
  EffectiveOptions o;
  o.covariance = diagonal_of(model_wv_covariance(m, m.given_values(), kN, wv.levels()));
  const EffectiveModel e = effective_model(wv, m, m.given_values(), o);
  ASSERT_EQ(e.model.to_string(), "AR1+WN") << e.model.to_string(e.theta);
  const double bonferroni =
      std::pow(boost::math::quantile(boost::math::complement(boost::math::normal(), 0.05 / 100)), 2);
  EXPECT_GT(e.threshold, kOneSidedQuantile + 4.0 * kQuantileSe);
  EXPECT_LT(e.threshold, bonferroni);
}

TEST(EffectiveModel, KeepsASlowAr1WhoseExcessIsBeyondItsThresholdAndDropsOneWithin) {
  // A slow AR1 at the exact covariance: at sigma2 = 3e-6 its statistic (1.7) is within the
  // simulated threshold (9.0) and it is dropped, the reduced model's values re-fitted; at
  // 3e-5 it is kept. (The issue-27 truth's 1e-5 was dropped while the model-based
  // covariance overstated the coarse levels of a 2^17 record; at the exact covariance its
  // statistic, about 15, is beyond the threshold.)
  const WaveletVariance wv = wv_of_length(kN);
  for (const char* s2 : {"3e-6", "3e-5"}) {
    const Model m = parse_model(std::string("AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=") + s2 + ")+WN(sigma2=1)");
    EffectiveOptions o;
    o.covariance = model_wv_covariance(m, m.given_values(), kN, wv.levels());
    const EffectiveModel e = effective_model(wv, m, m.given_values(), o);
    if (std::string(s2) == "3e-6") {
      EXPECT_FALSE(has_slow_ar1(e)) << e.model.to_string(e.theta);
      EXPECT_LE(e.statistic, e.threshold);
      EXPECT_GT(e.statistic, 0.0);
    } else {
      EXPECT_TRUE(has_slow_ar1(e)) << e.model.to_string(e.theta);
      EXPECT_FALSE(e.reduced());
    }
  }
}

TEST(EffectiveModel, DropsACollapsedComponentForFreeWithoutChangingTheTestOfOneThatCarriesAShare) {
  // A third AR1 collapsed to 1e-20 carries nothing: it is removed untested, and the test
  // of the slow AR1 (its statistic, threshold and degrees of freedom) is the one without it.
  const WaveletVariance wv = wv_of_length(kN);
  const std::string truth = "AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=5e-6)+WN(sigma2=1)";
  const Model plain = parse_model(truth), padded = parse_model(truth + "+AR1(phi=0.5,sigma2=1e-20)");
  EffectiveOptions o;
  o.covariance = model_wv_covariance(plain, plain.given_values(), kN, wv.levels());
  const EffectiveModel a = effective_model(wv, plain, plain.given_values(), o);
  const EffectiveModel b = effective_model(wv, padded, padded.given_values(), o);
  EXPECT_EQ(a.model.to_string(), b.model.to_string());
  EXPECT_EQ(a.tested_parameters, b.tested_parameters);
  EXPECT_EQ(b.removed_parameters, a.removed_parameters + 2);
  EXPECT_NEAR(b.statistic, a.statistic, 1e-9 * (1.0 + a.statistic));
  EXPECT_NEAR(b.threshold, a.threshold, 1e-9 * (1.0 + a.threshold));
}

TEST(EffectiveModel, StillMergesAnAr1ThatIsAWhiteNoiseAndCountsItsParameter) {
  // An AR1 at phi ~ 0 carries a share (it is the white noise) and is WN-like: the
  // reduction replaces it and tests one parameter (phi).
  const WaveletVariance wv = wv_of_length(kN);
  const Model m = parse_model("AR1(phi=0.0005,sigma2=1)+AR1(phi=0.9,sigma2=0.1)");
  const Eigen::VectorXd theta = m.given_values();
  EffectiveOptions o;
  o.covariance = model_wv_covariance(m, theta, kN, wv.levels());
  const EffectiveModel e = effective_model(wv, m, theta, o);
  EXPECT_EQ(e.model.to_string(), "AR1+WN") << e.model.to_string(e.theta);
  EXPECT_EQ(e.tested_parameters, 1);
}

TEST(EffectiveModel, TestsAnAr1AsRwLikeUnderTheRandomWalksOwnVariancesWhenToldWhereTheCovarianceWasTaken) {
  // Issue 27: a selection's V is the model's at its pilot fit, which follows the coarse
  // levels' chance lows (so its variances there are several times too small). An AR1 that
  // bends just below a random walk's line at the coarsest levels (T = N / 7) then stands
  // out from the RW it stands for if V is taken as it is; tested under its null, V at the
  // RW-like model's own levels, it is RW-like. The fit's own WV is the data here.
  const Model fit = parse_model("AR1(phi=0.99994,sigma2=3e-6)+WN(sigma2=1)+QN(Q2=1)");
  const Eigen::VectorXd theta = fit.given_values();
  WaveletVariance wv = wv_of_length(kN);
  const Eigen::VectorXd nu = fit.wv(theta, wv.tau);
  wv.wv.assign(nu.data(), nu.data() + nu.size());
  EffectiveOptions o;
  o.covariance = model_wv_covariance(fit, theta, kN, wv.levels());
  const EffectiveModel as_given = effective_model(wv, fit, theta, o);
  o.covariance_wv = nu;
  const EffectiveModel at_null = effective_model(wv, fit, theta, o);
  EXPECT_EQ(as_given.model.to_string(), "AR1+WN+QN") << as_given.model.to_string(as_given.theta);
  EXPECT_EQ(at_null.model.to_string(), "WN+QN+RW") << at_null.model.to_string(at_null.theta);
  ASSERT_FALSE(at_null.reductions.empty());
  EXPECT_NE(at_null.reductions.front().find("RW-like"), std::string::npos) << at_null.reductions.front();
  EXPECT_LE(at_null.statistic, at_null.threshold);
  // A covariance_wv of the wrong size is ignored (V as it is).
  o.covariance_wv = Eigen::VectorXd::Ones(3);
  EXPECT_EQ(effective_model(wv, fit, theta, o).model.to_string(), as_given.model.to_string());
}

TEST(EffectiveModel, RejectsACovarianceOfTheWrongSize) {
  const WaveletVariance wv = wv_of_length(1 << 10);
  const Model m = parse_model("AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)");
  EffectiveOptions o;
  o.covariance = Eigen::MatrixXd::Identity(3, 3);
  try {
    effective_model(wv, m, m.given_values(), o);
    FAIL() << "no error";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("the covariance is 3 x 3, the WV has 10 levels"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace gmwm
