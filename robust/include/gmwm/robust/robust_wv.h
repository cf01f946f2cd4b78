#pragma once
// The robust Haar wavelet variance (docs/statistics.md section 2): per level, the scale
// M-estimator (Huber's Proposal 2 or Tukey's bisquare) of the MODWT coefficients, with
// the Fisher-consistency constant a(c) and c tuned to a target Gaussian efficiency.
//
//   gmwm::robust::RobustWvOptions o;      // huber, efficiency 0.6
//   gmwm::WaveletVariance w = gmwm::robust::robust_wv(x, n, o);
//   // w.wv[j] is NaN (and w.notes[j] says why) where the equation has no root
//
// Confidence intervals: chi-square with eta replaced by eff x eta (variance inflated by
// 1/efficiency); w.eta holds that value, so the engine's diag Omega and the fit use the
// robust variance without knowing about this module.
//
// Small samples: a(c) gives consistency as the number of coefficients grows, not at
// coarse levels with few effective coefficients, where the robust estimate is biased
// upwards (~+0.35 / eta on white noise; +8% at eta = 7, +15% at eta = 3, +24% at eta = 1
// in the median, spec section 2). Levels with kRobustMinEta <= eta_j <= 3000 are
// corrected by the second-order bias of the estimating equation, its long-run
// covariances estimated from the level's own coefficients (robust/src/small_sample.h);
// below kRobustMinEta the level falls back to the classical estimate and says so in
// w.notes. w.small_sample states both.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust {

/// Levels with eta_j = max(M_j / tau_j, 1) below this use the classical estimate: the
/// robust one's small-sample bias is then above ~5% (spec section 2; our Monte-Carlo
/// check in tests/robust/robust_wv_test.cc keeps levels at eta >= 10 within 10%).
inline constexpr double kRobustMinEta = 10.0;

struct RobustWvOptions {
  RobustKind estimator = RobustKind::kHuber;
  double efficiency = kDefaultEfficiency;  ///< target Gaussian efficiency, in (0, 1)
  int levels = 0;                          ///< <= 0: J = floor(log2 N)
  double alpha = 0.05;                     ///< CIs at level 1 - alpha
  /// Replace isolated spikes and short glitches before the transform (spike_screen.h).
  bool screen_spikes = true;
  /// (tasks done, total) of the several-series robust_wv: one task per series prepared
  /// (screened and transformed), one per level of each; may throw gmwm::Cancelled to stop
  /// it (error.h). Not called by the one-series form, which bootstrap draws use.
  std::function<void(int, int)> progress;
  /// Empty when valid, else one line naming the option.
  std::string Validate() const;
};

/// The root of mean chi(W_t^2 / s) = a(c) in s (the scale nu^2 of one level).
struct ScaleSolution {
  double scale = 0.0;  ///< NaN when there is no root
  bool has_root = false;
  double zero_fraction = 0.0;  ///< share of coefficients exactly 0 (quantized data)
  int passes = 0;              ///< passes over the coefficients
};

/// Solves the estimating equation for one level's coefficients. start: a positive
/// guess (the classical WV). Huber: the unique root, by Newton steps in log s inside a
/// bracket (bisection when a step leaves it); none when (1 - p0) c^2 <= a(c), p0 the
/// share of zero coefficients. Bisquare: the upper root (the lower one is spurious, near
/// s = 0), bracketed by descending from above.
ScaleSolution solve_scale(std::span<const double> w, const Tuning& tuning, double start);

/// Robust WV of one series. Throws gmwm::InvalidArgument on invalid options or n < 16.
WaveletVariance robust_wv(const double* x, std::int64_t n, const RobustWvOptions& options = {});

/// Robust WV of several series, in parallel (TBB) over series x levels.
std::vector<WaveletVariance> robust_wv(const std::vector<std::span<const double>>& series,
                                       const RobustWvOptions& options = {});

/// The same, reusing `transforms` (haar_transforms(series): the classical WV's, one per
/// series) for every series whose spike screen replaces nothing, instead of transforming it
/// again; a screened series gets its own transform. The results are those of the form above.
std::vector<WaveletVariance> robust_wv(const std::vector<std::span<const double>>& series,
                                       const RobustWvOptions& options,
                                       const std::vector<std::unique_ptr<HaarModwt>>& transforms);

/// The robust WV of a record with missing samples (issue 47): at each level the equation is
/// solved on the coefficients classical_wv_with_gaps reads (its complete windows, or the
/// near-complete ones where they at least double them: GappyWindows), so a gap
/// never enters a coefficient; eta, intervals, the small-sample correction and the classical
/// fallback below kRobustMinEta as robust_wv's, from those windows. The spike screen runs on
/// each segment between gaps, against the robust scale of the jumps inside the segments (a
/// step across a gap is no sample's jump); its replaced ranges are grid positions (observed
/// and missing samples together, as the WV's n). A level without a usable window is NaN with
/// a note, as classical_wv_with_gaps's. Without missing samples, robust_wv's values (to
/// rounding). Throws as classical_wv_with_gaps, InvalidArgument on invalid options.
WaveletVariance robust_wv_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                    const RobustWvOptions& options = {});

/// robust_wv_with_gaps as a strategy object (GappyWvEstimator's robust twin): the gap
/// diagnosis's simulated series are whole grids of the record's length, read through the
/// record's own missing samples, so each draw has the data's windows.
class GappyRobustWvEstimator final : public WvEstimator {
 public:
  GappyRobustWvEstimator(RobustWvOptions options, std::vector<MissingRun> missing);
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override;
  std::string name() const override { return to_string(options_.estimator); }

 private:
  RobustWvOptions options_;
  std::vector<MissingRun> missing_;
};

/// The robust estimator as a strategy object (bootstrap Omega, gap reference
/// distributions recompute "the same WV" on simulated series).
class RobustWvEstimator final : public WvEstimator {
 public:
  explicit RobustWvEstimator(RobustWvOptions options);
  using WvEstimator::compute;  // the transform-taking form: the robust WV screens x first
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override;
  std::string name() const override { return to_string(options_.estimator); }

 private:
  RobustWvOptions options_;
};

}  // namespace gmwm::robust
