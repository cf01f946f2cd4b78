#pragma once
// Internals shared by the fit and its inference.

#include <Eigen/Core>

#include "gmwm/engine/fit.h"

namespace gmwm::detail {

/// Sandwich covariance, CIs and goodness of fit for a finished fit (fills r.covariance,
/// r.se, r.ci_low, r.ci_high, r.gof, r.wv_covariance unless already set, r.notes).
/// `parameter_v`, when given, is the Cov(nuhat) the parameters' covariance is measured
/// with (Cov(nuhat) at the final estimate where r.wv_covariance, which the goodness of fit
/// is calibrated with, is the pilot's that formed Omega); else r.wv_covariance.
void run_inference(const WaveletVariance& wv, const FitOptions& options, bool omega_is_v_inverse, FitResult& r,
                   const Eigen::MatrixXd* parameter_v = nullptr);

}  // namespace gmwm::detail
