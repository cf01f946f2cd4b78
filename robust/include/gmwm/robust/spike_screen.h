#pragma once
// Spike screen: isolated spikes and short glitches found at the finest scale and
// replaced before the robust WV is computed.
//
// Why: the per-level M-estimator bounds a spike's influence only where the spike is an
// outlier among the level's coefficients. A spike of m white-noise standard deviations
// adds (m / tau_j)^2 to tau_j coefficients of level j: at the fine levels a few gross
// outliers (clipped), at coarse levels a mild excess in a large share of the windows,
// which no scale M-estimator can tell from the signal. Spikes at a rate p then leave
// the robust WV with a non-white excess (0 at fine levels, up to p m^2 / tau_j at coarse
// ones) that a fit blames on its coloured processes (issue 3's contamination study:
// AR1 sigma2 78% off). Removing the spikes themselves, where they are visible, leaves
// every level clean.
//
// How: the level-1 Haar coefficients W_t = (x_t - x_{t-1}) / 2 are the jumps of the
// series. Jumps beyond kSpikeThreshold robust standard deviations (the level's robust
// scale, same estimator and tuning) are flagged; flagged jumps closer than
// kSpikeMaxGap samples form a cluster, and a cluster of two or more jumps (up then down:
// a spike, a glitch of a few samples, a burst) has its samples, from the first jump to
// the one before the last, replaced by the straight line between robust anchors on
// each side (medians of kAnchorSamples samples).
// A lone jump is a step, not a spike, and is left alone. On Gaussian data a flag has
// probability 5.7e-7 per coefficient, and a cluster needs two within 16 samples: about
// 1e-11 per sample, none in any record.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace gmwm::robust {

/// Flag threshold, in robust standard deviations of the level-1 coefficients: a spike
/// of m white-noise sd makes a level-1 z-score of ~m / sqrt(2), so spikes from ~7 sd on
/// are replaced (issue 3's 20-sd spikes: 14).
inline constexpr double kSpikeThreshold = 5.0;
/// Flagged jumps at most this many samples apart belong to one cluster (a glitch of up
/// to 16 samples; two independent spikes this close merge, and the clean samples
/// between them are interpolated too, which costs nothing measurable).
inline constexpr std::int64_t kSpikeMaxGap = 16;

/// A replaced range is a line between the medians of this many samples on each side.
inline constexpr std::int64_t kAnchorSamples = 8;

struct SpikeScreen {
  bool applied = false;                                       ///< false when the level-1 robust scale is undefined
  double scale = 0.0;                                         ///< robust variance of the level-1 coefficients
  std::vector<std::pair<std::int64_t, std::int64_t>> ranges;  ///< replaced samples, [first, last]
  std::int64_t samples = 0;                                   ///< total replaced
  std::string note;                                           ///< one sentence for the output
};

/// The level-1 jumps W_t = (x_t - x_{t-1}) / 2, t = 1..n-1 (exactly 0 on repeated
/// values of quantized data).
std::vector<double> level_one_jumps(const double* x, std::int64_t n);
/// The same into `out` (resized to n - 1): a buffer the caller reuses, whose pages are
/// already there (a fresh 8 MB vector is mostly page faults and zeroing).
void level_one_jumps(const double* x, std::int64_t n, std::vector<double>& out);

/// Finds the spike ranges of x (n >= 2), given the robust variance of its level-1 jumps
/// (NaN or <= 0: not applied, with a note saying so).
SpikeScreen screen_spikes(const double* x, std::int64_t n, double level_one_scale);

/// "spike screen: N samples in R ranges replaced by interpolation (clusters of ...)": an
/// applied screen's note, from its ranges and samples.
std::string describe_screen(const SpikeScreen& screen);

/// x with each range replaced by the straight line between the medians of the
/// kAnchorSamples samples on each side (a range at an end takes the one side's median).
std::vector<double> replace_ranges(const double* x, std::int64_t n,
                                   const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges);

}  // namespace gmwm::robust
