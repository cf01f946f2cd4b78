#pragma once
// The classical Haar wavelet variance of a record with missing samples (issue 47, item 1):
// at each level the MODWT coefficients whose window of 2^j samples holds no missing sample
// enter the estimate, so a gap never puts a jump inside a coefficient (joining the samples
// end to end does: a random walk's level 1 is inflated by every join). The estimate at level
// j is the mean of the M_j complete windows' W_{j,t}^2, with the chi-square interval at
// eta_j = max(M_j / 2^j, 1) (Percival & Walden 2000, eq. 313c) of those M_j; the
// missing-data GMWM of Voirol et al. (2024, GMWMX) uses the same complete-support
// coefficients. Where complete windows are scarce (long levels), a level reads instead the
// windows whose halves each miss at most kAllanMaxMissingShare of their samples, each half
// averaged over its observed ones, when they at least double its windows (its note says
// so; M_j then counts them). Memory: 8 bytes an observed sample, however long the gaps. A
// record without missing samples gives classical_wv's values (to rounding: the sums are
// accumulated in another order).
//
//   std::vector<MissingRun> gaps = {{1000, 25}};   // grid samples 1000..1024 were not recorded
//   WaveletVariance w = classical_wv_with_gaps(observed, gaps);
//   w.coefficients[j - 1]   // windows read at level j; w.notes says how many were lost

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

/// Samples missing from a regular record: grid positions [start, start + length) (0-based,
/// on the grid of observed and missing samples together).
struct MissingRun {
  std::int64_t start = 0;
  std::int64_t length = 0;
};

/// "" when `missing` describes gaps of a grid holding `observed` samples (runs of at least
/// one sample, in increasing order, neither overlapping nor touching, inside the grid), else
/// one line naming the first run that does not.
std::string missing_runs_problem(std::int64_t observed, std::span<const MissingRun> missing);

/// The samples the runs miss (the sum of their lengths).
std::int64_t missing_samples(std::span<const MissingRun> missing);

/// The classical WV from the complete windows (near-complete ones where they at least double a
/// level's windows). `observed` holds the recorded samples in time order; `missing` places the
/// gaps between them. Levels 1..J, J = floor(log2 N) of the grid's N samples (or
/// options.levels, at most that); a level without a usable window is NaN with a note. Throws
/// InvalidArgument for bad runs (missing_runs_problem), fewer than kMinSeriesLength observed
/// samples or invalid options.
WaveletVariance classical_wv_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                       const WvOptions& options = {});

/// The levels 1..j of `wv` before the first without a usable window (coefficients > 0): the
/// fit reads consecutive levels. Usually the deepest ones lack windows (a complete window of
/// 2^(j+1) samples holds two of 2^j); a level whose halves may miss a sample can follow one
/// that has none (segments of 14 samples: level 4 none, level 5 some), and is dropped with it.
int complete_levels(const WaveletVariance& wv);

/// Keeps the levels 1..complete_levels(wv) (the deepest ones, NaN, go; their notes with
/// them): the WV a fit, a plot and a table read.
void drop_incomplete_levels(WaveletVariance& wv);

/// The windows one level of classical_wv_with_gaps reads.
struct GappyLevelWindows {
  std::int64_t complete = 0;  ///< windows without a missing sample
  std::int64_t used = 0;      ///< windows read: the complete ones, or the near-complete ones
  /// Below this a coefficient's magnitude is rounding error of the sums it is made of (a
  /// quantized record's coefficients of exactly zero): HaarModwt::noise_floor's bound.
  double noise_floor = 0.0;
};

/// The windows of a record with missing samples, level by level, as classical_wv_with_gaps
/// reads them: built once (prefix sums of the observed samples, 8 bytes each), then each
/// level's coefficients for another estimator of the same windows (the robust WV of a
/// record with gaps, robust::robust_wv_with_gaps; its contamination diagnostic). Reading
/// levels from several threads at once is safe.
class GappyWindows {
 public:
  /// Throws as classical_wv_with_gaps (bad runs, too few observed samples).
  GappyWindows(std::span<const double> observed, std::span<const MissingRun> missing);
  ~GappyWindows();
  GappyWindows(const GappyWindows&) = delete;
  GappyWindows& operator=(const GappyWindows&) = delete;

  /// Observed and missing samples together.
  std::int64_t grid() const;

  /// Into `out`, in time order, the Haar coefficient (mean of the window's second half -
  /// mean of its first) / 2 of each window level j reads (its complete windows, or the
  /// near-complete ones where they at least double them): their mean square is that level's
  /// classical WV. Empty when the level has no usable window or is longer than the grid.
  /// Throws InvalidArgument for j outside 1..62.
  GappyLevelWindows coefficients(int j, std::vector<double>& out) const;

 private:
  struct Sums;
  std::unique_ptr<const Sums> sums_;
};

/// The samples of a grid of n (observed and missing places together) that `missing` leaves,
/// in order: what a strategy object reads a simulated grid through. Throws InvalidArgument
/// "WHAT: the missing runs fill a grid of n samples" when nothing is left.
std::vector<double> observed_samples(const char* what, const double* x, std::int64_t n,
                                     std::span<const MissingRun> missing);

/// classical_wv_with_gaps as a strategy object: the bootstrap's and the gap reference's
/// simulated series are whole grids of the record's length, and this estimator reads them
/// through the record's own missing samples, so every draw has the data's complete windows.
class GappyWvEstimator final : public WvEstimator {
 public:
  explicit GappyWvEstimator(std::vector<MissingRun> missing) : missing_(std::move(missing)) {}
  /// `x` is a grid of n samples (observed and missing places together); throws
  /// InvalidArgument when the runs do not fit in it.
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override;
  std::string name() const override { return "classical"; }

 private:
  std::vector<MissingRun> missing_;
};

/// The gap-resistant overlapping Allan deviation: at each averaging factor m of allan_factors
/// (on the grid's N samples), the mean of (ybar_2 - ybar_1)^2 / 2 over the windows of 2m
/// samples whose halves each miss at most floor(options.max_missing_share * m) samples, each
/// half's mean ybar over its observed samples (below 1 / max_missing_share samples a half must
/// be complete); the chi-square interval at max(M / 2m, 1) degrees of freedom of those M
/// windows (allan_deviation's rule). `complete` holds each point's windows without a missing
/// sample, `partial` those with some. An m without a usable window has no point (a longer one
/// may still have one). Without missing samples, allan_deviation's values. Throws as
/// classical_wv_with_gaps, InputError for invalid options, InvalidArgument for a non-positive
/// rate.
AllanDeviation allan_deviation_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                         double freq, const AllanOptions& options = {});

}  // namespace gmwm
