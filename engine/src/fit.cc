#include "gmwm/engine/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Dense>
#include <nlopt.h>
#include <spdlog/spdlog.h>

#include "gmwm/engine/choice.h"
#include "fit_internal.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_relations.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/samples.h"
#include "gmwm/engine/wv_covariance.h"
#include "starting_values.h"

namespace gmwm {

const char* to_string(OmegaKind k) {
  switch (k) {
    case OmegaKind::kDiag:
      return "diag";
    case OmegaKind::kFull:
      return "full";
    case OmegaKind::kBootstrap:
      return "bootstrap";
    case OmegaKind::kModel:
      return "model";
  }
  return "?";
}

namespace {
constexpr OmegaKind kOmegaKinds[] = {OmegaKind::kModel, OmegaKind::kDiag, OmegaKind::kFull, OmegaKind::kBootstrap};
}  // namespace

std::optional<OmegaKind> parse_omega_kind(const std::string& name) { return parse_among(name, kOmegaKinds); }

std::vector<std::string> omega_kind_names() { return names_among(kOmegaKinds); }

const char* to_string(FitStatus s) {
  switch (s) {
    case FitStatus::kConverged:
      return "converged";
    case FitStatus::kNotConverged:
      return "not_converged";
    case FitStatus::kFailed:
      return "failed";
  }
  return "?";
}

std::string FitOptions::Validate() const {
  std::ostringstream os;
  if (!(alpha > 0.0 && alpha < 1.0))
    os << "alpha must be in (0, 1), got " << alpha;
  else if (alpha < kMinAlpha)
    os << "alpha must be at least 1e-10 (the level 1 - alpha/2 rounds to 1 below ~1e-16), got " << alpha;
  else if (multistarts < 0)
    os << "multistarts must be at least 0 (0: only the given starts), got " << multistarts;
  else if (max_evaluations < 10)
    os << "max_evaluations must be at least 10, got " << max_evaluations;
  else if (nested_depth < 1)
    os << "nested_depth must be at least 1, got " << nested_depth;
  else if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0))
    os << "relative_tolerance must be in (0, 1), got " << relative_tolerance;
  else if (omega == OmegaKind::kBootstrap && bootstrap_replicates < 10)
    os << "bootstrap replicates must be at least 10 for a bootstrap Omega, got " << bootstrap_replicates;
  return os.str();
}

// No WV of the processes here decays faster than tau^-2 between scales (QN and SIN are
// the steepest: nu^2 ~ tau^-2, docs/statistics.md section 3), so nu_j^2 >= nu_{j-1}^2 / 4.
// The weights use max(nuhat_j^2, nuhat_{j-1}^2 / 4): a coarse level whose few
// coefficients happen to be tiny (with one coefficient nuhat^2 can be any fraction of
// nu^2) would otherwise get a weight ~1/nuhat^4 that swamps every other level.
constexpr double kSteepestDecayPerLevel = 0.25;
// Below this many equivalent degrees of freedom a level cannot size its own variance at
// all (the chi-square's coefficient of variation sqrt(2/eta) exceeds 0.7): its weight
// uses at least the value used at the level before it, instead of a quarter of that
// level's. A flat or rising WV is what those scales show in an IMU (RW, rate ramp, bias
// instability); a WN-like decay gets a weight ~4x too small, where a low draw got one
// ~1000x too large (WN+RW on 2^16 samples: last level, 1 coefficient, at 8e-4 of the
// truth; RW gamma2 fitted 430x low).
constexpr double kFewCoefficients = 4.0;

Eigen::MatrixXd diagonal_omega(const WaveletVariance& wv) {
  Eigen::VectorXd d(wv.levels());
  double previous = 0.0;  // the value used at the level before
  for (int j = 0; j < wv.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j);
    double v = wv.wv[i];
    if (j > 0 && std::isfinite(wv.wv[i - 1])) v = std::max(v, kSteepestDecayPerLevel * wv.wv[i - 1]);
    if (wv.eta[i] < kFewCoefficients && std::isfinite(previous)) v = std::max(v, previous);
    previous = v;
    const double var = 2.0 * v * v / wv.eta[i];
    d(j) = (var > 0.0 && std::isfinite(var)) ? 1.0 / var : 0.0;
  }
  return d.asDiagonal();
}

