#pragma once
// Cross-axis wavelet correlation (docs/gap.md, method note 2, "per axis: ... cross-axis wavelet correlation
// where several axes are given"): per level j, the correlation of two signals' Haar MODWT
// coefficients,
//   rho_j(a, b) = sum_t W^a_{j,t} W^b_{j,t} / sqrt(sum_t (W^a_{j,t})^2 sum_t (W^b_{j,t})^2),
// over the M_j = N - 2^j + 1 boundary-free coefficients (Whitcher, Guttorp & Percival 2000).
// A shared effect (a vibration, a temperature drift, a common step) shows as a correlation
// at its scales; independent noise as none.
//
// Significance: Fisher's z = atanh(rho) with the effective sample size M_j / 2^j (the
// coefficients within one filter length are strongly correlated; Whitcher et al. use
// this as a conservative approximation), Bonferroni over pairs x levels; a pair is
// reported at a level when it is significant and |rho| >= kCrossAxisMinRho.
#include <span>
#include <string>
#include <vector>

namespace gmwm::gap {

/// Practical size of a cross-axis correlation worth reporting (a shared component with at
/// least ~30% of each axis' variance at that scale).
inline constexpr double kCrossAxisMinRho = 0.3;
/// Effective sample sizes below this give no test at that level.
inline constexpr double kCrossAxisMinEffective = 8.0;

struct CrossAxisPair {
  int level = 0;     ///< 1-based
  double tau = 0.0;  ///< samples
  int a = 0, b = 0;  ///< signal indices, a < b
  double rho = 0.0;
  double z = 0.0;  ///< atanh(rho) sqrt(n_eff - 3)
  bool significant = false;
};

/// Every pair at every level with an effective sample size of at least
/// kCrossAxisMinEffective (up to `levels`; <= 0: all). All signals must have the same
/// length (InputError otherwise). `alpha` is the family-wise level.
std::vector<CrossAxisPair> cross_axis_correlation(const std::vector<std::span<const double>>& signals, int levels,
                                                  double alpha);

}  // namespace gmwm::gap
