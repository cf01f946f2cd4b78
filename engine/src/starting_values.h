#pragma once
// Starting values for the GMWM optimiser, derived from the shape of the empirical WV
// (STATISTICS.md section 4): white noise and quantisation from the finest scales, random
// walk and drift from the coarsest, components with a characteristic scale (AR1, GM,
// MA1, ARMA, SIN) placed at scales spread over the WV's range, each asked to explain a
// share of the WV there. Several placements and shares give the candidate set.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::detail {

/// Up to `count` valid starting points (natural space), the first being the plain
/// shape-based guess; deterministic for a given (wv, model, seed).
std::vector<Eigen::VectorXd> candidate_starts(const WaveletVariance& wv, const Model& model,
                                              int count, std::uint64_t seed);

}  // namespace gmwm::detail
