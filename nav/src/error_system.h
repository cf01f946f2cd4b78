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

/// The sensors' part of the error system, in the body frame: dx/dt = F x + w over
/// x = [dp, dv, psi, the gyro's states (axis by axis, component by component), the
/// accelerometer's], Cov(w) = Qc dt, x(0) ~ N(0, P0). What the trajectory changes (the
/// body-to-level rotation C and the specific force f) enters through at_pose.
struct ErrorSystem {
  Eigen::MatrixXd F, Qc, P0;  ///< at rest, heading north (C = I, f = (0, 0, -g))
  /// Body-frame couplings: the gyroscope's errors on the body axes are gyro_rows x (3 x n),
  /// the accelerometer's accel_rows x; the white parts' densities per body axis (SI^2/Hz).
  Eigen::MatrixXd gyro_rows, accel_rows;
  Eigen::Vector3d gyro_white = Eigen::Vector3d::Zero(), accel_white = Eigen::Vector3d::Zero();
  std::vector<std::string> notes;  ///< what the sensor models leave out
  int states() const { return static_cast<int>(F.rows()); }
};

/// The system of `model` (each sensor's form scaled to SI by its to_si). Throws
/// InputError naming the component without a continuous form.
ErrorSystem error_system(const ImuModel& model, const Scenario& scenario);

/// F and Qc of `sys` at a pose: the sensors' errors rotated to the level frame by C, and
/// d(dv)/dt = f x psi + C db_a, d(psi)/dt = -C db_g.
void at_pose(const ErrorSystem& sys, const Pose& pose, Eigen::MatrixXd& F, Eigen::MatrixXd& Qc);

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
