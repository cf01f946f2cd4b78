#pragma once
// The overlapping Allan deviation (IEEE Std 952-1997, Std 1554-2005), the curve inertial
// engineers read, of a series and of a model.
//
// At averaging factor m (tau = m / f seconds), with S the prefix sums of x:
//   AVAR(m) = 1 / (2 m^2 (N - 2m + 1)) sum_{t=0}^{N-2m} (S_{t+2m} - 2 S_{t+m} + S_t)^2,
// which is exactly twice the Haar wavelet variance at scale 2m (docs/statistics.md section 1), so a
// model's Allan variance is 2 nu^2(theta; 2m) for any m. Its 1 - alpha interval is the
// chi-square one with eta = max((N - 2m + 1) / (2m), 1) equivalent degrees of freedom,
// the WV's at tau = 2m.
//
//   gmwm::AllanOptions o;                    // 4 points per octave, 95% intervals
//   const gmwm::AllanDeviation a = gmwm::allan_deviation(x, 100.0, o);
//   a.tau[k], a.adev[k], a.ci_low[k], a.ci_high[k]

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm {

class HaarModwt;

/// The share of each half of an Allan window that may be missing when a record has gaps
/// (allan_deviation_with_gaps): such a half is averaged over its observed samples, as Sesia
/// and Tavella (Metrologia 45, 2008, S134) average the data available in each interval. At
/// 0.1 a half of fewer than 10 samples must be complete, and white noise's Allan variance
/// over a window missing its whole share is at most 1 / (1 - 0.1) = 1.11 times its value
/// (each half's mean over 0.9 m samples instead of m); the slow noises (walk, instability),
/// read at long tau where gaps cut every window, change by far less. Complete windows alone
/// end the curve at the longest run without a gap (issue 47: 5% lost in bursts ~20 s apart
/// ends it at 82 s, where the complete record's reaches 5000 s).
inline constexpr double kAllanMaxMissingShare = 0.1;

struct AllanOptions {
  /// Averaging factors m = round(2^(k / points_per_octave)), k = 0, 1, ..., distinct,
  /// up to N / 2; 1 gives the octave points (m = 1, 2, 4, ...).
  int points_per_octave = 4;
  double alpha = 0.05;  ///< intervals at level 1 - alpha
  /// With gaps: the largest share of each half window that may be missing, in [0, 0.5); 0
  /// keeps the complete windows alone (allantools' gradev). See kAllanMaxMissingShare.
  double max_missing_share = kAllanMaxMissingShare;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

struct AllanDeviation {
  std::vector<std::int64_t> m;  ///< averaging factor in samples
  std::vector<double> tau;      ///< m / freq in seconds
  std::vector<double> adev;     ///< sqrt(AVAR), in the data's unit
  std::vector<double> ci_low, ci_high;
  std::vector<double> edf;  ///< equivalent degrees of freedom of the interval
  /// With missing samples (allan_deviation_with_gaps): the windows of 2m samples that hold
  /// none, per point; empty for a regular record (every one of N - 2m + 1).
  std::vector<std::int64_t> complete;
  /// With missing samples: the windows used that hold some (each half missing at most
  /// AllanOptions::max_missing_share of its m samples, averaged over its observed ones).
  std::vector<std::int64_t> partial;
  double freq = 1.0;
  std::int64_t n = 0;
  double alpha = 0.05;
  std::size_t size() const { return m.size(); }
};

/// The averaging factors of AllanOptions for a series of n samples.
std::vector<std::int64_t> allan_factors(std::int64_t n, int points_per_octave);

/// The overlapping Allan deviation of x sampled at freq Hz. Throws InputError for invalid
/// options and InvalidArgument for fewer than 2 samples, a non-finite sample or a
/// non-positive rate.
AllanDeviation allan_deviation(std::span<const double> x, double freq, const AllanOptions& options = {});

/// The same for several series from their transforms (haar_transforms: the classical WV's),
/// every point of every series one task (in parallel): the same values as
/// allan_deviation(x, freq, options) without building the prefix sums again. `level_sums`
/// (classical_wv's, per series, may be empty) give the octave points m = 2^(j-1), which are
/// then not computed again. The series' samples are not checked again: a non-finite sample
/// or a sum of squares beyond a double gives non-finite values, which the caller's check of
/// the WV from the same transforms refuses. Throws InputError for invalid options and
/// InvalidArgument for a non-positive rate.
std::vector<AllanDeviation> allan_deviation(const std::vector<std::unique_ptr<HaarModwt>>& transforms, double freq,
                                            const AllanOptions& options = {},
                                            const std::vector<std::vector<double>>& level_sums = {});

/// The model's Allan deviation sqrt(2 nu^2(theta; 2m)) at each averaging factor.
std::vector<double> model_allan_deviation(const Model& model, const Eigen::VectorXd& theta,
                                          std::span<const std::int64_t> m);

/// Each component's Allan variance 2 nu_c^2(theta; 2m) at one averaging factor.
std::vector<double> component_allan_variances(const Model& model, const Eigen::VectorXd& theta, std::int64_t m);

}  // namespace gmwm
