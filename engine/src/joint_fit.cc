#include "gmwm/engine/joint_fit.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/random/uniform_int_distribution.hpp>

#include "fit_internal.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm {
namespace {

// The replicate test's Omega: at most this many updates theta -> argmin under V(theta)^-1,
// stopping once no parameter moves by more than kOmegaSettled (relative).
constexpr int kOmegaUpdates = 4;
constexpr double kOmegaSettled = 1e-3;

std::string replicate_name(std::size_t k) { return "replicate " + std::to_string(k + 1); }

// Stage 0: every replicate usable for the model, the options supported.
void check_inputs(std::span<const WaveletVariance> wvs, const Model& model, const FitOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("fit options: " + why);
  if (wvs.empty()) throw InputError("joint fit: no replicate given");
  if (model.num_components() == 0) throw InputError("joint fit: the model has no component");
  if (options.omega == OmegaKind::kBootstrap)
    throw InputError("joint fit: a bootstrap Omega is not supported for replicates (use diag or full)");
  if (options.omega_matrix)
    throw InputError("joint fit: a caller-given Omega is not supported (each replicate gets its own)");
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    try {
      check_model_fits_levels(model, wvs[k].levels());
    } catch (const InputError& e) {
      throw InputError(replicate_name(k) + ": " + e.what());
    }
    for (int j = 0; j < wvs[k].levels(); ++j)
      if (!std::isfinite(wvs[k].wv[static_cast<std::size_t>(j)]))
        throw InputError(replicate_name(k) + ": the wavelet variance at level " + std::to_string(j + 1) +
                         " is undefined");
  }
}

// Replicates of one length, levels and efficiency share their model-based V_k (and its
// inverse): computed once per such group (a fleet's units are mostly of one length, and
// one V costs ~20 ms at 2^18 samples). group[k] is the first replicate of k's group.
std::vector<std::size_t> covariance_groups(std::span<const WaveletVariance> wvs) {
  std::vector<std::size_t> group(wvs.size());
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    group[k] = k;
    for (std::size_t i = 0; i < k; ++i)
      if (group[i] == i && wvs[i].n == wvs[k].n && wvs[i].levels() == wvs[k].levels() &&
          wvs[i].coefficients == wvs[k].coefficients &&
          wvs[i].efficiency.value_or(1.0) == wvs[k].efficiency.value_or(1.0)) {
        group[k] = i;
        break;
      }
  }
  return group;
}

// V_k for every replicate at theta (in parallel over the distinct groups).
std::vector<Eigen::MatrixXd> model_covariances(std::span<const WaveletVariance> wvs, const Model& model,
                                               const Eigen::VectorXd& theta) {
  const std::vector<std::size_t> group = covariance_groups(wvs);
  std::vector<std::size_t> heads;
  for (std::size_t k = 0; k < wvs.size(); ++k)
    if (group[k] == k) heads.push_back(k);
  std::vector<Eigen::MatrixXd> v(wvs.size());
  gmwm::parallel_for(std::size_t{0}, heads.size(), [&](std::size_t h) {
    const WaveletVariance& w = wvs[heads[h]];
    v[heads[h]] = model_wv_covariance(model, theta, w) / w.efficiency.value_or(1.0);
  });
  for (std::size_t k = 0; k < wvs.size(); ++k)
    if (group[k] != k) v[k] = v[group[k]];
  return v;
}

Eigen::MatrixXd inverse(const Eigen::MatrixXd& v) {
  Eigen::MatrixXd w = v.completeOrthogonalDecomposition().pseudoInverse();
  return 0.5 * (w + w.transpose());
}

// V_k^-1 (pseudo-inverse, symmetrised) for every replicate, once per group of equal V_k.
std::vector<Eigen::MatrixXd> inverses(std::span<const WaveletVariance> wvs, const std::vector<Eigen::MatrixXd>& v) {
  const std::vector<std::size_t> group = covariance_groups(wvs);
  std::vector<Eigen::MatrixXd> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = group[k] == k ? inverse(v[k]) : out[group[k]];
  return out;
}

// Stage 1: the single-signal fits (in parallel; each is deterministic on its own).
std::vector<FitResult> single_fits(std::span<const WaveletVariance> wvs, const Model& model,
                                   const FitOptions& options) {
  std::vector<FitResult> singles(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t k) { singles[k] = fit_gmwm(wvs[k], model, options); });
  return singles;
}

// Stage 2: AGMWM, the average of the single estimates, with its standard error.
void average_estimates(const std::vector<FitResult>& singles, int p, JointFitResult& out) {
  std::vector<const Eigen::VectorXd*> ok;
  for (const auto& s : singles)
    if (s.status != FitStatus::kFailed && s.theta.size() == p && s.theta.allFinite()) ok.push_back(&s.theta);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.agmwm = Eigen::VectorXd::Constant(p, nan);
  out.agmwm_se = Eigen::VectorXd::Constant(p, nan);
  if (ok.empty()) return;
  out.agmwm.setZero();
  for (const auto* t : ok) out.agmwm += *t;
  out.agmwm /= static_cast<double>(ok.size());
  if (ok.size() < 2) return;
  Eigen::VectorXd ss = Eigen::VectorXd::Zero(p);
  for (const auto* t : ok) ss += (*t - out.agmwm).cwiseAbs2();
  out.agmwm_se = (ss / static_cast<double>(ok.size() - 1) / static_cast<double>(ok.size())).cwiseSqrt();
}

