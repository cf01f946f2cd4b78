// The robust WV of a record with missing samples (robust_wv_with_gaps, issue 47): the
// regular robust WV where nothing is missing; at each level the estimating equation solved
// on exactly the windows the classical gappy WV reads (a brute-force oracle on a grid with
// NaN holes); the spike screen run segment by segment, its ranges on the grid; inside the
// complete record's robust interval on a contaminated record; the strategy object; the
// error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "holed_record.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust {
namespace {

std::vector<double> simulated(const char* spec, std::int64_t n, std::uint64_t seed) {
  const Model m = parse_model(spec);
  return simulate(m, m.given_values(), n, seed);
}

using test::Holed;
using test::remove;

// The oracle's coefficients: half the difference of the two halves' means of every window
// of 2^j grid samples without a hole, in time order, summed directly.
std::vector<double> complete_window_coefficients(const std::vector<double>& grid, int j) {
  const std::size_t width = std::size_t{1} << j, half = width / 2;
  std::vector<double> out;
  for (std::size_t t = 0; t + width <= grid.size(); ++t) {
    double first = 0.0, second = 0.0;
    bool hole = false;
    for (std::size_t k = 0; k < width && !hole; ++k) {
      hole = std::isnan(grid[t + k]);
      (k < half ? first : second) += grid[t + k];
    }
    if (!hole) out.push_back((second - first) / static_cast<double>(width));
  }
  return out;
}

RobustWvOptions unscreened() {
  RobustWvOptions o;
  o.screen_spikes = false;
  return o;
}

TEST(RobustWvWithGaps, GivesTheRobustWvOfARecordWithoutGaps) {
  const std::vector<double> x = simulated("WN(sigma2=1)+RW(gamma2=1e-3)", 6000, 21);
  const WaveletVariance a = robust_wv_with_gaps(x, {});
  const WaveletVariance b = robust_wv(x.data(), static_cast<std::int64_t>(x.size()));
  ASSERT_EQ(a.levels(), b.levels());
  for (std::size_t i = 0; i < a.wv.size(); ++i) {
    // The coefficients come from other prefix sums (mean-centred, another order): a few ulps
    // apart, and the roots agree to the solver's tolerance (1e-10 in log s).
    EXPECT_NEAR(a.wv[i], b.wv[i], 1e-9 * b.wv[i]) << "level " << i + 1;
    EXPECT_NEAR(a.ci_low[i], b.ci_low[i], 1e-9 * b.ci_low[i]) << "level " << i + 1;
    EXPECT_DOUBLE_EQ(a.eta[i], b.eta[i]) << "level " << i + 1;
    EXPECT_EQ(a.notes[i], b.notes[i]) << "level " << i + 1;
  }
  EXPECT_EQ(a.estimator, "huber");
  EXPECT_EQ(a.screening, b.screening);
  EXPECT_EQ(a.small_sample, b.small_sample);
}

TEST(RobustWvWithGaps, SolvesTheEstimatingEquationOnTheWindowsTheClassicalGappyWvReads) {
  // 2^15 samples, five gaps: levels 1-3 have eta = M_j / 2^j above 3000, where no
  // small-sample correction applies, so each is the root of the equation on the complete
  // windows' coefficients, which the oracle sums directly on the grid with NaN holes.
  const std::vector<double> full = simulated("AR1(phi=0.9,sigma2=1)+WN(sigma2=2)+RW(gamma2=0.01)", 1 << 15, 5);
  const std::vector<MissingRun> runs = {{0, 3}, {100, 1}, {102, 7}, {15000, 40}, {32700, 10}};
  const Holed h = remove(full, runs);
  const WaveletVariance w = robust_wv_with_gaps(h.observed, runs, unscreened());
  const WaveletVariance classical = classical_wv_with_gaps(h.observed, runs);
  const Tuning t = tune(RobustKind::kHuber, kDefaultEfficiency);
  for (int j = 1; j <= 3; ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    const std::vector<double> coef = complete_window_coefficients(h.grid, j);
    ASSERT_EQ(static_cast<std::int64_t>(coef.size()), w.coefficients[i]) << "level " << j;
    ASSERT_GT(classical.eta[i], 3000.0) << "level " << j;
    const ScaleSolution root = solve_scale(coef, t, classical.wv[i]);
    ASSERT_TRUE(root.has_root);
    EXPECT_NEAR(w.wv[i], root.scale, 1e-8 * root.scale) << "level " << j;
    EXPECT_DOUBLE_EQ(w.eta[i], kDefaultEfficiency * classical.eta[i]) << "eta from the same windows, level " << j;
    EXPECT_EQ(w.notes[i], classical.notes[i]) << "the windows lost said as the classical WV says them, level " << j;
  }
  // The gappy levels' own functions read the same coefficients.
  std::vector<double> coef;
  const GappyLevelWindows windows = GappyWindows(h.observed, runs).coefficients(2, coef);
  const std::vector<double> oracle = complete_window_coefficients(h.grid, 2);
  ASSERT_EQ(coef.size(), oracle.size());
  EXPECT_EQ(windows.used, static_cast<std::int64_t>(oracle.size()));
  // From prefix sums: apart from the direct sums by their rounding, which the level's noise
  // floor bounds.
  ASSERT_GT(windows.noise_floor, 0.0);
  for (std::size_t k = 0; k < coef.size(); ++k) ASSERT_NEAR(coef[k], oracle[k], windows.noise_floor) << "window " << k;
}

TEST(RobustWvWithGaps, ScreensSpikesSegmentBySegmentAndPlacesTheirRangesOnTheGrid) {
  // White noise on 8192 samples, 50 missing from grid sample 2000, a level shift of 30 sd
  // across that gap (a walk's drift over a long gap), and a spike of 40 sd at grid sample
  // 6000 (observed sample 5950).
  std::vector<double> full = simulated("WN(sigma2=1)", 8192, 8);
  for (std::size_t k = 2050; k < full.size(); ++k) full[k] += 30.0;
  full[6000] += 40.0;
  const std::vector<MissingRun> runs = {{2000, 50}};
  const Holed h = remove(full, runs);
  const WaveletVariance w = robust_wv_with_gaps(h.observed, runs);
  ASSERT_EQ(w.replaced.size(), 1u) << w.screening;
  EXPECT_EQ(w.replaced[0].first, 6000) << "the grid position, not the observed index 5950";
  EXPECT_EQ(w.replaced[0].second, 6000);
  EXPECT_EQ(w.screening,
            "spike screen: 1 sample in 1 range replaced by interpolation (clusters of level-1 jumps beyond 5 robust "
            "sd, at most 16 samples apart), segment by segment between the record's gaps");
  // Level 1 reads no window across the gap: the shift is in none of its coefficients, and
  // with the spike replaced the level is white noise's 1 / 2 within its interval.
  EXPECT_LT(w.ci_low[0], 0.5);
  EXPECT_GT(w.ci_high[0], 0.5);
}

TEST(RobustWvWithGaps, StaysInsideTheCompleteRecordsRobustIntervalOnAContaminatedRecord) {
  // WN(1) + RW(1e-4) on 2^16 samples with 1% of the samples shifted by 6 sd (pairs, which
  // the spike screen's 5-sd jumps at level 1 partly miss), and about 5% of the grid missing
  // in 40 bursts of 80 samples. Robust WV with gaps against the complete record's robust WV:
  // inside its 95% interval at every level (a bar, not a rate: the two share 95% of their
  // windows). The classical gappy WV at level 1 is inflated by the outliers: above that
  // interval, which is why the robust WV has to read gappy records too.
  constexpr std::int64_t kN = std::int64_t{1} << 16;
  std::vector<double> full = simulated("WN(sigma2=1)+RW(gamma2=1e-4)", kN, 13);
  Rng rng = make_stream(13, {1});
  boost::random::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::int64_t k = 0; k + 1 < kN; ++k)
    if (u(rng) < 0.005) full[static_cast<std::size_t>(k)] += 6.0, full[static_cast<std::size_t>(k + 1)] += 6.0;
  std::vector<MissingRun> runs;
  for (int b = 0; b < 40; ++b) runs.push_back({1000 + b * 1600, 80});
  const Holed h = remove(full, runs);
  const WaveletVariance complete = robust_wv(full.data(), kN);
  WaveletVariance gappy = robust_wv_with_gaps(h.observed, runs);
  drop_incomplete_levels(gappy);
  ASSERT_GE(gappy.levels(), 12);
  for (int j = 1; j <= gappy.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    EXPECT_GE(gappy.wv[i], complete.ci_low[i]) << "level " << j;
    EXPECT_LE(gappy.wv[i], complete.ci_high[i]) << "level " << j;
  }
  const WaveletVariance classical = classical_wv_with_gaps(h.observed, runs);
  EXPECT_GT(classical.wv[0], complete.ci_high[0]) << "the outliers inflate the classical level 1";
}

