// Time-domain effects of the gap diagnosis (gap/src/gap_events.cc): a bias step, a
// warm-up transient and a temperature coupling added to a WN+RW series whose baseline is
// the WN+RW alone; and the same tests on the baseline's own data, where nothing is found.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <boost/random/normal_distribution.hpp>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap {
namespace {

constexpr std::int64_t kN = 1 << 16;
constexpr const char* kBase = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";
// sqrt(N gamma2): the random walk's typical displacement over the record (2.6e-3).
const double kRwSpread = std::sqrt(static_cast<double>(kN) * 1e-10);

std::vector<double> base_series(std::uint64_t seed) {
  const Model m = parse_model(kBase);
  return simulate(m, m.given_values(), kN, seed, 0);
}

GapResult diagnose(const std::vector<double>& x, std::uint64_t seed, const std::vector<double>* temperature = nullptr) {
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = seed;
  const WaveletVariance wv = classical_wv(x.data(), kN);
  const WaveletVariance r = robust::robust_wv(x.data(), kN);
  return diagnose_gap(wv, base, base.given_values(), o, &r, &x, temperature);
}

// A smooth temperature record: a slow random walk (the room), in degrees.
std::vector<double> temperature_series(std::uint64_t seed) {
  Rng rng = make_stream(seed, {1});
  boost::random::normal_distribution<double> n01;
  std::vector<double> t(static_cast<std::size_t>(kN));
  double level = 25.0;
  for (auto& v : t) {
    level += 0.01 * n01(rng);
    v = level;
  }
  return t;
}

TEST(GapTimeEffects, FindNoEventOnDataFromTheBaselineItself) {
  const GapResult g = diagnose(base_series(9101), 9201);
  ASSERT_TRUE(g.event_tested);
  EXPECT_LT(g.event_statistic, g.event_threshold);
  EXPECT_FALSE(g.event.has_value());
  EXPECT_EQ(g.effect, GapEffect::kNone);
}

TEST(GapTimeEffects, NameABiasStepStepWithItsTimeAndSize) {
  std::vector<double> x = base_series(9102);
  // A jump of 3 random-walk spreads at 40% of the record: a re-sized random walk in the
  // WV, but concentrated in the coarse coefficients around sample 26214.
  const std::int64_t t0 = 26214;
  const double size = 3.0 * kRwSpread;
  for (std::int64_t t = t0; t < kN; ++t) x[static_cast<std::size_t>(t)] += size;
  const GapResult g = diagnose(x, 9202);
  ASSERT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kStep);
  ASSERT_TRUE(g.event.has_value());
  EXPECT_GT(g.event->statistic, g.event->threshold);
  // Within one window of the sliding map (docs/gap.md, method note 5), in fact within a few samples.
  ASSERT_GT(g.window_length, 0);
  EXPECT_LT(std::abs(g.event->sample - t0), g.window_length);
  EXPECT_NEAR(g.event->size, size, 0.1 * size);
  // Removing it closes the gap.
  EXPECT_GT(g.shrinkage.excess_removed, 0.8);
  EXPECT_GE(g.shrinkage.p_value_after, 0.05);
}

TEST(GapTimeEffects, CallAShockThatReturnsToItsLevelABurstNotAStep) {
  std::vector<double> x = base_series(9108);
  // A shock as on adis_16405_imu1 accel_z at 3.3 s: up by ~17 white-noise deviations,
  // then down by ~14, back within 8 samples. A two-mean split across it reads a jump the
  // record's longer means do not show.
  const std::int64_t t0 = 20000;
  const double sd = 1e-2;  // sqrt(sigma2) of the base's white noise
  const std::vector<double> shock = {15, 19, 0, -14, -13, -9.5, -6.7};
  for (std::size_t k = 0; k < shock.size(); ++k) x[static_cast<std::size_t>(t0) + k] += shock[k] * sd;
  const GapResult g = diagnose(x, 9208);
  EXPECT_NE(g.effect, GapEffect::kStep);
  for (GapEffect e : g.steps) EXPECT_NE(e, GapEffect::kStep);
  // The shock concentrates level 5 (statistic above the threshold); located, it is the burst.
  ASSERT_TRUE(g.event.has_value()) << g.headline;
  {
    EXPECT_EQ(g.event->effect, GapEffect::kOutliers);
    EXPECT_GE(g.event->sample, t0);
    EXPECT_LE(g.event->sample + g.event->length, t0 + static_cast<std::int64_t>(shock.size()));
    EXPECT_NEAR(g.event->size, 19 * sd, 4 * sd);
  }
}