// A minimisation of one WV's objective under a fixed `omega`, from `starts`.
FitResult minimise_one(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega,
                       const std::vector<Eigen::VectorXd>& starts, const FitOptions& options) {
  FitOptions o = options;
  o.omega_matrix = omega;
  o.starts = starts;
  o.nested_starts = false;  // the replicates' own fits already carry their nested starts
  o.multistarts = 1;
  o.inference = false;
  return fit_gmwm(wv, model, o);
}

// Stage 3: the joint minimisation of the stacked objective, on its reduction, from
// `starts`. The objective returned is the stacked one (the reduced one plus C).
FitResult minimise(const ReducedReplicates& reduced, const Model& model, const std::vector<Eigen::VectorXd>& starts,
                   const FitOptions& options) {
  FitResult f = minimise_one(reduced.wv, model, reduced.weight, starts, options);
  if (f.status != FitStatus::kFailed) f.objective += reduced.within;
  return f;
}

// The inference's boundary rule (engine/src/inference.cc, kBoundaryShare): a component
// whose share of the implied WV is below 1e-8 at every level is left out of A.
constexpr double kInferenceBoundaryShare = 1e-8;

// The Jacobian at tau without the parameters of components on the boundary (as the
// inference leaves them out), for the stacked goodness of fit.
Eigen::MatrixXd active_jacobian(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau) {
  const Eigen::VectorXd nu = model.wv(theta, tau);
  const Eigen::MatrixXd full = model.jacobian(theta, tau);
  std::vector<Eigen::Index> keep;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& proc = *model.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> part(tau.size());
    proc.wv({theta.data() + model.offset(c), static_cast<std::size_t>(proc.size())}, tau, part);
    double share = 0.0;
    for (std::size_t j = 0; j < tau.size(); ++j)
      share = std::max(share, std::abs(part[j]) / std::max(std::abs(nu(static_cast<Eigen::Index>(j))), 1e-300));
    if (share < kInferenceBoundaryShare) continue;
    for (int i = 0; i < proc.size(); ++i) keep.push_back(model.offset(c) + i);
  }
  Eigen::MatrixXd A(full.rows(), static_cast<Eigen::Index>(keep.size()));
  for (Eigen::Index a = 0; a < A.cols(); ++a) A.col(a) = full.col(keep[static_cast<std::size_t>(a)]);
  return A;
}

// The stacked levels' misfits (replicate 1's levels, then replicate 2's, ...): z under
// each replicate's own V_k, as the inference of the stacked problem gave them.
std::vector<LevelMisfit> stacked_misfits(std::span<const WaveletVariance> wvs, const FitResult& fit,
                                         const std::vector<Eigen::MatrixXd>& v) {
  std::vector<LevelMisfit> out;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::VectorXd nu = fit.model.wv(fit.theta, wvs[k].tau);
    for (int j = 0; j < wvs[k].levels(); ++j) {
      LevelMisfit m;
      m.level = static_cast<int>(out.size()) + 1;
      m.tau = wvs[k].tau[static_cast<std::size_t>(j)];
      m.ratio = wvs[k].wv[static_cast<std::size_t>(j)] / nu(j);
      const double sd = std::sqrt(v[k](j, j));
      m.z = sd > 0.0 ? (wvs[k].wv[static_cast<std::size_t>(j)] - nu(j)) / sd : std::numeric_limits<double>::quiet_NaN();
      out.push_back(m);
    }
  }
  return out;
}

// The model-based weights of the joint fit from V_k: diag(1 / V_k,jj) (kDiag, kModel) or
// V_k^-1 (kFull).
std::vector<Eigen::MatrixXd> model_weights(std::span<const WaveletVariance> wvs, const std::vector<Eigen::MatrixXd>& v,
                                           OmegaKind kind) {
  if (kind == OmegaKind::kFull) return inverses(wvs, v);
  std::vector<Eigen::MatrixXd> omegas;
  for (const auto& vk : v) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(vk.rows(), vk.cols());
    for (Eigen::Index j = 0; j < vk.rows(); ++j)
      d(j, j) = vk(j, j) > 0.0 && std::isfinite(vk(j, j)) ? 1.0 / vk(j, j) : 0.0;
    omegas.push_back(std::move(d));
  }
  return omegas;
}

// Stage 4: the joint fit's objective terms and, with options.inference, its inference:
// the sandwich of the reduced problem (the stacked one's), then the goodness of fit and
// the per-level misfits of the stacked problem. `v`: the V_k the weights were formed from.
void finish_joint(std::span<const WaveletVariance> wvs, const FitOptions& options, bool omega_is_v_inverse,
                  std::vector<Eigen::MatrixXd> v, JointFitResult& out, FitResult& joint) {
  double total = 0.0;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::VectorXd r = wvs[k].values() - joint.model.wv(joint.theta, wvs[k].tau);
    out.objective_share.push_back(r.dot(out.omegas[k] * r));
    total += out.objective_share.back();
  }
  joint.objective = total;
  if (!options.inference) return;
  // The parameters' covariance with V at the final estimate (fit.cc says why); under
  // V^-1 weights the goodness of fit keeps the pilot's V they were formed from.
  const std::vector<Eigen::MatrixXd> v_final = model_covariances(wvs, joint.model, joint.theta);
  if (!omega_is_v_inverse || v.size() != wvs.size()) v = v_final;
  const ReducedReplicates gof = reduce_replicates(wvs, out.omegas, v);
  const ReducedReplicates par = reduce_replicates(wvs, out.omegas, v_final);
  joint.omega = gof.weight;
  joint.wv_covariance = *gof.wv.covariance;
  joint.implied_wv = joint.model.wv(joint.theta, gof.wv.tau);
  detail::run_inference(gof.wv, options, omega_is_v_inverse, joint, &*par.wv.covariance);
  const int p = joint.model.num_parameters();
  joint.gof = stacked_goodness_of_fit(gof, active_jacobian(joint.model, joint.theta, gof.wv.tau), total,
                                      static_cast<double>(gof.stacked_levels - p), omega_is_v_inverse);
  joint.misfits = stacked_misfits(wvs, joint, v);
}

}  // namespace