double gmwm_objective(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                      const Eigen::MatrixXd& omega) {
  const Eigen::VectorXd r = wv.values() - model.wv(theta, wv.tau);
  return r.dot(omega * r);
}

namespace {

// The relative size, against the data's WV, given to a component absent from the
// sub-model a warm start comes from: small enough not to change the objective
// noticeably, large enough to keep the log-parameters' gradients alive.
constexpr double kNegligibleShare = 1e-12;
// Re-placements of collapsed components tried per round (the best by objective after
// re-solving the sizes), and the relative decrease of the objective that counts as an
// escape (smaller gains are the optimiser's own tolerance, 1e-10 by default).
constexpr int kRevivalStarts = 3;
constexpr double kRevivalGain = 1e-9;

double bound_of(Transform t) {
  switch (t) {
    case Transform::kLog:
      return kLogBound;
    case Transform::kAtanh:
      return kAtanhBound;
    case Transform::kLogitHalf:
      return kLogitBound;
    case Transform::kIdentity:
      return kIdentityBound;
  }
  return kIdentityBound;
}

struct Problem {
  const WaveletVariance* wv;
  const Model* model;
  Eigen::MatrixXd omega;
  Eigen::VectorXd nuhat;
  int evaluations = 0;
};

double objective_u(unsigned n, const double* u, double* grad, void* data) {
  auto* P = static_cast<Problem*>(data);
  ++P->evaluations;
  Eigen::Map<const Eigen::VectorXd> uu(u, n);
  const Eigen::VectorXd theta = P->model->from_unconstrained(uu);
  // With a gradient, the WV and its jacobian in one pass (the same values as apart).
  Eigen::VectorXd nu;
  Eigen::MatrixXd A;
  if (grad)
    P->model->wv_and_jacobian(theta, P->wv->tau, nu, A);
  else
    nu = P->model->wv(theta, P->wv->tau);
  const Eigen::VectorXd r = P->nuhat - nu;
  const Eigen::VectorXd wr = P->omega * r;
  const double q = r.dot(wr);
  if (!std::isfinite(q)) {
    if (grad) std::fill(grad, grad + n, 0.0);
    return std::numeric_limits<double>::max();
  }
  if (grad) {
    const Eigen::VectorXd d = P->model->dtheta_du(uu);
    Eigen::Map<Eigen::VectorXd> g(grad, n);
    g = -2.0 * (A.transpose() * wr).cwiseProduct(d);
    for (unsigned k = 0; k < n; ++k)
      if (!std::isfinite(grad[k])) grad[k] = 0.0;
  }
  return q;
}

struct LocalResult {
  Eigen::VectorXd u;
  double value = std::numeric_limits<double>::infinity();
  nlopt_result code = NLOPT_FAILURE;
};

// The L-BFGS memory (correction pairs kept). NLopt's default (vector_storage 0) keeps
// min(1310720 / n, maxeval) pairs, i.e. every pair of a run of up to max_evaluations
// (3000) steps: each step then costs O(steps so far) (luksan's two-loop recursion and the
// shift of its stored pairs), quadratic in a run's length, and 2 x 3000 x n doubles are
// cleared per call. Measured (issue 44, AMD EPYC, one thread, imu1 gyro_x): luksan's
// vector routines were 25% of `gap --kalibr`'s CPU. Shorter memories are faster still
// (20 pairs: gap --replicates 40 4.66 -> 3.21 s, 100 pairs: 3.74 s) but change which of
// two near-equal minima a pilot fit reaches: select 2*AR1+WN+RW on gyro_x of
// adis_16405_imu2 and imu3 ended 1e-6 (relative) above the minimum the full memory finds
// with 10-60 pairs, at it with 100, 200 and 3000 (the select's objective, Allan curves at
// 1e-5). 100 keeps those minima and most of the gain.
constexpr unsigned kLbfgsMemory = 100;

LocalResult local_optimise(Problem& P, const Eigen::VectorXd& u0, const FitOptions& o) {
  const unsigned n = static_cast<unsigned>(u0.size());
  LocalResult best;
  best.u = u0;
  std::vector<double> lb(n), ub(n);
  for (unsigned k = 0; k < n; ++k) {
    const double b = bound_of(P.model->spec_of(static_cast<int>(k)).transform);
    lb[k] = -b;
    ub[k] = b;
  }
  std::vector<double> x(u0.data(), u0.data() + n);
  for (unsigned k = 0; k < n; ++k) x[k] = std::clamp(x[k], lb[k], ub[k]);
  // Two L-BFGS passes: the second restarts the Hessian approximation, which frees
  // runs that stopped on round-off far from a stationary point.
  for (int pass = 0; pass < 2; ++pass) {
    nlopt_opt opt = nlopt_create(NLOPT_LD_LBFGS, n);
    nlopt_set_min_objective(opt, objective_u, &P);
    nlopt_set_lower_bounds(opt, lb.data());
    nlopt_set_upper_bounds(opt, ub.data());
    nlopt_set_ftol_rel(opt, o.relative_tolerance);
    nlopt_set_maxeval(opt, o.max_evaluations);
    nlopt_set_vector_storage(opt, kLbfgsMemory);
    double f = 0.0;
    const nlopt_result code = nlopt_optimize(opt, x.data(), &f);
    nlopt_destroy(opt);
    if (code < 0 && code != NLOPT_ROUNDOFF_LIMITED && code != NLOPT_FORCED_STOP) {
      // Keep the best point found so far (NLopt leaves x at it for most failures).
      f = objective_u(n, x.data(), nullptr, &P);
    }
    if (std::isfinite(f) && f <= best.value) {
      best.value = f;
      best.u = Eigen::Map<Eigen::VectorXd>(x.data(), n);
      best.code = code;
    } else if (pass == 0) {
      best.code = code;
    }
    if (code == NLOPT_MAXEVAL_REACHED) break;
  }
  return best;
}

// L-BFGS stops once a step's relative decrease falls below ftol_rel, which in the long
// flat valleys of these objectives (AR1 with phi near 1, nearly collinear components)
// can leave ~1e-8 of the objective on the table: fits of nested models then disagree in
// the 9th digit. A damped Newton polish with the exact Hessian (Levenberg-Marquardt
// scaling, Marquardt 1963) finishes the job at quadratic speed. Parameters at a bound
// with the gradient pushing outwards stay fixed.
constexpr int kPolishIterations = 60;
constexpr double kPolishDampingStart = 1e-3;
constexpr double kPolishDampingMax = 1e12;
constexpr double kPolishRelativeDecrease = 1e-15;
// Below a few ulps two objective values cannot be ranked (the objective sums J rounded
// squared misfits), so a flat valley's minimum is resolved by the value only to ~the
// square root of the round-off in its flat direction: 1e-8 of theta there, which moved
// the objective of a fit weighed at it (a model-based Omega) by 1e-8 (issue 44,
// JointReduction tests). The gradient resolves it far better: a near-Newton step
// (damping at most kPolishNewtonDamping) whose value stays within kPolishRoundoff
// (relative) is taken when it lowers the gradient's norm, at most kPolishFlatSteps in a
// row; the polish is done once no free coordinate moves by more than kPolishStepSettled
// (unconstrained units: log-variances and the like, so relative in theta).
constexpr double kPolishRoundoff = 64.0 * std::numeric_limits<double>::epsilon();
constexpr double kPolishNewtonDamping = 1e-2;
constexpr int kPolishFlatSteps = 4;
constexpr double kPolishStepSettled = 1e-11;

void newton_polish(Problem& P, LocalResult& best) {
  const Model& model = *P.model;
  const int n = static_cast<int>(best.u.size());
  Eigen::VectorXd u = best.u;
  double f = best.value;
  double lambda = kPolishDampingStart;
  int flat_steps = 0;
  std::vector<double> lb(static_cast<std::size_t>(n)), ub(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double b = bound_of(model.spec_of(k).transform);
    lb[static_cast<std::size_t>(k)] = -b;
    ub[static_cast<std::size_t>(k)] = b;
  }
  for (int it = 0; it < kPolishIterations; ++it) {
    const Eigen::VectorXd theta = model.from_unconstrained(u);
    Eigen::VectorXd nu;
    Eigen::MatrixXd A;
    model.wv_and_jacobian(theta, P.wv->tau, nu, A);
    const Eigen::VectorXd r = P.nuhat - nu;
    const Eigen::VectorXd wr = P.omega * r;
    const auto hess = model.hessians(theta, P.wv->tau);
    const Eigen::VectorXd g_theta = -2.0 * A.transpose() * wr;
    Eigen::MatrixXd H_theta = 2.0 * A.transpose() * P.omega * A;
    for (std::size_t j = 0; j < hess.size(); ++j) H_theta -= 2.0 * wr(static_cast<Eigen::Index>(j)) * hess[j];
    const Eigen::VectorXd d = model.dtheta_du(u);
    Eigen::VectorXd g = g_theta.cwiseProduct(d);
    Eigen::MatrixXd H = d.asDiagonal() * H_theta * d.asDiagonal();
    for (int k = 0; k < n; ++k) H(k, k) += g_theta(k) * d2natural_du2(model.spec_of(k).transform, u(k));
    if (!g.allFinite() || !H.allFinite()) return;
    std::vector<int> fr;
    for (int k = 0; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const bool at_lb = u(k) <= lb[kk] * (1.0 - 1e-12) && g(k) > 0.0;
      const bool at_ub = u(k) >= ub[kk] * (1.0 - 1e-12) && g(k) < 0.0;
      if (!at_lb && !at_ub) fr.push_back(k);
    }
    if (fr.empty()) return;
    const auto m = static_cast<Eigen::Index>(fr.size());
    Eigen::MatrixXd Hf(m, m);
    Eigen::VectorXd gf(m), scale(m);
    for (Eigen::Index a = 0; a < m; ++a) {
      gf(a) = g(fr[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < m; ++b)
        Hf(a, b) = H(fr[static_cast<std::size_t>(a)], fr[static_cast<std::size_t>(b)]);
    }
    const double hmax = std::max(Hf.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    for (Eigen::Index a = 0; a < m; ++a) scale(a) = std::max(std::abs(Hf(a, a)), 1e-12 * hmax);
    bool accepted = false;
    double gain = 0.0, moved = 0.0;
    while (lambda <= kPolishDampingMax) {
      Eigen::MatrixXd K = Hf;
      K.diagonal() += lambda * scale;
      Eigen::LDLT<Eigen::MatrixXd> ldlt(K);
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) {
        lambda *= 10.0;
        continue;
      }
      const Eigen::VectorXd step = ldlt.solve(-gf);
      Eigen::VectorXd trial = u;
      for (Eigen::Index a = 0; a < m; ++a) {
        const int k = fr[static_cast<std::size_t>(a)];
        trial(k) = std::clamp(u(k) + step(a), lb[static_cast<std::size_t>(k)], ub[static_cast<std::size_t>(k)]);
      }
      const double ft = objective_u(static_cast<unsigned>(n), trial.data(), nullptr, &P);
      bool flat = false;  // taken on the gradient's word (kPolishRoundoff)
      if (std::isfinite(ft) && ft >= f && ft <= f + kPolishRoundoff * std::abs(f) && lambda <= kPolishNewtonDamping &&
          flat_steps < kPolishFlatSteps) {
        std::vector<double> gt(static_cast<std::size_t>(n));
        objective_u(static_cast<unsigned>(n), trial.data(), gt.data(), &P);
        double norm_t = 0.0;
        for (int k : fr) norm_t += gt[static_cast<std::size_t>(k)] * gt[static_cast<std::size_t>(k)];
        flat = norm_t < gf.squaredNorm();
      }
      if (std::isfinite(ft) && (ft < f || flat)) {
        gain = f - ft;
        moved = (trial - u).cwiseAbs().maxCoeff();
        u = trial;
        f = ft;
        flat_steps = flat ? flat_steps + 1 : 0;
        lambda = std::max(lambda / 10.0, 1e-12);
        accepted = true;
        break;
      }
      lambda *= 10.0;
    }
    if (!accepted || moved <= kPolishStepSettled) break;
    if (gain > 0.0 && gain <= kPolishRelativeDecrease * f && lambda > kPolishNewtonDamping) break;
  }
  if (f <= best.value + kPolishRoundoff * std::abs(best.value)) {
    best.u = u;
    best.value = f;
  }
}

// Maps an NLopt outcome to a fit status. L-BFGS often ends with ROUNDOFF_LIMITED at an
// optimum whose objective cannot decrease further in double precision: it counts as
// converged when the gradient in the unconstrained space is small relative to the
// objective (kRoundoffGradient, i.e. a relative change below 1e-6 per unit step).
constexpr double kRoundoffGradient = 1e-6;

FitStatus status_of(nlopt_result code, Problem& P, const Eigen::VectorXd& u, double value, std::string& message) {
  switch (code) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
    case NLOPT_FTOL_REACHED:
    case NLOPT_XTOL_REACHED:
      message = "converged (NLopt code " + std::to_string(code) + ")";
      return FitStatus::kConverged;
    case NLOPT_MAXEVAL_REACHED:
    case NLOPT_MAXTIME_REACHED:
      message = "stopped at the evaluation limit before converging";
      return FitStatus::kNotConverged;
    case NLOPT_ROUNDOFF_LIMITED:
    case NLOPT_FAILURE: {
      // L-BFGS reports a generic failure when its line search cannot progress, which
      // at an optimum is the same situation as ROUNDOFF_LIMITED: judge by the gradient.
      std::vector<double> g(static_cast<std::size_t>(u.size()));
      objective_u(static_cast<unsigned>(u.size()), u.data(), g.data(), &P);
      double gmax = 0.0;
      for (int k = 0; k < u.size(); ++k) {
        // Components pinned at a bound are at a constrained optimum.
        const double b = bound_of(P.model->spec_of(k).transform);
        if (std::abs(u(k)) >= b * (1.0 - 1e-12)) continue;
        gmax = std::max(gmax, std::abs(g[static_cast<std::size_t>(k)]));
      }
      if (gmax <= kRoundoffGradient * std::max(1.0, value)) {
        message = "converged (line search limited by round-off at a stationary point)";
        return FitStatus::kConverged;
      }
      message = "stopped on round-off with a gradient of " + std::to_string(gmax);
      return FitStatus::kNotConverged;
    }
    default:
      message = "optimiser failed (NLopt code " + std::to_string(code) + ")";
      return FitStatus::kFailed;
  }
}

}  // namespace

