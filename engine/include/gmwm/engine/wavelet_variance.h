#pragma once
// The wavelet variance (WV) of one signal: the estimator's input to every fit.
// Levels j = 1..J, tau_j = 2^j samples; "wv" is nu^2 (a variance, not a deviation).

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace gmwm {

struct WaveletVariance {
  std::vector<double> tau;                 ///< scales in samples (2^j)
  std::vector<double> wv;                  ///< estimate nu_hat_j^2 (NaN where undefined)
  std::vector<double> ci_low, ci_high;     ///< two-sided CI at level 1 - alpha
  std::vector<double> variance;            ///< Var(nu_hat_j^2) used for diag Omega
  std::vector<double> eta;                 ///< equivalent degrees of freedom of the CI
  std::vector<std::int64_t> coefficients;  ///< M_j = N - tau_j + 1
  /// Full Cov(nu_hat) when the caller knows it better than the model-based one at a fit
  /// (a stacked WV of replicates carries blockdiag(V_k) here): used instead of it by the
  /// fit's inference and the selection's optimism and goodness of fit. Unset by the
  /// estimators.
  std::optional<Eigen::MatrixXd> covariance;
  double alpha = 0.05;
  std::int64_t n = 0;                      ///< series length
  std::string estimator = "classical";     ///< "classical" | "huber" | "bisquare"
  std::optional<double> efficiency;        ///< robust estimators only
  std::vector<std::string> notes;          ///< per level, empty when nothing to say
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

/// Strategy for computing a WV from a series, so that bootstrap and gap code can
/// recompute "the same WV" on simulated data without engine/ depending on robust/.
class WvEstimator {
 public:
  virtual ~WvEstimator() = default;
  /// WV of levels 1..levels (levels <= 0: J = floor(log2 N)) at CI level 1 - alpha.
  virtual WaveletVariance compute(const double* x, std::int64_t n, int levels,
                                  double alpha) const = 0;
  virtual std::string name() const = 0;
};

}  // namespace gmwm
