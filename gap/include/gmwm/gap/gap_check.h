#pragma once
// The gap diagnosis' self-check on data whose effect is known because it was withheld
// (docs/gap.md, method note 5): series from a WN+RW base plus one effect the base lacks, at a grid of
// strengths with random nuisance parameters; the diagnosis gets only the base model and
// is scored on detection, location, attribution, parameters and shrinkage. The null side:
// the base alone (must give "no new effect") and the base with its parameters off by
// +-20% (must give REPARAMETERISE or no new effect).
//
// Strength (docs/gap.md, method note 5): for effects with a WV, the largest ratio over levels of the
// effect's WV to the base's; for OUTLIERS, the relative excess the spikes cause in the
// classical WV at level 1.
//
// Seeds: the cases' data come from streams of `seed`; each diagnosis calibrates its
// thresholds on its own reference replicates from a different seed family
// (seed + kCalibrationSeedOffset), so calibration and evaluation never share draws.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "gmwm/gap/gap.h"

namespace gmwm::gap {

struct GapCheckOptions {
  /// Cases per effect family; the null side has 5x as many base-only cases and 2x as
  /// many with the base's parameters off (issue 5: 100, 500, 200).
  int cases = 100;
  /// Strengths, cycled through each family's cases.
  std::vector<double> strengths = {2.0, 4.0, 8.0};
  std::int64_t n = std::int64_t{1} << 18;
  double freq = 100.0;
  /// Reference replicates of each diagnosis.
  int replicates = 100;
  std::uint64_t seed = 0;
  /// The withheld families (those the diagnosis implements).
  std::vector<GapEffect> families = {GapEffect::kQN,  GapEffect::kDR,       GapEffect::kAR1,  GapEffect::kFlicker,
                                     GapEffect::kSin, GapEffect::kOutliers, GapEffect::kStep, GapEffect::kTransient};
  bool null_side = true;
  /// Called with (cases done, total).
  std::function<void(int, int)> progress;
  std::string Validate() const;
};

struct GapCheckCase {
  GapEffect truth = GapEffect::kNone;  ///< kNone: base only; kReparameterise: base off by +-20%
  double strength = 0.0;               ///< 0 on the null side
  std::string injected;                ///< the effect with its values (or the altered base)
  GapEffect reported = GapEffect::kNone;
  bool detected = false;
  bool located = false;  ///< a reported band overlaps the effect's dominant levels
  bool correct = false;  ///< top-1 attribution (null side: none / REPARAMETERISE)
  double excess_removed = 0.0;
  /// SIN: |f_hat / f - 1|; AR1, TRANSIENT: |log(T_hat / T)| / log 2 (<= 1: within a factor
  /// 2); STEP: |t_hat - t| / the window length (<= 1: within one window); NaN otherwise.
  double parameter_error = 0.0;
  /// The oracle's non-centrality at strength 1 (item 7 of issue 14): dnu' V0^-1 dnu, with
  /// dnu the effect's expected WV at strength 1 (this case's shape: AR1 T, SIN f, STEP
  /// time ...) and V0 the exact Cov(nuhat) of the base. The one-sided test of "amplitude
  /// 0" that knows everything but the amplitude has power Phi(s sqrt(nc) - z_0.95) at
  /// strength s (NaN on the null side).
  double oracle_nc = 0.0;
  /// DR only: the oracle is the Neyman-Pearson test on the series itself (a drift is a
  /// deterministic mean omega t, so the most powerful test of omega = 0 is the GLS
  /// z-test under the base's exact covariance; the WV's Gaussian approximation at the
  /// few-coefficient levels where a drift shows would claim more power than that bound).
  /// oracle_nc is then omega_1^2 t' Sigma^-1 t at strength 1, and since omega grows as
  /// sqrt(strength) the power is Phi(sqrt(s nc) - z_0.95).
  bool oracle_time_domain = false;
};

/// Where a power curve crosses 90%: interpolated (log strength) between two strengths of
/// the grid, at most the grid's smallest strength, or beyond its largest.
enum class Crossing { kInterpolated, kAtMost, kBeyond };
const char* to_string(Crossing c);

struct GapCheckFamily {
  int cases = 0, correct = 0, located = 0, detected = 0;
  double median_excess_removed = 0.0;  ///< over the correctly attributed cases
  std::map<double, double> power;      ///< strength -> share correctly attributed
  /// The strength at which the share correctly attributed reaches 90% (see `crossing`),
  /// the oracle's (mean of its power over this family's cases = 90%), and their ratio,
  /// the figure of merit (goal <= 1.5). NaN on the null side.
  double strength_90 = 0.0, oracle_strength_90 = 0.0, oracle_ratio = 0.0;
  Crossing crossing = Crossing::kInterpolated;
};

struct GapCheckResult {
  std::vector<GapCheckCase> cases;
  std::map<std::string, std::map<std::string, int>> confusion;  ///< truth -> reported -> count
  std::map<std::string, GapCheckFamily> families;               ///< per truth (incl. "none", "REPARAMETERISE")
  int correct = 0;
  int false_alarms = 0;  ///< null-side cases given a new effect
};

/// Runs the self-check. Throws InputError on invalid options.
GapCheckResult run_gap_check(const GapCheckOptions& options);

/// The withheld families of a comma-separated list ("QN,STEP", as `gap-check --families` and
/// Python's gap_check take it); InputError naming the unknown one and the known ones.
std::vector<GapEffect> parse_gap_families(const std::string& list);

/// The strengths of a comma-separated list ("2,4,8"): positive decimal numbers (no "inf", no
/// hex); InputError naming the bad one.
std::vector<double> parse_gap_strengths(const std::string& list);

}  // namespace gmwm::gap
