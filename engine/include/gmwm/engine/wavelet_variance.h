#pragma once
// The wavelet variance (WV) of one signal: the estimator's input to every fit.
// Levels j = 1..J, tau_j = 2^j samples; "wv" is nu^2 (a variance, not a deviation).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace gmwm {

class HaarModwt;

struct WaveletVariance {
  std::vector<double> tau;                 ///< scales in samples (2^j)
  std::vector<double> wv;                  ///< estimate nu_hat_j^2 (NaN where undefined)
  std::vector<double> ci_low, ci_high;     ///< two-sided CI at level 1 - alpha
  std::vector<double> variance;            ///< Var(nu_hat_j^2) used for diag Omega
  std::vector<double> eta;                 ///< equivalent degrees of freedom of the CI
  std::vector<std::int64_t> coefficients;  ///< M_j = N - tau_j + 1
  /// With missing samples (classical_wv_with_gaps): the windows read at each level that
  /// miss some samples (each half at most a tenth, averaged over its observed ones; 0 where
  /// the level reads complete windows only); empty for a regular record.
  std::vector<std::int64_t> partial;
  /// Full Cov(nu_hat) when the caller knows it better than the model-based one at a fit
  /// (a stacked WV of replicates carries blockdiag(V_k) here): used instead of it by the
  /// fit's inference and the selection's optimism and goodness of fit. Unset by the
  /// estimators.
  std::optional<Eigen::MatrixXd> covariance;
  double alpha = 0.05;
  std::int64_t n = 0;                   ///< series length
  std::string estimator = "classical";  ///< "classical" | "huber" | "bisquare"
  std::optional<double> efficiency;     ///< robust estimators only
  std::vector<std::string> notes;       ///< per level, empty when nothing to say
  /// How the estimator treats levels with few effective coefficients (robust
  /// estimators: bias correction and fallback), empty for the classical one.
  std::string small_sample;
  /// Samples the estimator replaced before the transform ([first, last], 0-based; the
  /// robust estimators' spike screen) and one sentence on what it did.
  std::vector<std::pair<std::int64_t, std::int64_t>> replaced;
  std::string screening;

  int levels() const { return static_cast<int>(wv.size()); }
  /// The WV as an Eigen vector (a copy).
  Eigen::VectorXd values() const {
    return Eigen::Map<const Eigen::VectorXd>(wv.data(), static_cast<Eigen::Index>(wv.size()));
  }
};

/// The range of a WV level's value (a variance) that doubles hold with its own variance
/// Var(nu_hat_j^2) ~ 2 nu_j^4 / M_j, whose inverse weighs the level in a fit: both must be
/// normal doubles (2.2e-308 .. 1.8e308). Data of magnitude 1e-300 (their squares underflow
/// to 0) or 1e150 (sums of squares overflow) fall outside.
inline constexpr double kMinRepresentableWv = 1e-150;
inline constexpr double kMaxRepresentableWv = 1e150;

/// The range of WV levels a fit can take: the fit's parameters are exp(u) with |u| <=
/// kLogBound = 100 (process.h), so variances within 3.7e-44 .. 2.7e43; levels within
/// [1e-30, 1e30] leave 13 orders of magnitude for components far below the total (a random
/// walk's gamma2 is about nu_j^2 / tau_j, tau_j up to 2^40). Every real sensor unit is well
/// inside (a gyroscope in rad/s: 1e-8 .. 1e-14; a magnetometer in tesla: about 1e-18).
inline constexpr double kMinFittableWv = 1e-30;
inline constexpr double kMaxFittableWv = 1e30;

/// Why `wv` (of series x) is unusable, as a phrase, "" when it is usable: a level that is
/// not finite (sums of squares overflowed), zero at every level (a constant series), or a
/// level outside [kMinRepresentableWv, kMaxRepresentableWv]; with `for_fit`, outside
/// [kMinFittableWv, kMaxFittableWv]. Ends with what to do about it.
std::string wv_range_problem(const WaveletVariance& wv, std::span<const double> x, bool for_fit);

/// Strategy for computing a WV from a series, so that bootstrap and gap code can
/// recompute "the same WV" on simulated data without engine/ depending on robust/.
class WvEstimator {
 public:
  virtual ~WvEstimator() = default;
  /// WV of levels 1..levels (levels <= 0: J = floor(log2 N)) at CI level 1 - alpha.
  virtual WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const = 0;
  /// The same WV when the caller already holds x's Haar transform (the gap reference
  /// builds one per replicate for its time-domain statistics too): estimators that work
  /// from the transform alone use it instead of building their own; the default ignores it.
  virtual WaveletVariance compute(const HaarModwt& modwt, const double* x, std::int64_t n, int levels,
                                  double alpha) const {
    static_cast<void>(modwt);
    return compute(x, n, levels, alpha);
  }
  virtual std::string name() const = 0;
};

/// The level (tau = 2^level samples) of the WV's first entry: 1 for every estimator's
/// output, more after drop_fine_levels; 1 for an empty WV.
int first_level(const WaveletVariance& wv);

/// The WV from level `level` on (tau >= 2^level samples): what a fit takes when the finer
/// scales are known to be biased (held or interpolated samples smooth them:
/// repeated_samples.h). Every per-level field and the covariance (when set) are sliced; the
/// result's first_level() is `level`. Throws InvalidArgument unless first_level(wv) <=
/// level <= the WV's last level.
WaveletVariance drop_fine_levels(const WaveletVariance& wv, int level);

/// `inner`'s WV without its levels below `level`: asked for L levels, computes
/// L + level - 1 and drops the finer ones, so that a bootstrap or a gap reference of a WV
/// that drop_fine_levels cut recomputes "the same WV" on simulated data. Holds a reference
/// to `inner`.
class FromLevelEstimator final : public WvEstimator {
 public:
  FromLevelEstimator(const WvEstimator& inner, int level);
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override;
  WaveletVariance compute(const HaarModwt& modwt, const double* x, std::int64_t n, int levels,
                          double alpha) const override;
  std::string name() const override { return inner_.name(); }

 private:
  const WvEstimator& inner_;
  int level_;
};

}  // namespace gmwm
