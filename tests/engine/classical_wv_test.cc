// Classical WV against reproducible series generated in this file (a 32-bit LCG, s_0 = 12345), with reference values from an independent high-precision computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/haar_modwt.h"

namespace gmwm {
namespace {

// s_0 = 12345, s_{k+1} = (1664525 s_k + 1013904223) mod 2^32, x_k = s_k / 2^32 - 0.5.
std::vector<double> lcg_series(int n) {
  std::vector<double> x;
  std::uint64_t s = 12345;
  for (int k = 1; k <= n; ++k) {
    s = (1664525ULL * s + 1013904223ULL) % 4294967296ULL;
    x.push_back(static_cast<double>(s) / 4294967296.0 - 0.5);
  }
  return x;
}

struct Row {
  double wv, eta, lo, hi;
};
const Row kReference[] = {
    {0.04253747205206102, 499.5, 0.037718255449903565, 0.04834826581903962},
    {0.020127080004931127, 249.25, 0.017013013260045094, 0.024186813107700003},
    {0.009743175180872426, 124.125, 0.00771014043297574, 0.012706217353006902},
    {0.00403855146434386, 61.5625, 0.0029202102653904786, 0.005952794695067195},
    {0.002052588982184266, 30.28125, 0.0013131706316662256, 0.003656020177833201},
    {0.0015745520344519572, 14.640625, 0.0008538645702438307, 0.0038210255494375393},
    {0.0008289920578525559, 6.8203125, 0.0003593210225269759, 0.0035214565343343373},
    {0.0002691779601164682, 2.91015625, 8.53314146299347e-05, 0.003990115214799916},
    {0.0002125993833911233, 1, 4.2317714905231776e-05, 0.21648108027531404},
};
const double kAllan[] = {0.0402541600098623,  0.0194863503617449,  0.00807710292868772,  0.00410517796436853,
                         0.00314910406890391, 0.00165798411570511, 0.000538355920232936, 0.000425198766782247};

TEST(ClassicalWv, ReproducesTheReferenceSeriesFirstValues) {
  const auto x = lcg_series(2);
  EXPECT_NEAR(x[0], -0.4795973142609, 1e-13);
  EXPECT_NEAR(x[1], -0.4834521517623216, 1e-16);
}

TEST(ClassicalWv, MatchesTheReferenceWvCountsAndCisTo1e12) {
  const auto x = lcg_series(1000);
  const WaveletVariance w = classical_wv(x.data(), 1000);
  ASSERT_EQ(w.levels(), 9);
  const std::int64_t counts[] = {999, 997, 993, 985, 969, 937, 873, 745, 489};
  for (int j = 0; j < 9; ++j) {
    SCOPED_TRACE(j + 1);
    EXPECT_EQ(w.coefficients[j], counts[j]);
    EXPECT_DOUBLE_EQ(w.tau[j], std::ldexp(1.0, j + 1));
    EXPECT_NEAR(w.wv[j] / kReference[j].wv, 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(w.eta[j], kReference[j].eta);
    EXPECT_NEAR(w.ci_low[j] / kReference[j].lo, 1.0, 1e-12);
    EXPECT_NEAR(w.ci_high[j] / kReference[j].hi, 1.0, 1e-12);
    EXPECT_NEAR(w.variance[j], 2.0 * w.wv[j] * w.wv[j] / w.eta[j], 1e-30);
  }
}

TEST(ClassicalWv, AllanVarianceIsTwiceTheWvAtDoubleTheAveragingTime) {
  const auto x = lcg_series(1000);
  const auto avar = allan_variance(classical_wv(x.data(), 1000));
  ASSERT_EQ(avar.size(), 9u);
  for (int k = 0; k < 8; ++k) {
    EXPECT_DOUBLE_EQ(avar[k + 1].first, std::ldexp(1.0, k + 1));  // m = 2..256
    EXPECT_NEAR(avar[k + 1].second / kAllan[k], 1.0, 1e-12);
  }
}

TEST(ClassicalWv, UsesTheLastLevelEvenWithASingleCoefficient) {
  const auto x = lcg_series(1024);
  const WaveletVariance w = classical_wv(x.data(), 1024);
  ASSERT_EQ(w.levels(), 10);
  EXPECT_EQ(w.coefficients[9], 1);
  EXPECT_TRUE(std::isfinite(w.wv[9]));
  EXPECT_GT(w.wv[9], 0.0);
  EXPECT_DOUBLE_EQ(w.eta[9], 1.0);
}

TEST(ClassicalWv, PrefixSumCoefficientsEqualTheDirectHaarFilter) {
  const auto x = lcg_series(300);
  HaarModwt modwt(x.data(), 300);
  std::vector<double> w;
  for (int j = 1; j <= modwt.max_levels(); ++j) {
    modwt.coefficients(j, w);
    const int tau = 1 << j, m = tau / 2;
    for (std::size_t k = 0; k < w.size(); k += 7) {
      const int t = static_cast<int>(k) + tau - 1;
      double direct = 0.0;
      for (int i = 0; i < m; ++i) direct += x[t - i];
      for (int i = m; i < tau; ++i) direct -= x[t - i];
      EXPECT_NEAR(w[k], direct / tau, 1e-14);
    }
  }
}

TEST(ClassicalWv, LevelSquaresGiveTheSumOfSquaresBitForBitAndTheLargestSquaredCoefficient) {
  const auto x = lcg_series(1001);  // M_j not a multiple of four at every level: the tail loop counts
  HaarModwt modwt(x.data(), 1001);
  std::vector<double> w;
  for (int j = 1; j <= modwt.max_levels(); ++j) {
    modwt.coefficients(j, w);
    double peak = 0.0;
    for (double v : w) peak = std::max(peak, v * v);
    const HaarModwt::Squares s = modwt.squares_of_level(j);
    EXPECT_EQ(s.sum, modwt.sum_of_squares(j)) << "level " << j;
    EXPECT_EQ(s.peak, peak) << "level " << j;  // tau a power of two: the scaling is exact
  }
  // Levels without coefficients: zero, not a shift by a negative count.
  EXPECT_EQ(modwt.squares_of_level(0).sum, 0.0);
  EXPECT_EQ(modwt.squares_of_level(modwt.max_levels() + 1).peak, 0.0);
}

TEST(ClassicalWv, KeptSquaresChangeNoWvAndATransformGivenToTheEstimatorGivesTheSameWv) {
  const auto x = lcg_series(1001);
  const WaveletVariance direct = ClassicalWvEstimator().compute(x.data(), 1001, 0, 0.05);
  HaarModwt modwt(x.data(), 1001);
  modwt.keep_squares(2, 5);
  modwt.keep_squares(0, 99);  // clamped to the transform's levels
  const WaveletVariance shared = ClassicalWvEstimator().compute(modwt, x.data(), 1001, 0, 0.05);
  ASSERT_EQ(shared.wv.size(), direct.wv.size());
  for (std::size_t j = 0; j < direct.wv.size(); ++j) EXPECT_EQ(shared.wv[j], direct.wv[j]) << "level " << j + 1;
  EXPECT_THROW(ClassicalWvEstimator().compute(modwt, x.data(), 1000, 0, 0.05), InvalidArgument);
}

TEST(HaarModwt, KeptSquaresFromSharedPassesEqualEachLevelsOwnPassBitForBit) {
  // keep_squares passes over the levels together in blocks of 2^17: three blocks and a tail
  // that is not a multiple of four, every level of the transform, sums and peaks exactly.
  const int n = 3 * (1 << 17) + 5;
  const auto x = lcg_series(n);
  HaarModwt kept(x.data(), n);
  const HaarModwt fresh(x.data(), n);
  kept.keep_squares(1, kept.max_levels());
  for (int j = 1; j <= kept.max_levels(); ++j) {
    const HaarModwt::Squares a = kept.squares_of_level(j), b = fresh.squares_of_level(j);
    EXPECT_EQ(a.sum, b.sum) << "level " << j;
    EXPECT_EQ(a.peak, b.peak) << "level " << j;
  }
}

TEST(HaarModwt, CountAboveCountsTheMaterialisedCoefficientsBeyondTheCutExactly) {
  // Cuts at quantiles of each level's squares (ties and the boundary itself included:
  // "above" is strict), no cut, every cut; levels outside the transform count nothing.
  const int n = 70001;
  const auto x = lcg_series(n);
  const HaarModwt modwt(x.data(), n);
  std::vector<double> w;
  for (int j = 1; j <= modwt.max_levels(); ++j) {
    modwt.coefficients(j, w);
    std::vector<double> sq(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) sq[k] = w[k] * w[k];
    std::vector<double> sorted = sq;
    std::sort(sorted.begin(), sorted.end());
    for (double q : {0.0, 0.5, 0.9, 0.999, 1.0}) {
      const double cut = sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
      const auto expected = std::count_if(sq.begin(), sq.end(), [&](double v) { return v > cut; });
      EXPECT_EQ(modwt.count_above(j, cut), expected) << "level " << j << ", quantile " << q;
    }
    EXPECT_EQ(modwt.count_above(j, -1.0), modwt.count(j)) << "level " << j;
  }
  EXPECT_EQ(modwt.count_above(0, -1.0), 0);
  EXPECT_EQ(modwt.count_above(modwt.max_levels() + 1, -1.0), 0);
}

TEST(HaarModwt, SharedPassesGiveEverySumBitForBitAsOnePassEach) {
  // Three blocks of the shared pass (2^17 values each) and a tail that is not a multiple of
  // four; half-widths from 1 to past half the series (no term: 0) and an invalid 0.
  const int n = 3 * (1 << 17) + 5;
  const auto x = lcg_series(n);
  const HaarModwt modwt(x.data(), n);
  const std::vector<std::int64_t> m = {1, 3, 7, 1000, (1 << 17) - 1, (1 << 17) + 3, n / 2 - 1, n / 2, n / 2 + 1, 0};
  const std::vector<double> shared = modwt.sums_of_squares_half_width(m);
  ASSERT_EQ(shared.size(), m.size());
  for (std::size_t i = 0; i < m.size(); ++i)
    EXPECT_EQ(shared[i], modwt.sum_of_squares_half_width(m[i])) << "half-width " << m[i];
  EXPECT_EQ(shared[8], 0.0);
  EXPECT_EQ(shared[9], 0.0);
}

TEST(HaarModwt, ParallelSumsOfSeveralTransformsEqualEachTransformsOwnWhateverTheGrouping) {
  const auto x = lcg_series(40000);
  const std::vector<double> y(x.rbegin(), x.rend() - 7);
  const auto transforms = haar_transforms({std::span<const double>(x), std::span<const double>(y)});
  // Lists longer and shorter than the number of groups.
  const std::vector<std::vector<std::int64_t>> m = {{1, 2, 3, 5, 8, 13, 21, 34, 55, 89}, {4, 9}};
  const auto sums = sums_of_squares_half_width(transforms, m);
  for (std::size_t c = 0; c < m.size(); ++c)
    for (std::size_t i = 0; i < m[c].size(); ++i)
      EXPECT_EQ(sums[c][i], transforms[c]->sum_of_squares_half_width(m[c][i])) << "series " << c << ", m " << m[c][i];
  EXPECT_THROW(sums_of_squares_half_width(transforms, {{1}}), InvalidArgument);
}

TEST(ClassicalWv, OfTransformsEqualsTheWvOfTheSeriesAndGivesItsLevelSums) {
  const auto x = lcg_series(5000);
  const auto transforms = haar_transforms({std::span<const double>(x)});
  std::vector<std::vector<double>> sums;
  const auto wv = classical_wv(transforms, WvOptions{}, &sums);
  const WaveletVariance direct = classical_wv(x.data(), 5000);
  EXPECT_EQ(wv.front().wv, direct.wv);
  EXPECT_EQ(wv.front().ci_low, direct.ci_low);
  ASSERT_EQ(sums.front().size(), direct.wv.size());
  for (int j = 1; j <= direct.levels(); ++j)
    EXPECT_EQ(sums.front()[static_cast<std::size_t>(j - 1)], transforms.front()->sum_of_squares(j)) << "level " << j;
}

TEST(ClassicalWv, IgnoresAConstantOffset) {
  auto x = lcg_series(4096);
  const WaveletVariance a = classical_wv(x.data(), 4096);
  for (double& v : x) v += 1e4;
  const WaveletVariance b = classical_wv(x.data(), 4096);
  for (int j = 0; j < a.levels(); ++j) EXPECT_NEAR(b.wv[j] / a.wv[j], 1.0, 1e-9);
}

TEST(ClassicalWv, ParallelMultiColumnEqualsOneColumnAtATime) {
  const auto x = lcg_series(5000);
  std::vector<double> y(x.rbegin(), x.rend());
  const auto both = classical_wv(std::vector<std::span<const double>>{x, y});
  const auto a = classical_wv(x.data(), 5000), b = classical_wv(y.data(), 5000);
  EXPECT_EQ(both[0].wv, a.wv);
  EXPECT_EQ(both[1].wv, b.wv);
  EXPECT_EQ(both[1].ci_high, b.ci_high);
}

TEST(ClassicalWv, HonoursARequestedNumberOfLevelsAndAlpha) {
  const auto x = lcg_series(1000);
  WvOptions o;
  o.levels = 4;
  o.alpha = 0.1;
  const WaveletVariance w = classical_wv(x.data(), 1000, o);
  EXPECT_EQ(w.levels(), 4);
  EXPECT_GT(w.ci_low[0], classical_wv(x.data(), 1000).ci_low[0]);
}

TEST(ClassicalWv, RejectsTooShortSeriesAndBadOptionsWithClearMessages) {
  const auto x = lcg_series(15);
  try {
    classical_wv(x.data(), 15);
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_STREQ(e.what(), "classical_wv: series length is 15, but must be at least 16");
  }
  WvOptions o;
  o.alpha = 1.5;
  EXPECT_EQ(o.Validate(), "alpha must be in (0, 1), got 1.5");
  const auto y = lcg_series(100);
  EXPECT_THROW(classical_wv(y.data(), 100, o), InvalidArgument);
}

}  // namespace
}  // namespace gmwm