TEST(RobustWvWithGaps, TheStrategyObjectReadsAGridThroughTheRecordsMissingSamples) {
  const std::vector<double> full = simulated("WN(sigma2=1)+RW(gamma2=1e-4)", 5000, 4);
  const std::vector<MissingRun> runs = {{700, 20}, {3000, 300}};
  const Holed h = remove(full, runs);
  const GappyRobustWvEstimator estimator(RobustWvOptions{}, runs);
  const WaveletVariance a = estimator.compute(full.data(), 5000, 0, 0.05);
  WaveletVariance b = robust_wv_with_gaps(h.observed, runs);
  drop_incomplete_levels(b);
  ASSERT_EQ(a.levels(), b.levels());
  for (std::size_t i = 0; i < a.wv.size(); ++i) EXPECT_EQ(a.wv[i], b.wv[i]) << "level " << i + 1;
  EXPECT_EQ(estimator.name(), "huber");
  EXPECT_THROW(estimator.compute(full.data(), 310, 0, 0.05), InvalidArgument);
}

TEST(RobustWvWithGaps, RefusesBadRunsTooFewSamplesAndInvalidOptionsNamingWhat) {
  const std::vector<double> x = simulated("WN(sigma2=1)", 100, 2);
  const auto message = [&](const std::vector<MissingRun>& runs, const RobustWvOptions& o, std::size_t n) {
    try {
      robust_wv_with_gaps(std::span<const double>(x.data(), n), runs, o);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{5, 2}, {7, 1}}, {}, 100),
            "robust_wv_with_gaps: missing run 2 (at 7): overlaps or touches the run before it (runs must be increasing "
            "and apart)");
  EXPECT_NE(message({}, {}, 10).find("robust_wv_with_gaps: observed samples"), std::string::npos);
  RobustWvOptions bad;
  bad.efficiency = 1.5;
  EXPECT_EQ(message({}, bad, 100), "robust_wv_with_gaps: efficiency must be in (0, 1) (exclusive), got 1.5");
}

}  // namespace
}  // namespace gmwm::robust