Eigen::MatrixXd block_diagonal(std::span<const Eigen::MatrixXd> blocks) {
  Eigen::Index n = 0;
  for (const auto& b : blocks) n += b.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index at = 0;
  for (const auto& b : blocks) {
    out.block(at, at, b.rows(), b.cols()) = b;
    at += b.rows();
  }
  return out;
}

WaveletVariance stack_wv(std::span<const WaveletVariance> wvs) {
  WaveletVariance s;
  if (wvs.empty()) return s;
  s.alpha = wvs.front().alpha;
  s.estimator = wvs.front().estimator;
  s.efficiency = wvs.front().efficiency;
  for (const auto& w : wvs) {
    s.n = std::max(s.n, w.n);
    const auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    append(s.tau, w.tau);
    append(s.wv, w.wv);
    append(s.ci_low, w.ci_low);
    append(s.ci_high, w.ci_high);
    append(s.variance, w.variance);
    append(s.eta, w.eta);
    append(s.coefficients, w.coefficients);
    append(s.notes, w.notes);
  }
  s.notes.resize(s.wv.size());
  return s;
}

namespace {

// A level's tau agrees across replicates to this relative tolerance (2^j written by each
// estimator: equal bit for bit in practice).
constexpr double kTauTolerance = 1e-12;

// The common levels: the longest replicate's taus; every replicate's must be a prefix.
const WaveletVariance& longest_of(std::span<const WaveletVariance> wvs) {
  const WaveletVariance* longest = &wvs.front();
  for (const auto& w : wvs)
    if (w.levels() > longest->levels()) longest = &w;
  for (std::size_t k = 0; k < wvs.size(); ++k)
    for (int j = 0; j < wvs[k].levels(); ++j) {
      const double a = wvs[k].tau[static_cast<std::size_t>(j)], b = longest->tau[static_cast<std::size_t>(j)];
      if (!(std::abs(a - b) <= kTauTolerance * std::abs(b)))
        throw InvalidArgument("reduce_replicates: replicate " + std::to_string(k + 1) + "'s level " +
                              std::to_string(j + 1) + " is at tau " + std::to_string(a) + ", the others' at " +
                              std::to_string(b));
    }
  return *longest;
}

// x restricted to the kept levels.
Eigen::MatrixXd kept_block(const Eigen::MatrixXd& x, const std::vector<int>& kept) {
  const auto m = static_cast<Eigen::Index>(kept.size());
  Eigen::MatrixXd out(m, m);
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b)
      out(a, b) = x(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]);
  return out;
}

// Solves W X = B for PSD W: Cholesky of W scaled to a unit diagonal (the levels' weights
// span many orders of magnitude; scaled, W is as well conditioned as the levels'
// correlation), else its pseudo-inverse (B lies in W's range).
Eigen::MatrixXd solve_weight(const Eigen::MatrixXd& w, const Eigen::MatrixXd& b) {
  const Eigen::VectorXd s = w.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd ws = s.asDiagonal() * w * s.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (ws + ws.transpose()));
  if (llt.info() == Eigen::Success) {
    Eigen::MatrixXd x = s.asDiagonal() * llt.solve(s.asDiagonal() * b);
    if (x.allFinite()) return x;
  }
  return s.asDiagonal() * (ws.completeOrthogonalDecomposition().pseudoInverse() * (s.asDiagonal() * b));
}

// The V_k terms of a reduction: U, U2 and the traces of the stacked goodness of fit, and
// Var(nutilde) = W^-1 U W^-1 as the reduced WV's covariance (and its diagonal as its variance).
void add_covariance_terms(std::span<const WaveletVariance> wvs, std::span<const Eigen::MatrixXd> omegas,
                          std::span<const Eigen::MatrixXd> covariances, Eigen::Index J, ReducedReplicates& r) {
  WaveletVariance& w = r.wv;
  const auto m = static_cast<Eigen::Index>(r.kept.size());
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(J, J), U2 = Eigen::MatrixXd::Zero(J, J);
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::Index Jk = wvs[k].levels();
    const Eigen::MatrixXd ov = omegas[k] * covariances[k];
    const Eigen::MatrixXd ovo = ov * omegas[k];
    U.topLeftCorner(Jk, Jk) += ovo;
    U2.topLeftCorner(Jk, Jk) += ov * ovo;
    r.trace_ov += ov.trace();
    r.trace_ov2 += (ov * ov).trace();
  }
  r.meat = kept_block(0.5 * (U + U.transpose()), r.kept);
  r.meat2 = kept_block(0.5 * (U2 + U2.transpose()), r.kept);
  const Eigen::MatrixXd wu = solve_weight(r.weight, r.meat);     // W^-1 U
  Eigen::MatrixXd cov = solve_weight(r.weight, wu.transpose());  // W^-1 U W^-1
  cov = 0.5 * (cov + cov.transpose());
  for (Eigen::Index a = 0; a < m; ++a) w.variance[static_cast<std::size_t>(a)] = cov(a, a);
  w.covariance = std::move(cov);
}

}  // namespace

