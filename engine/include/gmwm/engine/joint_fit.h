#pragma once
// The multi-signal GMWM: one model from K replicates of a sensor axis (recordings of the
// same axis on different days, or several units of one model), each with its own length,
// levels and weighting matrix:
//
//   theta_hat = argmin_theta  sum_k (nuhat_k - nu(theta; tau_k))' Omega_k (nuhat_k - nu(theta; tau_k))
//
// (Bakalli et al., IEEE/ION PLANS 2018; Radi et al., IEEE Trans. Instrum. Meas.). It is a
// GMWM fit of the stacked WV [nuhat_1; ...; nuhat_K] with a block-diagonal Omega, started
// from every replicate's own fit and from their average (AGMWM, reported beside it).
// Inference is the sandwich over the stacked WV with V = blockdiag(V_k), V_k the
// model-based covariance of replicate k's WV at theta_hat (independent replicates).
//
// Every joint computation runs on the exact reduction of that stacked problem to one WV on
// the replicates' common levels (reduce_replicates): the weighted mean nutilde under
// W = sum_k Omega_k, whose objective differs from the stacked one by a constant and whose
// sandwich terms are the stacked ones. Setting it up costs O(K J^2) (J levels), each
// objective evaluation then a single signal's; the stacked problem's K J x K J Omega (635 MB
// for K = 495 units of 18 levels) is never formed.
//
//   gmwm::JointFitResult r = gmwm::fit_gmwm_joint(wvs, model, options);
//   r.joint.theta, r.joint.ci_low, r.joint.gof ...;  r.agmwm;  r.singles[k]

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

struct JointFitResult {
  /// MGMWM: the joint estimate (canonical order), its objective (the sum over the
  /// replicates), sandwich inference and goodness of fit of the stacked problem
  /// (df = sum_k J_k - p). Its per-level misfits index the stacked levels (replicate 1's,
  /// then replicate 2's, ...); its omega, wv_covariance and implied_wv are those of the
  /// reduced problem on the common levels (W, Var(nutilde) and nu there: reduce_replicates).
  FitResult joint;
  /// Replicate k's weighting matrix Omega_k (J_k x J_k) in the joint fit: its block of the
  /// stacked Omega.
  std::vector<Eigen::MatrixXd> omegas;
  /// Each replicate's own fit (same options), the joint fit's starting points.
  std::vector<FitResult> singles;
  /// AGMWM: the mean of the single-signal estimates over the replicates whose fit did not
  /// fail (canonical order; repeated components matched by that order, e.g. AR1s by
  /// increasing phi), and its standard error sd / sqrt(K) (NaN when K < 2).
  Eigen::VectorXd agmwm, agmwm_se;
  /// Replicate k's term of the joint objective at theta_hat.
  std::vector<double> objective_share;
  /// Replicate k's levels J_k: its rows of the stacked WV follow those of replicates < k.
  std::vector<int> levels;
};

/// The K WVs as one: levels of replicate 1, then of replicate 2, ... (tau, values,
/// variances, CIs and coefficient counts stacked; n the longest length). The stacked
/// problem itself, which the joint functions reduce (reduce_replicates); its taus are not
/// sorted.
WaveletVariance stack_wv(std::span<const WaveletVariance> wvs);

/// The block-diagonal matrix of `blocks` in order: the stacked WV's Omega or V from each
/// replicate's own block ((sum_k J_k)^2 doubles: for small K only).
Eigen::MatrixXd block_diagonal(std::span<const Eigen::MatrixXd> blocks);

