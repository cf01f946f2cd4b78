// Sim-to-real gap diagnosis (gap/src/gap.cc) on simulated data whose effect is known:
// nothing added, a sinusoid, an AR1 (bias instability band), a mis-set white noise, spikes.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"

#include <boost/random/normal_distribution.hpp>
#include "gmwm/robust/robust_wv.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap {
namespace {

constexpr std::int64_t kN = 1 << 16;
constexpr const char* kBase = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";

struct Case {
  std::vector<double> x;
  WaveletVariance wv;
};

Case simulate_case(const std::string& spec, std::uint64_t seed) {
  const Model m = parse_model(spec);
  Case c;
  c.x = simulate(m, m.given_values(), kN, seed, 0);
  c.wv = classical_wv(c.x.data(), kN);
  return c;
}

GapResult diagnose(const Case& c, std::uint64_t seed, bool with_robust = false) {
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = seed;
  if (!with_robust) return diagnose_gap(c.wv, base, base.given_values(), o);
  const WaveletVariance r = robust::robust_wv(c.x.data(), kN);
  return diagnose_gap(c.wv, base, base.given_values(), o, &r, &c.x);
}

TEST(GapEffects, EveryEffectReadsBackFromItsNameAndTheAttributionTriesTheLatentOnesInOrder) {
  // One table (gap_candidates.cc) gives the names, the parser and the candidates.
  for (int k = static_cast<int>(GapEffect::kNone); k <= static_cast<int>(GapEffect::kReparameterise); ++k) {
    const auto e = static_cast<GapEffect>(k);
    EXPECT_EQ(parse_gap_effect(to_string(e)), e) << to_string(e);
  }
  EXPECT_FALSE(parse_gap_effect("wn").has_value());
  std::vector<std::string> tried;
  for (GapEffect e : wv_candidate_effects()) tried.emplace_back(to_string(e));
  EXPECT_EQ(tried, (std::vector<std::string>{"WN", "QN", "RW", "DR", "AR1", "FLICKER", "SIN", "REPARAMETERISE"}));
}

TEST(DiagnoseGap, FindsNoEffectOnDataFromTheBaselineItself) {
  const GapResult g = diagnose(simulate_case(kBase, 8101), 8201);
  EXPECT_EQ(g.effect, GapEffect::kNone);
  EXPECT_TRUE(g.steps.empty());
  EXPECT_GT(g.p_value, 0.0);
  ASSERT_EQ(g.levels.size(), 16u);
  // Pointwise 95% bands: about 0.8 of 16 levels outside by chance.
  EXPECT_LE(g.shrinkage.levels_outside_before, 3);
  for (const auto& l : g.levels) EXPECT_LT(std::abs(l.z), 4.0) << l.tau;
  EXPECT_FALSE(g.notes.empty());
}

TEST(DiagnoseGap, AttributesAnInjectedSinusoidAndRecoversItsFrequency) {
  // f = 0.02 cycles/sample: its WV hump at tau ~ 0.742 / f ~ 37 samples, levels 5-6.
  const GapResult g = diagnose(simulate_case(std::string(kBase) + "+SIN(A2=4e-4,f=0.02)", 8102), 8202);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kSin);
  ASSERT_FALSE(g.bands.empty());
  EXPECT_EQ(g.bands.front().direction, "excess");
  EXPECT_LE(g.bands.front().tau_from, 64.0);
  EXPECT_GE(g.bands.back().tau_to, 32.0);
  ASSERT_EQ(g.final_fit.theta.size(), 2);
  EXPECT_NEAR(g.final_fit.theta(1), 0.02, 0.05 * 0.02);
  EXPECT_GE(g.shrinkage.excess_removed, 0.8);
  EXPECT_LT(g.shrinkage.levels_outside_after, g.shrinkage.levels_outside_before);
}

