// Inference for a GMWM fit (docs/statistics.md section 5): sandwich covariance
// H^-1 A' Omega V Omega A H^-1 with H = A' Omega A + D, CIs, goodness of fit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include "fit_internal.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm::detail {
namespace {

// A direction of the scaled Hessian (curvature per relative change of each parameter)
// whose eigenvalue is below this fraction of the largest is flat: 1e-10 is far below
// any curvature the data can determine (the weakest identified ones on the shared
// recordings are ~1e-6) and far above round-off in the Hessian (~1e-14).
constexpr double kFlatCurvature = 1e-10;
// A parameter loading on a flat direction by more than this (the eigenvector's entry)
// is not identified.
constexpr double kFlatLoading = 0.3;

/// The closure of a parameter's natural domain.
std::pair<double, double> domain_of(Transform t) {
  switch (t) {
    case Transform::kLog:
      return {0.0, std::numeric_limits<double>::infinity()};
    case Transform::kAtanh:
      return {-1.0, 1.0};
    case Transform::kLogitHalf:
      return {0.0, 0.5};
    case Transform::kIdentity:
      break;
  }
  return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

// A component whose share of the implied WV is below this at every level is "on the
// boundary" (a variance driven towards 0): its parameters are not identified and are
// dropped from A and D (docs/statistics.md section 6), their se reported as NaN.
constexpr double kBoundaryShare = 1e-8;

}  // namespace

void run_inference(const WaveletVariance& wv, const FitOptions& options, bool omega_is_v_inverse, FitResult& r,
                   const Eigen::MatrixXd* v_at_estimate) {
  const Model& model = r.model;
  const int p = model.num_parameters();
  const int J = wv.levels();
  const Eigen::VectorXd nu = r.implied_wv;
  const Eigen::MatrixXd& omega = r.omega;

  // V: the one behind Omega when there is one, else model-based at theta_hat.
  // A robust WV's variance is the Gaussian one inflated by 1/efficiency (spec s.2).
  if (r.wv_covariance.size() == 0) r.wv_covariance = wv_covariance_at(wv, model, r.theta);
  const Eigen::MatrixXd& V = r.wv_covariance;

  // Active parameters (components not on the boundary).
  std::vector<int> active;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& proc = *model.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> part(static_cast<std::size_t>(J));
    proc.wv({r.theta.data() + model.offset(c), static_cast<std::size_t>(proc.size())}, wv.tau, part);
    double share = 0.0;
    for (int j = 0; j < J; ++j)
      share = std::max(share, std::abs(part[static_cast<std::size_t>(j)]) / std::max(std::abs(nu(j)), 1e-300));
    if (share < kBoundaryShare) {
      r.notes.push_back("component " + std::to_string(c + 1) + " (" + proc.name() +
                        ") is at the boundary (negligible at every scale): dropped from the "
                        "covariance, its standard errors are undefined");
      continue;
    }
    for (int i = 0; i < proc.size(); ++i) active.push_back(model.offset(c) + i);
  }
  const int q = static_cast<int>(active.size());
  const Eigen::MatrixXd A_full = model.jacobian(r.theta, wv.tau);
  const auto hess = model.hessians(r.theta, wv.tau);
  const Eigen::VectorXd resid = omega * (nu - wv.values());
  Eigen::MatrixXd A(J, q), D = Eigen::MatrixXd::Zero(q, q);
  for (int a = 0; a < q; ++a) A.col(a) = A_full.col(active[static_cast<std::size_t>(a)]);
  for (int j = 0; j < J; ++j)
    for (int a = 0; a < q; ++a)
      for (int b = 0; b < q; ++b)
        D(a, b) += hess[static_cast<std::size_t>(j)](active[static_cast<std::size_t>(a)],
                                                     active[static_cast<std::size_t>(b)]) *
                   resid(j);
  const Eigen::MatrixXd B = A.transpose() * omega * A;
  const Eigen::MatrixXd H = B + D;
  // Directions along which the objective is flat (relative curvature below
  // kFlatCurvature): the pseudo-inverse would give them a variance of 0, i.e. a
  // zero-width interval. The parameters that load on them are not identified.
  std::vector<bool> flat(static_cast<std::size_t>(q), false);
  Eigen::MatrixXd Hinv = Eigen::MatrixXd::Zero(q, q);
  if (q > 0) {
    // Scale-free: curvature per relative change of a variance (log-parameters), per unit
    // change of a bounded one (phi, theta, frequencies).
    Eigen::VectorXd scale(q);
    for (int a = 0; a < q; ++a) {
      const int k = active[static_cast<std::size_t>(a)];
      scale(a) = model.spec_of(k).transform == Transform::kLog ? std::max(std::abs(r.theta(k)), 1e-300) : 1.0;
    }
    const Eigen::MatrixXd Hs = scale.asDiagonal() * (0.5 * (H + H.transpose())) * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Hs);
    const double top = eig.eigenvalues().cwiseAbs().maxCoeff();
    Eigen::MatrixXd inv = Eigen::MatrixXd::Zero(q, q);
    bool any_flat = false;
    for (int e = 0; e < q; ++e) {
      const double lambda = eig.eigenvalues()(e);
      const Eigen::VectorXd v = eig.eigenvectors().col(e);
      if (lambda > kFlatCurvature * top) {
        inv += v * v.transpose() / lambda;
        continue;
      }
      any_flat = true;
      for (int a = 0; a < q; ++a)
        if (std::abs(v(a)) > kFlatLoading) flat[static_cast<std::size_t>(a)] = true;
    }
    Hinv = scale.asDiagonal() * inv * scale.asDiagonal();
    if (any_flat) {
      std::string names;
      for (int a = 0; a < q; ++a)
        if (flat[static_cast<std::size_t>(a)])
          names += (names.empty() ? "" : ", ") + model.parameter_label(active[static_cast<std::size_t>(a)]);
      r.notes.push_back("the objective is flat along " +
                        (names.empty() ? std::string("a combination of parameters") : names) +
                        " (its Hessian is singular there): not identified, no interval");
    }
  }
  // Cov(nuhat) at the estimate being tested: the parameters' covariance, the misfits and
  // the GoF all use it (issue 43, item 4: the GoF with the pilot's V rejected true models
  // in 11-14% of series at 5%; with V at the estimate 3.0-7.0%, tools/bench/bench_gof_level).
  const bool at_estimate = v_at_estimate && v_at_estimate->rows() == J;
  const Eigen::MatrixXd& Vp = at_estimate ? *v_at_estimate : V;
  const Eigen::MatrixXd meat = A.transpose() * omega * Vp * omega * A;
  const Eigen::MatrixXd cov_active = Hinv * meat * Hinv.transpose();

  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.covariance = Eigen::MatrixXd::Constant(p, p, nan);
  for (int a = 0; a < q; ++a)
    for (int b = 0; b < q; ++b)
      if (!flat[static_cast<std::size_t>(a)] && !flat[static_cast<std::size_t>(b)])
        r.covariance(active[static_cast<std::size_t>(a)], active[static_cast<std::size_t>(b)]) = cov_active(a, b);
  r.se = Eigen::VectorXd::Constant(p, nan);
  r.ci_low = Eigen::VectorXd::Constant(p, nan);
  r.ci_high = Eigen::VectorXd::Constant(p, nan);
  // CIs at 1 - alpha with z_{1-alpha/2}: built in the unconstrained space (log for
  // variances, atanh for phi) by the delta method and mapped back, so they stay inside
  // the parameter's domain; but where the natural Wald interval reaches the domain's edge
  // (phi = 0.9999999 with se 3e-5) that map saturates (atanh's derivative vanishes: the
  // interval would be the whole of (-1, 1) around a tiny se), so the interval is the Wald
  // one closed by the edge: one-sided, e.g. [0.99994, 1). A variance whose Wald interval
  // reaches 0 (the data do not exclude it) gets [0, the log interval's upper end]: a
  // variance estimate is right-skewed (a random walk's gamma2 at 2^17: 2.5% and 97.5%
  // quantiles at 0.31 and 1.88 of the truth), and the linear upper end, x + z se, fell
  // below the truth in three quarters of such series (issue 27).
  const double z = boost::math::quantile(boost::math::normal(), 1.0 - options.alpha / 2.0);
  const Eigen::VectorXd u = model.to_unconstrained(r.theta);
  const Eigen::VectorXd d = model.dtheta_du(u);
  r.interval.assign(static_cast<std::size_t>(p), IntervalKind::kBoundary);
  for (int a = 0; a < q; ++a) {
    const int k = active[static_cast<std::size_t>(a)];
    if (flat[static_cast<std::size_t>(a)]) {
      r.interval[static_cast<std::size_t>(k)] = IntervalKind::kNotIdentified;
      continue;
    }
    const double var = r.covariance(k, k);
    if (!(var >= 0.0)) continue;
    const double se = std::sqrt(var);
    r.se(k) = se;
    const Transform t = model.spec_of(k).transform;
    const auto [lo, hi] = domain_of(t);
    // A negative signed-magnitude value (a falling drift): the interval of |x|, mirrored.
    const double sign = model.spec_of(k).signed_magnitude && r.theta(k) < 0.0 ? -1.0 : 1.0;
    const double x = sign * r.theta(k);
    auto set_interval = [&](double from, double to) {
      r.ci_low(k) = sign > 0.0 ? from : -to;
      r.ci_high(k) = sign > 0.0 ? to : -from;
    };
    const double se_u = se / std::abs(d(k));
    if (x - z * se <= lo || x + z * se >= hi) {
      double upper = std::min(hi, x + z * se);
      if (t == Transform::kLog && std::isfinite(se_u)) {
        const double log_upper = from_unconstrained(t, u(k) + z * se_u);
        if (std::isfinite(log_upper) && log_upper > upper) upper = log_upper;
      }
      set_interval(std::max(lo, x - z * se), upper);
      r.interval[static_cast<std::size_t>(k)] = IntervalKind::kOneSided;
      continue;
    }
    if (std::isfinite(se_u))
      set_interval(from_unconstrained(t, u(k) - z * se_u), from_unconstrained(t, u(k) + z * se_u));
    r.interval[static_cast<std::size_t>(k)] = IntervalKind::kTwoSided;
  }
  for (int k = 0; k < p; ++k)
    if (r.interval[static_cast<std::size_t>(k)] == IntervalKind::kOneSided) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " is at the edge of its domain: one-sided interval [%.6g, %.6g]", r.ci_low(k),
                    r.ci_high(k));
      r.notes.push_back(model.parameter_label(k) + buf);
    }
  // Where the data depart from the fit, level by level.
  r.misfits.clear();
  for (int j = 0; j < J; ++j) {
    LevelMisfit m;
    m.level = first_level(wv) + j;
    m.tau = wv.tau[static_cast<std::size_t>(j)];
    m.ratio = wv.wv[static_cast<std::size_t>(j)] / nu(j);
    const double sd = std::sqrt(Vp(j, j));
    m.z = sd > 0.0 ? (wv.wv[static_cast<std::size_t>(j)] - nu(j)) / sd : std::numeric_limits<double>::quiet_NaN();
    r.misfits.push_back(m);
  }

  r.gof = goodness_of_fit(A, r.objective, J - p, omega, Vp, omega_is_v_inverse && !at_estimate);
}

}  // namespace gmwm::detail

