// A fit above the smoothed scales (issue 47, item 2): drop_fine_levels keeps the WV from a
// level on, the model covariance, the bootstrap and the starting values follow the cut WV's
// own scales, and a white noise + random walk measured at 200 Hz and copied onto 400 Hz
// stamps (held samples: every other sample repeats the one before) is rejected by the
// goodness of fit on every level and accepted above the smoothed ones, its N within 5% of
// the measured noise's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/repeated_samples.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm {
namespace {

constexpr double kMeasuredRate = 200.0, kStampRate = 400.0;
constexpr double kSigma2 = 4e-4, kGamma2 = 1e-10;  // a 200 Hz measurement's white noise, random walk
constexpr std::int64_t kN = std::int64_t{1} << 17;

// The 200 Hz series copied onto 400 Hz stamps.
std::vector<double> held_record(std::uint64_t seed) {
  const Model m = parse_model("WN(sigma2=4e-4)+RW(gamma2=1e-10)", ProcessContext{kMeasuredRate, true});
  const std::vector<double> a = simulate(m, m.given_values(), kN / 2, seed);
  std::vector<double> y(static_cast<std::size_t>(kN));
  for (std::size_t t = 0; t < y.size(); ++t) y[t] = a[t / 2];
  return y;
}

WaveletVariance wv_of(const std::vector<double>& x) {
  return classical_wv(x.data(), static_cast<std::int64_t>(x.size()), WvOptions{});
}

TEST(FirstLevel, DropFineLevelsKeepsEveryPerLevelFieldFromTheLevelOn) {
  const std::vector<double> x = held_record(3);
  const WaveletVariance w = wv_of(x);
  const WaveletVariance c = drop_fine_levels(w, 5);
  ASSERT_EQ(c.levels(), w.levels() - 4);
  EXPECT_EQ(first_level(w), 1);
  EXPECT_EQ(first_level(c), 5);
  EXPECT_EQ(c.tau.front(), 32.0);
  EXPECT_EQ(c.tau.back(), w.tau.back());
  for (int j = 0; j < c.levels(); ++j) {
    const auto a = static_cast<std::size_t>(j), b = static_cast<std::size_t>(j + 4);
    EXPECT_EQ(c.wv[a], w.wv[b]);
    EXPECT_EQ(c.ci_low[a], w.ci_low[b]);
    EXPECT_EQ(c.ci_high[a], w.ci_high[b]);
    EXPECT_EQ(c.eta[a], w.eta[b]);
    EXPECT_EQ(c.coefficients[a], w.coefficients[b]);
  }
  EXPECT_EQ(c.n, w.n);
  EXPECT_EQ(first_level(drop_fine_levels(c, 5)), 5);
}

TEST(FirstLevel, DropFineLevelsRefusesALevelOutsideTheWvsWithItsRange) {
  const WaveletVariance w = wv_of(held_record(3));
  const WaveletVariance c = drop_fine_levels(w, 5);
  try {
    drop_fine_levels(c, 3);
    FAIL() << "a level below the cut WV's first was taken";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(std::string(e.what()), "drop_fine_levels: level 3 is outside the WV's levels 5..17");
  }
  EXPECT_THROW(drop_fine_levels(w, 18), InvalidArgument);
}

TEST(FirstLevel, TheModelCovarianceOfACutWvIsTheBlockOfTheFullOnes) {
  const WaveletVariance w = wv_of(held_record(3));
  const Model m = parse_model("WN+RW", ProcessContext{kStampRate, true});
  Eigen::VectorXd theta(2);
  theta << 2.0 * kSigma2, kGamma2 / 2.0;
  const Eigen::MatrixXd full = model_wv_covariance(m, theta, w);
  const Eigen::MatrixXd cut = model_wv_covariance(m, theta, drop_fine_levels(w, 6));
  ASSERT_EQ(cut.rows(), w.levels() - 5);
  EXPECT_LE((cut - full.bottomRightCorner(cut.rows(), cut.cols())).cwiseAbs().maxCoeff(),
            1e-12 * full.bottomRightCorner(cut.rows(), cut.cols()).cwiseAbs().maxCoeff());
}

TEST(FirstLevel, TheFromLevelEstimatorRecomputesTheCutWv) {
  const std::vector<double> x = held_record(4);
  const WaveletVariance w = wv_of(x);
  const ClassicalWvEstimator classical;
  const FromLevelEstimator from5(classical, 5);
  const WaveletVariance c = from5.compute(x.data(), static_cast<std::int64_t>(x.size()), w.levels() - 4, w.alpha);
  const WaveletVariance expected = drop_fine_levels(w, 5);
  ASSERT_EQ(c.levels(), expected.levels());
  for (int j = 0; j < c.levels(); ++j)
    EXPECT_EQ(c.wv[static_cast<std::size_t>(j)], expected.wv[static_cast<std::size_t>(j)]);
  EXPECT_EQ(first_level(c), 5);
}

// N = sqrt(sigma2 / rate) of the fitted white noise, in units / sqrt(Hz).
double fitted_n(const FitResult& f) { return std::sqrt(f.theta(0) / kStampRate); }

TEST(FirstLevel, AHeldRecordsFitIsRejectedOnEveryLevelAndAcceptedAboveTheSmoothedOnes) {
  const double truth = std::sqrt(kSigma2 / kMeasuredRate);  // the measured noise's N
  const Model m = parse_model("WN+RW", ProcessContext{kStampRate, true});
  const std::vector<double> x = held_record(5);
  const RepeatedSamples r = detect_repeated_samples(x.data(), static_cast<std::int64_t>(x.size()));
  ASSERT_TRUE(r.held());
  ASSERT_GT(r.first_clean_level, 1);
  const WaveletVariance w = wv_of(x);
  const FitResult all = fit_gmwm(w, m);
  ASSERT_EQ(all.status, FitStatus::kConverged) << all.message;
  EXPECT_LT(all.gof.p_value, 1e-6) << "the smoothed levels 1.." << r.first_clean_level - 1 << " went unnoticed";
  const int first = first_fit_level(r, w);
  EXPECT_GE(first, r.first_clean_level);
  const FitResult above = fit_gmwm(drop_fine_levels(w, first), m);
  ASSERT_EQ(above.status, FitStatus::kConverged) << above.message;
  EXPECT_GT(above.gof.p_value, 0.05);
  EXPECT_EQ(above.gof.df, w.levels() - first + 1 - 2);
  EXPECT_NEAR(fitted_n(above) / truth, 1.0, 0.05);
  // The interval of the white noise covers the measured one's (2 sigma2 at 400 Hz).
  EXPECT_LE(above.ci_low(0), 2.0 * kSigma2);
  EXPECT_GE(above.ci_high(0), 2.0 * kSigma2);
  ASSERT_FALSE(above.misfits.empty());
  EXPECT_EQ(above.misfits.front().level, first);
  EXPECT_EQ(above.misfits.front().tau, std::ldexp(1.0, first));
}

TEST(FirstLevel, TheFirstFitLevelLeavesABiasWithinAQuarterOfItsStandardErrorAndIsOneWithoutRepetition) {
  const std::vector<double> x = held_record(7);
  const RepeatedSamples r = detect_repeated_samples(x.data(), static_cast<std::int64_t>(x.size()));
  const WaveletVariance w = wv_of(x);
  const int first = first_fit_level(r, w);
  ASSERT_GT(first, 1);
  const auto at = [&](int level) {
    const auto j = static_cast<std::size_t>(level - 1);
    return repetition_wv_shortfall(2, static_cast<std::int64_t>(w.tau[j]), false) / std::sqrt(2.0 / w.eta[j]);
  };
  EXPECT_LE(at(first), RepeatedSamples::kFitBiasOfStandardError);
  EXPECT_GT(at(first - 1), RepeatedSamples::kFitBiasOfStandardError);
  const Model m = parse_model("WN(sigma2=1)", ProcessContext{kStampRate, true});
  const std::vector<double> natural = simulate(m, m.given_values(), kN, 8);
  const RepeatedSamples none = detect_repeated_samples(natural.data(), kN);
  EXPECT_EQ(first_fit_level(none, wv_of(natural)), 1);
}

TEST(FirstLevel, TheBootstrapWeightsOfACutWvAreSimulatedOnItsOwnLevels) {
  const Model m = parse_model("WN+RW", ProcessContext{kStampRate, true});
  const std::vector<double> x = held_record(6);
  const WaveletVariance c = drop_fine_levels(wv_of(x), 5);
  FitOptions o;
  o.omega = OmegaKind::kBootstrap;
  o.bootstrap_replicates = 20;
  o.seed = 9;
  const FitResult f = fit_gmwm(c, m, o);
  ASSERT_NE(f.status, FitStatus::kFailed) << f.message;
  ASSERT_EQ(f.wv_covariance.rows(), c.levels());
  // The simulated first level's variance is that of tau = 32 samples, not of tau = 2: within
  // a factor of 3 of the model's (20 draws give a relative sd of about sqrt(2 / 19) = 0.32).
  const Eigen::MatrixXd model = model_wv_covariance(m, f.theta, c);
  EXPECT_NEAR(std::log(f.wv_covariance(0, 0) / model(0, 0)), 0.0, std::log(3.0));
}

}  // namespace
}  // namespace gmwm