TEST(DiagnoseGap, AttributesAnInjectedGaussMarkovBandToAr1) {
  const GapResult g = diagnose(simulate_case(std::string(kBase) + "+AR1(phi=0.995,sigma2=2e-7)", 8103), 8203);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kAR1);
  // Every candidate was scored, and the chosen one cleared its calibrated threshold.
  EXPECT_GE(g.candidates.size(), 6u);
  for (const auto& c : g.candidates)
    if (c.effect == GapEffect::kAR1) {
      EXPECT_TRUE(c.cleared);
      EXPECT_GT(c.improvement, c.threshold);
      EXPECT_GT(c.threshold, 0.0);
    }
  ASSERT_EQ(g.final_fit.theta.size(), 2);
  EXPECT_NEAR(g.final_fit.theta(0), 0.995, 0.003);
  EXPECT_GE(g.shrinkage.excess_removed, 0.8);
}

TEST(DiagnoseGap, CallsAMisSetWhiteNoiseReparameterise) {
  const GapResult g = diagnose(simulate_case("WN(sigma2=1.3e-4)+RW(gamma2=1e-10)", 8104), 8204);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kReparameterise);
}

TEST(DiagnoseGap, FindsWhatAFittedFamilyLacksWhenTheBaselineIsRefitted) {
  // --fit mode: WN+RW fitted on data that also hold an AR1; the family is re-estimated
  // together with each candidate, and the effect is reported on its own.
  const Case c = simulate_case(std::string(kBase) + "+AR1(phi=0.995,sigma2=2e-7)", 8107);
  FitOptions fo;
  fo.inference = false;
  const FitResult base = fit_gmwm(c.wv, parse_model("WN+RW"), fo);
  GapOptions o;
  o.replicates = 100;
  o.seed = 8207;
  o.refit_baseline = true;
  const GapResult g = diagnose_gap(c.wv, base.model, base.theta, o);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kAR1);
  for (const auto& k : g.candidates) EXPECT_NE(k.effect, GapEffect::kReparameterise) << "no re-sizing in --fit mode";
  ASSERT_EQ(g.final_fit.model.to_string(), "AR1");
  EXPECT_NEAR(g.final_fit.theta(0), 0.995, 0.003);
  EXPECT_EQ(g.final_model.to_string(), "AR1+WN+RW");
}

TEST(DiagnoseGap, MapsABurstToItsTimeWindowAndAStationarySeriesToNone) {
  Case c = simulate_case(kBase, 8108);
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = 8208;
  const GapResult quiet = diagnose_gap(c.wv, base, base.given_values(), o, nullptr, &c.x);
  EXPECT_TRUE(quiet.windows_checked);
  EXPECT_EQ(quiet.window_length, 8192);  // 2^16 / 8 windows
  EXPECT_TRUE(quiet.windows.empty()) << quiet.windows.size() << " windows flagged on stationary data";
  // Extra white noise (5 x the baseline's) in samples [20000, 22000): window 2 of 8.
  Rng rng = make_stream(8308, {1});
  boost::random::normal_distribution<double> z(0.0, std::sqrt(5e-4));
  for (std::size_t t = 20000; t < 22000; ++t) c.x[t] += z(rng);
  c.wv = classical_wv(c.x.data(), kN);
  const GapResult burst = diagnose_gap(c.wv, base, base.given_values(), o, nullptr, &c.x);
  ASSERT_FALSE(burst.windows.empty());
  for (const auto& w : burst.windows) {
    EXPECT_EQ(w.first_sample, 2 * 8192) << w.tau;
    EXPECT_EQ(w.last_sample, 3 * 8192 - 1);
    EXPECT_GT(w.z, 0.0);
  }
}

TEST(DiagnoseGap, NamesSpikesOutliers) {
  Case c = simulate_case(kBase, 8105);
  // 0.1% of the samples, 20 level-1 wavelet standard deviations.
  const double sd1 = std::sqrt(c.wv.wv[0]);
  for (std::int64_t t = 500; t < kN; t += 1000) c.x[static_cast<std::size_t>(t)] += (t % 2000 ? 20.0 : -20.0) * sd1;
  c.wv = classical_wv(c.x.data(), kN);
  const GapResult g = diagnose(c, 8205, true);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kOutliers);
}

