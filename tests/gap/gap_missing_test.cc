// Gap diagnosis of a record with missing samples (GapOptions::missing, issue 47): the WV from
// the windows without a gap against replicates read through the same gaps; nothing found
// against the truth, a sinusoid attributed with its frequency, spikes found by the
// contamination screen among the same windows, the time-domain stages left out with a note
// saying so, and a temperature channel refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/gap/gap.h"
#include "gmwm/robust/robust_wv.h"
#include "holed_record.h"

namespace gmwm::gap {
namespace {

constexpr std::int64_t kN = 1 << 16;
constexpr const char* kBase = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";

// About 3% of the grid missing: 40 gaps of 50 samples, the first at 700, every 1600.
std::vector<MissingRun> runs() {
  std::vector<MissingRun> r;
  for (int k = 0; k < 40; ++k) r.push_back({700 + 1600 * k, 50});
  return r;
}

struct GappyCase {
  test::Holed h;
  WaveletVariance wv;
};

GappyCase gappy_case(std::vector<double> full) {
  GappyCase c{test::remove(full, runs()), {}};
  c.wv = classical_wv_with_gaps(c.h.observed, c.h.runs);
  drop_incomplete_levels(c.wv);
  return c;
}

std::vector<double> simulated(const std::string& spec, std::uint64_t seed) {
  const Model m = parse_model(spec);
  return simulate(m, m.given_values(), kN, seed, 0);
}

GapResult diagnose(const GappyCase& c, std::uint64_t seed, bool with_robust = false) {
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = seed;
  o.missing = c.h.runs;
  if (!with_robust) return diagnose_gap(c.wv, base, base.given_values(), o, nullptr, &c.h.observed);
  WaveletVariance r = robust::robust_wv_with_gaps(c.h.observed, c.h.runs);
  drop_incomplete_levels(r);
  return diagnose_gap(c.wv, base, base.given_values(), o, &r, &c.h.observed);
}

// Options for the refusal tests: the fewest replicates, the record's runs.
GapOptions refusal_options(const GappyCase& c) {
  GapOptions o;
  o.replicates = 40;
  o.missing = c.h.runs;
  return o;
}

const std::string kNote =
    "the record misses 2000 samples in 40 gaps: the WV and its reference read the windows without a gap; the "
    "time-window map, the split halves and the time-domain effects (STEP, TRANSIENT, the trend, TEMPERATURE) read a "
    "regular series and were not tried";

TEST(DiagnoseGapWithMissingSamples, FindsNoEffectAgainstTheTruthAndSaysWhatItLeftOut) {
  const GapResult g = diagnose(gappy_case(simulated(kBase, 8301)), 8401);
  EXPECT_EQ(g.effect, GapEffect::kNone);
  EXPECT_TRUE(g.steps.empty());
  ASSERT_EQ(g.levels.size(), 16u) << "every level of 2^16 has windows (the long ones near-complete)";
  // Pointwise 95% bands: about 0.8 of 16 levels outside by chance, as on a regular record.
  EXPECT_LE(g.shrinkage.levels_outside_before, 3);
  for (const auto& l : g.levels) EXPECT_LT(std::abs(l.z), 4.0) << l.tau;
  EXPECT_NE(std::find(g.notes.begin(), g.notes.end(), kNote), g.notes.end());
  EXPECT_TRUE(g.windows.empty()) << "no time-window map of a series with holes";
}

TEST(DiagnoseGapWithMissingSamples, AttributesAnInjectedSinusoidAndRecoversItsFrequency) {
  const GapResult g = diagnose(gappy_case(simulated(std::string(kBase) + "+SIN(A2=4e-4,f=0.02)", 8302)), 8402);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kSin);
  ASSERT_EQ(g.final_fit.theta.size(), 2);
  EXPECT_NEAR(g.final_fit.theta(1), 0.02, 0.05 * 0.02);
  EXPECT_GE(g.shrinkage.excess_removed, 0.8);
}

TEST(DiagnoseGapWithMissingSamples, NamesSpikesOutliersFromTheWindowsWithoutAGap) {
  std::vector<double> full = simulated(kBase, 8303);
  // 0.1% of the samples, 20 level-1 wavelet standard deviations (sqrt(2e-4 / 4)).
  const double sd1 = std::sqrt(2e-4 / 4.0);
  for (std::int64_t t = 500; t < kN; t += 1000) full[static_cast<std::size_t>(t)] += (t % 2000 ? 20.0 : -20.0) * sd1;
  const GapResult g = diagnose(gappy_case(full), 8403, true);
  EXPECT_TRUE(g.contamination_screened);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kOutliers);
}

TEST(DiagnoseGapWithMissingSamples, RefusesATemperatureChannelNamingTheGaps) {
  const GappyCase c = gappy_case(simulated(kBase, 8304));
  const Model base = parse_model(kBase);
  GapOptions o = refusal_options(c);
  const std::vector<double> temperature(c.h.observed.size(), 20.0);
  try {
    diagnose_gap(c.wv, base, base.given_values(), o, nullptr, &c.h.observed, &temperature);
    FAIL() << "a temperature channel of a record with gaps was read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "gap: TEMPERATURE reads a regular record; this one misses samples in 40 gaps");
  }
}

TEST(DiagnoseGapWithMissingSamples, RefusesRunsThatDoNotPlaceTheSamplesOnTheWvsGrid) {
  const GappyCase c = gappy_case(simulated(kBase, 8305));
  const Model base = parse_model(kBase);
  GapOptions o = refusal_options(c);
  o.missing.back().length += 1;  // one sample more than the WV's grid holds
  try {
    diagnose_gap(c.wv, base, base.given_values(), o, nullptr, &c.h.observed);
    FAIL() << "runs of another grid were read";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(std::string(e.what()),
              "diagnose_gap: options.missing does not place x on the WV's grid of 65536 "
              "samples: x and the runs make a grid of 65537");
  }
  o.missing = c.h.runs;
  EXPECT_THROW(diagnose_gap(c.wv, base, base.given_values(), o), InvalidArgument) << "no observed samples given";
}

}  // namespace
}  // namespace gmwm::gap
