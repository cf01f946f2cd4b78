#include "gmwm/selection/optimism.h"

#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "gmwm/engine/check.h"

namespace gmwm::selection {
namespace {

void check_sizes(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau,
                 const Eigen::VectorXd& nuhat, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v) {
  const auto J = static_cast<Eigen::Index>(tau.size());
  auto bad = [](const std::string& what) { throw InvalidArgument("analytic_optimism: " + what); };
  if (theta.size() != model.num_parameters())
    bad("theta has " + std::to_string(theta.size()) + " values, the model " + std::to_string(model.num_parameters()));
  if (nuhat.size() != J) bad("nuhat has " + std::to_string(nuhat.size()) + " levels, tau " + std::to_string(J));
  if (omega.rows() != J || omega.cols() != J) bad("Omega must be " + std::to_string(J) + " x " + std::to_string(J));
  if (v.rows() != J || v.cols() != J) bad("V must be " + std::to_string(J) + " x " + std::to_string(J));
}

}  // namespace

Optimism analytic_optimism(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau,
                           const Eigen::VectorXd& nuhat, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v) {
  check_sizes(model, theta, tau, nuhat, omega, v);
  Optimism out;
  const Eigen::Index J = nuhat.size();
  // Parameters kept: those of components off the boundary.
  std::vector<Eigen::Index> keep;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> f(tau.size());
    p.wv({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, tau, f);
    bool boundary = true;
    for (Eigen::Index j = 0; j < J && boundary; ++j)
      boundary = !(std::abs(f[static_cast<std::size_t>(j)]) > kBoundaryShare * std::abs(nuhat(j)));
    if (boundary) {
      out.boundary_components.push_back(c);
      continue;
    }
    for (int k = 0; k < p.size(); ++k) keep.push_back(model.offset(c) + k);
  }
  const auto K = static_cast<Eigen::Index>(keep.size());
  if (K == 0) {
    out.value = 0.0;
    out.status = OptimismStatus::kOk;
    out.message = "every component is at the boundary: optimism 0";
    return out;
  }
  const Eigen::MatrixXd A_full = model.jacobian(theta, tau);
  const std::vector<Eigen::MatrixXd> H = model.hessians(theta, tau);
  const Eigen::VectorXd r = omega * (model.wv(theta, tau) - nuhat);
  Eigen::MatrixXd A(J, K), D = Eigen::MatrixXd::Zero(K, K);
  for (Eigen::Index a = 0; a < K; ++a) A.col(a) = A_full.col(keep[static_cast<std::size_t>(a)]);
  for (Eigen::Index j = 0; j < J; ++j)
    for (Eigen::Index a = 0; a < K; ++a)
      for (Eigen::Index b = 0; b < K; ++b)
        D(a, b) +=
            H[static_cast<std::size_t>(j)](keep[static_cast<std::size_t>(a)], keep[static_cast<std::size_t>(b)]) * r(j);
  const Eigen::MatrixXd M = A.transpose() * omega * A + D;
  const Eigen::MatrixXd G = A.transpose() * (omega * v * omega) * A;  // K x K
  // tr(A M^-1 A' W) = tr(M^-1 A' W A). Scale M to unit diagonal for the condition check
  // (natural parameters differ by orders of magnitude: phi ~ 1, sigma2 ~ 1e-10).
  Eigen::VectorXd s = M.diagonal().cwiseAbs().cwiseSqrt();
  for (Eigen::Index a = 0; a < K; ++a)
    if (!(s(a) > 0.0)) s(a) = 1.0;
  const Eigen::MatrixXd Ms = s.cwiseInverse().asDiagonal() * M * s.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd Gs = s.cwiseInverse().asDiagonal() * G * s.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Ms + Ms.transpose()));
  if (eig.info() != Eigen::Success || !eig.eigenvalues().allFinite()) {
    out.status = OptimismStatus::kFailed;
    out.value = std::numeric_limits<double>::quiet_NaN();
    out.message = "B + D could not be decomposed";
    return out;
  }
  // At an interior minimum B + D (half the Hessian of the objective) is positive
  // definite. A direction of non-positive curvature means the optimum sits at the edge of
  // the parameter space along it (a variance near 0, phi near 1), where the first-order
  // condition behind the delta method does not hold: such directions are left out like
  // the boundary components, as are near-null ones (pseudo-inverse).
  const double big = eig.eigenvalues().cwiseAbs().maxCoeff();
  const double floor = kMinReciprocalCondition * big;
  int negative = 0, dropped = 0;
  for (Eigen::Index a = 0; a < K; ++a) {
    if (eig.eigenvalues()(a) < -floor) ++negative;
    if (!(eig.eigenvalues()(a) > floor)) ++dropped;
  }
  if (dropped == 0) {
    out.value = 2.0 * Ms.llt().solve(Gs).trace();
    out.status = OptimismStatus::kOk;
  } else {
    Eigen::VectorXd inv = eig.eigenvalues();
    for (Eigen::Index a = 0; a < K; ++a) inv(a) = inv(a) > floor ? 1.0 / inv(a) : 0.0;
    const Eigen::MatrixXd pinv = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
    out.value = 2.0 * (pinv * Gs).trace();
    out.status = OptimismStatus::kPseudoInverse;
  }
  std::ostringstream os;
  if (!out.boundary_components.empty()) {
    os << "component" << (out.boundary_components.size() > 1 ? "s" : "");
    for (int c : out.boundary_components) os << " " << c + 1;
    os << " at the boundary (WV below " << kBoundaryShare << " of the data's at every level): dropped from A and D";
  }
  if (out.status == OptimismStatus::kPseudoInverse) {
    os << (os.tellp() > 0 ? "; " : "") << "B + D ";
    if (negative > 0)
      os << "not positive definite (" << negative << " direction" << (negative > 1 ? "s" : "")
         << " of negative curvature: a parameter at the edge of its space)";
    else
      os << "near singular";
    os << ": pseudo-inverse over its " << K - dropped << " positive direction" << (K - dropped != 1 ? "s" : "");
  }
  out.message = os.str();
  return out;
}

}  // namespace gmwm::selection