// Half the replicates are the global test's null sample: its smallest p-value is
// 1 / (1 + replicates / 2), so 38 replicates (p >= 1/20) could never reject at 5% and every
// departure, however plain, read "no gap".
TEST(DiagnoseGap, RefusesTooFewReplicatesForTheGlobalTestToRejectAtItsLevel) {
  EXPECT_EQ(min_gap_replicates(0.05), 40);
  EXPECT_EQ(min_gap_replicates(0.1), 20);
  EXPECT_EQ(min_gap_replicates(0.01), 200);
  for (double alpha : {0.05, 0.1, 0.01, 0.2, 0.003})
    EXPECT_LT(1.0 / (1.0 + static_cast<double>(min_gap_replicates(alpha) / 2)), alpha) << alpha;
  for (double alpha : {0.05, 0.01, 0.003})
    EXPECT_GE(1.0 / (1.0 + static_cast<double>(min_gap_replicates(alpha) / 2 - 1)), alpha) << alpha;
  GapOptions o;
  o.replicates = 38;
  EXPECT_EQ(o.Validate(),
            "replicates must be at least 40 for the global test to reject at alpha 0.05 (its smallest p-value is "
            "1 / (1 + replicates / 2)), got 38");
  o.replicates = 40;
  EXPECT_EQ(o.Validate(), "");
  o.alpha = 1e-9;
  EXPECT_NE(o.Validate().find("below what the global test can reach with 100000 replicates"), std::string::npos);
}

TEST(DiagnoseGap, RejectsBadOptionsAndABaselineWithoutValues) {
  const Case c = simulate_case(kBase, 8106);
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 5;
  try {
    diagnose_gap(c.wv, base, base.given_values(), o);
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("replicates must be in [20, 100000], got 5"), std::string::npos) << e.what();
  }
  o = GapOptions{};
  Eigen::VectorXd bad = base.given_values();
  bad(0) = -1.0;
  try {
    diagnose_gap(c.wv, base, bad, o);
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gap: baseline"), std::string::npos) << e.what();
  }
}

TEST(DiagnoseGap, KeepsOnlyEffectsThatMakeTheFitBetterAndSaysTheGapRemains) {
  // An AR1 withheld, but only QN may be tried: whatever is kept must lower the objective
  // without putting more levels outside the band, and the headline must say the gap
  // remains (with its scales) while the final model is still rejected.
  const Case c = simulate_case(std::string(kBase) + "+AR1(phi=0.995,sigma2=2e-7)", 8111);
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = 8211;
  o.candidates = {GapEffect::kQN};
  const GapResult g = diagnose_gap(c.wv, base, base.given_values(), o);
  ASSERT_TRUE(g.detected);
  EXPECT_LE(g.shrinkage.objective_after, g.shrinkage.objective_before);
  EXPECT_LE(g.shrinkage.levels_outside_after, g.shrinkage.levels_outside_before);
  EXPECT_LT(g.shrinkage.p_value_after, o.alpha);
  EXPECT_FALSE(g.remaining.empty());
  EXPECT_FALSE(g.closed);
  EXPECT_NE(g.headline.find("gap remains at "), std::string::npos) << g.headline;
  EXPECT_NE(g.headline.find("levels outside "), std::string::npos) << g.headline;
  EXPECT_EQ(g.headline.find("gap closed"), std::string::npos) << g.headline;
  EXPECT_GE(g.shrinkage.excess_removed, 0.0);
  EXPECT_LE(g.shrinkage.excess_removed, 1.0);
}

TEST(DiagnoseGap, SaysTheGapIsClosedOnlyWhenTheFinalModelIsNotRejected) {
  const GapResult g = diagnose(simulate_case(std::string(kBase) + "+AR1(phi=0.995,sigma2=2e-7)", 8103), 8203);
  ASSERT_TRUE(g.detected);
  EXPECT_GE(g.shrinkage.p_value_after, 0.05);
  EXPECT_TRUE(g.remaining.empty());
  EXPECT_TRUE(g.closed);
  EXPECT_NE(g.headline.find("gap closed"), std::string::npos) << g.headline;
  EXPECT_NE(g.headline.find("AR1 with correlation time"), std::string::npos) << g.headline;
  EXPECT_LE(g.shrinkage.excess_removed, 1.0);
}