namespace gmwm {

const char* to_string(IntervalKind k) {
  switch (k) {
    case IntervalKind::kTwoSided:
      return "two-sided";
    case IntervalKind::kOneSided:
      return "one-sided";
    case IntervalKind::kNotIdentified:
      return "not identified";
    case IntervalKind::kBoundary:
      return "boundary";
  }
  return "?";
}

std::vector<LevelMisfit> FitResult::worst_levels(int count) const {
  std::vector<LevelMisfit> v;
  for (const auto& m : misfits)
    if (std::isfinite(m.z)) v.push_back(m);
  std::sort(v.begin(), v.end(),
            [](const LevelMisfit& a, const LevelMisfit& b) { return std::abs(a.z) > std::abs(b.z); });
  if (static_cast<int>(v.size()) > count) v.resize(static_cast<std::size_t>(count));
  return v;
}

bool FitResult::degenerate() const {
  for (IntervalKind k : interval)
    if (k == IntervalKind::kNotIdentified || k == IntervalKind::kBoundary) return true;
  return false;
}

GoodnessOfFit goodness_of_fit(const Eigen::MatrixXd& A, double objective, double df, const Eigen::MatrixXd& omega,
                              const Eigen::MatrixXd& V, bool omega_is_v_inverse) {
  // With Omega = V^-1 the objective is chi-square(J - p). With another Omega,
  // Q ~ sum_k lambda_k chi2_1 with lambda = eig(M V), M = P' Omega P,
  // P = I - A B^-1 A' Omega; matched to a scaled chi-square a chi2_b (Satterthwaite 1946).
  GoodnessOfFit g;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  g.statistic = objective;
  g.df = df;
  if (g.df <= 0) {
    g.p_value = nan;
    g.method = "none (no degrees of freedom)";
    return g;
  }
  if (omega_is_v_inverse) {
    g.p_value = boost::math::cdf(boost::math::complement(boost::math::chi_squared(g.df), std::max(objective, 0.0)));
    g.method = "chi-square";
    return g;
  }
  const Eigen::Index J = omega.rows();
  const Eigen::MatrixXd B = A.transpose() * omega * A;
  const Eigen::MatrixXd Binv = B.completeOrthogonalDecomposition().pseudoInverse();
  const Eigen::MatrixXd Pm = Eigen::MatrixXd::Identity(J, J) - A * Binv * A.transpose() * omega;
  const Eigen::MatrixXd MV = Pm.transpose() * omega * Pm * V;
  detail::satterthwaite_match(g, MV.trace(), (MV * MV).trace());
  return g;
}

void detail::satterthwaite_match(GoodnessOfFit& g, double t1, double t2) {
  if (!(t1 > 0.0 && t2 > 0.0)) {
    g.p_value = std::numeric_limits<double>::quiet_NaN();
    g.method = "satterthwaite (degenerate)";
    return;
  }
  const double scale = t2 / t1, dof = t1 * t1 / t2;
  g.p_value =
      boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), std::max(g.statistic, 0.0) / scale));
  g.method = "satterthwaite";
}

}  // namespace gmwm
