#pragma once
// The effective form of a fitted model: the smallest model the data cannot tell apart
// from it. A fit of 3*AR1 may hold an AR1 with phi ~ 0 (a white noise), one whose
// correlation time is far beyond the record (a random walk over it) and two at the same
// phi (one AR1); a fit of AR1+WN+RW may hold a WN at 1e-16 (nothing). Reporting such a
// fit as it stands misleads (a "3*AR1" with no white noise exports a noise density of 0)
// and counting its parameters as free over-penalises it; its effective form says what it
// is, and is what the ranking of a selection shows and counts.
//
// Reductions, tried greedily (the least visible first), each against the original fit:
//   - drop a component (a collapsed term);
//   - replace a component by a simpler process it may be indistinguishable from
//     (Process::simpler_forms: an AR1 as WN-like or RW-like, an MA1 as WN- or QN-like ...),
//     its size re-solved by weighted least squares to the component's own WV;
//   - merge two components of the same process (Process::merged: AR1s at one phi).
// A reduction is accepted while the fit's WV cannot be told apart from the reduced one's
// at level alpha. Statistic: S = min over the reduced model's parameters (Gauss-Newton
// from the reduction's values; the effective model carries the values reached) of
// sum_j (nu_eff_j - nu_fit_j)^2 / V_jj, V = EffectiveOptions::covariance (the exact
// Cov(nuhat) the selection's inference uses; without it, the chi-square approximation's
// diagonal, 2-5x too large in variance). Null: simulated (Hansen 1996) from 2000 seeded
// draws of N(0, V) through the linearised fit, each removed part contributing the largest
// excess over its shapes (Process::shape_family: an AR1's phi is not identified once its
// variance is 0), so the level holds with correlated levels and a nuisance parameter
// (docs/model-selection.md: 3.0% +- 1.2% at nominal 5%; the chi-square rule gave 23%). A
// component whose own WV is within kNoShare of zero is removed without a test and adds
// nothing to the null.
//
//   const gmwm::EffectiveModel e = gmwm::effective_model(wv, fit.model, fit.theta);
//   e.model.to_string(e.theta);  e.reductions  // "AR1 (phi = 0.0031) is WN-like", ...

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

struct EffectiveOptions {
  double alpha = 0.05;  ///< level of the indistinguishability test
  /// Cov(nuhat) (levels x levels) whose diagonal the test measures distances with. Empty:
  /// the chi-square approximation (eta_j equivalent degrees of freedom), whose variance is
  /// 2-5x the exact one for the processes selection meets.
  std::optional<Eigen::MatrixXd> covariance;
  /// The model WV at which `covariance` was computed (the selection's pilot fit). Given,
  /// each reduction is tested under its null: V's variances taken at the reduced model's
  /// levels (V rescaled level by level by (nu_reduced / nu_at)^2, its correlation kept).
  /// Empty: `covariance` as it is for every reduction.
  std::optional<Eigen::VectorXd> covariance_wv;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

struct EffectiveModel {
  Model model;                          ///< canonical order
  Eigen::VectorXd theta;                ///< its parameters
  std::vector<std::string> reductions;  ///< one line per reduction, in the order applied
  /// Labels of the effective model's components that stand for another process
  /// ("WN-like" for a WN that was an AR1), per component, empty when it is as fitted.
  std::vector<std::string> labels;
  double statistic = 0.0;  ///< S of the accepted reductions (0 when none)
  double threshold = 0.0;  ///< its simulated 1 - alpha quantile (0 when none)
  int removed_parameters = 0;
  /// Removed parameters of components that carried a share of the WV (tested; a collapsed
  /// term's are removed for free).
  int tested_parameters = 0;
  bool reduced() const { return !reductions.empty(); }
  int parameters() const { return model.num_parameters(); }
};

/// The effective form of the fit (model, theta) of `wv`. A model with nothing to reduce
/// comes back as it is (canonical). Throws InvalidArgument for a theta of the wrong size
/// and InputError for invalid options.
EffectiveModel effective_model(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                               const EffectiveOptions& options = {});

}  // namespace gmwm
