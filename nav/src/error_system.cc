#include "error_system.h"

#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <unsupported/Eigen/MatrixFunctions>

#include "gmwm/engine/error.h"

namespace gmwm::nav::detail {

namespace {

// The largest error system: 9 navigation states and 3 x 2 sensor axes of up to ~30 states
// each (a FLICKER is 14). Each block step costs ~n^3 and the exact step's exponential of a
// 2n x 2n matrix; 240 keeps both well under a second, where 6 x 200 states took minutes.
constexpr int kMaxStates = 240;

// One sensor's forms, component by component (SensorModel::Validate has checked them),
// scaled from the model's unit to SI: the states (and the output) by to_si, so F is
// unchanged and Qc, P0 and the white density scale by to_si^2.
std::vector<ContinuousForm> forms_of(const SensorModel& s) {
  std::vector<ContinuousForm> out;
  const double k2 = s.to_si * s.to_si;
  for (int c = 0; c < s.model.num_components(); ++c) {
    const Process& p = *s.model.components()[static_cast<std::size_t>(c)].process;
    ContinuousForm f =
        *p.continuous_form({s.theta.data() + s.model.offset(c), static_cast<std::size_t>(p.size())}, s.freq);
    f.Qc *= k2;
    f.P0 *= k2;
    f.white *= k2;
    out.push_back(std::move(f));
  }
  return out;
}

int states_of(const std::vector<ContinuousForm>& forms) {
  int n = 0;
  for (const auto& f : forms) n += f.states();
  return n;
}

// Adds a sensor's states, axis by axis, at `at`: their dynamics, and the rows by which
// they drive the sensor's body-frame error (`rows`, 3 x n) and its white densities.
void add_sensor(const std::array<std::vector<ContinuousForm>, 3>& axes, Eigen::MatrixXd& rows, Eigen::Vector3d& white,
                int& at, ErrorSystem& sys) {
  for (int axis = 0; axis < 3; ++axis) {
    for (const ContinuousForm& f : axes[static_cast<std::size_t>(axis)]) {
      const int n = f.states();
      if (n > 0) {
        sys.F.block(at, at, n, n) = f.F;
        sys.Qc.block(at, at, n, n) = f.Qc;
        sys.P0.block(at, at, n, n) = f.P0;
        rows.block(axis, at, 1, n) = f.H;
      }
      white(axis) += f.white;
      at += n;
    }
  }
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
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
  if (n > kMaxStates)
    throw InputError((model.label.empty() ? std::string("a model") : model.label) + ": its error system has " +
                     std::to_string(n) + " states, more than " + std::to_string(kMaxStates) +
                     " (each AR1, GM or RW is a state per axis, a DR two, a FLICKER 14)");
  ErrorSystem sys;
  sys.F = Eigen::MatrixXd::Zero(n, n);
  sys.Qc = Eigen::MatrixXd::Zero(n, n);
  sys.P0 = Eigen::MatrixXd::Zero(n, n);
  sys.gyro_rows = Eigen::MatrixXd::Zero(3, n);
  sys.accel_rows = Eigen::MatrixXd::Zero(3, n);
  for (int k = 0; k < 3; ++k) sys.F(kPosition + k, kVelocity + k) = 1.0;  // d(dp)/dt = dv
  for (int k = 0; k < 3; ++k) {
    sys.P0(kPosition + k, kPosition + k) = scenario.initial_position * scenario.initial_position;
    sys.P0(kVelocity + k, kVelocity + k) = scenario.initial_velocity * scenario.initial_velocity;
    sys.P0(kAttitude + k, kAttitude + k) = scenario.initial_attitude * scenario.initial_attitude;
  }
  int at = kNavStates;
  add_sensor(gyro, sys.gyro_rows, sys.gyro_white, at, sys);
  add_sensor(accel, sys.accel_rows, sys.accel_white, at, sys);
  // The densities in SI squared (to_si^2 Qc): an inflation of 1e160 overflows them.
  if (!sys.Qc.allFinite() || !sys.P0.allFinite() || !sys.gyro_white.allFinite() || !sys.accel_white.allFinite())
    throw InputError((model.label.empty() ? std::string("a model") : model.label) +
                     ": its noise densities in SI units overflow a double when squared (beyond 1.8e308): expected "
                     "smaller noise figures");
  Eigen::MatrixXd F, Qc;
  at_pose(sys, Pose{0.0, Eigen::Vector3d(0.0, 0.0, -scenario.gravity)}, F, Qc);
  sys.F = F;
  sys.Qc = Qc;
  static const char* const kAxis[] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a)
    for (const auto* forms : {&gyro[a], &accel[a]})
      for (const ContinuousForm& f : *forms)
        for (const std::string& note : f.notes)
          sys.notes.push_back(std::string(forms == &gyro[a] ? "gyroscope " : "accelerometer ") + kAxis[a] + ": " +
                              note);
  return sys;
}

void at_pose(const ErrorSystem& sys, const Pose& pose, Eigen::MatrixXd& F, Eigen::MatrixXd& Qc) {
  const Eigen::Matrix3d C = Eigen::AngleAxisd(pose.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const int n = sys.states(), ns = n - kNavStates;
  F = sys.F;
  Qc = sys.Qc;
  F.block(kVelocity, kAttitude, 3, 3) = skew(pose.specific_force);  // f x psi
  F.block(kVelocity, kNavStates, 3, ns) = C * sys.accel_rows.rightCols(ns);
  F.block(kAttitude, kNavStates, 3, ns) = -C * sys.gyro_rows.rightCols(ns);
  Qc.block(kVelocity, kVelocity, 3, 3) = C * sys.accel_white.asDiagonal() * C.transpose();
  Qc.block(kAttitude, kAttitude, 3, 3) = C * sys.gyro_white.asDiagonal() * C.transpose();
}

Step discretise(const Eigen::MatrixXd& F, const Eigen::MatrixXd& Qc, double dt) {
  const Eigen::Index n = F.rows();
  // The exponential's top-right block is linear in Qc (the matrix is block upper
  // triangular), so Qc enters scaled to F's size by a power of two (exact) and Q is scaled
  // back. Unscaled, the exponential's scaling and squaring took its number of squarings
  // from the whole matrix's norm: a Qc dt of 1e20 beside an F dt of 0.1 (a gyroscope white
  // noise of sigma2 = 1e22 at 100 Hz) had it square 2^-66 F dt, which vanishes beside the
  // identity: Phi came out as I, the position no longer followed the velocity, and the
  // analysis reported errors of 0 m.
  const double f_norm = (F * dt).cwiseAbs().colwise().sum().maxCoeff();
  const double q_norm = (Qc * dt).cwiseAbs().colwise().sum().maxCoeff();
  int scale = 0;  // Q = 2^scale Q(Qc 2^-scale)
  if (q_norm > 0.0 && std::isfinite(q_norm)) std::frexp(q_norm / std::max(f_norm, 1.0), &scale);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  m.topLeftCorner(n, n) = -F * dt;
  m.topRightCorner(n, n) = (Qc * dt).unaryExpr([scale](double x) { return std::ldexp(x, -scale); });
  m.bottomRightCorner(n, n) = F.transpose() * dt;
  const Eigen::MatrixXd e = m.exp();
  Step s;
  s.Phi = e.bottomRightCorner(n, n).transpose();
  s.Q = (s.Phi * e.topRightCorner(n, n)).unaryExpr([scale](double x) { return std::ldexp(x, scale); });
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
