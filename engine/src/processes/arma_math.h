#pragma once
// Exact autocovariance and Haar WV of an ARMA(p, q) process
//   x_t = phi_1 x_{t-1} + ... + phi_p x_{t-p} + e_t + theta_1 e_{t-1} + ... + theta_q e_{t-q},
// with e_t ~ N(0, sigma2). Everything here is per unit sigma2 (the WV, gamma and their
// derivatives are proportional to sigma2).
//
// Autocovariance (Brockwell & Davis, Introduction to Time Series and Forecasting, s.3.2,
// "third method"): with psi_0 = 1, psi_j = theta_j + sum_{i<=min(j,p)} phi_i psi_{j-i}
// (j = 0..q) and r_k = sum_{j=k}^{q} theta_j psi_{j-k} (theta_0 = 1; r_k = 0 for k > q),
//   gamma(k) - sum_i phi_i gamma(|k - i|) = r_k  for every k >= 0.
// The equations k = 0..p are a (p+1) x (p+1) linear system; for k > p they are the
// recursion gamma(k) = sum_i phi_i gamma(k - i) + r_k. Nothing is truncated.
//
// Near a unit root gamma(0) ~ 1/(1 - sum phi_i) is huge and the WV, a zero-sum
// combination of the gamma(k), would cancel catastrophically. The system is therefore
// solved for u = gamma(0) (1 - sum phi_i) and the semivariogram v(k) = gamma(0) - gamma(k)
// (well conditioned up to the unit root), and v obeys v(k) = u + sum_i phi_i v(k-i) - r_k.
// With m = tau/2 and weights w_m(k) = 3k - 2m (k < m), 2m - k (m <= k < 2m),
//   nu^2 = (2/tau^2) sum_{k=1}^{2m-1} w_m(k) v(k) = (2/tau^2) [m gamma(0) - sum w_m(k) gamma(k)],
// which is [2 Var(S_m) - 2 Cov(S_m, S'_m)] / tau^2 of docs/statistics.md section 3. Both sums are
// accumulated (O(tau) per level) and, per level, the one with the smaller sum of |terms|
// (hence the smaller rounding error) is returned: the v form near a unit root, the gamma
// form for short memory at coarse scales.
//
// Derivatives with respect to (phi_1..phi_p, theta_1..theta_q) are propagated exactly
// through the linear system (Gaussian elimination on jets) and both recursions.

#include <span>
#include <vector>

#include <Eigen/Core>

namespace gmwm::internal {

/// Largest p and q accepted by ARMA(p, q) (a model with more coefficients than a WV
/// has levels cannot be identified; 10 + 10 + 1 parameters already needs J >= 21).
inline constexpr long kArmaMaxOrder = 10;

/// Value with gradient and Hessian (sizes n and n x n when requested, else empty) with
/// respect to the n = p + q coefficients (phi_1..phi_p, theta_1..theta_q).
struct ArmaJet {
  double v = 0.0;
  Eigen::VectorXd g;
  Eigen::MatrixXd h;
};

/// 0 when 1 - a_1 z - ... - a_k z^k has every root strictly outside the unit circle,
/// else the order (1-based) of the first reflection coefficient with modulus >= 1
/// (Schur-Cohn / Levinson step-down recursion).
int first_unstable_reflection(std::span<const double> a);

/// nu^2(tau_k) / sigma2 for each scale (even integers >= 2). order 0: values; 1: and
/// gradients; 2: and Hessians.
std::vector<ArmaJet> arma_unit_wv(std::span<const double> phi, std::span<const double> theta,
                                  std::span<const double> tau, int order);

/// gamma(h) / sigma2 for h = 0..out.size()-1.
void arma_unit_autocovariance(std::span<const double> phi, std::span<const double> theta, std::span<double> out);

/// psi_0..psi_{count-1} (the MA(infinity) weights; used only for short prefixes).
std::vector<double> arma_psi_weights(std::span<const double> phi, std::span<const double> theta, std::size_t count);

}  // namespace gmwm::internal