std::vector<Eigen::VectorXd> nested_starts(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega,
                                           const FitOptions& options) {
  std::vector<Eigen::VectorXd> out;
  FitOptions sub_options = options;
  sub_options.omega_matrix = omega;
  sub_options.nested_starts = options.nested_depth > 1;
  sub_options.nested_depth = std::max(1, options.nested_depth - 1);
  sub_options.inference = false;
  sub_options.starts.clear();
  for (const Model& sub : representation_neighbours(model)) {
    const FitResult f = fit_gmwm(wv, sub, sub_options);
    if (f.status == FitStatus::kFailed) continue;
    if (auto start = represent_start(model, f.model, f.theta, wv)) out.push_back(std::move(*start));
  }
  return out;
}

Eigen::VectorXd embed_start(const Model& sub, const Eigen::VectorXd& theta_sub, const Model& super,
                            const WaveletVariance& wv) {
  Eigen::VectorXd theta(super.num_parameters());
  std::vector<bool> used(static_cast<std::size_t>(sub.num_components()), false);
  std::vector<double> small(wv.wv);
  for (double& v : small) v = std::max(v, 1e-300) * kNegligibleShare;
  for (int c = 0; c < super.num_components(); ++c) {
    const Process& p = *super.components()[static_cast<std::size_t>(c)].process;
    int match = -1;
    for (int s = 0; s < sub.num_components() && match < 0; ++s) {
      const Process& q = *sub.components()[static_cast<std::size_t>(s)].process;
      if (!used[static_cast<std::size_t>(s)] && q.name() == p.name() && q.structure() == p.structure()) match = s;
    }
    if (match >= 0) {
      used[static_cast<std::size_t>(match)] = true;
      theta.segment(super.offset(c), p.size()) = theta_sub.segment(sub.offset(match), p.size());
    } else {
      GuessContext ctx{wv.tau, small, wv.tau[wv.tau.size() / 2]};
      const auto g = p.initial_guess(ctx);
      for (int i = 0; i < p.size(); ++i) theta(super.offset(c) + i) = g[static_cast<std::size_t>(i)];
    }
  }
  return theta;
}

