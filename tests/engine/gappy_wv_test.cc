// classical_wv_with_gaps (issue 47, item 1): the WV from the complete windows only, against a
// brute-force oracle (each window's coefficient summed directly on a grid with NaN holes),
// against classical_wv on a record without gaps, and against the complete record's interval
// where joining the samples end to end is far outside it.
#include "gmwm/engine/gappy_wv.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "holed_record.h"

namespace gmwm {
namespace {

std::vector<double> simulated(const char* spec, std::int64_t n, std::uint64_t seed) {
  const Model m = parse_model(spec, ProcessContext{100.0, true});
  return simulate(m, m.given_values(), n, seed);
}

using test::Holed;
using test::remove;

// Bursts of missing samples: about `share` of the record, in runs of 1..max_run samples.
std::vector<MissingRun> bursts(std::int64_t n, double share, std::int64_t max_run, std::uint64_t seed) {
  Rng rng = make_stream(seed, {0});
  boost::random::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<MissingRun> runs;
  const double mean_run = static_cast<double>(max_run + 1) / 2.0;
  const double start_probability = share / mean_run;
  for (std::int64_t k = 1; k < n - max_run - 1; ++k) {
    if (u(rng) >= start_probability) continue;
    const auto len = 1 + static_cast<std::int64_t>(u(rng) * static_cast<double>(max_run));
    runs.push_back({k, len});
    k += len + 1;  // runs apart
  }
  return runs;
}

// The oracle, summed directly on the grid with NaN holes: the mean square of the Haar
// coefficients (half the difference of the two halves' means) over the windows of 2^j
// samples without a hole; or, where they at least double the windows, over those whose
// halves each miss at most floor(0.1 * 2^(j-1)) samples, each mean over its observed ones.
struct BruteForceLevel {
  double wv;
  std::int64_t read, partial;  // windows read, those of them missing a sample
};
BruteForceLevel brute_force_level(const std::vector<double>& grid, int j) {
  const std::size_t width = std::size_t{1} << j, half = width / 2;
  const auto allowed = static_cast<std::size_t>(std::floor(kAllanMaxMissingShare * static_cast<double>(half)));
  double sum[2] = {0.0, 0.0};      // complete, near-complete
  std::int64_t count[2] = {0, 0};  // the same
  for (std::size_t t = 0; t + width <= grid.size(); ++t) {
    double mean[2] = {0.0, 0.0};
    std::size_t seen[2] = {0, 0};
    for (std::size_t k = 0; k < width; ++k)
      if (!std::isnan(grid[t + k])) mean[k / half] += grid[t + k], ++seen[k / half];
    if (half - seen[0] > allowed || half - seen[1] > allowed) continue;
    const double c = (mean[1] / static_cast<double>(seen[1]) - mean[0] / static_cast<double>(seen[0])) / 2.0;
    for (int kind = seen[0] + seen[1] == width ? 0 : 1; kind < 2; ++kind) sum[kind] += c * c, ++count[kind];
  }
  const auto all = static_cast<std::int64_t>(grid.size() - width + 1);
  const int kind = allowed > 0 && count[0] < all && count[1] >= 2 * count[0] && count[1] > 0 ? 1 : 0;
  const std::int64_t m = count[kind];
  return {m ? sum[kind] / static_cast<double>(m) : std::numeric_limits<double>::quiet_NaN(), m,
          kind ? count[1] - count[0] : 0};
}

TEST(GappyWv, EqualsABruteForceSumOverTheWindowsItReadsAndCountsThoseMissingSamplesAtEveryLevel) {
  const std::vector<double> full = simulated("AR1(phi=0.9,sigma2=1)+WN(sigma2=2)+RW(gamma2=0.01)", 3000, 3);
  const Holed h = remove(full, {{0, 3}, {100, 1}, {102, 7}, {1500, 40}, {2990, 10}});
  const WaveletVariance w = classical_wv_with_gaps(h.observed, h.runs);
  ASSERT_EQ(w.levels(), 11);  // floor(log2 3000)
  for (int j = 1; j <= w.levels(); ++j) {
    const auto [v, m, partial] = brute_force_level(h.grid, j);
    const auto i = static_cast<std::size_t>(j - 1);
    EXPECT_EQ(w.coefficients[i], m) << "level " << j;
    EXPECT_EQ(w.partial[i], partial) << "the windows read that miss a sample, level " << j;
    ASSERT_GT(m, 0) << "every level has windows: the deep ones near-complete, level " << j;
    // Prefix sums against direct sums: a relative round-off of a few ulps per sample summed.
    EXPECT_NEAR(w.wv[i], v, 1e-9 * v) << "level " << j;
    EXPECT_FALSE(w.notes[i].empty()) << "every level lost windows to the gaps: level " << j;
  }
  // Level 1 loses the windows holding a missing sample: 3 + 2 + 8 + 41 + 10 of 2999.
  EXPECT_EQ(w.notes[0], "2935 of 2999 windows of 2 samples complete (64 hold a missing sample)");
  // Level 11: no window of 2048 samples between the gaps; those missing at most 102 of
  // each half are read (every window of the grid: its 61 missing samples never reach 102).
  EXPECT_EQ(w.notes[10],
            "0 of 953 windows of 2048 samples complete (953 hold a missing sample); read from the 953 whose halves "
            "each miss at most 102 samples, averaged over their observed ones");
}

TEST(GappyWv, GivesTheClassicalWvOfARecordWithoutGaps) {
  const std::vector<double> x = simulated("WN(sigma2=1)+RW(gamma2=1e-4)", 5000, 8);
  const WaveletVariance a = classical_wv_with_gaps(x, {});
  const WaveletVariance b = classical_wv(x.data(), static_cast<std::int64_t>(x.size()));
  ASSERT_EQ(a.levels(), b.levels());
  for (std::size_t i = 0; i < a.wv.size(); ++i) {
    EXPECT_EQ(a.coefficients[i], b.coefficients[i]);
    EXPECT_NEAR(a.wv[i], b.wv[i], 1e-11 * b.wv[i]) << "level " << i + 1;
    EXPECT_DOUBLE_EQ(a.eta[i], b.eta[i]);
    EXPECT_NEAR(a.ci_high[i], b.ci_high[i], 1e-11 * b.ci_high[i]);
    EXPECT_TRUE(a.notes[i].empty());
    EXPECT_EQ(a.partial[i], 0) << "no window misses a sample, level " << i + 1;
  }
  EXPECT_TRUE(b.partial.empty()) << "the regular estimator has no missing samples to count";
}

TEST(GappyWv, StaysInsideTheCompleteRecordsIntervalWhereJoiningEndToEndLeavesIt) {
  // A random walk over a little white noise, 5% of 2^16 samples missing in bursts of up to
  // 50. The gappy WV stays inside the complete record's 95% interval at every level (a bar, not a rate: the two share 95% of their windows, so they
  // differ far less than the interval's half-width). Joining the samples end to end puts
  // each gap's walk in one level-1 coefficient: nu_1^2 = (2 sigma2 + gamma2) / 4 = 0.255,
  // and the joins add about share x gamma2 / 4 = 0.0125 to it (+4.9%), where the interval
  // reaches +1.5% (eta = M_1 / 2 ~ 32768).
  constexpr std::int64_t kN = std::int64_t{1} << 16;
  const std::vector<double> full = simulated("WN(sigma2=0.01)+RW(gamma2=1)", kN, 21);
  const Holed h = remove(full, bursts(kN, 0.05, 50, 22));
  const WaveletVariance complete = classical_wv(full.data(), kN);
  const WaveletVariance gappy = classical_wv_with_gaps(h.observed, h.runs);
  const WaveletVariance joined = classical_wv(h.observed.data(), static_cast<std::int64_t>(h.observed.size()));
  const double missing = static_cast<double>(kN) - static_cast<double>(h.observed.size());
  EXPECT_NEAR(missing / static_cast<double>(kN), 0.05, 0.01);
  // Every level of the complete record, the deep ones (beyond the longest run without a
  // gap) from the windows missing at most a tenth of each half.
  ASSERT_EQ(gappy.levels(), complete.levels());
  for (int j = 1; j <= complete.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    EXPECT_GE(gappy.wv[i], complete.ci_low[i]) << "level " << j;
    EXPECT_LE(gappy.wv[i], complete.ci_high[i]) << "level " << j;
  }
  EXPECT_GT(joined.wv[0], complete.ci_high[0]);
  EXPECT_NEAR(joined.wv[0] / complete.wv[0], 1.049, 0.015);
}

TEST(GappyWv, MakesALevelWithoutACompleteWindowNanAndSaysSo) {
  std::vector<double> x = simulated("WN(sigma2=1)", 64, 5);
  // Two samples missing in every 16: no window of 16 or more samples is complete, and every
  // half of 16 or 32 misses 2 or 4, more than the 1 or 3 (a tenth) allowed.
  const Holed h = remove(x, {{14, 2}, {30, 2}, {46, 2}, {62, 2}});
  const WaveletVariance w = classical_wv_with_gaps(h.observed, h.runs);
  ASSERT_EQ(w.levels(), 6);
  EXPECT_GT(w.coefficients[2], 0);  // 8 samples: some windows fit between the gaps
  for (const std::size_t i : {3u, 4u, 5u}) {
    EXPECT_EQ(w.coefficients[i], 0) << "level " << i + 1;
    EXPECT_TRUE(std::isnan(w.wv[i]) && std::isnan(w.ci_high[i]) && std::isnan(w.variance[i])) << "level " << i + 1;
  }
  EXPECT_EQ(w.notes[4], "0 of 33 windows of 32 samples complete (33 hold a missing sample)");
}

TEST(GappyWv, RefusesRunsThatAreEmptyUnorderedOverlappingOrOutsideTheRecordNamingThem) {
  const std::vector<double> x(100, 1.0);
  const auto problem = [&](std::vector<MissingRun> runs) {
    return missing_runs_problem(static_cast<std::int64_t>(x.size()), runs);
  };
  EXPECT_EQ(problem({}), "");
  EXPECT_EQ(problem({{0, 5}, {10, 5}, {110, 5}}), "");  // the grid holds 115 samples
  EXPECT_EQ(problem({{3, 0}}), "missing run at 3: its length must be at least 1");
  EXPECT_EQ(problem({{10, 5}, {12, 2}}),
            "missing run 2 (at 12): overlaps or touches the run before it (runs must be increasing and apart)");
  EXPECT_EQ(problem({{10, 5}, {15, 2}}),
            "missing run 2 (at 15): overlaps or touches the run before it (runs must be increasing and apart)");
  EXPECT_EQ(problem({{100, 5}}), "");  // the last five of 105
  EXPECT_EQ(problem({{101, 5}}), "missing run 1 (at 101): outside the record's 105 samples");
  EXPECT_EQ(problem({{-1, 5}}), "missing run 1 (at -1): outside the record's 105 samples");
  try {
    classical_wv_with_gaps(x, std::vector<MissingRun>{{3, 0}});
    FAIL() << "a run of no samples was taken";
  } catch (const InvalidArgument& e) {
    EXPECT_STREQ(e.what(), "classical_wv_with_gaps: missing run at 3: its length must be at least 1");
  }
  const std::vector<double> few(15, 1.0);
  EXPECT_THROW(classical_wv_with_gaps(few, {}), InvalidArgument);
}

// Directly on the grid with NaN holes: every window of 2m samples whose halves each miss at
// most floor(share * m) samples, (mean_2 - mean_1)^2 / 2 with each mean over the observed.
struct BruteAllan {
  double avar = 0.0;
  std::int64_t complete = 0, partial = 0;
};

BruteAllan brute_allan(const std::vector<double>& grid, std::size_t m, double share) {
  const auto allowed = static_cast<std::size_t>(std::floor(share * static_cast<double>(m)));
  double sum = 0.0;
  BruteAllan b;
  for (std::size_t t = 0; t + 2 * m <= grid.size(); ++t) {
    double mean[2] = {0.0, 0.0};
    std::size_t seen[2] = {0, 0};
    for (std::size_t i = 0; i < 2 * m; ++i)
      if (!std::isnan(grid[t + i])) {
        mean[i / m] += grid[t + i];
        ++seen[i / m];
      }
    if (m - seen[0] > allowed || m - seen[1] > allowed) continue;
    const double d = mean[1] / static_cast<double>(seen[1]) - mean[0] / static_cast<double>(seen[0]);
    sum += d * d / 2.0;
    ++(seen[0] + seen[1] == 2 * m ? b.complete : b.partial);
  }
  b.avar = sum / static_cast<double>(b.complete + b.partial);
  return b;
}

TEST(GappyWv, AllanDeviationWithGapsEqualsABruteForceSumAndTheRegularOneWithoutGaps) {
  const std::vector<double> full = simulated("WN(sigma2=2)+RW(gamma2=0.01)", 3000, 31);
  const Holed h = remove(full, {{0, 3}, {100, 1}, {102, 7}, {1500, 40}, {2990, 10}});
  for (const double share : {0.0, kAllanMaxMissingShare, 0.3}) {
    AllanOptions o;
    o.max_missing_share = share;
    const AllanDeviation a = allan_deviation_with_gaps(h.observed, h.runs, 100.0, o);
    ASSERT_FALSE(a.m.empty());
    ASSERT_EQ(a.complete.size(), a.m.size());
    ASSERT_EQ(a.partial.size(), a.m.size());
    for (std::size_t k = 0; k < a.m.size(); ++k) {
      const auto m = static_cast<std::size_t>(a.m[k]);
      const BruteAllan b = brute_allan(h.grid, m, share);
      EXPECT_EQ(a.complete[k], b.complete) << "share " << share << ", m " << m;
      EXPECT_EQ(a.partial[k], b.partial) << "share " << share << ", m " << m;
      EXPECT_NEAR(a.adev[k], std::sqrt(b.avar), 1e-9 * a.adev[k]) << "share " << share << ", m " << m;
      EXPECT_LT(a.ci_low[k], a.adev[k]);
      EXPECT_GT(a.ci_high[k], a.adev[k]);
    }
    if (share == 0.0) {
      // Complete windows alone stop before the first m without one of 2m samples (the
      // longest segment holds 1490 samples: m = 724 fits, no factor above 745 does).
      EXPECT_LE(2 * a.m.back(), 1490);
    } else {
      // Near-complete windows cross the gaps: the curve reaches the record's last factor, as
      // it does without gaps (the gap of 40 fits a half of m >= 40 / share samples).
      EXPECT_EQ(a.m.back(), allan_factors(static_cast<std::int64_t>(h.grid.size()), 4).back()) << share;
    }
  }

  const AllanDeviation gapless = allan_deviation_with_gaps(full, {}, 100.0);
  const AllanDeviation regular = allan_deviation(full, 100.0);
  ASSERT_EQ(gapless.m, regular.m);
  for (std::size_t k = 0; k < regular.m.size(); ++k) {
    EXPECT_NEAR(gapless.adev[k], regular.adev[k], 1e-11 * regular.adev[k]) << "m " << regular.m[k];
    EXPECT_NEAR(gapless.ci_high[k], regular.ci_high[k], 1e-11 * regular.ci_high[k]) << "m " << regular.m[k];
    EXPECT_DOUBLE_EQ(gapless.tau[k], regular.tau[k]);
    EXPECT_EQ(gapless.partial[k], 0);
  }
}

TEST(GappyWv, AnAllanFactorWithoutAUsableWindowIsSkippedNotTheEndOfTheCurve) {
  // One sample lost in every 15 (segments of 14): no window of 16 is complete (m = 8, a
  // half below 10 samples must be complete), yet from m = 10 a half may miss one sample and
  // every window is usable. The WV, which reads consecutive levels, stops before level 4.
  const std::vector<double> full = simulated("WN(sigma2=1)", 1500, 43);
  std::vector<MissingRun> runs;
  for (std::int64_t k = 14; k < 1500; k += 15) runs.push_back({k, 1});
  const Holed h = remove(full, runs);
  const AllanDeviation a = allan_deviation_with_gaps(h.observed, h.runs, 100.0);
  auto has = [&](std::int64_t m) { return std::find(a.m.begin(), a.m.end(), m) != a.m.end(); };
  EXPECT_TRUE(has(7)) << "windows of 14: one in each segment";
  EXPECT_FALSE(has(8));
  ASSERT_TRUE(has(10)) << "the curve goes on past the factor without a window";
  for (std::size_t k = 0; k < a.m.size(); ++k) {
    const BruteAllan b = brute_allan(h.grid, static_cast<std::size_t>(a.m[k]), kAllanMaxMissingShare);
    EXPECT_EQ(a.complete[k] + a.partial[k], b.complete + b.partial) << "m " << a.m[k];
    EXPECT_NEAR(a.adev[k], std::sqrt(b.avar), 1e-9 * a.adev[k]) << "m " << a.m[k];
  }
  EXPECT_EQ(a.m.back(), allan_factors(1500, 4).back());
  WaveletVariance w = classical_wv_with_gaps(h.observed, h.runs);
  EXPECT_EQ(w.coefficients[3], 0);
  EXPECT_GT(w.coefficients[4], 0) << "level 5's halves of 16 may miss one sample";
  EXPECT_EQ(complete_levels(w), 3);
}

TEST(GappyWv, AllanOptionsRefuseAMissingShareOutsideZeroToAHalf) {
  AllanOptions o;
  for (const double bad : {-0.01, 0.5, std::numeric_limits<double>::quiet_NaN()}) {
    o.max_missing_share = bad;
    EXPECT_NE(o.Validate().find("missing share of a half window must be in [0, 0.5)"), std::string::npos) << bad;
  }
  o.max_missing_share = 0.0;
  EXPECT_EQ(o.Validate(), "");
}

TEST(GappyWv, TakesAGapOfATrillionSamplesWithoutHoldingItsGrid) {
  // A record cut by a day-long outage at 10 MHz: the estimator sums each segment on its own,
  // so the gap's length costs no memory. The levels beyond the longest segment are NaN.
  const std::vector<double> x = simulated("WN(sigma2=1)", 4096, 41);
  const std::vector<double> before(x.begin(), x.begin() + 2048), after(x.begin() + 2048, x.end());
  const std::vector<MissingRun> gap = {{2048, std::int64_t{1} << 40}};
  const WaveletVariance w = classical_wv_with_gaps(x, gap);
  EXPECT_EQ(w.levels(), 40);
  // Windows of 2048 samples: one complete in each segment, and 102 on each side of the gap
  // missing at most 102 samples of one half (a tenth of 1024); none of 4096 spans it.
  EXPECT_EQ(complete_levels(w), 11);
  EXPECT_EQ(w.coefficients[10], 2 + 2 * 102);
  // Two segments' complete windows: their pooled mean square, each summed on its own.
  const WaveletVariance a = classical_wv(before.data(), 2048), b = classical_wv(after.data(), 2048);
  for (std::size_t i = 0; i < 5; ++i) {
    const double pooled =
        (a.wv[i] * static_cast<double>(a.coefficients[i]) + b.wv[i] * static_cast<double>(b.coefficients[i])) /
        static_cast<double>(a.coefficients[i] + b.coefficients[i]);
    EXPECT_NEAR(w.wv[i], pooled, 1e-9 * pooled) << "level " << i + 1;
  }
  // The Allan deviation steps over the gap too (in a few steps per factor, not 2^40): its
  // points end where no half of 2048 observed samples misses at most the allowed share.
  const AllanDeviation adev = allan_deviation_with_gaps(x, gap, 1e7);
  ASSERT_FALSE(adev.m.empty());
  EXPECT_LE(static_cast<double>(adev.m.back()), 2048.0 / (1.0 - kAllanMaxMissingShare));
  EXPECT_GE(2 * adev.m.back(), 2048);
}

}  // namespace
}  // namespace gmwm