/// The stacked problem of K replicates reduced to one WV on their common levels, exactly.
/// With every Omega_k padded to the common levels 1..J (zero rows and columns where
/// replicate k has no level),
///
///   sum_k (nuhat_k - nu)' Omega_k (nuhat_k - nu) = (nutilde - nu)' W (nutilde - nu) + C,
///   W = sum_k Omega_k,  nutilde = W^-1 sum_k Omega_k nuhat_k,
///   C = sum_k (nuhat_k - nutilde)' Omega_k (nuhat_k - nutilde)   (independent of nu),
///
/// (expand both sides: sum_k Omega_k nuhat_k = W nutilde). A model's Jacobian A is the same
/// at every replicate's level j, so the sandwich terms are the stacked ones too:
/// A_s' Omega_s A_s = A' W A and A_s' Omega_s V_s Omega_s A_s = A' U A with
/// U = sum_k Omega_k V_k Omega_k; the reduced WV's covariance is Var(nutilde) = W^-1 U W^-1,
/// and the reduced fit has the stacked estimate, covariance and analytic optimism. Its
/// objective is the stacked one minus C; the goodness of fit keeps the stacked problem's
/// sum_k J_k - p degrees of freedom (stacked_goodness_of_fit). A level no replicate weighs
/// (a zero row of W) is dropped; W is inverted on the rest (pseudo-inverse if singular:
/// sum_k Omega_k nuhat_k lies in W's range, so the identity holds).
struct ReducedReplicates {
  /// nutilde on the kept levels (tau, values; eta and coefficient counts summed over the
  /// replicates, CIs from the chi-square with that eta); covariance = Var(nutilde) and
  /// variance its diagonal when the V_k were given. n, alpha, estimator, efficiency: the
  /// longest replicate's length, the first replicate's others.
  WaveletVariance wv;
  Eigen::MatrixXd weight;  ///< W on the kept levels
  double within = 0.0;     ///< C: the stacked objective is the reduced one plus C
  std::vector<int> kept;   ///< the kept levels, 0-based on the common levels
  int stacked_levels = 0;  ///< sum_k J_k
  /// For the stacked goodness of fit (V_k given; empty otherwise): U, U2 =
  /// sum_k Omega_k V_k Omega_k V_k Omega_k (kept levels), sum_k tr(Omega_k V_k) and
  /// sum_k tr((Omega_k V_k)^2).
  Eigen::MatrixXd meat, meat2;
  double trace_ov = 0.0, trace_ov2 = 0.0;
};

/// Reduces replicates `wvs` under weights `omegas` (Omega_k, J_k x J_k) and, when given,
/// covariances `covariances` (V_k). Every replicate's levels must be the first J_k of the
/// longest's (tau_j = 2^j at one rate). Throws InvalidArgument on inconsistent sizes or taus.
ReducedReplicates reduce_replicates(std::span<const WaveletVariance> wvs, std::span<const Eigen::MatrixXd> omegas,
                                    std::span<const Eigen::MatrixXd> covariances = {});

/// The stacked problem's goodness of fit from its reduction (V_k given): statistic
/// `objective` (the stacked one), `df` degrees of freedom (sum_k J_k - p); chi-square when
/// every Omega_k = V_k^-1, else the stacked Satterthwaite match of goodness_of_fit (fit.h),
/// whose traces reduce exactly: with B = A' W A,
///   tr(M V) = sum_k tr(Omega_k V_k) - tr(B^+ A' U A),
///   tr((M V)^2) = sum_k tr((Omega_k V_k)^2) - 2 tr(B^+ A' U2 A) + tr((B^+ A' U A)^2)
/// (M = P' Omega P = Omega - Omega A B^+ A' Omega, as B^+ B B^+ = B^+). A: the model's
/// Jacobian at r.wv.tau, its boundary parameters left out as the caller's inference does.
/// Throws InvalidArgument for the Satterthwaite match of a reduction made without the V_k.
GoodnessOfFit stacked_goodness_of_fit(const ReducedReplicates& r, const Eigen::MatrixXd& A, double objective, double df,
                                      bool omega_is_v_inverse);

/// Fits `model` jointly to the replicates' WVs (classical or robust alike), in two steps:
/// a pilot under each replicate's own data-based diag(1 / Var(nuhat_kj)), then the fit
/// under model-based weights from V_k, the covariance of replicate k's WV at the pilot:
/// diag(1 / V_k,jj) for OmegaKind::kDiag, V_k^-1 for kFull. (Data-based weights favour, at
/// each coarse level, the replicate whose WV came out lowest, and bias long-memory terms
/// down the more the more replicates there are.) Throws InputError when there is no replicate, when a
/// replicate has too few levels for the model or an undefined level (naming it by its
/// 1-based index), for OmegaKind::kBootstrap or a caller-given omega_matrix (not supported
/// for the joint fit), or for invalid options.
JointFitResult fit_gmwm_joint(std::span<const WaveletVariance> wvs, const Model& model, const FitOptions& options = {});

