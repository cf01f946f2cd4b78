// The frequency-stability deviations (stability/deviation.h) against published values: the
// NBS14 9-point set (NIST SP 1065 table 31, to 1e-6) and Stable32's results for the NBS14
// 1000-point set (its PHASE.DAT; every octave and tau 10 and 99, to the digits Stable32
// prints), one battery over every kind; the overlapping Allan deviation equals the engine's;
// the factor sets; and the error paths with their messages. Every kind, the six of
// total_deviation_test.cc and theo1_time_error_test.cc too, in the scaling, thread-count and
// factor-set tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/samples.h"
#include "gmwm/stability/confidence.h"
#include "gmwm/stability/deviation.h"
#include "nbs14.h"

namespace gmwm::stability {
namespace {

// NBS14's 9-point fractional-frequency set, tau0 = 1 s.
const std::vector<double> kNbs9 = {892, 809, 823, 798, 671, 644, 883, 903, 677};

using testing::nbs1000;

double printed_tolerance(double v) { return testing::printed_half_unit(v); }

struct Row {
  std::int64_t m, terms;
  double sigma;
};

TEST(Deviation, GivesNbs14NinePointValuesAtTauOneAndTwo) {
  // NIST SP 1065 table 31 (the deviations of the 9-point set at tau 1 and 2).
  const std::map<std::string, std::pair<double, double>> published = {
      {"adev", {91.22945, 115.8082}},   {"oadev", {91.22945, 85.95287}}, {"mdev", {91.22945, 74.78849}},
      {"totdev", {91.22945, 93.90379}}, {"hdev", {70.80608, 116.7980}},  {"tdev", {52.67135, 86.35831}},
      {"ohdev", {70.80607, 85.61487}}};
  const std::vector<double> x = phase_from_frequency(kNbs9, 1.0);
  ASSERT_EQ(x.size(), 10u);
  for (const auto& [name, published_values] : published) {
    const DeviationKind kind = *deviation_from_name(name);
    const auto& [one, two] = published_values;
    const std::vector<std::int64_t> m = {1, 2};
    const DeviationCurve c = deviation(kind, x, 1.0, m);
    EXPECT_NEAR(c.value[0] / one, 1.0, 1e-6) << deviation_name(kind);
    EXPECT_NEAR(c.value[1] / two, 1.0, 1e-6) << deviation_name(kind);
  }
}

TEST(Deviation, GivesStable32sValuesAndTermCountsForTheNbs14ThousandPointSet) {
  // Stable32 1.60 on PHASE.DAT: each kind's octave rows and its rows at tau 10 and 99 (AF, #,
  // sigma), as printed.
  const std::map<std::string, std::vector<Row>> stable32 = {{"adev",
                                                             {{1, 999, 2.9223e-01},
                                                              {2, 499, 2.0510e-01},
                                                              {4, 249, 1.4943e-01},
                                                              {8, 124, 1.1013e-01},
                                                              {16, 61, 6.2381e-02},
                                                              {32, 30, 5.6233e-02},
                                                              {64, 14, 3.2550e-02},
                                                              {128, 6, 3.3855e-02},
                                                              {10, 99, 9.9657e-02},
                                                              {99, 9, 3.5841e-02}}},
                                                            {"oadev",
                                                             {{1, 999, 2.9223e-01},
                                                              {2, 997, 2.0102e-01},
                                                              {4, 993, 1.4479e-01},
                                                              {8, 985, 1.0570e-01},
                                                              {16, 969, 6.1915e-02},
                                                              {32, 937, 4.8082e-02},
                                                              {64, 873, 3.6237e-02},
                                                              {128, 745, 2.7674e-02},
                                                              {10, 981, 9.1600e-02},
                                                              {99, 803, 3.2616e-02}}},
                                                            {"mdev",
                                                             {{1, 999, 2.9223e-01},
                                                              {2, 996, 1.5821e-01},
                                                              {4, 990, 1.0780e-01},
                                                              {8, 978, 7.4192e-02},
                                                              {16, 954, 4.1376e-02},
                                                              {32, 906, 3.4255e-02},
                                                              {64, 810, 2.7871e-02},
                                                              {128, 618, 1.8669e-02},
                                                              {10, 972, 6.1724e-02},
                                                              {99, 705, 2.1850e-02}}},
                                                            {"tdev",
                                                             {{1, 999, 1.6872e-01},
                                                              {2, 996, 1.8268e-01},
                                                              {4, 990, 2.4895e-01},
                                                              {8, 978, 3.4268e-01},
                                                              {16, 954, 3.8221e-01},
                                                              {32, 906, 6.3287e-01},
                                                              {64, 810, 1.0298e+00},
                                                              {128, 618, 1.3797e+00},
                                                              {10, 972, 3.5636e-01},
                                                              {99, 705, 1.2489e+00}}},
                                                            {"hdev",
                                                             {{1, 998, 2.9439e-01},
                                                              {2, 498, 2.0716e-01},
                                                              {4, 248, 1.4890e-01},
                                                              {8, 123, 1.1649e-01},
                                                              {16, 60, 5.9589e-02},
                                                              {32, 29, 5.4697e-02},
                                                              {64, 13, 3.0569e-02},
                                                              {128, 5, 3.8060e-02},
                                                              {10, 98, 1.0528e-01},
                                                              {99, 8, 3.3647e-02}}},
                                                            {"ohdev",
                                                             {{1, 998, 2.9439e-01},
                                                              {2, 995, 2.0125e-01},
                                                              {4, 989, 1.4368e-01},
                                                              {8, 977, 1.0987e-01},
                                                              {16, 953, 6.0638e-02},
                                                              {32, 905, 4.5095e-02},
                                                              {64, 809, 3.3824e-02},
                                                              {128, 617, 2.9147e-02},
                                                              {10, 971, 9.5811e-02},
                                                              {99, 704, 3.2526e-02}}},
                                                            {"totdev",
                                                             {{1, 999, 2.9223e-01},
                                                              {2, 999, 2.0089e-01},
                                                              {4, 999, 1.4444e-01},
                                                              {8, 999, 1.0540e-01},
                                                              {16, 999, 6.1788e-02},
                                                              {32, 999, 4.8580e-02},
                                                              {64, 999, 3.5905e-02},
                                                              {128, 999, 3.1259e-02},
                                                              {256, 999, 1.3369e-02},
                                                              {10, 999, 9.1347e-02},
                                                              {99, 999, 3.4106e-02}}}};
  const std::vector<double> x = phase_from_frequency(nbs1000(), 1.0);
  ASSERT_EQ(x.size(), 1001u);
  for (const auto& [name, rows] : stable32) {  // the other kinds: total_deviation_test.cc, theo1_time_error_test.cc
    const DeviationKind kind = *deviation_from_name(name);
    std::vector<std::int64_t> m;
    for (const Row& r : rows) m.push_back(r.m);
    const DeviationCurve c = deviation(kind, x, 1.0, m);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      EXPECT_NEAR(c.value[k], rows[k].sigma, printed_tolerance(rows[k].sigma))
          << deviation_name(kind) << " AF " << rows[k].m;
      EXPECT_EQ(c.terms[k], rows[k].terms) << deviation_name(kind) << " AF " << rows[k].m;
      EXPECT_EQ(c.tau[k], static_cast<double>(rows[k].m));
    }
  }
}

TEST(Deviation, TheOverlappingAllanDeviationIsTheEnginesOfTheSameRate) {
  // The engine's AVAR(m) of a rate series is OAVAR of its phase: two derivations, one value.
  const std::vector<double> y = nbs1000();
  const double freq = 200.0;
  AllanOptions o;
  o.points_per_octave = 1;
  const AllanDeviation a = allan_deviation(y, freq, o);
  const DeviationCurve c = deviation(DeviationKind::kOadev, phase_from_frequency(y, 1.0 / freq), 1.0 / freq, a.m);
  ASSERT_EQ(c.value.size(), a.adev.size());
  for (std::size_t k = 0; k < a.adev.size(); ++k) {
    EXPECT_NEAR(c.value[k] / a.adev[k], 1.0, 1e-12) << "m " << a.m[k];
    EXPECT_NEAR(c.tau[k] / a.tau[k], 1.0, 1e-15);
  }
}

TEST(Deviation, ScalesWithThePhaseFromTheSmallestToTheLargestDoubles) {
  // Every deviation is linear in the phase: 1e-300 and 1e300 times the 9-point set (and the
  // 1000-point set for Theo1, whose factors start at 10) give 1e-300 and 1e300 times its values
  // (summed as they are, the squares underflow to 0 or overflow to infinity).
  for (const double factor : {1e-300, 1e300}) {
    for (const DeviationKind kind : deviation_kinds()) {
      const std::vector<double> x = phase_from_frequency(kind == DeviationKind::kTheo1 ? nbs1000() : kNbs9, 1.0);
      std::vector<double> scaled = x;
      for (double& v : scaled) v *= factor;
      std::vector<std::int64_t> m = factors(TauSet::kAll, kind, static_cast<std::int64_t>(x.size()));
      m.resize(2);
      m.push_back(max_factor(kind, static_cast<std::int64_t>(x.size())));
      const DeviationCurve a = deviation(kind, x, 1.0, m), b = deviation(kind, scaled, 1.0, m);
      for (std::size_t k = 0; k < m.size(); ++k)
        EXPECT_NEAR(b.value[k] / (a.value[k] * factor), 1.0, 1e-12) << deviation_name(kind) << " x " << factor;
    }
  }
}

TEST(Deviation, IsTheSameWhateverTheThreadCount) {
  const std::vector<double> x = phase_from_frequency(nbs1000(), 1.0);
  for (const DeviationKind kind : deviation_kinds()) {
    const std::vector<std::int64_t> m = factors(TauSet::kAll, kind, static_cast<std::int64_t>(x.size()));
    const DeviationCurve many = deviation(kind, x, 1.0, m);
    oneapi::tbb::global_control one(oneapi::tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(deviation(kind, x, 1.0, m).value, many.value) << deviation_name(kind);
  }
}

// A sum longer than one piece (kinds_internal.h: 2^16 terms) is summed piece by piece in
// parallel: the same value on one thread as on all, and the direct long-double sum's to
// 1e-13 (the double lanes' rounding over 3e5 squares: ~sqrt(3e5) x 1.1e-16 = 6e-14).
TEST(Deviation, SumsLongerThanAPieceAreTheSameWhateverTheThreadCountAndMatchALongDoubleSum) {
  std::mt19937_64 rng(48);
  std::normal_distribution<double> normal;
  std::vector<double> y(300000);
  for (double& v : y) v = normal(rng);
  const std::vector<double> x = phase_from_frequency(y, 1.0);
  const std::vector<std::int64_t> m = {1, 2, 4};
  for (const DeviationKind kind : {DeviationKind::kAdev, DeviationKind::kOadev, DeviationKind::kHdev,
                                   DeviationKind::kOhdev, DeviationKind::kTotdev, DeviationKind::kTierms}) {
    const DeviationCurve many = deviation(kind, x, 1.0, m);
    {
      const oneapi::tbb::global_control one(oneapi::tbb::global_control::max_allowed_parallelism, 1);
      EXPECT_EQ(deviation(kind, x, 1.0, m).value, many.value) << deviation_name(kind);
    }
    if (kind != DeviationKind::kOadev && kind != DeviationKind::kAdev) continue;
    for (std::size_t k = 0; k < m.size(); ++k) {  // AVAR = sum (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 m^2 terms)
      const std::int64_t f = m[k], stride = kind == DeviationKind::kAdev ? f : 1;
      long double sum = 0.0L;
      for (std::int64_t t = 0; t < many.terms[k]; ++t) {
        const auto i = static_cast<std::size_t>(t * stride), step = static_cast<std::size_t>(f);
        const long double d = static_cast<long double>(x[i + 2 * step]) - 2.0L * x[i + step] + x[i];
        sum += d * d;
      }
      const double direct = std::sqrt(static_cast<double>(sum / (2.0L * f * f * many.terms[k])));
      EXPECT_NEAR(many.value[k], direct, 1e-13 * direct) << deviation_name(kind) << " m = " << f;
    }
  }
}

// A record in a temporary file (samples.h): its phase goes to one too, and every kind the
// study reads in bounded memory gives the same values and intervals as from memory (the same
// pieces, in the same order; only the pages released differ).
TEST(Deviation, APhaseInATemporaryFileGivesTheSameDeviationsAndIntervalsAsInMemory) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::vector<double> y(200000);
  double walk = 0.0;
  for (double& v : y) v = normal(rng) + (walk += 1e-3 * normal(rng));
  SampleFileWriter writer;
  writer.append(y.data(), y.size());
  const Samples in_file = writer.finish();
  ASSERT_TRUE(in_file.in_file());
  const Samples phase_file = phase_from_record(in_file, 0.1), phase_memory = phase_from_record(y, 0.1);
  ASSERT_TRUE(phase_file.in_file());
  ASSERT_FALSE(phase_memory.in_file());
  EXPECT_TRUE(phase_file == phase_memory);
  for (const DeviationKind kind :
       {DeviationKind::kAdev, DeviationKind::kOadev, DeviationKind::kMdev, DeviationKind::kTdev, DeviationKind::kHdev,
        DeviationKind::kOhdev, DeviationKind::kTotdev, DeviationKind::kTierms}) {
    const std::vector<std::int64_t> m = factors(TauSet::kOctave, kind, static_cast<std::int64_t>(phase_file.size()));
    const DeviationCurve a = deviation(kind, phase_file, 0.1, m), b = deviation(kind, phase_memory, 0.1, m);
    EXPECT_EQ(a.value, b.value) << deviation_name(kind);
    const DeviationIntervals ia = deviation_intervals(a, phase_file), ib = deviation_intervals(b, phase_memory);
    for (std::size_t k = 0; k < m.size(); ++k) {  // equal, or both absent (TIE rms has no interval)
      EXPECT_EQ(ia.noise[k].alpha, ib.noise[k].alpha) << deviation_name(kind) << " m = " << m[k];
      EXPECT_TRUE(ia.low[k] == ib.low[k] || (std::isnan(ia.low[k]) && std::isnan(ib.low[k])));
      EXPECT_TRUE(ia.high[k] == ib.high[k] || (std::isnan(ia.high[k]) && std::isnan(ib.high[k])));
    }
  }
}

TEST(Deviation, PhaseLessAnOffsetIsThePhaseOfTheRateLessIt) {
  std::vector<double> shifted = kNbs9;
  for (double& v : shifted) v -= 800.0;
  const std::vector<double> a = phase_from_frequency(kNbs9, 0.5, 800.0), b = phase_from_frequency(shifted, 0.5);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_DOUBLE_EQ(a[i], b[i]) << i;
}

TEST(Deviation, FactorSetsStopWhereTheDefinitionLeavesNoTerm) {
  EXPECT_EQ(factors(TauSet::kOctave, DeviationKind::kOadev, 1001),
            (std::vector<std::int64_t>{1, 2, 4, 8, 16, 32, 64, 128, 256}));
  EXPECT_EQ(factors(TauSet::kDecade, DeviationKind::kOadev, 1001),
            (std::vector<std::int64_t>{1, 2, 4, 10, 20, 40, 100, 200, 400}));
  EXPECT_EQ(factors(TauSet::kAll, DeviationKind::kOhdev, 10), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(factors(TauSet::kOctave, DeviationKind::kMtie, 1001),
            (std::vector<std::int64_t>{1, 3, 7, 15, 31, 63, 127, 255, 511}));
  EXPECT_EQ(factors(TauSet::kDecade, DeviationKind::kTheo1, 1001),
            (std::vector<std::int64_t>{10, 20, 40, 100, 200, 400, 1000}));
  EXPECT_EQ(factors(TauSet::kOctave, DeviationKind::kHtotdev, 1001),
            (std::vector<std::int64_t>{1, 2, 4, 8, 16, 32, 64, 128, 256}));
  for (const DeviationKind kind : deviation_kinds()) {
    const std::int64_t n = 1001, top = max_factor(kind, n);
    EXPECT_GE(terms(kind, n, top), 1) << deviation_name(kind);
    // The total deviation averages N - 2 squares at every factor (its reflected phase); it
    // stops where the overlapping Allan deviation does, as Stable32's total does.
    if (kind != DeviationKind::kTotdev) {
      EXPECT_LT(terms(kind, n, top + 1), 1) << deviation_name(kind);
    }
    EXPECT_EQ(max_factor(kind, min_phase_points(kind) - 1), 0) << deviation_name(kind);
  }
  for (const TauSet s : {TauSet::kAll, TauSet::kOctave, TauSet::kDecade})
    EXPECT_EQ(tau_set_from_name(tau_set_name(s)), s);
  EXPECT_FALSE(tau_set_from_name("fortnight"));
}

TEST(Deviation, AFactorsWorkIsOnePointInMForTheNonOverlappingKindsAndTheRecordForTheOthers) {
  const std::int64_t n = 1000001;
  EXPECT_DOUBLE_EQ(factor_work(DeviationKind::kAdev, n, 1000), 1000.001);
  EXPECT_DOUBLE_EQ(factor_work(DeviationKind::kHdev, n, 10), 100000.1);
  for (const DeviationKind kind : {DeviationKind::kOadev, DeviationKind::kMdev, DeviationKind::kTotdev,
                                   DeviationKind::kMtotdev, DeviationKind::kMtie, DeviationKind::kTierms})
    EXPECT_DOUBLE_EQ(factor_work(kind, n, 4096), 1000001.0) << deviation_name(kind);
  // Theo1: m points a point summed directly up to m = 256, 7 log2(m)^2 through correlations.
  EXPECT_DOUBLE_EQ(factor_work(DeviationKind::kTheo1, n, 100), 100.0 * 1000001.0);
  EXPECT_DOUBLE_EQ(factor_work(DeviationKind::kTheo1, n, 4096), 7.0 * 144.0 * 1000001.0);
  // Every factor: O(N log N) points for ADEV, O(N^2) for OADEV.
  double adev = 0.0, oadev = 0.0;
  for (const std::int64_t m : factors(TauSet::kAll, DeviationKind::kAdev, n))
    adev += factor_work(DeviationKind::kAdev, n, m);
  for (const std::int64_t m : factors(TauSet::kAll, DeviationKind::kOadev, n))
    oadev += factor_work(DeviationKind::kOadev, n, m);
  EXPECT_NEAR(adev / (static_cast<double>(n) * std::log(static_cast<double>(n) / 2.0)), 1.0, 0.05);
  EXPECT_DOUBLE_EQ(oadev, 500000.0 * static_cast<double>(n));
}

TEST(Deviation, EachKindIsNamedOnceAndAnUnknownNameIsRefusedListingTheKinds) {
  for (const DeviationKind kind : deviation_kinds()) EXPECT_EQ(deviation_from_name(deviation_name(kind)), kind);
  try {
    deviation_of("allan");
    FAIL() << "took 'allan'";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "--kind: found 'allan', expected adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev, "
                 "htotdev, theo1, mtie or tierms");
  }
}

TEST(Deviation, RefusesBadPhaseSpacingAndFactorsNamingThem) {
  const std::vector<double> x = phase_from_frequency(kNbs9, 1.0);
  const auto refusal = [&](DeviationKind kind, std::span<const double> phase, double tau0,
                           std::vector<std::int64_t> m) {
    try {
      deviation(kind, phase, tau0, m);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal(DeviationKind::kOadev, x, 1.0, {5}),
            "oadev: averaging factor 5 is outside 1 .. 4 (10 phase points)");
  EXPECT_EQ(refusal(DeviationKind::kHdev, x, 1.0, {0}), "hdev: averaging factor 0 is outside 1 .. 3 (10 phase points)");
  EXPECT_EQ(refusal(DeviationKind::kOadev, x, 0.0, {1}),
            "tau0: found 0, expected a positive, finite spacing in seconds");
  EXPECT_EQ(refusal(DeviationKind::kOhdev, std::span<const double>(x).first(3), 1.0, {1}),
            "ohdev: found 3 phase points, expected at least 4");
  std::vector<double> holed = x;
  holed[6] = NAN;
  EXPECT_EQ(refusal(DeviationKind::kMdev, holed, 1.0, {1}), "phase point 6 is not a finite number");
  holed[6] = x[6];
  holed[8] = -INFINITY;
  EXPECT_EQ(refusal(DeviationKind::kAdev, holed, 1.0, {1}), "phase point 8 is not a finite number");
  const std::vector<double> apart = {-1e308, 0.0, 1e308, 0.0};  // finite, 2e308 apart
  EXPECT_EQ(refusal(DeviationKind::kAdev, apart, 1.0, {1}),
            "phase: points differ by more than a double holds (1.8e308)");
  std::vector<double> y = kNbs9;
  y[2] = INFINITY;
  try {
    phase_from_frequency(y, 1.0);
    FAIL() << "took an infinite sample";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "sample 2 is not a finite number");
  }
  try {
    phase_from_frequency(kNbs9, 1.0, NAN);
    FAIL() << "took a NaN offset";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "offset: found nan, expected a finite number");
  }
}

}  // namespace
}  // namespace gmwm::stability
