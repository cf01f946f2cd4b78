#pragma once
// The GMWM estimator (docs/statistics.md sections 4-5):
//   theta_hat = argmin (nuhat - nu(theta))' Omega (nuhat - nu(theta)),
// optimised with NLopt (L-BFGS, analytic gradients) in the unconstrained space, from
// starting values derived from the WV's shape plus multi-starts and the fits of the
// models one step below it in the representation order (one component removed or
// replaced by a simpler one it contains: model_relations.h), so a model never ends above
// a model it can represent; components that
// collapsed to nothing are re-placed and the optimisation resumed; a damped Newton
// polish with the exact Hessian finishes. Then inference (sandwich covariance, CIs,
// goodness of fit).
//
//   gmwm::FitOptions options;            // validated by options.Validate()
//   gmwm::FitResult r = gmwm::fit_gmwm(wv, model, options);
//   if (r.status != gmwm::FitStatus::kConverged) ... r.message ...
//   logger->info(r.Report());   // the library itself never prints

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

enum class OmegaKind {
  kDiag,       ///< diag(1 / Var(nuhat_j)) from the WV's own variance (data only)
  kFull,       ///< V^-1, V the model-based covariance at a pilot (diag) fit
  kBootstrap,  ///< V^-1, V from a parametric bootstrap at a pilot (diag) fit
  /// diag(1 / V_jj), V the model-based covariance at a pilot (diag) fit: the selection's
  /// default weights. The data-only weights (kDiag) are ~1 / nuhat_j^2, so a level whose
  /// estimate happens to fall low weighs more: a random walk read off the coarse levels
  /// comes out low (median -20% at 2^17, 95% intervals covering 85%; issue 27).
  kModel,
};
const char* to_string(OmegaKind k);
/// "diag", "full", "bootstrap", "model"; nullopt for anything else.
std::optional<OmegaKind> parse_omega_kind(const std::string& name);
/// The names parse_omega_kind takes, in the order a user reads them: model, diag, full,
/// bootstrap (choice.h: every face's check and refusal).
std::vector<std::string> omega_kind_names();

enum class FitStatus { kConverged, kNotConverged, kFailed };
const char* to_string(FitStatus s);

struct FitOptions {
  /// The default, as `gmwm fit` and Python's fit: model-based diagonal weights (kModel).
  OmegaKind omega = OmegaKind::kModel;
  /// A weighting matrix given by the caller (e.g. common to all models of a selection);
  /// overrides `omega` when set.
  std::optional<Eigen::MatrixXd> omega_matrix;
  double alpha = 0.05;  ///< parameter CIs at level 1 - alpha
  /// Local optimisations from the best shape-based starts (placements of the components
  /// on the WV); 0: only from `starts` (and the nested starts), with one placement only when
  /// none of those is a valid point (a bootstrap refit warm-started from the fit).
  int multistarts = 4;
  int max_evaluations = 3000;         ///< per local optimisation
  double relative_tolerance = 1e-12;  ///< NLopt ftol_rel
  /// Additional starting points (natural space), e.g. warm starts from nested models.
  std::vector<Eigen::VectorXd> starts;
  int bootstrap_replicates = 100;          ///< for OmegaKind::kBootstrap
  std::uint64_t seed = 0;                  ///< for the bootstrap streams
  const WvEstimator* estimator = nullptr;  ///< WV of simulated series (default classical)
  bool inference = true;                   ///< compute covariance, CIs and GoF
  /// Log a warning when the optimiser does not converge (the status says so either way);
  /// callers that run many fits and summarise their statuses (bootstrap refits) turn it off.
  bool log_not_converged = true;
  /// Also start from the fits of every model one step below in the representation order
  /// (representation_neighbours: one component removed, or replaced by a simpler process
  /// it contains such as AR1 -> WN or RW; fitted
  /// with the same Omega, without nested starts of their own), so that the model's
  /// objective is never above theirs. Costs one fit per distinct sub-model; a caller
  /// that fits the sub-models anyway (model selection) turns it off and passes their
  /// fits through `starts` (embed_start).
  bool nested_starts = true;
  /// How deep those warm starts go: 1 fits the neighbours without starts of their own,
  /// 2 gives each neighbour its own neighbours' fits, and so on (cost ~ components^depth).
  int nested_depth = 2;
  /// (draws done, total) while the bootstrap Omega (OmegaKind::kBootstrap) is simulated;
  /// may throw gmwm::Cancelled to stop the fit (error.h).
  std::function<void(int, int)> progress;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

struct GoodnessOfFit {
  double statistic = 0.0;  ///< minimised objective under Omega
  double df = 0.0;         ///< J - p
  double p_value = 0.0;    ///< chi-square (Omega = V^-1) or Satterthwaite-calibrated
  std::string method;      ///< "chi-square" or "satterthwaite"
};

/// How a parameter's interval was formed (FitResult::interval).
enum class IntervalKind {
  kTwoSided,       ///< the delta-method interval, built in the unconstrained space
  kOneSided,       ///< the Wald interval reaches the edge of the parameter's domain (phi at
                   ///< +-1, a variance at 0): that edge closes it, e.g. phi in [0.9998, 1)
  kNotIdentified,  ///< the objective is flat along this parameter (a null direction of its
                   ///< Hessian): no standard error, no interval
  kBoundary,       ///< its component collapsed (negligible at every scale): no interval
};
const char* to_string(IntervalKind k);

/// How far the data's WV is from the fit's at one level.
struct LevelMisfit {
  int level = 0;       ///< 1-based
  double tau = 0.0;    ///< samples
  double ratio = 0.0;  ///< data / model
  double z = 0.0;      ///< (nuhat - nu) / sqrt(V_jj)
};

struct FitResult {
  Model model;            ///< canonical order (AR1 by increasing phi)
  Eigen::VectorXd theta;  ///< natural parameters, canonical order
  double objective = 0.0;
  FitStatus status = FitStatus::kFailed;
  std::string message;
  int evaluations = 0;
  Eigen::MatrixXd omega;          ///< the weighting matrix used
  Eigen::MatrixXd wv_covariance;  ///< V used for inference
  Eigen::VectorXd implied_wv;     ///< nu(theta_hat)
  // Inference (natural parameters).
  Eigen::MatrixXd covariance;
  Eigen::VectorXd se, ci_low, ci_high;
  GoodnessOfFit gof;
  std::vector<IntervalKind> interval;  ///< per parameter (inference only)
  std::vector<LevelMisfit> misfits;    ///< per level (inference only)
  std::vector<std::string> notes;      ///< e.g. boundary parameters dropped from inference
  double seconds_optimise = 0.0, seconds_inference = 0.0;