TEST(DiagnoseGap, NeverDetectsFromALevelWithOneCoefficientAlone) {
  // Data from the baseline itself, the coarsest level (one coefficient) inflated 1000x:
  // that level alone must not make a gap band.
  Case c = simulate_case(kBase, 8112);
  c.wv.wv.back() *= 1000.0;
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = 8212;
  const GapResult g = diagnose_gap(c.wv, base, base.given_values(), o);
  for (const auto& b : g.bands) EXPECT_LT(b.last_level, static_cast<int>(c.wv.levels())) << b.first_level;
  EXPECT_FALSE(g.detected) << g.headline;
  bool noted = false;
  for (const auto& n : g.notes) noted |= n.find("fewer than 4 effective coefficients") != std::string::npos;
  EXPECT_TRUE(noted);
}

// The diagnosis against a baseline given with its values (100 replicates).
GapResult diagnose_against(const Case& c, const std::string& baseline, std::uint64_t seed) {
  const Model base = parse_model(baseline);
  GapOptions o;
  o.replicates = 100;
  o.seed = seed;
  return diagnose_gap(c.wv, base, base.given_values(), o);
}

// Whether the final model has a `process` whose first parameter satisfies `ok`.
template <class Ok>
bool final_has(const GapResult& g, const std::string& process, Ok ok) {
  for (int k = 0; k < g.final_model.num_components(); ++k)
    if (g.final_model.components()[static_cast<std::size_t>(k)].process->name() == process &&
        ok(g.final_theta(g.final_model.offset(k))))
      return true;
  return false;
}

bool took(const GapResult& g, GapEffect e) { return std::find(g.steps.begin(), g.steps.end(), e) != g.steps.end(); }

TEST(DiagnoseGap, ResizesADatasheetWhiteNoiseEightTimesTooHigh) {
  // The README example's situation: the baseline's white noise is ~8x the data's, and the
  // data hold an AR1 the baseline lacks. REPARAMETERISE must re-size the white noise to the
  // data's (within 5%: its estimate's relative sd at 2^16 samples is ~1%) and the final
  // model must describe the data (the global test does not reject it).
  const Case c = simulate_case("AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-10)", 8113);
  const GapResult g = diagnose_against(c, "WN(sigma2=7.6e-5)+RW(gamma2=4e-12)", 8213);
  ASSERT_TRUE(g.detected);
  EXPECT_TRUE(took(g, GapEffect::kReparameterise)) << g.headline;
  EXPECT_TRUE(final_has(g, "WN", [](double s2) { return std::abs(s2 / 1e-5 - 1.0) < 0.05; }))
      << g.final_model.to_string(g.final_theta);
  EXPECT_GE(g.shrinkage.p_value_after, GapOptions{}.alpha) << g.headline;
  EXPECT_NE(g.headline.find("gap closed"), std::string::npos) << g.headline;
}

TEST(DiagnoseGap, ReachesTheTruthFromADatasheetFarBelowTheDataAtCoarseScales) {
  // A datasheet baseline (white noise 7.6x too high, a flicker floor) whose coarse levels
  // lie ~200x below data that hold AR1 + RW: the objective's weights keep the baseline's
  // (far smaller) spread where the data exceed it, and with them the re-sizing chased the
  // coarse levels, swapped the white noise for QN and stopped with 11 of 16 levels outside.
  // With the candidates' weights following the re-sized base (docs/gap.md, "The
  // objective") the search must name the AR1 (1 / (1 - phi) = 1000 samples, within a
  // factor 2) and close the gap.
  const Case c = simulate_case("AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-10)", 20261121);
  const GapResult g = diagnose_against(c, "WN(sigma2=7.6e-5)+FLICKER(B2=3.4e-8)", 8214);
  ASSERT_TRUE(g.detected);
  EXPECT_FALSE(took(g, GapEffect::kQN)) << g.headline;
  EXPECT_TRUE(took(g, GapEffect::kAR1)) << g.headline;
  EXPECT_TRUE(final_has(g, "AR1", [](double phi) { return 1.0 / (1.0 - phi) > 500.0 && 1.0 / (1.0 - phi) < 2000.0; }))
      << g.final_model.to_string(g.final_theta);
  EXPECT_EQ(g.shrinkage.levels_outside_after, 0) << g.headline;
  EXPECT_NE(g.headline.find("gap closed"), std::string::npos) << g.headline;
}