ReducedReplicates reduce_replicates(std::span<const WaveletVariance> wvs, std::span<const Eigen::MatrixXd> omegas,
                                    std::span<const Eigen::MatrixXd> covariances) {
  if (wvs.empty()) throw InvalidArgument("reduce_replicates: no replicate given");
  check_size_match("reduce_replicates", "omegas", omegas.size(), "replicates", wvs.size());
  if (!covariances.empty())
    check_size_match("reduce_replicates", "covariances", covariances.size(), "replicates", wvs.size());
  const WaveletVariance& longest = longest_of(wvs);
  const Eigen::Index J = longest.levels();
  ReducedReplicates r;
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(J, J);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(J), eta = Eigen::VectorXd::Zero(J);
  std::vector<std::int64_t> coefficients(static_cast<std::size_t>(J), 0);
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::Index Jk = wvs[k].levels();
    if (omegas[k].rows() != Jk || omegas[k].cols() != Jk ||
        (!covariances.empty() && (covariances[k].rows() != Jk || covariances[k].cols() != Jk)))
      throw InvalidArgument("reduce_replicates: replicate " + std::to_string(k + 1) + " has " + std::to_string(Jk) +
                            " levels, its Omega or V another size");
    W.topLeftCorner(Jk, Jk) += omegas[k];
    b.head(Jk) += omegas[k] * wvs[k].values();
    for (Eigen::Index j = 0; j < Jk; ++j) {
      eta(j) += wvs[k].eta.size() == static_cast<std::size_t>(Jk) ? wvs[k].eta[static_cast<std::size_t>(j)] : 0.0;
      if (wvs[k].coefficients.size() == static_cast<std::size_t>(Jk))
        coefficients[static_cast<std::size_t>(j)] += wvs[k].coefficients[static_cast<std::size_t>(j)];
    }
    r.stacked_levels += static_cast<int>(Jk);
  }
  for (Eigen::Index j = 0; j < J; ++j)
    if (W(j, j) > 0.0) r.kept.push_back(static_cast<int>(j));
  if (r.kept.empty()) throw InvalidArgument("reduce_replicates: no level has a positive weight");
  const auto m = static_cast<Eigen::Index>(r.kept.size());
  r.weight = kept_block(W, r.kept);
  r.weight = 0.5 * (r.weight + r.weight.transpose());
  Eigen::VectorXd bk(m);
  for (Eigen::Index a = 0; a < m; ++a) bk(a) = b(r.kept[static_cast<std::size_t>(a)]);
  const Eigen::VectorXd nutilde = solve_weight(r.weight, bk);

  // C = sum_k (nuhat_k - nutilde)' Omega_k (nuhat_k - nutilde), each term >= 0.
  Eigen::VectorXd full_nutilde = Eigen::VectorXd::Zero(J);
  for (Eigen::Index a = 0; a < m; ++a) full_nutilde(r.kept[static_cast<std::size_t>(a)]) = nutilde(a);
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const Eigen::Index Jk = wvs[k].levels();
    const Eigen::VectorXd d = wvs[k].values() - full_nutilde.head(Jk);
    r.within += d.dot(omegas[k] * d);
  }

  WaveletVariance& w = r.wv;
  w.alpha = wvs.front().alpha;
  w.estimator = wvs.front().estimator;
  w.efficiency = wvs.front().efficiency;
  w.n = longest.n;
  for (Eigen::Index a = 0; a < m; ++a) {
    const auto j = static_cast<std::size_t>(r.kept[static_cast<std::size_t>(a)]);
    w.tau.push_back(longest.tau[j]);
    w.wv.push_back(nutilde(a));
    w.eta.push_back(eta(static_cast<Eigen::Index>(j)));
    w.coefficients.push_back(coefficients[j]);
    const double e = eta(static_cast<Eigen::Index>(j));
    const auto ci = e > 0.0 && nutilde(a) > 0.0
                        ? chi_square_ci(nutilde(a), e, w.alpha)
                        : std::pair{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    w.ci_low.push_back(ci.first);
    w.ci_high.push_back(ci.second);
    w.variance.push_back(e > 0.0 ? 2.0 * nutilde(a) * nutilde(a) / e : std::numeric_limits<double>::quiet_NaN());
  }
  w.notes.resize(static_cast<std::size_t>(m));
  if (covariances.empty()) return r;

  add_covariance_terms(wvs, omegas, covariances, static_cast<Eigen::Index>(longest.levels()), r);
  return r;
}