/// Do the replicates share one theta? (the near-stationarity test of the multi-signal
/// GMWM). Two statistics, both under Omega_k = V_k^-1, V_k the model-based covariance of
/// replicate k's WV at theta_hat, the fixed point theta_hat = argmin under V_k(theta_hat)^-1
/// started from the joint estimate (the same Omega for the data and every
/// bootstrap draw, so that the statistic and its null distribution share one scale):
///   T = min_theta sum_k (nuhat_k - nu(theta))' Omega_k (nuhat_k - nu(theta))   (joint misfit)
///   H = T - sum_k min_theta_k (nuhat_k - nu(theta_k))' Omega_k (...)          (heterogeneity:
///       what forcing one theta costs beyond each replicate's own best fit)
/// Null distributions by parametric bootstrap from theta_hat, each replicate simulated at
/// its own length and its WV recomputed with the same estimator; p = (1 + #{null >= obs}) /
/// (1 + B). T also rejects a model that fits no replicate; H is the test of a shared theta.
/// Or (ReplicateCalibration::kChiSquare) by their asymptotic chi-square distributions.
/// The WV estimator of replicate k's simulated series: each[k] when `each` is given (one per
/// replicate), else `common`, else `fallback`. Throws InputError ("WHAT: N estimators for K
/// replicates") when `each` is given with another size than `replicates`.
const WvEstimator& replicate_estimator(std::span<const WvEstimator* const> each, std::size_t k,
                                       const WvEstimator* common, const WvEstimator& fallback);
void check_replicate_estimators(const std::string& what, std::span<const WvEstimator* const> each,
                                std::size_t replicates);

enum class ReplicateCalibration {
  /// The parametric bootstrap above (the default): B x K simulated series.
  kBootstrap,
  /// Under efficient weights (Omega_k = V_k^-1, as here) and a shared theta in the interior,
  /// H is the distance-metric statistic of the K - 1 restrictions theta_1 = ... = theta_K
  /// on the unrestricted fits (Newey & West 1987, "Hypothesis testing with efficient method
  /// of moments estimation", Int. Econ. Rev. 28:777): H ~ chi2((K - 1) q); and T
  /// is Hansen's (1982, Econometrica 50:1029) overidentification statistic, T ~
  /// chi2(sum_k J_k - q); q = the joint fit's parameters off the boundary. No simulation:
  /// for fleets, where K x B series take too long (docs/multi-signal.md gives the costs and
  /// the level measured against the bootstrap).
  kChiSquare,
};
const char* to_string(ReplicateCalibration c);

