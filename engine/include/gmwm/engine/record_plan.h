#pragma once
// How long to record (issue 28 item 5): from a noise model (fitted, or from a datasheet),
// the record length at which the GMWM estimate of a noise figure or of a model parameter
// reaches a relative precision at a confidence level, and the precision a given record
// length reaches. The figures: N, the noise density of the model's white noise term
// (sqrt(sigma2 / f)), or, for a model without one (the white noise carried by a fast AR1,
// as select often chooses), N as the model's Allan deviation shows it (model_only_figures)
// with the delta method at its read point; K, the random walk of its random walk term (sqrt(gamma2 f); both
// Process::physical, physical.h); B, the bias instability read at the minimum of the
// model's Allan deviation over the record (noise_figures.h, model_only_figures). For a
// WN + RW model N and K are what the Allan read-off gives; where an AR1 bends the curve
// near 1 s the read-off counts it or not and moves where it reads, so that a fit's
// read-off jumps between records even where the model is resolved (AR1(0.99, 1e-4) +
// WN(1) + RW(1e-6) at 100 Hz, 19338 samples: simulated sd of the read-off's N 3.5%, of
// the WN term's 0.64%, planned 0.53%): no delta method sizes those jumps, so the plan
// sizes the terms.
//
// The basis is the estimator's own asymptotic covariance at length n (docs/statistics.md
// section 5), taken at the model itself (the residual term D of the Hessian vanishes there):
//   Cov(theta_hat) = H^-1 A' W V_n W A H^-1,   H = A' W A,
// over the levels 1..J = floor(log2 n) the default WV has, with V_n the exact finite-n
// covariance of the classical WV (model_wv_covariance) and W = diag(1 / V_n,jj), the
// model-based diagonal weights of `gmwm fit`'s default (OmegaKind::kModel); the delta
// method carries it to a figure. A target's relative standard error is se / |value|, and
// the plan is the smallest n with z_{(1+c)/2} se / |value| <= precision, searched by
// bisection on log2 n (the se falls with n as a rule; a curve with a step, where a new
// level or a new read-off point appears, gives one of the lengths where it crosses), and
// for N, K and parameters never shorter than the length at which the model's components
// are resolved (RecordPlan::resolved_samples), where the sandwich starts to describe the fit.
//
//   gmwm::RecordPlanOptions o;       // o.precision = 0.1, o.confidence = 0.95
//   o.targets = {"N", "K", "RW[2].gamma2"};
//   o.record_seconds = 7200;         // also: what does a 2 h record give?
//   const gmwm::RecordPlan plan = gmwm::plan_record_length(model, theta, 100.0, o);
//   plan.targets[0].seconds, plan.targets[0].precision_at_record ...

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm {

/// The longest record the search considers: 2^34 samples (5.4 years at 100 Hz; at that
/// length the WV has 34 levels and its covariance still costs milliseconds).
inline constexpr std::int64_t kMaxPlannedSamples = std::int64_t{1} << 34;

struct RecordPlanOptions {
  /// Relative half-width of the interval: 0.1 asks for the estimate within +-10% of the truth.
  double precision = 0.1;
  /// Probability of landing within that half-width: z = Phi^-1((1 + confidence) / 2).
  double confidence = 0.95;
  /// "N" (white noise density), "K" (random walk), "B" (bias instability), or a parameter's
  /// label in `model` as given (Model::parameter_label: "WN[1].sigma2", "AR1[2].phi").
  /// Empty: those of N, K and B the model has (a WN term, an RW term, a minimum of its
  /// Allan deviation over a record of max_samples).
  std::vector<std::string> targets;
  /// Also report the precision each target reaches with a record of this many seconds
  /// (0: not asked).
  double record_seconds = 0.0;
  /// The search's cap, in samples: a target still short of its precision there is
  /// reported unreachable.
  std::int64_t max_samples = kMaxPlannedSamples;
  /// Empty when valid, else one line naming the field.
  std::string Validate() const;
};

struct RecordTarget {
  std::string name;          ///< as asked: "N", "K", "B" or a parameter label
  double value = 0.0;        ///< under the model (figures in the data's unit pattern, noise_figures.h)
  bool reachable = false;    ///< the precision is reached within max_samples
  std::int64_t samples = 0;  ///< the planned length (max_samples when unreachable)
  /// The length the target's own se asks for: `samples` is the larger of it and
  /// RecordPlan::resolved_samples (B: it alone; 0 when the precision is not reached within
  /// max_samples).
  std::int64_t own_samples = 0;
  double seconds = 0.0;      ///< samples / freq
  double relative_se = 0.0;  ///< se / |value| at `samples` (z * relative_se <= precision when reachable)
  /// z * relative_se with a record of RecordPlanOptions::record_seconds (NaN when not
  /// asked; +inf when that record is shorter than the model's resolution, where no
  /// precision can be promised).
  double precision_at_record = 0.0;
  /// One line: how the se was obtained, or why the precision is out of reach.
  std::string basis;
  /// Why precision_at_record is +inf (the record shorter than the model's resolution, or
  /// the figure not read from the model's Allan deviation over it); empty otherwise.
  std::string record_basis;
};

struct RecordPlan {
  double z = 0.0;     ///< the normal quantile used
  double freq = 0.0;  ///< Hz
  /// The model's resolution: the shortest record at which the fit's intervals at the
  /// plan's confidence are all two-sided, every parameter's z se within its distance to
  /// the edge of its domain (a variance to 0, phi to +-1); max_samples when it is not
  /// resolved there (every target is then unreachable). Shorter, a fit may trade
  /// components (an AR1 of phi ~ 0 standing in for the white noise, one of phi ~ 1 for
  /// the random walk) and the sandwich describes none of its outcomes: no plan of a term's
  /// figure (N, K) or of a parameter is shorter. B, a figure of the whole curve however the
  /// fit splits it, has no such floor.
  std::int64_t resolved_samples = 0;
  double resolved_seconds = 0.0;
  std::string resolved_by;            ///< the parameter resolved last ("RW[2].gamma2")
  std::vector<RecordTarget> targets;  ///< in the order asked
};

/// The plan for (model, theta) sampled at freq Hz. Throws InputError for invalid options,
/// freq or theta, and for a target the model has no term for (N without a WN term nor a
/// -1/2 slope on its Allan deviation, K
/// without an RW term, B without a minimum of the Allan deviation over max_samples, a
/// parameter label it does not have), naming it and the model.
RecordPlan plan_record_length(const Model& model, const Eigen::VectorXd& theta, double freq,
                              const RecordPlanOptions& options = {});

/// The value of each target under (model, theta) for a record of n samples, as the plan
/// defines it (B's read point depends on n): what a check compares a fit's with.
/// NaN for a figure the model does not have (B: the read-off's bound when it shows no
/// minimum). Throws InputError as plan_record_length, and for n < kMinSeriesLength
/// (classical_wv.h).
std::vector<double> record_target_values(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                         const std::vector<std::string>& targets);

/// The relative standard error se / |value| of each target (names as in
/// RecordPlanOptions::targets) with a record of n samples: the plan's basis. +inf where
/// the record is too short (fewer levels than parameters, parameters not identified, or
/// the figure not read from the model's Allan deviation at that length).
std::vector<double> record_relative_se(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                       const std::vector<std::string>& targets);

}  // namespace gmwm
