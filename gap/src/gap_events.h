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
// TEMPERATURE: with a temperature channel, the coupling k of the signal to it, pooled
// over levels from the wavelet covariances (weights 1 / nu_j(baseline)):
//   k = sum_j cov_j(x, T) / nu_j  /  sum_j var_j(T) / nu_j,
// calibrated by the replicates (series of the baseline, independent of the temperature by
// construction, give k's null distribution conditionally on the recorded temperature).
#include <cstdint>
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

/// Per-series statistics shared by the data and every reference replicate: the event
/// levels' concentrations c_j, the trend slope, then (with a temperature channel) the
/// coupling k. `modwt` is x's Haar transform; it keeps the event levels' squares
/// (HaarModwt::keep_squares), so a WV computed from it afterwards reuses them.
Eigen::VectorXd series_statistics(const std::vector<double>& x, HaarModwt& modwt,
                                  const std::vector<double>* temperature, const Eigen::VectorXd& nu_base);

/// Calibrated tests on the data's statistics against the replicates' (rows of `reps`).
struct TimeEffectTests {
  // Event.
  bool event_tested = false;
  double event_statistic = 0.0, event_threshold = 0.0;
  int event_level = 0;          ///< 1-based, the most concentrated level
  std::vector<double> event_z;  ///< per event level
  int first_event_level = 0;
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
  double trend_null_mean = 0.0, trend_null_sd = 0.0, trend_level_z = 0.0;  ///< to re-test after the event
  double ci_z = 0.0;                                                       ///< z of the 1 - alpha intervals
  int event_level = 0;
  double event_statistic = 0.0, event_threshold = 0.0;
  std::vector<double> event_z;
  int first_event_level = 0;
};

/// Runs the tests at `level` (the event's and the coupling's) and records them in `g`
/// (event_tested/statistic/threshold; temperature with its 1 - alpha interval).
TimeFindings run_time_tests(const std::vector<double>& x, const std::vector<double>* temperature,
                            const Eigen::VectorXd& nu_base, const Eigen::MatrixXd& reps, double level, double alpha,
                            GapResult& g);

/// The gap band of a significant event when the WV shows none: the run of event levels
/// around the most concentrated one whose standardised concentration clears the threshold.
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