struct ReplicateTestOptions {
  int bootstrap = 100;                     ///< B (kBootstrap)
  std::uint64_t seed = 0;                  ///< bootstrap streams (seed, b, k)
  const WvEstimator* estimator = nullptr;  ///< WV of simulated series (default classical)
  /// Per replicate, the WV estimator of its simulated series when the replicates are read
  /// differently (each through its own gaps: GappyWvEstimator); empty: `estimator` for all.
  /// Its size must be the replicates' (InputError otherwise).
  std::vector<const WvEstimator*> estimators;
  FitOptions fit;                          ///< minimisation settings (Omega is set here)
  std::function<void(int, int)> progress;  ///< (done, total) bootstrap draws
  ReplicateCalibration calibration = ReplicateCalibration::kBootstrap;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// The level at which the shared-theta test is read ("the replicates do not share one
/// theta" when heterogeneity_p <= it): the conventional 5%, at which its level was
/// measured (tools/bench/RESULTS.md). With B draws the smallest p is 1 / (1 + B), so B = 19
/// can just reject.
inline constexpr double kReplicateTestLevel = 0.05;

struct ReplicateTest {
  double statistic = 0.0, p_value = 1.0;              ///< T and its p
  double heterogeneity = 0.0, heterogeneity_p = 1.0;  ///< H and its p
  std::vector<double> own_minimum;                    ///< per replicate, its own minimum under Omega_k
  int draws = 0;                                      ///< bootstrap draws that gave a finite statistic (0: chi-square)
  ReplicateCalibration calibration = ReplicateCalibration::kBootstrap;
  /// The chi-square's degrees of freedom, (K - 1) q and sum_k J_k - q (NaN for the bootstrap).
  double df_heterogeneity = std::numeric_limits<double>::quiet_NaN();
  double df_statistic = std::numeric_limits<double>::quiet_NaN();
  /// The replicates do not share one theta: heterogeneity_p <= kReplicateTestLevel.
  bool rejects() const { return heterogeneity_p <= kReplicateTestLevel; }
};

/// Throws InputError for invalid options or when `joint` has no usable estimate.
ReplicateTest replicate_test(std::span<const WaveletVariance> wvs, const JointFitResult& joint,
                             const ReplicateTestOptions& options = {});

/// Intervals by bootstrap over whole replicates: the joint fit redone on resamples of the
/// K replicates drawn with replacement (each replicate's WV and its block of the joint
/// Omega kept whole: JointFitResult::omegas), started from the joint estimate. When the distinct resamples
/// (multisets, C(2K-1, K): 10 for K = 3) number at most max_draws, every one is fitted and
/// weighted by its bootstrap probability K! / (prod m_i! K^K); else max_draws resamples
/// are drawn (streams from seed).
///
/// The interval at level 1 - alpha is the replicate-t interval: in each parameter's
/// unconstrained space (log for a variance), u_hat +- t_{K-1, 1-alpha/2} sqrt(K / (K-1))
/// sd*(u), sd* the bootstrap standard deviation. Its percentile interval is given too, but
/// it cannot cover: the resampled fits stay within the range of the K replicates'
/// estimates, which misses the truth with probability 2^(1-K) (25% for K = 3), and the
/// bootstrap variance of a mean of K is (K-1)/K of its variance.
/// A parameter of the joint fit that is not identified or whose component collapsed gets
/// no replicate-t interval (NaN): the resamples' fits sit at the same collapsed value, and
/// their spread says nothing of its uncertainty.
/// Each resample's fit starts from the joint estimate and from its replicates' own fits.
struct ReplicateBootstrap {
  Eigen::VectorXd ci_low,
      ci_high;  ///< replicate-t interval (natural parameters, canonical order; NaN when no draw, collapsed or not identified)
  Eigen::VectorXd percentile_low, percentile_high;  ///< the plain percentile interval
  Eigen::VectorXd se;                               ///< sqrt(K / (K-1)) x the bootstrap sd (natural scale)
  int draws = 0;                                    ///< fits that did not fail
  bool exhaustive = false;                          ///< every distinct resample was fitted
};
ReplicateBootstrap replicate_bootstrap(std::span<const WaveletVariance> wvs, const JointFitResult& joint,
                                       double alpha = 0.05, int max_draws = 200, std::uint64_t seed = 0,
                                       const FitOptions& fit = {});

/// The sign of every signed-magnitude parameter (DR's omega): each single fit from its own
/// series' slope, the joint fit from the pooled slope (each replicate with its own
/// intercept: sum_k Sxy_k / sum_k Sxx_k). `series[k]` is replicate k. Returns the pooled slope.
double orient_by_replicates(JointFitResult& r, std::span<const std::span<const double>> series);

/// The whole analysis of one axis over its replicates, as `gmwm fit --joint` gives it:
/// the joint fit (fit_gmwm_joint), the drift signs from the series (orient_by_replicates),
/// and with two or more replicates and a usable joint estimate the shared-theta test
/// (replicate_test) and the replicate-t intervals (replicate_bootstrap).
struct JointAnalysisOptions {
  FitOptions fit;             ///< the joint fit's settings (alpha: the intervals' level)
  ReplicateTestOptions test;  ///< its fit settings are the joint fit's, without inference
  int bootstrap_draws = 200;  ///< max_draws of replicate_bootstrap (all distinct resamples up to K = 5)
  /// Empty when valid, else one line.
  std::string Validate() const;
};
struct JointAnalysis {
  JointFitResult fit;
  double pooled_slope = 0.0;                    ///< the drift's slope pooled over the replicates
  std::optional<ReplicateTest> test;            ///< none with one replicate or a failed fit
  std::optional<ReplicateBootstrap> bootstrap;  ///< likewise
};
/// `series[k]` is replicate k (its WV is wvs[k]). Throws as the functions it calls.
JointAnalysis analyse_replicates(std::span<const WaveletVariance> wvs, std::span<const std::span<const double>> series,
                                 const Model& model, const JointAnalysisOptions& options = {});

}  // namespace gmwm
