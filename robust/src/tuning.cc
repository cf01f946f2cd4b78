#include "gmwm/robust/tuning.h"

#include <cmath>
#include <cstdint>
#include <utility>

#include <boost/math/constants/constants.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/roots.hpp>

#include "gmwm/engine/check.h"

namespace gmwm::robust {
namespace {

double Phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
double phi(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * boost::math::constants::pi<double>()); }

// Huber, closed forms (docs/statistics.md section 2).
double huber_a(double c) { return (2.0 * Phi(c) - 1.0) - 2.0 * c * phi(c) + 2.0 * c * c * (1.0 - Phi(c)); }
double huber_eff(double c) {
  const double mu2 = 2.0 * Phi(c) - 1.0 - 2.0 * c * phi(c);
  const double mu4 = 3.0 * (2.0 * Phi(c) - 1.0) - 2.0 * c * (c * c + 3.0) * phi(c);
  const double a = huber_a(c);
  const double var = mu4 + 2.0 * std::pow(c, 4) * (1.0 - Phi(c)) - a * a;
  return 2.0 * mu2 * mu2 / var;
}

// Bisquare: chi vanishes beyond c, so every expectation is a smooth integral over
// [0, c] of a polynomial times the Gaussian density: 61-point Gauss-Kronrod is exact to
// round-off there (the integrand is entire).
template <class F>
double gaussian_integral_0c(F f, double c) {
  auto g = [&](double z) { return 2.0 * f(z) * phi(z); };  // symmetric: twice [0, c]
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, 0.0, c, 0, 1e-15);
}
double bisquare_chi_of_z(double c, double z) {
  const double u = 1.0 - z * z / (c * c);
  return z * z * u * u * u * u;
}
double bisquare_a(double c) {
  return gaussian_integral_0c([&](double z) { return bisquare_chi_of_z(c, z); }, c);
}
double bisquare_eff(double c) {
  // Z chi'(Z) = 2 Z^2 (1 - u)^3 (1 - 5u), u = Z^2 / c^2.
  const double d = gaussian_integral_0c(
      [&](double z) {
        const double u = z * z / (c * c);
        return 2.0 * z * z * std::pow(1.0 - u, 3) * (1.0 - 5.0 * u);
      },
      c);
  const double m2 = gaussian_integral_0c(
      [&](double z) {
        const double x = bisquare_chi_of_z(c, z);
        return x * x;
      },
      c);
  const double a = bisquare_a(c);
  return d * d / (2.0 * (m2 - a * a));
}

// Bisquare's second-order constants (tuning.h): with v = u / c^2 on u < c^2,
// chi'(u) u = u (1 - v)^3 (1 - 5v) and chi''(u) u^2 = -u^2 (1 - v)^2 (8 - 20v) / c^2.
double bisquare_slope(double c) {
  return gaussian_integral_0c(
      [&](double z) {
        const double u = z * z, v = u / (c * c);
        return u * std::pow(1.0 - v, 3) * (1.0 - 5.0 * v);
      },
      c);
}
double bisquare_curvature(double c) {
  return gaussian_integral_0c(
      [&](double z) {
        const double u = z * z, v = u / (c * c);
        return 2.0 * u * std::pow(1.0 - v, 3) * (1.0 - 5.0 * v) -
               u * u * (1.0 - v) * (1.0 - v) * (8.0 - 20.0 * v) / (c * c);
      },
      c);
}

// Search interval for c: efficiency is increasing in c for both estimators; at these
// ends it is below 1e-3 and above 1 - 1e-6 (Huber: eff(0.05) ~ 1e-4, eff(8) ~ 1 - 1e-13;
// bisquare: eff(0.5) ~ 1e-3 ... the bracket is checked, not assumed).
constexpr double kHuberCLow = 0.01, kHuberCHigh = 10.0;
constexpr double kBisquareCLow = 0.05, kBisquareCHigh = 60.0;

}  // namespace

const char* to_string(RobustKind k) { return k == RobustKind::kHuber ? "huber" : "bisquare"; }

std::optional<RobustKind> parse_robust_kind(std::string_view s) {
  if (s == "huber") return RobustKind::kHuber;
  if (s == "bisquare") return RobustKind::kBisquare;
  return std::nullopt;
}

double consistency(RobustKind kind, double c) {
  check_positive("consistency", "c", c);
  return kind == RobustKind::kHuber ? huber_a(c) : bisquare_a(c);
}

double efficiency(RobustKind kind, double c) {
  check_positive("efficiency", "c", c);
  return kind == RobustKind::kHuber ? huber_eff(c) : bisquare_eff(c);
}

double chi(RobustKind kind, double c, double r2) {
  const double c2 = c * c;
  if (kind == RobustKind::kHuber) return r2 < c2 ? r2 : c2;
  if (r2 >= c2) return 0.0;
  const double u = 1.0 - r2 / c2;
  return r2 * u * u * u * u;
}

Tuning tune(RobustKind kind, double target) {
  check_open_interval("tune", "efficiency", target, 0.0, 1.0);
  const bool huber = kind == RobustKind::kHuber;
  const double lo = huber ? kHuberCLow : kBisquareCLow, hi = huber ? kHuberCHigh : kBisquareCHigh;
  auto f = [&](double c) { return efficiency(kind, c) - target; };
  const double flo = f(lo), fhi = f(hi);
  if (!(flo < 0.0 && fhi > 0.0))
    detail::throw_check("tune", "efficiency", target,
                        std::string("reachable by the ") + to_string(kind) + " estimator");
  std::uintmax_t iters = 200;
  const auto [c1, c2] =
      boost::math::tools::toms748_solve(f, lo, hi, flo, fhi, boost::math::tools::eps_tolerance<double>(52), iters);
  Tuning t;
  t.kind = kind;
  t.efficiency = target;
  t.c = 0.5 * (c1 + c2);
  t.a = consistency(kind, t.c);
  if (huber) {
    const double mu2 = 2.0 * Phi(t.c) - 1.0 - 2.0 * t.c * phi(t.c);
    t.slope = mu2;
    t.curvature = 2.0 * mu2 - t.c * t.c * t.c * phi(t.c);
  } else {
    t.slope = bisquare_slope(t.c);
    t.curvature = bisquare_curvature(t.c);
  }
  return t;
}

}  // namespace gmwm::robust
