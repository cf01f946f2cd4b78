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
//   gmwm::JointFitResult r = gmwm::fit_gmwm_joint(wvs, model, options);
//   r.joint.theta, r.joint.ci_low, r.joint.gof ...;  r.agmwm;  r.singles[k]

#include <cstdint>
#include <functional>
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
  /// replicates), the stacked Omega and V, sandwich inference and goodness of fit
  /// (df = sum_k J_k - p). Its per-level misfits index the stacked levels.
  FitResult joint;
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
/// variances, CIs and coefficient counts stacked; n the longest length). For the joint
/// objective and its inference only: its taus are not sorted.
WaveletVariance stack_wv(std::span<const WaveletVariance> wvs);

/// The block-diagonal matrix of `blocks` in order: the stacked WV's Omega or V from each
/// replicate's own block.
Eigen::MatrixXd block_diagonal(std::span<const Eigen::MatrixXd> blocks);

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
struct ReplicateTestOptions {
  int bootstrap = 100;                     ///< B
  std::uint64_t seed = 0;                  ///< bootstrap streams (seed, b, k)
  const WvEstimator* estimator = nullptr;  ///< WV of simulated series (default classical)
  FitOptions fit;                          ///< minimisation settings (Omega is set here)
  std::function<void(int, int)> progress;  ///< (done, total) bootstrap draws
  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// The level at which the shared-theta test is read ("the replicates do not share one
/// theta" when heterogeneity_p <= it): the conventional 5%, at which its level was
/// measured (tools/bench/RESULTS.md). With B draws the smallest p is 1 / (1 + B), so B = 19
/// can just reject.
inline constexpr double kReplicateTestLevel = 0.05;

struct ReplicateTest {
  double statistic = 0.0, p_value = 1.0;              ///< T and its bootstrap p
  double heterogeneity = 0.0, heterogeneity_p = 1.0;  ///< H and its bootstrap p
  std::vector<double> own_minimum;                    ///< per replicate, its own minimum under Omega_k
  int draws = 0;                                      ///< bootstrap draws that gave a finite statistic
  /// The replicates do not share one theta: heterogeneity_p <= kReplicateTestLevel.
  bool rejects() const { return heterogeneity_p <= kReplicateTestLevel; }
};

/// Throws InputError for invalid options or when `joint` has no usable estimate.
ReplicateTest replicate_test(std::span<const WaveletVariance> wvs, const JointFitResult& joint,
                             const ReplicateTestOptions& options = {});

/// Intervals by bootstrap over whole replicates: the joint fit redone on resamples of the
/// K replicates drawn with replacement (each replicate's WV and its block of the joint
/// Omega kept whole), started from the joint estimate. When the distinct resamples
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
