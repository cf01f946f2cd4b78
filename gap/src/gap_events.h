#pragma once
// Time-domain effects of the gap diagnosis (docs/gap.md, method note 3, table), internal to gap.cc:
//
// STEP / TRANSIENT: a bias step at an unknown time has the WV of a random walk
// (shrinking as 1/N), and a warm-up transient a exp(-t/T) a hump that shrinks alike; the
// WV cannot tell them from a re-sized random walk. Their coefficients can: a step puts
// all of a coarse level's excess into the 2^j coefficients around it (a triangle of peak
// size/2), where a random walk spreads it over the record. The test statistic per level
// is the concentration c_j = log(max_t W_{j,t}^2 / mean_t W_{j,t}^2) (scale-free, so a
// re-sized baseline does not move it), standardised by its mean and spread over the
// baseline's reference replicates; the event statistic is the largest standardised c_j
// over the event levels, calibrated against the same maximum over the replicates (a
// Gumbel law matched to their moments: the maximum of many weakly dependent terms).
// The event is located by the matched filter (the coefficient of largest magnitude at
// the most concentrated level), refined by a two-mean least-squares split around it; an
// event at the record's start is a TRANSIENT when a exp(-t/T) fits the start better than
// a step does.
//
// STEP scan (docs/gap.md, "The step scan"): the concentration looks at one level at a
// time, and a small step spreads its evidence over several (a/2 in the centred coefficient
// of every level). The scan combines them as the generalised likelihood ratio of a step at
// t0 restricted to the centred Haar coefficients W_j(t0) of the event levels: with Sigma
// their covariance under the baseline (from its generalised autocovariance) and s = (1/2,
// ..., 1/2) the step's signature, z(t0) = s' Sigma^-1 W(t0) / sqrt(s' Sigma^-1 s), N(0, 1)
// under the baseline and N(a sqrt(s' Sigma^-1 s), 1) with a step a at t0. On the
// self-check's base (WN 1e-4 + RW 1e-10, N = 2^18) its non-centrality is 99.0% of the exact
// GLR's on the whole series (the local-level filter's: z per unit step 2224.6 against
// 2236.1). Each level's coefficients are centred first (a drift's are a constant), and z is
// divided by its RMS over the record away from its maximum where that RMS exceeds 1, so that
// a baseline quieter than the data does not make a step of its noise: the statistic is
// max_t |z(t)| / max(1, RMS). A baseline noisier than the data (RMS < 1) is not scaled up:
// it can only hide a step, never invent one, and z's RMS has few degrees of freedom (z is
// smooth over the coarsest filter), so dividing by it always widened the null law of the
// maximum like a t's (0.625% quantile 5.05 against the oracle's 4.79; with the floor 4.80),
// which cost the scan 17 points of power at 0.85 of the oracle's 90% size (issue 43, item
// 5). It is calibrated on the baseline's replicates at the record's length, by the law of a
// scan's maximum fitted to their maxima (gap_events.cc, scan_max_quantile).
//
// TEMPERATURE: with a temperature channel, the coupling k of the signal to it, pooled
// over levels from the wavelet covariances (weights 1 / nu_j(baseline)):
//   k = sum_j cov_j(x, T) / nu_j  /  sum_j var_j(T) / nu_j,
// calibrated by the replicates (series of the baseline, independent of the temperature by
// construction, give k's null distribution conditionally on the recorded temperature).
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/model.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

/// Event levels: from kEventMinLevel (coarser than the finest levels where spikes show,
/// docs/gap.md, method note 3: robust/classical ratio at tau = 2..8) to the deepest level with at least
/// kEventMinBlocks filter lengths in the record.
inline constexpr int kEventMinLevel = 5;
inline constexpr int kEventMinBlocks = 16;
/// DR: the drift's slope from the means of the record's first and last 1/kTrendSegments
/// (close to the most powerful test of a drift in white noise plus a random walk, whose
/// end-segment means average the white noise away while the random walk's displacement
/// over the record bounds any estimator; see bench_gap's oracle bound).
inline constexpr int kTrendSegments = 16;

/// (mean of the last n/kTrendSegments samples - mean of the first) / (n - n/kTrendSegments).
double trend_slope(const std::vector<double>& x);

/// The levels [first, last] (1-based) of the event statistic for a series of length n,
/// or first > last when the series is too short.
std::pair<int, int> event_levels(std::int64_t n);

/// g(h), h = 0..size-1: the model's generalised autocovariance, summed over its components.
std::vector<double> autocovariance(const Model& m, const Eigen::VectorXd& theta, std::size_t size);