// Issue 43, item 5: small steps on the self-check's base at its length (2^18 at 100 Hz).
constexpr std::int64_t kLongN = std::int64_t{1} << 18;

GapResult diagnose_long(const std::vector<double>& x, std::uint64_t seed) {
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = seed;
  o.context = ProcessContext{100.0, true};
  const WaveletVariance wv = classical_wv(x.data(), kLongN);
  const WaveletVariance r = robust::robust_wv(x.data(), kLongN);
  return diagnose_gap(wv, base, base.given_values(), o, &r, &x);
}

// The oracle of tools/bench/bench_gap_step.cc: the local-level filter's GLR scan for one
// step at an unknown time, max over t0 of |z(t0)| (exactly N(0, 1) at each t0 under the base).
double oracle_scan(const std::vector<double>& x) {
  const double s2 = 1e-4, g2 = 1e-10;  // kBase's values
  const std::size_t n = x.size();
  std::vector<double> v(n), f(n), k(n);
  double a = 0.0, p = g2;
  for (std::size_t t = 0; t < n; ++t) {
    f[t] = p + s2;
    v[t] = x[t] - a;
    k[t] = p / f[t];
    a += k[t] * v[t];
    p = p * (1.0 - k[t]) + g2;
  }
  double num = 0.0, den = 0.0, best = 0.0;
  for (std::size_t t = n; t-- > 1;) {
    num = v[t] / f[t] + (1.0 - k[t]) * num;
    den = 1.0 / f[t] + (1.0 - k[t]) * (1.0 - k[t]) * den;
    best = std::max(best, std::abs(num) / std::sqrt(den));
  }
  return best;
}

// The oracle's null 99% quantile at this length, by simulation (tools/bench/bench_gap_step.cc:
// 4.723 over 2000 series of the base; the issue quoted 4.43): the steps below are ones the
// oracle sees.
constexpr double kOracleNull99 = 4.723;
// The scan's standard error of a jump's size on this base (its non-centrality per unit
// step, 2224.6; gap_events.h): a located step's size is within 3.5 of them.
constexpr double kStepSizeSe = 1.0 / 2224.6;

TEST(GapTimeEffects, FindSmallStepsTheOracleScanSeesAndKeepThemWhereTheyAre) {
  // Issue 43, item 5: steps of 0.0031-0.0038 on the self-check's base at 2^18 samples, at
  // unknown times; before the step scan, 3 of 6 such steps were found, and one that passed
  // the matched filter was refused ("removing it does not make the fit better").
  const double sizes[] = {0.0031, 0.0035, 0.0038};
  const double where[] = {0.55, 0.85, 0.4};
  for (int i = 0; i < 3; ++i)
    for (std::uint64_t seed = 43130 + 10 * i; seed < 43130 + 10 * i + 2; ++seed) {
      const Model base = parse_model(kBase);
      std::vector<double> x = simulate(base, base.given_values(), kLongN, seed, 0);
      const auto t0 = static_cast<std::int64_t>(where[i] * kLongN);
      const double a = (i % 2 ? 1.0 : -1.0) * sizes[i];
      for (std::int64_t t = t0; t < kLongN; ++t) x[static_cast<std::size_t>(t)] += a;
      ASSERT_GT(oracle_scan(x), kOracleNull99) << "seed " << seed;
      const GapResult g = diagnose_long(x, seed + 1000);
      const std::string what = "size " + std::to_string(a) + " seed " + std::to_string(seed) + ": " + g.headline;
      EXPECT_EQ(g.effect, GapEffect::kStep) << what;
      EXPECT_TRUE(g.step_scan_tested) << what;
      EXPECT_GT(g.step_scan_statistic, g.step_scan_threshold) << what;
      ASSERT_TRUE(g.event.has_value()) << what;
      EXPECT_NEAR(static_cast<double>(g.event->sample), static_cast<double>(t0), 0.002 * kLongN) << what;
      EXPECT_NEAR(g.event->size, a, 3.5 * kStepSizeSe) << what;
    }
}

