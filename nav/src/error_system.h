#pragma once
// The linear navigation-error system of one IMU model (navigation.h) and its exact
// discretisation: what the covariance analysis and the Monte Carlo share.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/nav/navigation.h"

namespace gmwm::nav::detail {

/// Indices of the navigation errors in every state vector: position, velocity, attitude.
inline constexpr int kPosition = 0, kVelocity = 3, kAttitude = 6, kNavStates = 9;

/// dx/dt = F x + w, Cov(w) = Qc dt (white), x(0) ~ N(0, P0); x = [dp, dv, psi, the gyro's
/// states (axis by axis, component by component), the accelerometer's].
struct ErrorSystem {
  Eigen::MatrixXd F, Qc, P0;
  std::vector<std::string> notes;  ///< what the sensor models leave out
  int states() const { return static_cast<int>(F.rows()); }
};

/// The system of `model` under `scenario` (at rest: f_n = (0, 0, -g), C = I). Throws
/// InputError naming the component without a continuous form.
ErrorSystem error_system(const ImuModel& model, const Scenario& scenario);

/// x_{k+1} = Phi x_k + v_k, Cov(v_k) = Q.
struct Step {
  Eigen::MatrixXd Phi, Q;
};

/// The exact step of length dt (Van Loan 1978, "Computing integrals involving the matrix
/// exponential"): Phi = exp(F dt), Q = int_0^dt exp(F s) Qc exp(F' s) ds, both from one
/// exponential of the block matrix [[-F, Qc], [0, F']] dt.
Step discretise(const Eigen::MatrixXd& F, const Eigen::MatrixXd& Qc, double dt);

/// k steps of `one` as one: Phi^k and sum_{i<k} Phi^i Q Phi^i' (binary powers, O(log k)).
Step repeat(const Step& one, std::int64_t k);

/// A square root L (L L' = Q) of a symmetric positive semi-definite Q (its eigenvalues
/// clipped at 0): for Q singular too (a drift's slope has no driving noise).
Eigen::MatrixXd square_root(const Eigen::MatrixXd& Q);

}  // namespace gmwm::nav::detail