FitResult fit_gmwm(const WaveletVariance& wv, const Model& model_in, const FitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("fit options: " + why);
  check_model_fits_levels(model_in, wv.levels());
  if (model_in.num_components() == 0) throw InputError("fit: the model has no component");
  for (int j = 0; j < wv.levels(); ++j)
    if (!std::isfinite(wv.wv[static_cast<std::size_t>(j)]))
      throw InputError(
          "fit: the wavelet variance at level " + std::to_string(first_level(wv) + j) + " is undefined (" +
          (wv.notes[static_cast<std::size_t>(j)].empty() ? "no value" : wv.notes[static_cast<std::size_t>(j)]) + ")");

  Problem P;
  P.wv = &wv;
  P.model = &model_in;
  P.nuhat = wv.values();
  P.omega = options.omega_matrix ? *options.omega_matrix : diagonal_omega(wv);
  check_size_match("fit_gmwm", "omega", static_cast<std::size_t>(P.omega.rows()), "levels",
                   static_cast<std::size_t>(wv.levels()));

  auto optimise = [&](std::vector<Eigen::VectorXd> extra) {
    if (options.nested_starts)
      for (auto& s : nested_starts(wv, model_in, P.omega, options)) extra.push_back(std::move(s));
    std::vector<Eigen::VectorXd> starts;
    for (auto& s : extra)
      if (model_in.validate(s).empty()) starts.push_back(s);
    const int placements = starts.empty() ? std::max(options.multistarts, 1) : options.multistarts;
    if (placements > 0)
      for (auto& c : detail::candidate_starts(wv, model_in, P.omega, placements)) starts.push_back(c);
    LocalResult best;
    for (const auto& s : starts) {
      LocalResult r = local_optimise(P, model_in.to_unconstrained(s), options);
      if (r.value < best.value) best = r;
    }
    // A component that collapsed to nothing stays there (its size's gradient vanishes
    // with it): re-place it, keep the rest, and see whether the objective improves.
    for (int round = 0; round < model_in.num_components() && std::isfinite(best.value); ++round) {
      bool improved = false;
      const Eigen::VectorXd at = model_in.from_unconstrained(best.u);
      for (const auto& s : detail::revival_starts(wv, model_in, at, P.omega, kRevivalStarts)) {
        LocalResult r = local_optimise(P, model_in.to_unconstrained(s), options);
        if (r.value < best.value * (1.0 - kRevivalGain)) {
          best = r;
          improved = true;
        }
      }
      if (!improved) break;
    }
    if (std::isfinite(best.value)) newton_polish(P, best);
    return best;
  };

  std::vector<Eigen::VectorXd> extra = options.starts;
  LocalResult best = optimise(extra);
  bool omega_is_v_inverse = false;
  Eigen::MatrixXd v_for_omega;
  if (!options.omega_matrix && options.omega != OmegaKind::kDiag && std::isfinite(best.value)) {
    // Pilot (diag) fit done: build V at the pilot estimate, then refit with V^-1.
    const Eigen::VectorXd pilot = model_in.from_unconstrained(best.u);
    if (options.omega == OmegaKind::kFull || options.omega == OmegaKind::kModel) {
      // A robust WV's variance is the Gaussian one inflated by 1/efficiency (spec s.2).
      v_for_omega = model_wv_covariance(model_in, pilot, wv) / wv.efficiency.value_or(1.0);
    } else {
      ClassicalWvEstimator classical;  // below: a WV drop_fine_levels cut simulates its own levels
      const FromLevelEstimator from_level(options.estimator ? *options.estimator : classical, first_level(wv));
      v_for_omega = bootstrap_wv_covariance(model_in, pilot, wv.n, wv.levels(), options.bootstrap_replicates,
                                            options.seed, from_level, wv.alpha, options.progress);
    }
    if (options.omega == OmegaKind::kModel) {
      // diag(1 / V_jj); a level whose V_jj is not positive and finite keeps the data's weight.
      for (Eigen::Index j = 0; j < P.omega.rows(); ++j) {
        const double vj = v_for_omega(j, j);
        const double keep = P.omega(j, j);
        P.omega.row(j).setZero();
        P.omega(j, j) = vj > 0.0 && std::isfinite(vj) ? 1.0 / vj : keep;
      }
    } else {
      P.omega = v_for_omega.completeOrthogonalDecomposition().pseudoInverse();
      P.omega = 0.5 * (P.omega + P.omega.transpose());
      omega_is_v_inverse = true;
    }
    extra.push_back(pilot);
    best = optimise(extra);
  }

  FitResult r;
  r.evaluations = P.evaluations;
  r.omega = P.omega;
  if (!std::isfinite(best.value)) {
    r.model = model_in;
    r.status = FitStatus::kFailed;
    r.message = "no starting point gave a finite objective";
    r.theta = Eigen::VectorXd::Constant(model_in.num_parameters(), std::numeric_limits<double>::quiet_NaN());
    return r;
  }
  r.status = status_of(best.code, P, best.u, best.value, r.message);
  Eigen::VectorXd theta = model_in.from_unconstrained(best.u);
  // Signed-magnitude parameters (DR's omega) come out positive: the WV cannot see their
  // sign, so it is carried from the first start (or given value) that has one.
  for (int k = 0; k < model_in.num_parameters(); ++k) {
    if (!model_in.spec_of(k).signed_magnitude) continue;
    double sign = 0.0;
    for (const auto& s : options.starts)
      if (s.size() == theta.size() && std::isfinite(s(k)) && s(k) != 0.0) {
        sign = s(k);
        break;
      }
    if (sign == 0.0) {
      const Eigen::VectorXd given = model_in.given_values();
      if (std::isfinite(given(k)) && given(k) != 0.0) sign = given(k);
    }
    if (sign < 0.0) theta(k) = -theta(k);
  }
  r.model = model_in.canonical(&theta);
  r.theta = theta;
  r.objective = gmwm_objective(wv, r.model, r.theta, P.omega);
  r.implied_wv = r.model.wv(r.theta, wv.tau);
  if (v_for_omega.size()) r.wv_covariance = v_for_omega;
  const auto t1 = std::chrono::steady_clock::now();
  r.seconds_optimise = std::chrono::duration<double>(t1 - t0).count();
  if (r.status != FitStatus::kConverged && options.log_not_converged)
    spdlog::get("gmwm") ? spdlog::get("gmwm")->warn("fit of {}: {}", r.model.to_string(), r.message)
                        : spdlog::warn("fit of {}: {}", r.model.to_string(), r.message);
  if (options.inference) {
    // The parameters' covariance is measured with Cov(nuhat) at the final estimate, not at
    // the pilot that formed the weights: the pilot is the data-weighted fit, whose
    // long-memory terms come out low (a random walk's gamma2 by ~20% at 2^17), and V at the
    // coarse levels scales with them, so the standard errors came out ~20% short and the
    // 95% intervals of a random walk covered 84-88% (issue 27; tools/bench/bench_random_walk).
    // The goodness of fit is measured with that V too (Satterthwaite: Omega is the pilot's
    // weights, no longer V^-1): with the pilot's V it rejected true models in 11.5-14% of
    // series at 5% (issue 43, item 4; tools/bench/bench_gof_level). A bootstrap V is the
    // user's own estimate and serves both.
    Eigen::MatrixXd v_final;
    if (v_for_omega.size() && options.omega != OmegaKind::kBootstrap && !wv.covariance)
      v_final = wv_covariance_at(wv, r.model, r.theta);
    detail::run_inference(wv, options, omega_is_v_inverse, r, v_final.size() ? &v_final : nullptr);
  }
  r.seconds_inference = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  return r;
}