/// The step scan's weights for the baseline at a record length (see the header comment).
/// For k = 1..L, the first k event levels (those whose filters fit around t0: near the
/// record's ends the coarse ones do not): the weight of each level's centred coefficient
/// in z(t0), Sigma_k^-1 s_k / sqrt(nc_k), and 1 / sqrt(nc_k), which turns z(t0) into the
/// jump's best linear unbiased estimate. Empty (not usable) when the record has no event
/// level or the baseline gives the coefficients no positive-definite covariance.
struct StepScan {
  int first = 0, last = -1;  ///< the event levels (1-based)
  std::vector<std::vector<double>> weight;
  std::vector<double> size_per_z;
  bool usable() const { return !weight.empty(); }
};
StepScan make_step_scan(const Model& m, const Eigen::VectorXd& theta, std::int64_t n);

/// The least scale the scan's maximum is divided by: z is N(0, 1) at each t under the
/// baseline, so its RMS is 1 when the baseline is right; only a larger one (data noisier than
/// the baseline) rescales the statistic (see the header comment).
inline constexpr double kStepScaleFloor = 1.0;

/// The (1 - level) quantile of a Gumbel law matched to the sample's mean and variance (the
/// concentration's null maximum over the replicates).
double gumbel_quantile(const Eigen::VectorXd& sample, double level);
/// The (1 - level) quantile of the law of a scan's maximum, exp(-C b^a phi(b)), fitted to
/// the replicates' maxima by maximum likelihood (gap_step_scan.cc; the Gumbel law when the
/// fit has no finite likelihood).
double scan_max_quantile(const Eigen::VectorXd& sample, double level);

/// The scan of one series.
struct StepScanResult {
  double statistic =
      0.0;           ///< max_t |z(t)| / max(kStepScaleFloor, the RMS of z more than half the coarsest filter away)
  double rms = 0.0;  ///< that RMS (z is N(0, 1) at each t under the baseline)
  std::int64_t sample = 0;    ///< where |z| peaks: the first sample after the jump
  double size = 0.0;          ///< the jump there (data units)
  int level = 0;              ///< the level contributing most to z there (1-based)
  std::vector<double> share;  ///< per event level: its contribution to z there / the largest one
};
/// The scan of the series whose transform is `modwt` (it reads the transform's prefix sums).
StepScanResult scan_step(const HaarModwt& modwt, const StepScan& scan);
/// The same of a series without its transform (one is built).
StepScanResult scan_step(const std::vector<double>& x, const StepScan& scan);

/// An event band from the step scan: the run of event levels around the one contributing
/// most whose contribution is at least this share of it (the self-check's dominant-scale
/// rule, gap/src/gap_check.cc kDominantShare).
inline constexpr double kStepBandShare = 0.5;

/// Per-series statistics shared by the data and every reference replicate: the event
/// levels' concentrations c_j, the step scan's statistic, the trend slope, then (with a
/// temperature channel) the coupling k. `modwt` is x's Haar transform; it keeps every
/// level's squares (HaarModwt::keep_squares, one shared pass), so a WV computed from it
/// afterwards reads them instead of a pass per level. `details`, when given, gets the
/// whole scan.
Eigen::VectorXd series_statistics(const std::vector<double>& x, HaarModwt& modwt,
                                  const std::vector<double>* temperature, const Eigen::VectorXd& nu_base,
                                  const StepScan& scan, StepScanResult* details = nullptr);

/// Calibrated tests on the data's statistics against the replicates' (rows of `reps`).
struct TimeEffectTests {
  // Event.
  bool event_tested = false;
  double event_statistic = 0.0, event_threshold = 0.0;
  int event_level = 0;          ///< 1-based, the most concentrated level
  std::vector<double> event_z;  ///< per event level
  int first_event_level = 0;
  // Step scan.
  bool step_tested = false;
  double step_statistic = 0.0, step_threshold = 0.0;
  // Trend (DR).
  double trend = 0.0, trend_mean = 0.0, trend_sd = 0.0, trend_z = 0.0, trend_threshold = 0.0;
  // Temperature.
  bool coupling_tested = false;
  double coupling = 0.0, coupling_sd = 0.0, coupling_z = 0.0, coupling_threshold = 0.0;
};

TimeEffectTests test_time_effects(const Eigen::VectorXd& data_stats, const Eigen::MatrixXd& reps, std::int64_t n,
                                  bool with_temperature, double level);