GoodnessOfFit stacked_goodness_of_fit(const ReducedReplicates& r, const Eigen::MatrixXd& A, double objective, double df,
                                      bool omega_is_v_inverse) {
  if (omega_is_v_inverse || df <= 0)  // the chi-square, or no test: neither reads V
    return goodness_of_fit(A, objective, df, r.weight, r.weight, omega_is_v_inverse);
  if (r.meat.size() == 0)
    throw InvalidArgument("stacked_goodness_of_fit: the reduction was made without the replicates' covariances");
  GoodnessOfFit g;
  g.statistic = objective;
  g.df = df;
  const Eigen::MatrixXd B = A.transpose() * r.weight * A;
  const Eigen::MatrixXd Binv = B.completeOrthogonalDecomposition().pseudoInverse();
  const Eigen::MatrixXd BU = Binv * (A.transpose() * r.meat * A);
  const double t1 = r.trace_ov - BU.trace();
  const double t2 = r.trace_ov2 - 2.0 * (Binv * (A.transpose() * r.meat2 * A)).trace() + (BU * BU).trace();
  detail::satterthwaite_match(g, t1, t2);
  return g;
}

JointFitResult fit_gmwm_joint(std::span<const WaveletVariance> wvs, const Model& model_in, const FitOptions& options) {
  check_inputs(wvs, model_in, options);
  // Canonical from the start, so that every replicate's estimate lines up with the others.
  const Model model = model_in.canonical();
  const int p = model.num_parameters();
  JointFitResult out;
  for (const auto& w : wvs) out.levels.push_back(w.levels());

  out.singles = single_fits(wvs, model, options);
  average_estimates(out.singles, p, out);

  std::vector<Eigen::VectorXd> starts;
  for (const auto& s : out.singles)
    if (s.status != FitStatus::kFailed && s.theta.size() == p && s.theta.allFinite()) starts.push_back(s.theta);
  if (out.agmwm.allFinite()) starts.push_back(out.agmwm);
  for (const auto& s : options.starts) starts.push_back(s);

  for (const auto& w : wvs) out.omegas.push_back(diagonal_omega(w));
  FitResult joint = minimise(reduce_replicates(wvs, out.omegas), model, starts, options);

  bool omega_is_v_inverse = false;
  std::vector<Eigen::MatrixXd> v;
  if (joint.status != FitStatus::kFailed) {
    // That was the pilot, under each replicate's own data-based weights. Its weights
    // 1 / Var(nuhat_kj) ~ 1 / nuhat_kj^2 favour, at each coarse level, the replicate whose
    // WV came out lowest, so long-memory terms come out low, the more so the more
    // replicates there are (a resolved RW: RMSE 1.28 x AGMWM's at K = 3, 1.56 x at K = 6).
    // The weights are therefore model-based: V_k at the pilot, the same for every
    // replicate at a given scale and length; diag(1 / V_k,jj) (kDiag) or V_k^-1 (kFull).
    v = model_covariances(wvs, joint.model, joint.theta);
    std::vector<Eigen::MatrixXd> omegas = model_weights(wvs, v, options.omega);
    starts.push_back(joint.theta);
    FitResult refit = minimise(reduce_replicates(wvs, omegas), model, starts, options);
    if (refit.status != FitStatus::kFailed) {
      joint = std::move(refit);
      out.omegas = std::move(omegas);
      omega_is_v_inverse = options.omega == OmegaKind::kFull;
    } else {
      v.clear();
    }
  }
  if (joint.status != FitStatus::kFailed) finish_joint(wvs, options, omega_is_v_inverse, std::move(v), out, joint);
  out.joint = std::move(joint);
  return out;
}

const WvEstimator& replicate_estimator(std::span<const WvEstimator* const> each, std::size_t k,
                                       const WvEstimator* common, const WvEstimator& fallback) {
  if (k < each.size() && each[k]) return *each[k];
  return common ? *common : fallback;
}

void check_replicate_estimators(const std::string& what, std::span<const WvEstimator* const> each,
                                std::size_t replicates) {
  if (!each.empty() && each.size() != replicates)
    throw InputError(what + ": " + std::to_string(each.size()) + " estimators for " + std::to_string(replicates) +
                     " replicates (one per replicate, or none)");
}

const char* to_string(ReplicateCalibration c) {
  return c == ReplicateCalibration::kChiSquare ? "chi-square" : "bootstrap";
}

std::string ReplicateTestOptions::Validate() const {
  if (calibration == ReplicateCalibration::kBootstrap && bootstrap < 19)
    return "bootstrap must be at least 19 (a p-value of 0.05 needs 19 draws), got " + std::to_string(bootstrap);
  return fit.Validate();
}

namespace {

// T and H of a set of WVs under the per-replicate Omega_k, every minimisation started
// from `starts`; the replicates' own minimisations in parallel (each writes its slot).
struct Statistics {
  double t = 0.0, h = 0.0;
  std::vector<double> own;
};
Statistics statistics(std::span<const WaveletVariance> wvs, const Model& model,
                      const std::vector<Eigen::MatrixXd>& omegas, const std::vector<Eigen::VectorXd>& starts,
                      const FitOptions& options) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Statistics s;
  const FitResult joint = minimise(reduce_replicates(wvs, omegas), model, starts, options);
  s.t = joint.status == FitStatus::kFailed ? nan : joint.objective;
  s.own.assign(wvs.size(), nan);
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t k) {
    const FitResult f = minimise_one(wvs[k], model, omegas[k], starts, options);
    if (f.status != FitStatus::kFailed) s.own[k] = f.objective;
  });
  double sum = 0.0;
  for (double o : s.own) sum += o;
  // A replicate's own minimum cannot exceed the joint's share at the joint optimum: the
  // difference is >= 0 up to the optimiser's tolerance.
  s.h = std::max(0.0, s.t - sum);
  return s;
}

