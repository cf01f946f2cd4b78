#pragma once
// Starting values for the GMWM optimiser, derived from the shape of the empirical WV
// (STATISTICS.md section 4). White noise and quantisation are anchored at the finest
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

}  // namespace gmwm::detail
