#include "error_system.h"

#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include "gmwm/engine/error.h"

namespace gmwm::nav::detail {

namespace {

// One sensor's forms, component by component (SensorModel::Validate has checked them).
std::vector<ContinuousForm> forms_of(const SensorModel& s) {
  std::vector<ContinuousForm> out;
  for (int c = 0; c < s.model.num_components(); ++c) {
    const Process& p = *s.model.components()[static_cast<std::size_t>(c)].process;
    out.push_back(*p.continuous_form({s.theta.data() + s.model.offset(c), static_cast<std::size_t>(p.size())}, s.freq));
  }
  return out;
}

int states_of(const std::vector<ContinuousForm>& forms) {
  int n = 0;
  for (const auto& f : forms) n += f.states();
  return n;
}

// Adds a sensor's states, axis by axis, at `at`, driving row block `target` (the velocity
// for an accelerometer, sign +1; the attitude for a gyroscope, sign -1).
void add_sensor(const std::array<std::vector<ContinuousForm>, 3>& axes, int target, double sign, int& at,
                ErrorSystem& sys) {
  for (int axis = 0; axis < 3; ++axis) {
    for (const ContinuousForm& f : axes[static_cast<std::size_t>(axis)]) {
      const int n = f.states();
      if (n > 0) {
        sys.F.block(at, at, n, n) = f.F;
        sys.Qc.block(at, at, n, n) = f.Qc;
        sys.P0.block(at, at, n, n) = f.P0;
        sys.F.block(target + axis, at, 1, n) = sign * f.H;
      }
      sys.Qc(target + axis, target + axis) += f.white;
      at += n;
    }
  }
}

}  // namespace

ErrorSystem error_system(const ImuModel& model, const Scenario& scenario) {
  if (const std::string why = model.Validate(); !why.empty()) throw InputError(why);
  std::array<std::vector<ContinuousForm>, 3> gyro, accel;
  int n = kNavStates;
  for (std::size_t a = 0; a < 3; ++a) {
    gyro[a] = forms_of(model.gyro[a]);
    accel[a] = forms_of(model.accel[a]);
    n += states_of(gyro[a]) + states_of(accel[a]);
  }
  ErrorSystem sys;
  sys.F = Eigen::MatrixXd::Zero(n, n);
  sys.Qc = Eigen::MatrixXd::Zero(n, n);
  sys.P0 = Eigen::MatrixXd::Zero(n, n);
  // d(dp)/dt = dv; d(dv)/dt = f_n x psi with f_n = (0, 0, -g) at rest: [f_n x] psi =
  // (g psi_y, -g psi_x, 0).
  for (int k = 0; k < 3; ++k) sys.F(kPosition + k, kVelocity + k) = 1.0;
  const double g = scenario.gravity;
  sys.F(kVelocity + 0, kAttitude + 1) = g;
  sys.F(kVelocity + 1, kAttitude + 0) = -g;
  for (int k = 0; k < 3; ++k) {
    sys.P0(kPosition + k, kPosition + k) = scenario.initial_position * scenario.initial_position;
    sys.P0(kVelocity + k, kVelocity + k) = scenario.initial_velocity * scenario.initial_velocity;
    sys.P0(kAttitude + k, kAttitude + k) = scenario.initial_attitude * scenario.initial_attitude;
  }
  int at = kNavStates;
  add_sensor(gyro, kAttitude, -1.0, at, sys);
  add_sensor(accel, kVelocity, 1.0, at, sys);
  static const char* const kAxis[] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a)
    for (const auto* forms : {&gyro[a], &accel[a]})
      for (const ContinuousForm& f : *forms)
        for (const std::string& note : f.notes)
          sys.notes.push_back(std::string(forms == &gyro[a] ? "gyroscope " : "accelerometer ") + kAxis[a] + ": " + note);
  return sys;
}

Step discretise(const Eigen::MatrixXd& F, const Eigen::MatrixXd& Qc, double dt) {
  const Eigen::Index n = F.rows();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  m.topLeftCorner(n, n) = -F * dt;
  m.topRightCorner(n, n) = Qc * dt;
  m.bottomRightCorner(n, n) = F.transpose() * dt;
  const Eigen::MatrixXd e = m.exp();
  Step s;
  s.Phi = e.bottomRightCorner(n, n).transpose();
  s.Q = s.Phi * e.topRightCorner(n, n);
  s.Q = 0.5 * (s.Q + s.Q.transpose());
  return s;
}

Step repeat(const Step& one, std::int64_t k) {
  const Eigen::Index n = one.Phi.rows();
  Step result{Eigen::MatrixXd::Identity(n, n), Eigen::MatrixXd::Zero(n, n)};
  Step power = one;  // one^(2^b)
  for (; k > 0; k >>= 1) {
    if (k & 1) {  // result then power: x -> power(result(x))
      result.Q = power.Phi * result.Q * power.Phi.transpose() + power.Q;
      result.Phi = power.Phi * result.Phi;
    }
    if (k > 1) {
      power.Q = power.Phi * power.Q * power.Phi.transpose() + power.Q;
      power.Phi = power.Phi * power.Phi;
    }
  }
  result.Q = 0.5 * (result.Q + result.Q.transpose());
  return result;
}

Eigen::MatrixXd square_root(const Eigen::MatrixXd& Q) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Q + Q.transpose()));
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

}  // namespace gmwm::nav::detail