double upper_p(const std::vector<double>& null, double observed) {
  int above = 0;
  for (double v : null) above += v >= observed;
  return (1.0 + above) / (1.0 + static_cast<double>(null.size()));
}

// The bootstrap's theta and the Omega_k it shares with the data: iterated to a fixed
// point theta = argmin under V_k(theta)^-1. (A diag-Omega estimate puts the random walk
// low (weights 1 / nuhat_j^2 favour low draws at the coarse levels); V_k there is then
// too small for the data's coarse levels but right for draws from it, and the test
// rejected a shared theta in 25% of data sets at 5%.) Returns theta; `omegas` are its V_k^-1.
Eigen::VectorXd efficient_point(std::span<const WaveletVariance> wvs, const FitResult& j, const FitOptions& fit,
                                std::vector<Eigen::MatrixXd>& omegas) {
  Eigen::VectorXd theta = j.theta;
  for (int it = 0; it < kOmegaUpdates; ++it) {
    omegas = inverses(wvs, model_covariances(wvs, j.model, theta));
    const FitResult f = minimise(reduce_replicates(wvs, omegas), j.model, {theta, j.theta}, fit);
    if (f.status == FitStatus::kFailed) break;
    const bool settled = ((f.theta - theta).array().abs() <= kOmegaSettled * theta.array().abs()).all();
    theta = f.theta;
    if (settled) break;
  }
  omegas = inverses(wvs, model_covariances(wvs, j.model, theta));
  return theta;
}

// The chi-square calibration: H ~ chi2((K - 1) q), T ~ chi2(sum_k J_k - q), q the
// parameters off the boundary at theta (the inference's rule).
void chi_square_p(std::span<const WaveletVariance> wvs, const Model& model, const Eigen::VectorXd& theta,
                  ReplicateTest& out) {
  int stacked_levels = 0;
  for (const auto& w : wvs) stacked_levels += w.levels();
  const auto q = static_cast<double>(active_jacobian(model, theta, longest_of(wvs).tau).cols());
  const auto K = static_cast<double>(wvs.size());
  out.calibration = ReplicateCalibration::kChiSquare;
  out.df_heterogeneity = (K - 1.0) * q;
  out.df_statistic = static_cast<double>(stacked_levels) - q;
  const auto upper = [](double x, double df) {
    if (!(df > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    return boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), std::max(x, 0.0)));
  };
  out.heterogeneity_p = upper(out.heterogeneity, out.df_heterogeneity);
  out.p_value = upper(out.statistic, out.df_statistic);
}

}  // namespace

ReplicateTest replicate_test(std::span<const WaveletVariance> wvs, const JointFitResult& joint,
                             const ReplicateTestOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("replicate test: " + why);
  const FitResult& j = joint.joint;
  if (j.status == FitStatus::kFailed || !j.theta.allFinite() || wvs.size() != joint.singles.size())
    throw InputError("replicate test: the joint fit has no usable estimate");
  check_replicate_estimators("replicate test", options.estimators, wvs.size());
  const Model& model = j.model;
  std::vector<Eigen::MatrixXd> omegas;
  const Eigen::VectorXd theta = efficient_point(wvs, j, options.fit, omegas);

  // The data and every draw alike: each minimisation starts from theta (and the WV's shape).
  const Statistics data = statistics(wvs, model, omegas, {theta}, options.fit);
  ReplicateTest out;
  out.statistic = data.t;
  out.heterogeneity = data.h;
  out.own_minimum = data.own;
  if (options.calibration == ReplicateCalibration::kChiSquare) {
    chi_square_p(wvs, model, theta, out);
    return out;
  }

  const ClassicalWvEstimator classical;
  FitOptions draw_fit = options.fit;
  draw_fit.log_not_converged = false;  // K + 1 minimisations per draw: their statuses are not the data's
  std::vector<double> t(static_cast<std::size_t>(options.bootstrap)), h(t.size());
  std::atomic<int> done{0};
  gmwm::parallel_for(0, options.bootstrap, [&](int b) {
    std::vector<WaveletVariance> sim;
    for (std::size_t k = 0; k < wvs.size(); ++k) {
      const std::vector<double> x =
          simulate(model, theta, wvs[k].n, options.seed, static_cast<std::uint64_t>(b) * wvs.size() + k);
      const WvEstimator& estimator = replicate_estimator(options.estimators, k, options.estimator, classical);
      sim.push_back(estimator.compute(x.data(), wvs[k].n, wvs[k].levels(), wvs[k].alpha));
    }
    bool finite = true;
    for (const auto& w : sim) finite &= w.values().allFinite();
    const Statistics s = finite ? statistics(sim, model, omegas, {theta}, draw_fit) : Statistics{NAN, NAN, {}};
    t[static_cast<std::size_t>(b)] = s.t;
    h[static_cast<std::size_t>(b)] = s.h;
    const int d = ++done;
    if (options.progress) options.progress(d, options.bootstrap);
  });
  std::vector<double> nt, nh;
  for (std::size_t b = 0; b < t.size(); ++b)
    if (std::isfinite(t[b]) && std::isfinite(h[b])) {
      nt.push_back(t[b]);
      nh.push_back(h[b]);
    }
  out.draws = static_cast<int>(nt.size());
  if (nt.empty()) throw InputError("replicate test: no bootstrap draw gave a finite statistic");
  out.p_value = upper_p(nt, out.statistic);
  out.heterogeneity_p = upper_p(nh, out.heterogeneity);
  return out;
}