TEST(GapTimeEffects, TheStepScanNamesNothingOnTheLongBaseAlone) {
  for (std::uint64_t seed : {43190u, 43191u}) {
    const Model base = parse_model(kBase);
    const std::vector<double> x = simulate(base, base.given_values(), kLongN, seed, 0);
    const GapResult g = diagnose_long(x, seed + 1000);
    EXPECT_EQ(g.effect, GapEffect::kNone) << g.headline;
    EXPECT_TRUE(g.step_scan_tested);
    EXPECT_LT(g.step_scan_statistic, g.step_scan_threshold) << g.headline;
  }
}

TEST(GapTimeEffects, TheStepScanDividesOutANoisierRecordButNeverScalesUpAQuieterOne) {
  // Issue 43, item 5: the scan's maximum is divided by z's RMS only where it exceeds 1
  // (data noisier than the baseline); always dividing widened its null law (5.05 against
  // the oracle's 4.79 at 0.625%) and cost 17 points of power. z is linear in the data, so
  // on c x: noisier (c = 3, 6) the statistic is scale-free, quieter (c = 1/4, 1/8: z's
  // RMS below 1) it shrinks with c, never growing toward a step the data do not hold.
  const std::vector<double> x = base_series(43195);
  const auto statistic = [&](double c) {
    std::vector<double> y(x);
    for (double& v : y) v *= c;
    const GapResult g = diagnose(y, 43196);
    EXPECT_TRUE(g.step_scan_tested);
    return g.step_scan_statistic;
  };
  const double noisier = statistic(3.0), noisier_still = statistic(6.0);
  EXPECT_NEAR(noisier_still, noisier, 1e-9 * noisier);
  const double quieter = statistic(0.25), quieter_still = statistic(0.125);
  EXPECT_GT(quieter, 0.0);
  EXPECT_NEAR(quieter_still, 0.5 * quieter, 1e-9 * quieter);
}

TEST(GapTimeEffects, NameAWarmUpTransientTransientWithItsTimeConstant) {
  std::vector<double> x = base_series(9103);
  const double T = 500.0, a = 0.05;  // 5 white-noise deviations at t = 0
  for (std::int64_t t = 0; t < kN; ++t) x[static_cast<std::size_t>(t)] += a * std::exp(-static_cast<double>(t) / T);
  const GapResult g = diagnose(x, 9203);
  ASSERT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kTransient);
  ASSERT_TRUE(g.event.has_value());
  EXPECT_EQ(g.event->sample, 0);
  EXPECT_LT(std::abs(std::log(g.event->time_constant / T)), std::log(2.0));  // within a factor 2
  EXPECT_NEAR(g.event->size, a, 0.2 * a);
  EXPECT_GT(g.shrinkage.excess_removed, 0.8);
}

TEST(GapTimeEffects, NameADriftDrWithItsSlopeInsideItsInterval) {
  std::vector<double> x = base_series(9107);
  // A drift of 6 random-walk spreads over the record: omega N = 6 sqrt(N gamma2).
  const double omega = 6.0 * kRwSpread / static_cast<double>(kN);
  for (std::int64_t t = 0; t < kN; ++t) x[static_cast<std::size_t>(t)] += omega * static_cast<double>(t);
  const GapResult g = diagnose(x, 9207);
  ASSERT_TRUE(g.trend.has_value());
  EXPECT_TRUE(g.trend->significant);
  EXPECT_EQ(g.effect, GapEffect::kDR);
  EXPECT_LT(g.trend->ci_low, omega);
  EXPECT_GT(g.trend->ci_high, omega);
  // The final model carries the drift, so the integrated error grows with it.
  EXPECT_NE(g.final_model.to_string(g.final_theta).find("DR("), std::string::npos);
  ASSERT_EQ(g.step_drops.size(), g.steps.size());
}

