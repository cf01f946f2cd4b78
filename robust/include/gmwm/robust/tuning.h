#pragma once
// Tuning of the robust scale M-estimators of the wavelet variance (docs/statistics.md
// section 2). For r = W / nu the estimating equation is mean chi(r) = a(c), with
//   Huber's Proposal 2:  chi(r) = min(r^2, c^2),
//   Tukey's bisquare:    chi(r) = r^2 (1 - r^2/c^2)^4 for |r| <= c, else 0,
// and a(c) = E[chi(Z)], Z ~ N(0, 1), the Fisher-consistency constant. The Gaussian
// efficiency of the scale estimate (i.i.d. coefficients) is
//   eff(c) = (E[Z chi'(Z)])^2 / (2 Var chi(Z)),
// which for Huber is 2 mu2(c)^2 / Var(min(Z^2, c^2)) as written in the spec. c is solved
// from a target efficiency with Boost.Math's toms748 root finder.

#include <optional>
#include <string>
#include <string_view>

namespace gmwm::robust {

enum class RobustKind { kHuber, kBisquare };

/// "huber" | "bisquare".
const char* to_string(RobustKind k);
/// The estimator named s, or nullopt (the caller reports the unknown name).
std::optional<RobustKind> parse_robust_kind(std::string_view s);

/// Default target efficiency (docs/statistics.md section 2, docs/cli.md `--eff 0.6`).
inline constexpr double kDefaultEfficiency = 0.6;

/// a(c) = E[chi_c(Z)].
double consistency(RobustKind kind, double c);
/// Gaussian efficiency of the scale estimate at tuning constant c.
double efficiency(RobustKind kind, double c);
/// chi_c(r) (r^2 is passed, the functions only depend on it).
double chi(RobustKind kind, double c, double r2);

struct Tuning {
  RobustKind kind = RobustKind::kHuber;
  double efficiency = kDefaultEfficiency;  ///< target Gaussian efficiency
  double c = 0.0;                          ///< tuning constant solving eff(c) = target
  double a = 0.0;                          ///< a(c)
  /// Second-order constants of the estimating equation at the Gaussian (U = Z^2), for
  /// the small-sample bias correction: slope = E[chi'(U) U] (Huber: mu2(c)) and
  /// curvature = E[2 chi'(U) U + chi''(U) U^2] (Huber: 2 mu2(c) - c^3 phi(c), the
  /// second term from the kink of min(u, c^2) at u = c^2).
  double slope = 0.0;
  double curvature = 0.0;
};

/// Solves eff(c) = target. Throws gmwm::InvalidArgument unless 0 < target < 1 (and the
/// target is reachable: every value in (0, 1) is, for both estimators).
Tuning tune(RobustKind kind, double target_efficiency);

}  // namespace gmwm::robust