namespace {

// Every count vector (m_1..m_K), sum K, in lexicographic order: the distinct resamples.
void multisets(int K, int at, int left, std::vector<int>& m, std::vector<std::vector<int>>& out) {
  if (at == K - 1) {
    m[static_cast<std::size_t>(at)] = left;
    out.push_back(m);
    return;
  }
  for (int c = left; c >= 0; --c) {
    m[static_cast<std::size_t>(at)] = c;
    multisets(K, at + 1, left - c, m, out);
  }
}

// log of K! / (prod m_i! K^K): the bootstrap probability of a resample with counts m.
double log_probability(const std::vector<int>& m) {
  const auto K = static_cast<double>(m.size());
  double l = std::lgamma(K + 1.0) - K * std::log(K);
  for (int c : m) l -= std::lgamma(static_cast<double>(c) + 1.0);
  return l;
}

// Weighted quantile q of values (weights sum to 1).
double weighted_quantile(std::vector<std::pair<double, double>> vw, double q) {
  std::sort(vw.begin(), vw.end());
  double acc = 0.0;
  for (const auto& [v, w] : vw) {
    acc += w;
    if (acc >= q) return v;
  }
  return vw.empty() ? std::numeric_limits<double>::quiet_NaN() : vw.back().first;
}

}  // namespace

ReplicateBootstrap replicate_bootstrap(std::span<const WaveletVariance> wvs, const JointFitResult& joint, double alpha,
                                       int max_draws, std::uint64_t seed, const FitOptions& fit) {
  const FitResult& j = joint.joint;
  if (j.status == FitStatus::kFailed || !j.theta.allFinite() || wvs.size() != joint.levels.size())
    throw InputError("replicate bootstrap: the joint fit has no usable estimate");
  if (!(alpha > 0.0 && alpha < 1.0)) throw InputError("replicate bootstrap: alpha must be in (0, 1)");
  if (max_draws < 10)
    throw InputError("replicate bootstrap: max_draws must be at least 10, got " + std::to_string(max_draws));
  const int K = static_cast<int>(wvs.size());
  if (K < 2) throw InputError("replicate bootstrap: needs at least 2 replicates, got " + std::to_string(K));
  // Each replicate's block of the joint Omega.
  if (joint.omegas.size() != wvs.size())
    throw InputError("replicate bootstrap: the joint fit has no weights for every replicate");
  const std::vector<Eigen::MatrixXd>& blocks = joint.omegas;
  // The resamples: all distinct ones with their probabilities, or max_draws drawn.
  std::vector<std::vector<int>> counts;
  std::vector<double> weight;
  ReplicateBootstrap out;
  {
    std::vector<int> m(static_cast<std::size_t>(K));
    std::vector<std::vector<int>> all;
    const double distinct = std::exp(std::lgamma(2.0 * K) - std::lgamma(K + 1.0) - std::lgamma(static_cast<double>(K)));
    if (distinct <= max_draws + 0.5) {
      multisets(K, 0, K, m, all);
      for (const auto& c : all) {
        counts.push_back(c);
        weight.push_back(std::exp(log_probability(c)));
      }
      out.exhaustive = true;
    } else {
      for (int b = 0; b < max_draws; ++b) {
        Rng rng = make_stream(seed, {0x7262u, static_cast<std::uint64_t>(b)});
        boost::random::uniform_int_distribution<int> pick(0, K - 1);
        std::vector<int> c(static_cast<std::size_t>(K), 0);
        for (int i = 0; i < K; ++i) ++c[static_cast<std::size_t>(pick(rng))];
        counts.push_back(c);
        weight.push_back(1.0 / max_draws);
      }
    }
  }
  std::vector<Eigen::VectorXd> thetas(counts.size());
  std::vector<char> ok(counts.size(), 0);
  gmwm::parallel_for(std::size_t{0}, counts.size(), [&](std::size_t b) {
    std::vector<WaveletVariance> part;
    std::vector<Eigen::MatrixXd> omega;
    for (int k = 0; k < K; ++k)
      for (int r = 0; r < counts[b][static_cast<std::size_t>(k)]; ++r) {
        part.push_back(wvs[static_cast<std::size_t>(k)]);
        omega.push_back(blocks[static_cast<std::size_t>(k)]);
      }
    std::vector<Eigen::VectorXd> starts = {j.theta};
    for (int k = 0; k < K; ++k) {
      const FitResult& own = joint.singles.size() == wvs.size() ? joint.singles[static_cast<std::size_t>(k)] : j;
      if (counts[b][static_cast<std::size_t>(k)] > 0 && own.status != FitStatus::kFailed && own.theta.allFinite() &&
          own.theta.size() == j.theta.size())
        starts.push_back(own.theta);
    }
    const FitResult f = minimise(reduce_replicates(part, omega), j.model, starts, fit);
    if (f.status == FitStatus::kFailed || !f.theta.allFinite()) return;
    thetas[b] = f.theta;
    // The WV cannot see a signed parameter's sign: the joint estimate's is kept.
    for (int k = 0; k < j.model.num_parameters(); ++k)
      if (j.model.spec_of(k).signed_magnitude && (j.theta(k) < 0.0) != (thetas[b](k) < 0.0))
        thetas[b](k) = -thetas[b](k);
    ok[b] = 1;
  });
  const Eigen::Index p = j.theta.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.ci_low = out.ci_high = out.percentile_low = out.percentile_high = out.se = Eigen::VectorXd::Constant(p, nan);
  double total = 0.0;
  for (std::size_t b = 0; b < counts.size(); ++b)
    if (ok[b]) {
      total += weight[b];
      ++out.draws;
    }
  if (out.draws == 0) return out;
  // The replicate-t interval: the bootstrap variance of a mean of K replicates is
  // (K - 1) / K times the usual s^2 / K, so it is inflated by K / (K - 1) and paired with
  // Student's t at K - 1 degrees of freedom (exact for a mean of K normal replicates);
  // built in the unconstrained space of each parameter (log for a variance, atanh for phi;
  // on |x| for a signed magnitude), as the sandwich intervals are.
  const double t = boost::math::quantile(boost::math::students_t(static_cast<double>(K - 1)), 1.0 - alpha / 2.0);
  const double inflate = std::sqrt(static_cast<double>(K) / static_cast<double>(K - 1));
  for (Eigen::Index i = 0; i < p; ++i) {
    std::vector<std::pair<double, double>> vw;
    for (std::size_t b = 0; b < counts.size(); ++b)
      if (ok[b]) vw.emplace_back(thetas[b](i), weight[b] / total);
    out.percentile_low(i) = weighted_quantile(vw, alpha / 2.0);
    out.percentile_high(i) = weighted_quantile(vw, 1.0 - alpha / 2.0);
    const auto& spec = j.model.spec_of(static_cast<int>(i));
    const double sign = spec.signed_magnitude && j.theta(i) < 0.0 ? -1.0 : 1.0;
    const auto u = [&](double x) { return to_unconstrained(spec.transform, spec.signed_magnitude ? std::abs(x) : x); };
    double mean = 0.0, var = 0.0, var_natural = 0.0, mean_natural = 0.0;
    for (const auto& [x, w] : vw) {
      mean += w * u(x);
      mean_natural += w * x;
    }
    for (const auto& [x, w] : vw) {
      var += w * (u(x) - mean) * (u(x) - mean);
      var_natural += w * (x - mean_natural) * (x - mean_natural);
    }
    out.se(i) = inflate * std::sqrt(var_natural);
    const double centre = u(j.theta(i));
    const double half = t * inflate * std::sqrt(var);
    if (!std::isfinite(centre) || !std::isfinite(half)) continue;
    if (j.interval.size() == static_cast<std::size_t>(p) &&
        (j.interval[static_cast<std::size_t>(i)] == IntervalKind::kBoundary ||
         j.interval[static_cast<std::size_t>(i)] == IntervalKind::kNotIdentified))
      continue;  // collapsed or not identified: no interval (see the header)
    const double a = from_unconstrained(spec.transform, centre - half);
    const double c = from_unconstrained(spec.transform, centre + half);
    out.ci_low(i) = sign > 0.0 ? a : -c;
    out.ci_high(i) = sign > 0.0 ? c : -a;
  }
  return out;
}

