#pragma once
// The analytic optimism of the WVIC (docs/statistics.md section 6):
//   optimism = 2 tr( A (B + D)^-1 A' Omega V Omega ),
// A = d nu / d theta (J x p, natural parameters), B = A' Omega A,
// D_kl = sum_j (d^2 nu_j / d theta_k d theta_l) r_j with r = Omega (nu(theta) - nuhat),
// V = Cov(nuhat). With D = 0 and V = Omega^-1 this is exactly 2p.
//
// Components at the boundary (a variance driven to 0 by an over-specified fit: their WV
// is below kBoundaryShare of nuhat at every level) make A rank-deficient; they are
// dropped from A and D and listed in the result.

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm::selection {

/// A component whose WV is below this share of the empirical WV at every level counts as
/// at the boundary (the fit's own collapse threshold, engine/src/starting_values.cc).
inline constexpr double kBoundaryShare = 1e-6;
/// (B + D) restricted to the kept parameters (diagonal-scaled) is solved by Cholesky when
/// every eigenvalue exceeds this share of the largest; otherwise by a pseudo-inverse over
/// the directions of positive curvature (negative curvature: a parameter at the edge of
/// its space, where the delta method's first-order condition fails), and the result says so.
inline constexpr double kMinReciprocalCondition = 1e-12;

enum class OptimismStatus { kOk, kPseudoInverse, kFailed };

struct Optimism {
  double value = 0.0;
  OptimismStatus status = OptimismStatus::kFailed;
  std::vector<int> boundary_components;  ///< dropped from A and D (0-based component indices)
  std::string message;                   ///< empty when kOk and nothing was dropped
};

/// The analytic optimism of `model` at theta (natural parameters) for the empirical WV
/// nuhat at scales tau, weight matrix omega and covariance V of nuhat (all J x J).
/// Throws InvalidArgument on inconsistent sizes.
Optimism analytic_optimism(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau,
                           const Eigen::VectorXd& nuhat, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v);

}  // namespace gmwm::selection