/// Locates the event at `level` (1-based) in x and estimates it: STEP (sample, size) or,
/// when it sits at the record's start and an exponential decay fits better, TRANSIENT
/// (amplitude, time constant in samples). Returns the event with effect, sample, size,
/// time_constant filled (seconds left to the caller).
GapEvent locate_event(const std::vector<double>& x, int level);
/// The same from the step scan: the sample where |z| peaks and the jump's estimate there,
/// at the level contributing most; TRANSIENT as above when it sits at the record's start.
GapEvent locate_event(const std::vector<double>& x, const StepScan& scan);

/// Whether a located STEP persists: a step of size a puts a/2 into the Haar coefficient
/// centred on it at every coarser level, a burst (a short excursion that returns, area A)
/// only A / 2^k. Over the kPersistLevels levels above the event's that fit in the
/// record, the coefficients are compared with both (squared distances weighted by the
/// data's WV, the coefficient's variance): true when they lie nearer a/2 than 0, or when
/// no coarser level fits.
inline constexpr int kPersistLevels = 4;
bool step_persists(const std::vector<double>& x, const GapEvent& step, const Eigen::VectorXd& nuhat);
/// A burst: samples near a located STEP that depart from the local level by more than
/// kBurstZ robust standard deviations and span at most half the event's scale (a shock
/// that returns where it started also concentrates one level's coefficients, and a
/// two-mean split across it reads a step that the record's longer means do not show).
/// The robust scale is the MAD of the first differences (/ sqrt 2) over the event's
/// window, the level its median. nullopt when no such samples are found.
/// kBurstZ: Hampel's rule flags |x - median| > 3 MADs; 5 keeps the chance of a flagged
/// Gaussian sample in a 2^13-sample window below 1%.
inline constexpr double kBurstZ = 5.0;
std::optional<GapEvent> burst_alternative(const std::vector<double>& x, const GapEvent& step);
/// x minus the event's signal (a step from `sample` on, a exp(-t/T), or a burst's
/// samples replaced by the local level).
void remove_event(std::vector<double>& x, const GapEvent& e);

/// What the time-domain tests found on the data.
/// The standard deviation of trend_slope on n samples of a model, exact: the slope is a
/// zero-sum filter of the series (the last n/kTrendSegments samples' mean less the
/// first's, over n - L), so its variance follows from the model's generalised
/// autocovariance (Process::generalized_autocovariance; a random walk's included).
/// O(n) time and memory.
double trend_slope_sd(const Model& m, const Eigen::VectorXd& theta, std::int64_t n);

struct TimeFindings {
  bool event = false, coupling = false, trend = false;
  /// The event was found by the step scan (it then locates it), else by the concentration.
  bool step = false;
  std::shared_ptr<const StepScan> scan;
  StepScanResult step_scan;
  double trend_null_mean = 0.0, trend_null_sd = 0.0, trend_level_z = 0.0;  ///< to re-test after the event
  double ci_z = 0.0;                                                       ///< z of the 1 - alpha intervals
  int event_level = 0;
  double event_statistic = 0.0, event_threshold = 0.0;
  std::vector<double> event_z;
  int first_event_level = 0;
};

/// Runs the tests at `level` (the concentration's, the step scan's and the coupling's) and
/// records them in `g` (event_tested/statistic/threshold, step_scan_*; temperature with its
/// 1 - alpha interval).
TimeFindings run_time_tests(const std::vector<double>& x, const std::vector<double>* temperature,
                            const Eigen::VectorXd& nu_base, std::shared_ptr<const StepScan> scan,
                            const Eigen::MatrixXd& reps, double level, double alpha, GapResult& g);

/// The gap band of a significant event when the WV shows none: the run of event levels
/// around the most concentrated one whose standardised concentration clears the threshold
/// (found by the step scan: around the level contributing most, kStepBandShare).
std::vector<GapBand> event_bands(const TimeFindings& f, const std::vector<GapLevel>& levels);

/// The bands with the located event's band merged in (overlapping excess bands joined):
/// the event levels whose concentration clears the threshold, for a STEP up to the
/// coarsest level (its WV excess over the baseline grows with the scale there: a random
/// walk's signature, shrinking as 1 / M_j).
std::vector<GapBand> merge_event_band(const std::vector<GapBand>& bands, const TimeFindings& f,
                                      const std::vector<GapLevel>& levels, GapEffect effect);

/// A copy of x corrected for the significant effects (the temperature coupling first, then
/// the located event, then the trend, re-tested once the event is gone: a step moves the
/// end-segment means too), each recorded in g (steps, event, trend, notes).
/// `event`, when given, replaces the located one (the burst alternative to a step).
std::vector<double> apply_time_effects(const std::vector<double>& x, const std::vector<double>* temperature,
                                       const TimeFindings& f, GapResult& g, const GapEvent* event = nullptr);

}  // namespace gmwm::gap::detail
