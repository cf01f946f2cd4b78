// The GMWM fit of a model to a given curve's WV (curve.h: fit_curve).
#include <algorithm>
#include <cmath>
#include <limits>

#include "gmwm/engine/curve.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm {
namespace {

// The curve fit's weights at the WV values v = nu^2 (the curve's own, guarded, or a pilot
// fit's): diag(eta_k / (2 v_k^2)), the inverse of a chi-square's variance 2 v^2 / eta. A value
// that is not positive and finite gives its point no weight.
Eigen::MatrixXd curve_omega(const WaveletVariance& wv, const Eigen::VectorXd& nu2) {
  Eigen::VectorXd d(nu2.size());
  for (Eigen::Index k = 0; k < nu2.size(); ++k) {
    const double v = nu2(k);
    const double w = 0.5 * wv.eta[static_cast<std::size_t>(k)] / (v * v);
    d(k) = v > 0.0 && std::isfinite(w) ? w : 0.0;
  }
  return d.asDiagonal();
}

// No process's WV falls faster than tau^-2 (QN and SIN are the steepest, statistics.md section
// 3), and below this many degrees of freedom a point cannot size its own variance (the
// chi-square's coefficient of variation sqrt(2 / eta) exceeds 0.7): fit.h's diagonal_omega
// guards a record's levels by both, and the curve's pilot weights its points the same way.
constexpr double kFewCurveEdf = 4.0;

// The curve's own values as a pilot's weights can take them: nuhat_k, but at least the value
// used at the point before scaled by (tau_{k-1} / tau_k)^2, and for a point of fewer than
// kFewCurveEdf degrees of freedom at least that value itself. A last point whose estimate
// happens to fall low (one term: it can be any fraction of its WV) would otherwise weigh
// ~1 / nuhat^4 and pull the long-memory terms low (issue 27's bias of the data's weights):
// on CurveStudy's WN+RW+AR1 record (2^18 samples, RW gamma2 = 1e-7, the record's own fit
// 7.16e-8) the curve fit gave gamma2 = 5.82e-8 unguarded, 7.34e-8 guarded.
Eigen::VectorXd guarded_values(const WaveletVariance& wv) {
  Eigen::VectorXd v = wv.values();
  for (Eigen::Index k = 1; k < v.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double ratio = wv.tau[i - 1] / wv.tau[i];
    v(k) = std::max(v(k), v(k - 1) * ratio * ratio);
    if (wv.eta[i] < kFewCurveEdf) v(k) = std::max(v(k), v(k - 1));
  }
  return v;
}

// What a curve fit's goodness of fit says: no p-value (curve.h, "Limits").
void without_test(FitResult& r) {
  r.gof.p_value = std::numeric_limits<double>::quiet_NaN();
  r.gof.method = "none (a given curve: the correlation of its points across taus is unknown)";
}

// The inference at the final estimate: Var(nuhat_k^2) = 2 nu_k^4(theta) / eta_k as the WV's
// covariance (fit.h: the caller's V), the fit resumed from its own estimate under the same
// weights (it stays there) so that the library's sandwich and intervals are the ones run.
FitResult with_inference(const WaveletVariance& wv, const FitResult& fit, FitOptions o) {
  WaveletVariance v = wv;
  Eigen::VectorXd var(fit.implied_wv.size());
  for (Eigen::Index k = 0; k < var.size(); ++k) {
    const double nu2 = fit.implied_wv(k);
    var(k) = 2.0 * nu2 * nu2 / wv.eta[static_cast<std::size_t>(k)];
  }
  v.covariance = Eigen::MatrixXd(var.asDiagonal());
  o.starts = {fit.theta};
  o.multistarts = 0;
  o.nested_starts = false;
  o.inference = true;
  o.omega_matrix = fit.omega;
  FitResult r = fit_gmwm(v, fit.model, o);
  if (r.status == FitStatus::kFailed) return fit;
  if (fit.status != FitStatus::kConverged) {
    r.status = fit.status;
    r.message = fit.message;
  }
  return r;
}

}  // namespace

FitResult fit_curve(const WaveletVariance& wv, const Model& model, const CurveFitOptions& options) {
  if (std::string why = options.Validate(); !why.empty()) throw InputError("curve fit: " + why);
  check_model_fits_levels(model, wv.levels());
  FitOptions o = options.fit;
  o.inference = false;
  o.omega_matrix = curve_omega(wv, guarded_values(wv));
  const FitResult pilot = fit_gmwm(wv, model, o);
  FitResult fit = pilot;
  if (options.omega == OmegaKind::kModel && pilot.status != FitStatus::kFailed) {
    o.omega_matrix = curve_omega(wv, pilot.implied_wv);
    o.starts = {pilot.theta};
    fit = fit_gmwm(wv, pilot.model, o);
    fit.evaluations += pilot.evaluations;
    fit.seconds_optimise += pilot.seconds_optimise;
  }
  if (fit.status == FitStatus::kFailed) return fit;
  const int evaluations = fit.evaluations;
  const double seconds = fit.seconds_optimise;
  fit = with_inference(wv, fit, o);
  fit.evaluations += evaluations;
  fit.seconds_optimise += seconds;
  fit.gof.statistic = fit.objective;
  fit.gof.df = wv.levels() - model.num_parameters();
  without_test(fit);
  return fit;
}

}  // namespace gmwm