// A WV cut by drop_fine_levels (the fine scales held or interpolated samples smooth) is
// compared from its first level: the reference replicates are cut the same way, the levels'
// map starts there, and the bands and flagged levels name the series' own levels.
TEST(DiagnoseGap, ComparesACutWvFromItsFirstLevelAndNamesBandsByTheSeriesLevels) {
  const Case c = simulate_case(std::string(kBase) + "+AR1(phi=0.995,sigma2=2e-7)", 8103);
  const Model base = parse_model(kBase);
  GapOptions o;
  o.replicates = 100;
  o.seed = 8203;
  const WaveletVariance robust = robust::robust_wv(c.x.data(), kN);
  const WaveletVariance wv = drop_fine_levels(c.wv, 3), cut_robust = drop_fine_levels(robust, 3);
  const GapResult g = diagnose_gap(wv, base, base.given_values(), o, &cut_robust, &c.x);
  EXPECT_EQ(g.first_level, 3);
  ASSERT_EQ(g.levels.size(), 14u);
  EXPECT_EQ(g.levels.front().tau, 8.0);
  EXPECT_EQ(g.levels_after.size(), 14u);
  EXPECT_TRUE(g.detected);
  EXPECT_EQ(g.effect, GapEffect::kAR1);
  ASSERT_FALSE(g.bands.empty());
  for (const GapBand& b : g.bands) {
    EXPECT_GE(b.first_level, 3);
    EXPECT_EQ(b.tau_from, g.levels[static_cast<std::size_t>(b.first_level - g.first_level)].tau);
    EXPECT_EQ(b.tau_to, g.levels[static_cast<std::size_t>(b.last_level - g.first_level)].tau);
    EXPECT_EQ(b.tau_from, std::ldexp(1.0, b.first_level));
  }
  for (int l : g.contaminated_levels) EXPECT_GE(l, 3);
  ASSERT_EQ(g.final_fit.theta.size(), 2);
  EXPECT_NEAR(g.final_fit.theta(0), 0.995, 0.003);
}

// Held samples (each measurement copied once, as a 2x-rate stream carries a slower sensor)
// leave the WV's finest levels at about half the sensor's: compared there, the true model is
// rejected; compared from level 5 (tau = 32 samples, where the detection of
// repeated_samples.h calls a copy of 2 clean), it is not.
TEST(DiagnoseGap, FindsNoGapAboveTheScalesHeldSamplesSmoothWhenTheBaselineIsTheTruth) {
  const Model m = parse_model(kBase);
  const std::vector<double> measured = simulate(m, m.given_values(), kN / 2, 8111, 0);
  std::vector<double> held(kN);
  for (std::int64_t t = 0; t < kN; ++t) held[static_cast<std::size_t>(t)] = measured[static_cast<std::size_t>(t / 2)];
  // The held record's own model at its rate: the white noise's density kept (sigma2 x 2),
  // the walk's increments spread over two samples (gamma2 / 2).
  const Model truth = parse_model("WN(sigma2=2e-4)+RW(gamma2=5e-11)");
  GapOptions o;
  o.replicates = 100;
  o.seed = 8211;
  const WaveletVariance wv = classical_wv(held.data(), kN);
  const GapResult every = diagnose_gap(wv, truth, truth.given_values(), o, nullptr, &held);
  EXPECT_TRUE(every.detected);
  ASSERT_FALSE(every.bands.empty());
  EXPECT_EQ(every.bands.front().first_level, 1);
  EXPECT_EQ(every.bands.front().direction, "deficit");
  const GapResult above = diagnose_gap(drop_fine_levels(wv, 5), truth, truth.given_values(), o, nullptr, &held);
  EXPECT_FALSE(above.detected) << above.headline;
  EXPECT_GT(above.p_value, o.alpha);
  EXPECT_TRUE(above.steps.empty());
}

}  // namespace
}  // namespace gmwm::gap
