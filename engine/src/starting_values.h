#pragma once
// Starting values for the GMWM optimiser, derived from the shape of the empirical WV
// (docs/statistics.md section 4). White noise and quantisation are anchored at the finest
// scales, random walk and drift at the coarsest; components with a characteristic
// scale (AR1, GM, MA1, ARMA, SIN) are placed at every combination of scales from a
// log-spaced grid over the WV's range (AR1 slots interchangeable, so only sorted
// combinations). For each placement the components' sizes are then solved exactly:
// the WV is linear in each component's scale parameter (sigma2, gamma2, A2, ... or
// omega^2), so the best sizes are a non-negative weighted least-squares problem
// (variable projection). Placements are ranked by the resulting objective.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::detail {

/// Up to `count` valid starting points (natural space), best objective first;
/// deterministic for given inputs.
std::vector<Eigen::VectorXd> candidate_starts(const WaveletVariance& wv, const Model& model,
                                              const Eigen::MatrixXd& omega, int count);

/// Keeps the shapes in theta and re-solves every free size by non-negative least squares;
/// false when the result is invalid. objective: the GMWM objective at the result.
bool solve_sizes(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega, Eigen::VectorXd& theta,
                 double& objective);

/// Index of the parameter that scales p's WV linearly at theta (sigma2, gamma2, Q2, A2 ...;
/// found numerically, no process names involved), or -1 when none does.
int linear_scale_parameter(const Process& p, const std::vector<double>& theta, std::span<const double> tau);

/// Components of theta whose WV is negligible at every level (below a tiny share of the
/// data's WV): a local optimum the optimiser cannot leave by itself.
std::vector<int> collapsed_components(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta);

/// Escapes from such optima: each collapsed component of theta is placed again at every
/// grid position (once at its anchor for WN, QN, RW, DR), the other components keep
/// their shapes, all sizes are re-solved; up to `count` of these, best objective first.
std::vector<Eigen::VectorXd> revival_starts(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                                            const Eigen::MatrixXd& omega, int count);

}  // namespace gmwm::detail
