#pragma once
// Internals shared by the fit and its inference.

#include <Eigen/Core>

#include "gmwm/engine/fit.h"

namespace gmwm::detail {

/// Sandwich covariance, CIs and goodness of fit for a finished fit (fills r.covariance,
/// r.se, r.ci_low, r.ci_high, r.gof, r.wv_covariance unless already set, r.notes).
/// `v_at_estimate`, when given, is Cov(nuhat) at the final estimate, where r.wv_covariance
/// is the pilot's that formed Omega: the parameters' covariance, the misfit z-scores and
/// the goodness of fit are all measured with it (Satterthwaite, Omega being the pilot's
/// weights); else with r.wv_covariance.
void run_inference(const WaveletVariance& wv, const FitOptions& options, bool omega_is_v_inverse, FitResult& r,
                   const Eigen::MatrixXd* v_at_estimate = nullptr);

/// The Satterthwaite (1946) match of Q ~ sum_k lambda_k chi2_1 (lambda = eig(M V)) to a
/// scaled chi-square a chi2_b from t1 = tr(M V) and t2 = tr((M V)^2): a = t2 / t1,
/// b = t1^2 / t2; sets g's p-value and method ("satterthwaite", or "satterthwaite
/// (degenerate)" with a NaN p when a trace is not positive). g.statistic is the objective.
void satterthwaite_match(GoodnessOfFit& g, double t1, double t2);

}  // namespace gmwm::detail
