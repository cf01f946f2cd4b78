#pragma once
// Sim-to-real gap diagnosis (docs/gap.md): where a baseline noise model (a simulator's
// configuration or a fitted model) departs from a real signal's WV, which unmodelled
// effect explains the departure, and how much of it that effect removes.
//
//   gmwm::gap::GapOptions o;                       // 200-replicate reference
//   auto g = gmwm::gap::diagnose_gap(wv, baseline, theta, o);
//   g.detected, g.bands, g.effect, g.shrinkage.excess_removed
//
// Locate (docs/gap.md, method note 2): B series simulated from the baseline at the data's length, their
// WV by the same estimator, give per level the mean m_j and spread s_j of log nuhat and
// their covariance. Per level: the ratio nuhat_j / nu_j(baseline) and
// z_j = (log nuhat_j - m_j) / s_j. Global test: the Mahalanobis distance of log nuhat from
// the reference, against its distribution over held-out replicates. Gap bands: runs of
// levels with |z_j| above the Bonferroni threshold z_{1 - alpha / (2J)} and a practical
// effect size |ratio - 1| > min_effect.
//
// Attribute (docs/gap.md, method note 3): each candidate effect is fitted on top of the baseline (the
// baseline fixed, or re-estimated with it when `refit_baseline`), and scored by its drop
// in the objective G = (nuhat - nu)' Omega (nuhat - nu), Omega = diag(1 / Var*(nuhat_j))
// from the reference replicates. The drop is calibrated: its threshold is the
// (1 - alpha / K) quantile of the drops the same candidate achieves on the reference
// replicates (data from the baseline alone), K the number of candidates; a candidate
// "clears" when its drop exceeds its threshold, and the cleared candidates rank by
// drop / threshold. REPARAMETERISE (the baseline's own terms re-estimated) is a
// candidate too, and wins whenever the re-estimated baseline alone leaves no gap.
// OUTLIERS is decided from the robust-vs-classical comparison at the finest levels
// (robust/contamination.h, calibrated against the data's rounding). Forward stepwise
// until nothing clears or max_steps effects were added.

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::gap {

/// The effects a gap can be attributed to (docs/cli.md, JSON "attribution.effect").
enum class GapEffect {
  kNone,
  kWN,
  kQN,
  kRW,
  kDR,
  kAR1,
  kFlicker,
  kSin,
  kOutliers,
  kStep,
  kTransient,
  kTemperature,
  kReparameterise,
};
const char* to_string(GapEffect e);
/// The effect named as to_string writes it ("STEP", "SIN", ...), or nullopt.
std::optional<GapEffect> parse_gap_effect(const std::string& name);

/// The effects the WV attribution can add (GapOptions::candidates), in the order tried:
/// WN, QN, RW, DR, AR1, FLICKER, SIN, REPARAMETERISE.
std::vector<GapEffect> wv_candidate_effects();
/// The candidates of a comma-separated list ("DR,AR1", as `gap --effects` and Python's
/// gap(effects=) take it); InputError "<option> '<list>': unknown effect ..." naming the
/// bad entry and the known ones.
std::vector<GapEffect> parse_gap_candidates(const std::string& list, const std::string& option);

/// The range of GapOptions::replicates: fewer than 20 leave each level's band too coarse; the
/// upper bound keeps the reference's memory (replicates x levels) bounded.
inline constexpr int kMinGapReplicates = 20;
inline constexpr int kMaxGapReplicates = 100000;

/// The fewest replicates whose global test can reject at `alpha`: half of them are its null
/// sample, so its smallest p-value is 1 / (1 + replicates / 2) (40 at alpha = 0.05). Fewer
/// would say "no gap" whatever the data (alpha in (0, 0.5)).
std::int64_t min_gap_replicates(double alpha);

/// Reference distributions kept for reuse by several diagnoses (opaque). Diagnoses handed
/// the same cache draw one reference for each distinct (baseline and its values, record
/// length, levels, replicates, seed, replicate estimator, temperature channel) instead of
/// one each: `gmwm gap` shares one across the columns of a file, so the three axes of a
/// sensor kind under a config's baseline simulate their reference once. The cached
/// reference is the one the diagnosis would have drawn: results are unchanged by it.
/// Safe to share between threads.
class ReferenceCache;
std::shared_ptr<ReferenceCache> make_reference_cache();
/// How many references `cache` holds (each simulated once).
std::size_t cached_references(const ReferenceCache& cache);

struct GapOptions {
  /// Reference replicates (docs/gap.md, method note 2; issue 5 asks for 200).
  int replicates = 200;
  std::uint64_t seed = 0;
  /// Level of the global test, of the gap bands (Bonferroni over levels) and of the
  /// candidates' thresholds (Bonferroni over candidates).
  double alpha = 0.05;
  /// Practical effect size of a gap band: |ratio - 1| above this (docs/gap.md, method note 2: 10%).
  double min_effect = 0.10;
  /// WV estimator of the simulated replicates (nullptr: classical).
  const WvEstimator* estimator = nullptr;
  /// --fit mode: the baseline is a fitted family, re-estimated together with each effect.
  bool refit_baseline = false;
  /// The effects tried (those with a WV signature); empty = all of them.
  std::vector<GapEffect> candidates;
  /// Forward-stepwise limit (steps that change the model: WV effects and REPARAMETERISE).
  int max_steps = 3;
  /// A band of levels decides detection only when one of its levels has at least this
  /// many effective coefficients (eta_j = M_j / 2^j): at the coarsest levels one or two
  /// coefficients make a chi-square with one or two degrees of freedom, whose spread
  /// (a factor 1000 between its 2.5% and 97.5% points) says nothing on its own.
  double min_deciding_coefficients = 4.0;
  /// Fit settings of the candidates (omega_matrix, starts, inference set per fit).
  FitOptions fit;
  /// The signal's sampling rate, for the candidates' display units (SIN's f in Hz).
  ProcessContext context;
  /// The data's unit for display ("deg/s"): STEP sizes, DR rates and burst peaks carry it
  /// in the step texts and the headline; empty: "data units".
  std::string unit;
  /// Called with (replicates done, total) while the reference is simulated, then again
  /// with (total, total) before each fit of the attribution; may throw gmwm::Cancelled to
  /// stop the diagnosis (error.h).
  std::function<void(int, int)> progress;
  /// Where references are kept for other diagnoses (make_reference_cache); null: each
  /// diagnosis simulates its own.
  std::shared_ptr<ReferenceCache> references;
  /// The record's missing samples (grid positions, as classical_wv_with_gaps reads them;
  /// issue 47): the WV compared is then the one from the windows without a gap, `x` holds
  /// the observed samples, the reference's replicates are read through the same gaps and the
  /// contamination screen counts among the same windows. The stages that read a regular
  /// series (the time-window map, the split halves, STEP, TRANSIENT, the trend and
  /// TEMPERATURE) are not run, and a note says so.
  std::vector<MissingRun> missing;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// Per level: the data against the baseline's reference.
struct GapLevel {
  double tau = 0.0;                      ///< samples
  double ratio = 1.0;                    ///< nuhat_j / nu_j(baseline), variances
  double z = 0.0;                        ///< (log nuhat_j - m_j) / s_j
  double ref_low = 0.0, ref_high = 0.0;  ///< pointwise 1 - alpha reference band of nuhat_j (bootstrap)
  /// The closed-form band: nu_j(baseline) q_{a/2, 1-a/2}(eta_j) / eta_j, eta_j = max(M_j / 2^j, 1)
  /// (the chi-square approximation of the WV's CIs; the bootstrap band is the one used).
  double analytic_low = 0.0, analytic_high = 0.0;
  bool outside = false;  ///< nuhat_j outside [ref_low, ref_high]
};

struct GapBand {
  int first_level = 0, last_level = 0;  ///< levels (tau = 2^level samples), inclusive
  double tau_from = 0.0, tau_to = 0.0;  ///< samples
  std::string direction;                ///< "excess" or "deficit"
  double peak_ratio = 1.0;              ///< the ratio farthest from 1 within the band
};

/// One candidate's score at one forward step.
struct GapCandidate {
  GapEffect effect = GapEffect::kNone;
  std::string model;         ///< what was added (canonical, with values), or the refitted baseline
  double improvement = 0.0;  ///< drop in G
  double threshold = 0.0;    ///< calibrated (1 - alpha/K) null quantile of the drop
  /// WVIC confirmation (docs/gap.md, method note 3): the candidate's optimism is its mean drop on data
  /// without it (the in-sample gain a parametric bootstrap of WVIC estimates), and WVIC
  /// prefers the augmented model when the drop exceeds twice that.
  double optimism = 0.0;
  bool wvic_confirmed = false;
  bool cleared = false;  ///< drop > threshold and WVIC confirms
  FitResult fit;         ///< the augmented model's fit (no inference)
};

struct GapShrinkage {
  double objective_before = 0.0, objective_after = 0.0;
  /// E_m[G] = sum_j omega_j Var_m(nuhat_j): G's mean on data from the model itself
  /// (the reference replicates rescaled to it), for the baseline and the final model.
  double null_mean = 0.0, null_mean_after = 0.0;
  /// The global test's statistic D (squared Mahalanobis distance of log nuhat from the
  /// model's reference) for the baseline and the final model, and its mean over the
  /// held-out null replicates (the same for every model: the reference is shifted).
  double distance_before = 0.0, distance_after = 0.0, null_distance_mean = 0.0;
  /// The excess of the baseline and of the final model over their null means,
  /// X = max(G - E_m[G], 0), G on the data the diagnosis compares at each stage.
  double excess_before = 0.0, excess_after = 0.0;
  /// The share of the gap removed, S = (X_before - X_after) / X_before (0 when the
  /// baseline has no excess), in [0, 1] by construction: every kept step lowers
  /// G - E_m[G]. S = 1 means the final model fits the data as well as a typical replicate
  /// of itself fits its own WV; it does not mean every level is inside its band.
  double excess_removed = 0.0;
  double rms_log_ratio_before = 0.0, rms_log_ratio_after = 0.0;  ///< over the gap bands' levels
  int levels_outside_before = 0, levels_outside_after = 0;
  double p_value_before = 1.0, p_value_after = 1.0;  ///< global test
};

/// A time window whose WV at one level departs from the record's typical window (the
/// median over windows, with the spread of the baseline's same-length reference):
/// non-stationarity such as warm-up, steps, bursts (docs/gap.md, method note 2).
struct GapWindow {
  std::int64_t first_sample = 0, last_sample = 0;  ///< inclusive, 0-based
  double tau = 0.0;                                ///< samples
  double ratio = 1.0;                              ///< window WV / the median window's at that level
  double z = 0.0;
};

/// A time-local effect found in the series by the coarse-level matched filter (STEP, or
/// TRANSIENT when it sits at the record's start and a exp(-t/T) fits it better).
struct GapEvent {
  GapEffect effect = GapEffect::kNone;
  std::int64_t sample = 0;     ///< STEP: the first sample after the jump; TRANSIENT: 0
  double size = 0.0;           ///< STEP: the jump; TRANSIENT: the amplitude a (data units)
  double time_constant = 0.0;  ///< TRANSIENT: T in samples
  /// OUTLIERS (a burst: a short excursion that returns to the level it left, e.g. a
  /// shock): `sample` is its first sample, `length` its samples, `size` its largest
  /// departure and `fill` the local level they are replaced by.
  std::int64_t length = 0;
  double fill = 0.0;
  int level = 0;                            ///< the level where its coefficients concentrate most (1-based)
  double statistic = 0.0, threshold = 0.0;  ///< calibrated concentration test
};

/// The signal's coupling to a temperature channel (data units per temperature unit).
struct GapCoupling {
  double k = 0.0, ci_low = 0.0, ci_high = 0.0;  ///< estimate and 1 - alpha interval
  double z = 0.0, threshold = 0.0;              ///< against the baseline's replicates
  bool significant = false;
};

/// docs/gap.md, method note 4: "what it means for navigation (predicted integrated error growth, e.g.
/// attitude error after 60 s)".
inline constexpr double kNavigationHorizonSeconds = 60.0;

/// The integral of the noise over the horizon (attitude error for a gyro, velocity error
/// for an accelerometer, in data units x s): RMS under the baseline and under the final
/// model (engine/integrated_error.h). NaN when the sampling rate is unknown.
struct GapNavigation {
  double horizon_seconds = kNavigationHorizonSeconds;
  double rms_without = std::numeric_limits<double>::quiet_NaN();
  double rms_with = std::numeric_limits<double>::quiet_NaN();
};

/// The record's linear trend (DR found in the time domain): slope per sample.
struct GapTrend {
  double omega = 0.0, ci_low = 0.0, ci_high = 0.0;  ///< data units per sample
  double z = 0.0, threshold = 0.0;                  ///< against the baseline's replicates
  bool significant = false;
};

/// The split-half check (docs/gap.md, method note 2): the two halves' WVs per level; they must agree
/// within their chi-square CIs on a stationary record.
struct GapSplitHalf {
  double tau = 0.0;       ///< samples
  double ratio = 1.0;     ///< second half's WV / first half's
  bool disjoint = false;  ///< the two halves' 1 - alpha CIs do not overlap
};

/// How a model with values fits the data the diagnosis ended on (the WV after OUTLIERS and
/// the time-domain corrections), on the diagnosis' own yardstick: its objective and the
/// reference shifted to the model.
struct GapAssessment {
  double objective = 0.0;
  double null_mean = 0.0;  ///< E_m[G] on data from the model itself
  int levels_outside = 0;
  double p_value = 1.0;            ///< global test
  std::vector<GapBand> remaining;  ///< deciding runs of levels outside the model's band
  /// RMS of the integrated noise over kNavigationHorizonSeconds (NaN: rate unknown).
  double navigation_rms = std::numeric_limits<double>::quiet_NaN();
};

/// Assesses other models against one diagnosis' data and reference (a corrected simulator
/// configuration, say); kept by GapResult::assessor. Thread-safe (const).
class GapAssessor {
 public:
  virtual ~GapAssessor() = default;
  /// Throws InputError for a theta that does not validate for the model.
  virtual GapAssessment assess(const Model& model, const Eigen::VectorXd& theta) const = 0;
};

struct GapResult {
  Model baseline;
  Eigen::VectorXd baseline_theta;
  /// The first level compared (tau = 2^first_level samples): 1, or the first level of a WV
  /// that drop_fine_levels cut (the finer scales smoothed by held or interpolated samples).
  /// `levels` and `levels_after` start there; bands and contaminated_levels name levels,
  /// so level l's entry is levels[l - first_level].
  int first_level = 1;
  std::vector<GapLevel> levels;
  double statistic = 0.0;  ///< Mahalanobis distance of log nuhat from the reference
  double p_value = 1.0;    ///< global test
  bool detected = false;   ///< p_value < alpha and at least one gap band
  std::vector<GapBand> bands;
  /// Sliding-window map: only the (window, level) cells beyond the Bonferroni threshold
  /// over all cells and the effect size; empty when none, and when the series is too
  /// short for kMinWindows windows (windows_checked false).
  std::vector<GapWindow> windows;
  bool windows_checked = false;
  std::int64_t window_length = 0;
  /// The split-half check (empty without the series or when a half is too short).
  std::vector<GapSplitHalf> split_half;
  GapEffect effect = GapEffect::kNone;  ///< the first step's attribution
  std::vector<GapEffect> steps;         ///< every effect added, in order
  /// Each step in a few words, in the order of `steps`: "AR1 with correlation time 10.7 s",
  /// "DR of -2.7e-07 per s", "STEP of 0.012 at 7049 s" (seconds when the rate is known).
  std::vector<std::string> step_details;
  std::vector<GapCandidate> candidates;  ///< the first step's scores
  Model final_model;                     ///< baseline + the effects added (values)
  Eigen::VectorXd final_theta;
  /// The first added effect's fit; its se / ci_low / ci_high are parametric-bootstrap
  /// intervals (percentile, level 1 - alpha) from the reference replicates rescaled to the
  /// augmented model. Failed when no process effect was added.
  FitResult final_fit;
  GapShrinkage shrinkage;
  GapNavigation navigation;
  /// Time-domain effects (need the series): the concentration test's outcome, the event
  /// when it is significant, and the temperature coupling when a channel was given.
  bool event_tested = false;
  double event_statistic = 0.0, event_threshold = 0.0;
  /// The step scan (docs/gap.md, "The step scan"): max_t |z(t)| / RMS against its threshold
  /// (the baseline's replicates at the event's level), and the sample where |z| peaks.
  bool step_scan_tested = false;
  double step_scan_statistic = 0.0, step_scan_threshold = 0.0;
  std::int64_t step_scan_sample = 0;
  std::optional<GapEvent> event;
  std::optional<GapCoupling> temperature;
  std::optional<GapTrend> trend;
  /// What each step removed: G before it minus G after it, in the order of `steps`.
  /// `effect` is the first step, except that a time-domain DR, STEP or TRANSIENT yields
  /// to a later non-REPARAMETERISE step that removed more.
  std::vector<double> step_drops;
  /// The model's excess X after each step, and each step's share: REPARAMETERISE's of the
  /// baseline's excess X_before, every other step's of the excess the re-sizing leaves
  /// (X_before less REPARAMETERISE's drop; X_before when none was taken); NaN when that
  /// excess is 0. In the order of `steps`.
  std::vector<double> step_excess, step_shares;
  std::vector<std::string> notes;  ///< e.g. why OUTLIERS, REPARAMETERISE or nothing
  /// The contamination screen (with the robust WV and the series): the levels (tau = 2^level
  /// samples) whose robust WV sits below the classical one beyond what the data's rounding
  /// explains, with an excess of far outliers (robust/contamination.h); empty when clean
  /// or not screened.
  std::vector<int> contaminated_levels;
  bool contamination_screened = false;
  /// The levels' map against the final model (its reference shifted to it).
  std::vector<GapLevel> levels_after;
  /// Where the final model still misses: runs of levels outside its reference band that
  /// decide (enough coefficients); empty when the gap is closed.
  std::vector<GapBand> remaining;
  /// No gap left: nothing detected, or the final model is no longer rejected by the
  /// global test and no deciding level remains outside its band.
  bool closed = true;
  /// Effects tried and refused because they did not make the fit better on the data
  /// (objective not lower, or more levels outside), e.g. "SIN (objective 16.3 -> 2.1e6)".
  std::vector<std::string> refused;
  /// The yardstick of this diagnosis, for other models (set by diagnose_gap).
  std::shared_ptr<const GapAssessor> assessor;
  /// One line: the bands, the effects added, levels outside before -> after, the global
  /// p after, "gap remains at SCALES" while the final model is still rejected, and the
  /// share of the excess removed. Scales in seconds when the rate is known.
  std::string headline;
};

/// The diagnosis of one signal. `wv` is the data's classical WV; `robust` (optional) its
/// robust WV for the OUTLIERS check together with `x` (the series, for the
/// rounding-calibrated contamination flags, the time-window map and the time-domain
/// effects STEP and TRANSIENT). `temperature` (optional, same length as x) adds the
/// TEMPERATURE effect. Throws InputError on invalid options, a baseline whose values are
/// missing or invalid, or a temperature channel of another length.
GapResult diagnose_gap(const WaveletVariance& wv, const Model& baseline, const Eigen::VectorXd& theta,
                       const GapOptions& options, const WaveletVariance* robust = nullptr,
                       const std::vector<double>* x = nullptr, const std::vector<double>* temperature = nullptr);

}  // namespace gmwm::gap