std::string rejection_summary(const FitResult& fit, double freq, bool freq_known, double level,
                              std::span<const int> replicate_levels) {
  if (!std::isfinite(fit.gof.p_value) || fit.gof.p_value >= level) return {};
  std::ostringstream os;
  os.precision(3);
  os << "rejected at " << 100.0 * level << "% (GoF p = " << fit.gof.p_value << ")";
  const auto worst = fit.worst_levels(3);
  if (!worst.empty()) {
    os << ": the data depart most at ";
    for (std::size_t i = 0; i < worst.size(); ++i) {
      const auto& m = worst[i];
      os << (i ? ", " : "");
      int first = 0;  // stacked levels: name the replicate
      for (std::size_t k = 0; k < replicate_levels.size(); ++k) {
        if (m.level <= first + replicate_levels[k]) {
          os << "replicate " << k + 1 << " at ";
          break;
        }
        first += replicate_levels[k];
      }
      if (freq_known)
        os << m.tau / freq << " s";
      else
        os << "tau = " << m.tau;
      os << " (data/model " << m.ratio << ", z = " << m.z << ")";
    }
  }
  return os.str();
}

std::string degeneracy_summary(const FitResult& fit) {
  if (!fit.degenerate()) return {};
  std::string collapsed, flat;
  for (int k = 0; k < static_cast<int>(fit.interval.size()); ++k) {
    const IntervalKind kind = fit.interval[static_cast<std::size_t>(k)];
    const int c = fit.model.component_of(k);
    if (kind == IntervalKind::kBoundary && k == fit.model.offset(c))
      collapsed += (collapsed.empty() ? "" : ", ") +
                   fit.model.components()[static_cast<std::size_t>(c)].process->name() + "[" + std::to_string(c + 1) +
                   "]";
    if (kind == IntervalKind::kNotIdentified) flat += (flat.empty() ? "" : ", ") + fit.model.parameter_label(k);
  }
  std::string out = "degenerate fit:";
  if (!collapsed.empty()) out += " " + collapsed + " collapsed to nothing (no share of the WV at any scale)";
  if (!flat.empty()) out += std::string(collapsed.empty() ? "" : ";") + " " + flat + " not identified (flat objective)";
  return out + "; the intervals describe the rest only";
}

