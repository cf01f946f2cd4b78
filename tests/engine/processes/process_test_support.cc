#include "process_test_support.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gmwm/engine/process_registry.h"
#include "gmwm/engine/random.h"

namespace gmwm::test {
namespace {

/// Relative finite-difference step (central differences: truncation ~ h^2, rounding
/// ~ eps/h, balanced near eps^(1/3) ~ 6e-6; 2e-5 keeps the rounding term, 1e3 eps/h ~ 1e-8
/// relative, well below the truncation allowance while resolving SIN's oscillation in f
/// at tau = 256, period ~ 1/128 in f).
constexpr double kRelativeStep = 2e-5;
constexpr double kEps = std::numeric_limits<double>::epsilon();
/// Allowed rounding error of a WV/jacobian evaluation, in units of eps.
constexpr double kRoundingUlps = 1e3;

// Step in the unconstrained coordinate u of the parameter (process.h transforms): the
// WV varies on O(1) scales in u even where it varies on O(1 - |phi|) scales in phi.
double step_for(const ParameterSpec& spec, double x) {
  if (spec.transform == Transform::kIdentity) return kRelativeStep * std::max(std::fabs(x), 1e-2);
  return kRelativeStep * std::max(std::fabs(to_unconstrained(spec.transform, x)), 1.0);
}

// Flattened f(theta): the WV (derivative order 0) or the jacobian (order 1).
Eigen::VectorXd evaluate(const Process& p, const std::vector<double>& theta, std::span<const double> tau, int order) {
  const auto J = static_cast<Eigen::Index>(tau.size());
  if (order == 0) {
    Eigen::VectorXd v(J);
    p.wv(theta, tau, std::span<double>(v.data(), tau.size()));
    return v;
  }
  Eigen::MatrixXd jac(J, p.size());
  p.wv_jacobian(theta, tau, jac);
  return Eigen::Map<Eigen::VectorXd>(jac.data(), jac.size());
}

}  // namespace

std::unique_ptr<Process> make_process(const std::string& name, const std::map<std::string, long>& structural,
                                      const ProcessContext& context) {
  ProcessArgs args;
  args.context = context;
  args.structural = structural;
  return ProcessRegistry::instance().create(name, args);
}

std::vector<double> dyadic_scales(int j_max, int j_min) {
  std::vector<double> tau;
  for (int j = j_min; j <= j_max; ++j) tau.push_back(std::ldexp(1.0, j));
  return tau;
}

std::vector<double> wv_of(const Process& p, std::span<const double> theta, std::span<const double> tau) {
  std::vector<double> out(tau.size());
  p.wv(theta, tau, out);
  return out;
}

std::vector<double> wv_from_autocovariance(const Process& p, std::span<const double> theta,
                                           std::span<const double> tau) {
  const auto tmax = static_cast<std::size_t>(*std::max_element(tau.begin(), tau.end()));
  std::vector<double> g(tmax);
  p.generalized_autocovariance(theta, g);
  std::vector<double> out;
  for (double t : tau) {
    const auto n = static_cast<std::size_t>(t);
    std::vector<double> a(n);
    for (std::size_t i = 0; i < n; ++i) a[i] = (i < n / 2 ? 1.0 : -1.0) / t;
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < n; ++k) s += a[i] * a[k] * g[i > k ? i - k : k - i];
    out.push_back(s);
  }
  return out;
}

void expect_all_relatively_near(const std::vector<double>& actual, const std::vector<double>& expected, double rel,
                                const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  for (std::size_t k = 0; k < actual.size(); ++k)
    EXPECT_NEAR(actual[k], expected[k], rel * std::fabs(expected[k]))
        << what << " at index " << k << " (relative error "
        << std::fabs(actual[k] - expected[k]) / std::fabs(expected[k]) << ")";
}