TEST(GapTimeEffects, CallTheSlopeOfAWalkLargerThanTheBaselinesAWalkNotADrift) {
  // The data's random walk is 25x the baseline's in gamma2 (a datasheet's K 5x too small):
  // its end-segment slope is far outside the baseline's replicates (sd 5x smaller), but
  // within the exact slope distribution of the baseline's family re-sized to the data.
  const Model truth = parse_model("WN(sigma2=1e-4)+RW(gamma2=2.5e-9)");
  int walks = 0, tested = 0;
  for (std::uint64_t seed : {9301u, 9302u, 9303u, 9304u}) {
    const std::vector<double> x = simulate(truth, truth.given_values(), kN, seed, 0);
    const GapResult g = diagnose(x, seed + 100);
    ASSERT_TRUE(g.trend.has_value());
    if (std::abs(g.trend->z) <= g.trend->threshold) continue;  // the baseline's own test did not fire
    ++tested;
    EXPECT_EQ(std::find(g.steps.begin(), g.steps.end(), GapEffect::kDR), g.steps.end()) << g.headline;
    EXPECT_FALSE(g.trend->significant);
    for (const auto& n : g.notes) walks += n.find("a random walk of the data's size, not a drift") != std::string::npos;
  }
  EXPECT_GE(tested, 2) << "the baseline's own trend test fires on most walks 5x its spread";
  EXPECT_EQ(walks, tested);
}

TEST(GapTimeEffects, NameATemperatureCouplingTemperatureWithItsCoefficient) {
  std::vector<double> x = base_series(9104);
  const std::vector<double> temp = temperature_series(9304);
  const double k = 2e-3;  // data units per degree
  for (std::size_t t = 0; t < x.size(); ++t) x[t] += k * temp[t];
  const GapResult g = diagnose(x, 9204, &temp);
  ASSERT_TRUE(g.temperature.has_value());
  EXPECT_TRUE(g.temperature->significant);
  EXPECT_EQ(g.effect, GapEffect::kTemperature);
  EXPECT_LT(g.temperature->ci_low, k);
  EXPECT_GT(g.temperature->ci_high, k);
  EXPECT_GT(g.shrinkage.excess_removed, 0.8);
}

TEST(GapTimeEffects, FindNoCouplingToAnUnrelatedTemperatureChannel) {
  const std::vector<double> x = base_series(9105);
  const std::vector<double> temp = temperature_series(9305);
  const GapResult g = diagnose(x, 9205, &temp);
  ASSERT_TRUE(g.temperature.has_value());
  EXPECT_FALSE(g.temperature->significant);
  EXPECT_LT(g.temperature->ci_low, 0.0);
  EXPECT_GT(g.temperature->ci_high, 0.0);
  EXPECT_EQ(g.effect, GapEffect::kNone);
}

TEST(GapTimeEffects, SplitHalvesAgreeOnAStationaryRecordAndNotWhenTheNoiseChanges) {
  const std::vector<double> x = base_series(9108);
  const GapResult g = diagnose(x, 9208);
  ASSERT_EQ(g.split_half.size(), 15u);  // J = 15 levels for each half of 2^16 samples
  int disjoint = 0;
  for (const auto& h : g.split_half) disjoint += h.disjoint;
  // 95% CIs overlap unless the halves differ by much more than their spread: a handful
  // of levels at most by chance (independent disjointness ~ 0.6% per level).
  EXPECT_LE(disjoint, 2);
  // A sinusoid of amplitude 0.01 near 1/3 cycle per sample in the second half only: its
  // variance 5e-5 adds half the white noise's at the finest level there.
  std::vector<double> y = base_series(9109);
  for (std::size_t t = y.size() / 2; t + 1 < y.size(); ++t) y[t] += 0.01 * std::sin(0.0 + static_cast<double>(t) * 2.1);
  const GapResult h = diagnose(y, 9209);
  EXPECT_TRUE(h.split_half.front().disjoint);
  EXPECT_GT(h.split_half.front().ratio, 1.5);
}

TEST(GapTimeEffects, RejectATemperatureChannelOfAnotherLength) {
  const std::vector<double> x = base_series(9106);
  const std::vector<double> temp(100, 25.0);
  try {
    diagnose(x, 9206, &temp);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "gap: the temperature channel has 100 samples, the signal 65536");
  }
}

}  // namespace
}  // namespace gmwm::gap