std::string FitResult::Report() const {
  std::ostringstream os;
  os.precision(6);
  os << "GMWM fit of " << model.to_string() << "\n";
  os << "  status: " << to_string(status) << " (" << message << "), " << evaluations << " evaluations\n";
  os << "  objective: " << objective << "\n";
  for (int k = 0; k < theta.size(); ++k) {
    os << "  " << model.parameter_label(k) << " = " << theta(k);
    if (se.size() == theta.size()) os << "  (se " << se(k) << ", CI [" << ci_low(k) << ", " << ci_high(k) << "])";
    os << "\n";
  }
  if (gof.df > 0)
    os << "  goodness of fit: statistic " << gof.statistic << ", df " << gof.df << ", p-value " << gof.p_value << " ("
       << gof.method << ")\n";
  for (const auto& n : notes) os << "  note: " << n << "\n";
  os << "  time: optimisation " << seconds_optimise << " s, inference " << seconds_inference << " s\n";
  return os.str();
}

double orient_by_series(FitResult& fit, std::span<const double> x) {
  // Least-squares slope of x on t = 0..n-1: sum (t - tbar)(x_t - xbar) / sum (t - tbar)^2,
  // accumulated in long double (n up to 1e9: sum t^2 ~ 1e27).
  const auto n = static_cast<long double>(x.size());
  if (x.size() < 2) return 0.0;
  const long double tbar = (n - 1.0L) / 2.0L;
  long double sxy = 0.0L, mean = 0.0L;
  for_each_block(x, [&](std::span<const double> part, std::size_t) {
    for (double v : part) mean += v;
  });
  mean /= n;
  for_each_block(x, [&](std::span<const double> part, std::size_t at) {
    for (std::size_t i = 0; i < part.size(); ++i) sxy += (static_cast<long double>(at + i) - tbar) * (part[i] - mean);
  });
  const long double sxx = n * (n * n - 1.0L) / 12.0L;
  const double slope = static_cast<double>(sxy / sxx);
  orient_by_slope(fit, slope);
  return slope;
}

bool has_sign_from_series(const FitResult& fit) {
  for (int k = 0; k < fit.model.num_parameters(); ++k)
    if (fit.model.spec_of(k).signed_magnitude) return true;
  return false;
}

void orient_by_slope(FitResult& fit, double slope) {
  if (fit.theta.size() != fit.model.num_parameters()) return;
  std::vector<int> flipped;
  for (int k = 0; k < fit.model.num_parameters(); ++k) {
    if (!fit.model.spec_of(k).signed_magnitude || !((slope < 0.0) != (fit.theta(k) < 0.0))) continue;
    fit.theta(k) = -fit.theta(k);
    if (fit.ci_low.size() == fit.theta.size()) {
      const double lo = fit.ci_low(k);
      fit.ci_low(k) = -fit.ci_high(k);
      fit.ci_high(k) = -lo;
    }
    flipped.push_back(k);
  }
  // The covariance's rows/columns of a flipped parameter change sign with it.
  if (fit.covariance.rows() == fit.theta.size())
    for (int k : flipped) {
      fit.covariance.row(k) *= -1.0;
      fit.covariance.col(k) *= -1.0;
    }
}

}  // namespace gmwm