double orient_by_replicates(JointFitResult& r, std::span<const std::span<const double>> series) {
  check_size_match("orient_by_replicates", "series", series.size(), "replicates", r.singles.size());
  long double sxy = 0.0L, sxx = 0.0L;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const double slope = orient_by_series(r.singles[k], series[k]);
    const auto n = static_cast<long double>(series[k].size());
    const long double s = n * (n * n - 1.0L) / 12.0L;  // sum (t - tbar)^2
    sxy += static_cast<long double>(slope) * s;
    sxx += s;
  }
  const double pooled = sxx > 0.0L ? static_cast<double>(sxy / sxx) : 0.0;
  orient_by_slope(r.joint, pooled);
  average_estimates(r.singles, static_cast<int>(r.joint.theta.size()), r);  // with the signs now set
  return pooled;
}

std::string JointAnalysisOptions::Validate() const {
  if (std::string why = fit.Validate(); !why.empty()) return why;
  if (std::string why = test.Validate(); !why.empty()) return why;
  if (bootstrap_draws < 10) return "bootstrap draws must be at least 10, got " + std::to_string(bootstrap_draws);
  return {};
}

JointAnalysis analyse_replicates(std::span<const WaveletVariance> wvs, std::span<const std::span<const double>> series,
                                 const Model& model, const JointAnalysisOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("joint analysis: " + why);
  check_size_match("analyse_replicates", "series", series.size(), "replicates", wvs.size());
  JointAnalysis out;
  out.fit = fit_gmwm_joint(wvs, model, options.fit);
  out.pooled_slope = orient_by_replicates(out.fit, series);
  if (wvs.size() < 2 || out.fit.joint.status == FitStatus::kFailed) return out;
  ReplicateTestOptions t = options.test;
  t.fit = options.fit;
  t.fit.inference = false;
  out.test = replicate_test(wvs, out.fit, t);
  out.bootstrap =
      replicate_bootstrap(wvs, out.fit, options.fit.alpha, options.bootstrap_draws, options.test.seed, t.fit);
  return out;
}

}  // namespace gmwm