  /// The `count` levels where the data depart most from the fit (largest |z| first).
  std::vector<LevelMisfit> worst_levels(int count = 3) const;
  /// True when a component collapsed or a parameter is not identified: the fit's
  /// intervals do not describe every parameter.
  bool degenerate() const;
  /// A multi-line human-readable summary.
  std::string Report() const;
};

/// Fits `model` to `wv`. Throws InputError when the model cannot be fitted at all
/// (p > J, invalid options). Numerical trouble is reported in the status.
FitResult fit_gmwm(const WaveletVariance& wv, const Model& model, const FitOptions& options = {});

/// The sign of every signed-magnitude parameter (DR's omega) of a fit, which the WV cannot
/// see, set from the series itself: the sign of its least-squares slope against time. The
/// estimate, its interval (mirrored) and the implied WV are updated; returns the slope.
double orient_by_series(FitResult& fit, std::span<const double> x);
/// The same from a slope already known (e.g. pooled over replicates).
void orient_by_slope(FitResult& fit, double slope);
/// Whether the fit has a parameter whose sign only the series can give (DR's omega): when
/// not, orient_by_series changes nothing and its pass over the series (0.4 s at 1e8
/// samples) can be left out.
bool has_sign_from_series(const FitResult& fit);

/// Goodness of fit of a minimised objective with `df` = J - p degrees of freedom, A the
/// J x p Jacobian at the fit (boundary parameters left out): chi-square(df) when
/// Omega = V^-1, else Q ~ sum lambda_k chi2_1 matched to a scaled chi-square
/// (Satterthwaite), lambda = eig(P' Omega P V), P = I - A (A' Omega A)^+ A' Omega.
GoodnessOfFit goodness_of_fit(const Eigen::MatrixXd& A, double objective, double df, const Eigen::MatrixXd& omega,
                              const Eigen::MatrixXd& V, bool omega_is_v_inverse);

/// One sentence saying that the fit is rejected by its goodness-of-fit test at `level` and
/// where the data depart most from it ("rejected at 5% (GoF p = 1.2e-78): the data depart
/// most at 0.02 s (data/model 1.25, z = 9.1), ..."), taus in seconds when the rate is known;
/// empty when the fit is not rejected or has no test.
/// For a joint fit over replicates (joint_fit.h) give `replicate_levels` (each replicate's
/// J_k, in stacking order): each scale is then named with its replicate.
std::string rejection_summary(const FitResult& fit, double freq, bool freq_known, double level = 0.05,
                              std::span<const int> replicate_levels = {});

/// One sentence naming what makes a fit degenerate (collapsed components, parameters not
/// identified); empty when it is not.
std::string degeneracy_summary(const FitResult& fit);

/// The GMWM objective (nuhat - nu(theta))' Omega (nuhat - nu(theta)).
double gmwm_objective(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                      const Eigen::MatrixXd& omega);

/// diag(eta_j / (2 nu_j^4)) with nu_j^2 = max(nuhat_j^2, nuhat_{j-1}^2 / 4): the inverse
/// chi-square variance, guarded against a coarse level whose estimate is tiny by chance.
Eigen::MatrixXd diagonal_omega(const WaveletVariance& wv);

/// A starting point for `super` built from a fit of `sub` whose components all appear in
/// `super`: shared components keep their values, the others get a negligible size.
Eigen::VectorXd embed_start(const Model& sub, const Eigen::VectorXd& theta_sub, const Model& super,
                            const WaveletVariance& wv);

/// Starting points for `model` from fits (under `omega`, no inference, no nested starts
/// of their own) of each representation_neighbours() model, mapped by represent_start.
std::vector<Eigen::VectorXd> nested_starts(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega,
                                           const FitOptions& options);

}  // namespace gmwm