void expect_derivatives_match_finite_differences(const Process& p, std::vector<double> theta,
                                                 std::span<const double> tau) {
  const int np = p.size();
  const auto J = static_cast<Eigen::Index>(tau.size());
  Eigen::MatrixXd jac(J, np), hess(J, np * np);
  p.wv_jacobian(theta, tau, jac);
  p.wv_hessian(theta, tau, hess);
  for (int order = 0; order <= 1; ++order) {
    // analytic(k, ...) = d f_k / d theta_l: jacobian column l, or Hessian block l.
    for (int l = 0; l < np; ++l) {
      const auto lz = static_cast<std::size_t>(l);
      const Transform tr = p.parameters()[lz].transform;
      const double u = to_unconstrained(tr, theta[lz]);
      const double h = step_for(p.parameters()[lz], theta[lz]);
      // Divided by the realised difference of the (rounded) natural values, so that the
      // rounding of theta_l +- step (1e-16 / (1 + phi) relative near phi = -1) cancels.
      auto central = [&](double step, Eigen::VectorXd* fmax) {
        std::vector<double> tp = theta, tm = theta;
        tp[lz] = from_unconstrained(tr, u + step);
        tm[lz] = from_unconstrained(tr, u - step);
        const double dx = tp[lz] - tm[lz];
        const Eigen::VectorXd fp = evaluate(p, tp, tau, order), fm = evaluate(p, tm, tau, order);
        *fmax = fp.cwiseAbs().cwiseMax(fm.cwiseAbs()) * (2.0 * step / dx);
        return Eigen::VectorXd((fp - fm) / dx);
      };
      Eigen::VectorXd fmax1, fmax2;
      const Eigen::VectorXd d1 = central(h, &fmax1), d2 = central(0.5 * h, &fmax2);
      Eigen::VectorXd analytic(d1.size());
      if (order == 0) {
        analytic = jac.col(l);
      } else {  // f = vec(jac) (column-major: index k + J m) and hess(k, l np + m)
        for (int m = 0; m < np; ++m)
          for (Eigen::Index k = 0; k < J; ++k) analytic(k + J * m) = hess(k, l * np + m);
      }
      const double scale = analytic.cwiseAbs().maxCoeff();
      for (Eigen::Index i = 0; i < d1.size(); ++i) {
        const double truncation = 2.0 * std::fabs(d1(i) - d2(i));
        const double rounding = kRoundingUlps * kEps * fmax2(i) / (0.5 * h);
        const double tol = truncation + rounding;
        std::ostringstream what;
        what << p.name() << p.structure() << (order == 0 ? " jacobian" : " hessian") << " entry " << i
             << " for parameter " << p.parameters()[static_cast<std::size_t>(l)].name
             << " (theta_l = " << theta[static_cast<std::size_t>(l)] << ", step " << h << ")";
        EXPECT_NEAR(analytic(i), d2(i), tol) << what.str();
        EXPECT_LE(truncation, 1e-5 * (std::fabs(analytic(i)) + scale) + rounding)
            << what.str() << ": the finite-difference tolerance is too loose to be a test";
      }
    }
  }
  // The Hessian is symmetric.
  for (Eigen::Index k = 0; k < J; ++k)
    for (int l = 0; l < np; ++l)
      for (int m = 0; m < l; ++m)
        EXPECT_NEAR(hess(k, l * np + m), hess(k, m * np + l), 1e-12 * (std::fabs(hess(k, l * np + m)) + 1e-300))
            << p.name() << " hessian symmetry";
}

namespace {

struct RunningMean {
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  void add(double x) {
    sum += x;
    sum2 += x * x;
    ++n;
  }
  double mean() const { return sum / n; }
  double se() const {
    const double m = mean();
    return std::sqrt(std::max(sum2 / n - m * m, 0.0) / (n - 1));
  }
};

void expect_within_3_se(const RunningMean& r, double target, const std::string& what) {
  const double se = r.se();
  EXPECT_NEAR(r.mean(), target, 3.0 * se + 1e-12 * std::fabs(target))
      << what << ": Monte-Carlo mean " << r.mean() << " +- " << se << ", theory " << target;
}

}  // namespace

void expect_simulated_moments_match(const Process& p, std::span<const double> theta, const SimulationCheck& check) {
  std::vector<double> g(3);
  p.generalized_autocovariance(theta, g);
  RunningMean dd, dd1, xx, xx1;
  Rng rng = make_stream(check.seed, {7});
  std::vector<double> x(static_cast<std::size_t>(check.length));
  for (int r = 0; r < check.replicates; ++r) {
    std::fill(x.begin(), x.end(), 0.0);
    p.simulate(theta, rng, x);
    double sdd = 0.0, sdd1 = 0.0, sxx = 0.0, sxx1 = 0.0;
    const std::size_t n = x.size();
    for (std::size_t t = 1; t < n; ++t) {
      const double d = x[t] - x[t - 1];
      sdd += d * d;
      if (t + 1 < n) sdd1 += d * (x[t + 1] - x[t]);
    }
    for (std::size_t t = 0; t < n; ++t) {
      sxx += x[t] * x[t];
      if (t + 1 < n) sxx1 += x[t] * x[t + 1];
    }
    dd.add(sdd / static_cast<double>(n - 1));
    dd1.add(sdd1 / static_cast<double>(n - 2));
    xx.add(sxx / static_cast<double>(n));
    xx1.add(sxx1 / static_cast<double>(n - 1));
  }
  const std::string name = p.name() + p.structure();
  expect_within_3_se(dd, 2.0 * g[0] - 2.0 * g[1], name + " variance of increments");
  expect_within_3_se(dd1, 2.0 * g[1] - g[0] - g[2], name + " lag-1 covariance of increments");
  if (check.stationary) {
    expect_within_3_se(xx, g[0], name + " variance");
    expect_within_3_se(xx1, g[1], name + " lag-1 autocovariance");
  }
}

void expect_first_sample_is_stationary(const Process& p, std::span<const double> theta, int replicates,
                                       std::uint64_t seed) {
  std::vector<double> g(1);
  p.generalized_autocovariance(theta, g);
  RunningMean x0;
  Rng rng = make_stream(seed, {11});
  std::vector<double> x(2);
  for (int r = 0; r < replicates; ++r) {
    std::fill(x.begin(), x.end(), 0.0);
    p.simulate(theta, rng, x);
    x0.add(x[0] * x[0]);
  }
  expect_within_3_se(x0, g[0], p.name() + p.structure() + " variance of the first sample");
}

}  // namespace gmwm::test
