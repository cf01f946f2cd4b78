#pragma once
// The classical (unbiased, no mean subtraction) Haar wavelet variance with chi-square
// confidence intervals at real-valued degrees of freedom, and the overlapping Allan
// variance obtained from the same coefficients (docs/statistics.md section 1).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

class HaarModwt;

/// The smallest alpha of any interval (WV, parameters, Allan deviation): at 1 - 1e-10 an
/// interval already spans ~6.5 standard errors, and below about 2^-53 the level
/// 1 - alpha/2 rounds to 1, where the chi-square quantile is infinite (a subnormal alpha
/// such as 1e-320 ended in an overflow inside Boost).
inline constexpr double kMinAlpha = 1e-10;

struct WvOptions {
  int levels = 0;       ///< number of levels; <= 0 means J = floor(log2 N)
  double alpha = 0.05;  ///< CIs at level 1 - alpha (two-sided)
  /// Empty when valid, else a one-line message.
  std::string Validate() const;
};

/// Minimum series length accepted by the WV (4 levels, so that a model with a few
/// parameters can be fitted at all).
inline constexpr std::int64_t kMinSeriesLength = 16;

/// Equivalent degrees of freedom of the chi-square CI: eta_j = max(M_j / 2^j, 1)
/// (Percival & Walden 2000, eq. 313c, "eta_3").
double wv_eta(std::int64_t coefficients, double tau);

/// Chi-square CI [eta v / q_{1-a/2}(eta), eta v / q_{a/2}(eta)] (real-valued eta).
std::pair<double, double> chi_square_ci(double wv, double eta, double alpha);

/// Classical WV of one series. Throws InvalidArgument for n < kMinSeriesLength or
/// invalid options.
WaveletVariance classical_wv(const double* x, std::int64_t n, const WvOptions& options = {});

/// Classical WV from an existing transform (the robust WV shares it). Throws
/// InvalidArgument for a transform of fewer than kMinSeriesLength samples or invalid
/// options.
WaveletVariance classical_wv(const HaarModwt& modwt, const WvOptions& options = {});

/// Classical WV of several series, computed in parallel (TBB) over series x levels.
std::vector<WaveletVariance> classical_wv(const std::vector<std::span<const double>>& series,
                                          const WvOptions& options = {});

/// The same from the series' transforms (haar_transforms), which stay available for other
/// statistics of the same prefix sums. `level_sums`, when given, receives per series the
/// sums of squares of its levels 1..J (HaarModwt::sum_of_squares): the Allan sums at the
/// octave points m = 2^(j-1) (allan.h takes them instead of passing over the data again).
std::vector<WaveletVariance> classical_wv(const std::vector<std::unique_ptr<HaarModwt>>& transforms,
                                          const WvOptions& options,
                                          std::vector<std::vector<double>>* level_sums = nullptr);

/// Overlapping Allan variance at averaging times m = tau/2 of every level
/// (AVAR(m) = 2 nu^2(tau = 2m), all N - 2m + 1 differences); returns pairs (m, avar).
std::vector<std::pair<double, double>> allan_variance(const WaveletVariance& wv);

/// The classical estimator as a strategy object (bootstrap, gap reference distributions).
class ClassicalWvEstimator final : public WvEstimator {
 public:
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override;
  WaveletVariance compute(const HaarModwt& modwt, const double* x, std::int64_t n, int levels,
                          double alpha) const override;
  std::string name() const override { return "classical"; }
};

}  // namespace gmwm
