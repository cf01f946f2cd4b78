#pragma once
// What a noise model means for navigation (issue 28): the position, velocity and attitude
// errors of an inertial navigation filter aided by position fixes, when its sensors' errors
// follow one model (the truth) and the filter assumes another, by linear covariance
// analysis of the mismatched filter (Maybeck 1979, vol. 1, ch. 6: the truth's states
// augmented with the filter's), exact at every output time for the linear error model;
// and the same by Monte Carlo as its check.
//
// The error model: a flat, non-rotating Earth in a local level frame (x north, y east,
// z down), errors e = [dp, dv, psi] (position m, velocity m/s, attitude rad):
//   d(dp)/dt = dv,  d(dv)/dt = f_n x psi + C db_a,  d(psi)/dt = -C db_g,
// f_n the specific force ((0, 0, -g) at rest), C the body-to-level rotation (the heading),
// db_a and db_g the accelerometer's and gyroscope's errors, each axis its own model
// (ContinuousForm of its components, process.h). Continuous time throughout; the
// discrete step is the exact one (Van Loan 1978), so a white gyro's attitude error is
// N sqrt(t) and a random walk's K t^(3/2) / sqrt(3) at every output time, to rounding.
// Constant velocity on this Earth has the same error dynamics as rest (no Coriolis, no
// transport rate); the scenario keeps the name for what a user asks. The manoeuvring
// trajectory (Trajectory::kManoeuvre) changes C and f_n second by second, so that the
// heading error and the horizontal biases become observable as on a real vehicle.
//
//   gmwm::nav::Scenario s;                 // at rest, 600 s, a fix every second (1 m)
//   s.outages = {{300.0, 360.0}};          // a 60 s outage
//   const auto a = gmwm::nav::analyse(truth, {truth, wn_rw_only}, s);
//   a.filters[1].position_rms.back(), a.filters[1].verdict
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm::nav {

/// One inertial sensor axis' error model: a GMWM model and its values at the sampling rate
/// `freq` (Hz), in SI units (rad/s for a gyroscope, m/s^2 for an accelerometer).
struct SensorModel {
  Model model;
  Eigen::VectorXd theta;
  double freq = 0.0;
  /// SI units per unit of the model (1 / Unit::per_si: 0.0174533 for deg/s, 9.80665 for g);
  /// the model's values are in its own unit, the analysis in SI.
  double to_si = 1.0;
  /// Empty when valid (every component with a continuous form, theta the model's size, a
  /// positive rate), else one line naming the component.
  std::string Validate() const;
};

/// An IMU's error model, axis by axis (x, y, z of the body: north, east, down here): what
/// the truth has, or what a filter assumes.
struct ImuModel {
  std::string label;  ///< e.g. "truth", "WN + RW projection", "datasheet"
  std::array<SensorModel, 3> gyro, accel;
  /// The same gyroscope and accelerometer models on the three axes.
  static ImuModel isotropic(std::string label, const SensorModel& gyro, const SensorModel& accel);
  /// Empty when valid, else one line naming the label, the sensor and the axis.
  std::string Validate() const;
};

struct Outage {
  double start = 0.0, end = 0.0;  ///< s, no position fix in [start, end)
};

/// What the vehicle does: at rest, at constant velocity (the same error dynamics on a flat,
/// non-rotating Earth), or the built-in manoeuvre: a 5 s acceleration north at 2 m/s^2 to
/// 10 m/s, then a square circuit repeated for the horizon, each side 20 s straight and a
/// 10 s coordinated 90-degree right turn (yaw rate 9 deg/s, centripetal 1.571 m/s^2). The
/// heading and the specific force are held constant over each second (at the second's
/// midpoint): the analysis is exact for that piecewise-constant trajectory.
enum class Trajectory { kStatic, kConstantVelocity, kManoeuvre };
const char* to_string(Trajectory t);  ///< "static", "constant-velocity", "manoeuvre"
std::optional<Trajectory> parse_trajectory(const std::string& name);
/// The names parse_trajectory takes: static, constant-velocity, manoeuvre (choice.h).
std::vector<std::string> trajectory_names();

/// The vehicle's state as the error dynamics see it: heading (rad, from north towards
/// east; the body is level) and the specific force in the level frame (m/s^2).
struct Pose {
  double heading = 0.0;
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();
};

/// The pose of `trajectory` over the second starting at whole second `second`.
Pose pose_at(Trajectory trajectory, std::int64_t second, double gravity);

struct Scenario {
  Trajectory trajectory = Trajectory::kStatic;
  /// IMU rate, Hz: the analysis' step (0: the truth's sampling rate). Every model is used
  /// through its continuous form, so a filter model given at another rate means the same.
  double imu_rate = 0.0;
  double horizon = 600.0;       ///< s
  double fix_rate = 1.0;        ///< Hz, position fixes (0: none)
  double fix_sigma = 1.0;       ///< m, per axis
  std::vector<Outage> outages;  ///< no fix inside these
  double gravity = 9.80665;     ///< m/s^2
  /// Initial 1-sigma errors per axis: position (m), velocity (m/s), attitude (rad).
  double initial_position = 1.0, initial_velocity = 0.1, initial_attitude = 1e-3;
  /// The NEES verdict counts the output times from this one on (s): a warm-up before it
  /// (a filter started without priors on its bias states) is shown but not judged.
  double judge_from = 0.0;
  /// Output every this many seconds (a multiple of the IMU period and of the fix period).
  double output_interval = 1.0;
  /// Empty when valid, else one line naming the field.
  std::string Validate() const;
};

/// The 95% band of the mean NEES over kNeesRuns runs at one time (Bar-Shalom, Li &
/// Kirubarajan 2001, s. 5.4): a consistent filter's expected NEES lies inside it.
inline constexpr int kNeesRuns = 100;

enum class Verdict { kConsistent, kOptimistic, kPessimistic };
const char* to_string(Verdict v);

/// One filter model's errors over time (every output time, and t = 0).
struct FilterErrors {
  std::string label;
  std::vector<double> time;  ///< s
  /// Root-mean-square error (the root of the actual error covariance's trace over the three
  /// axes) and what the filter claims (its own covariance's), per quantity.
  std::vector<double> position_rms, position_claimed;  ///< m
  std::vector<double> velocity_rms, velocity_claimed;  ///< m/s
  std::vector<double> attitude_rms, attitude_claimed;  ///< rad
  /// Expected NEES of the nine navigation errors, tr(P_filter^-1 P_actual) (9 when the
  /// filter is right), and the band of a mean over kNeesRuns runs.
  std::vector<double> nees;
  double nees_low = 0.0, nees_high = 0.0;
  /// Share of the judged output times (Scenario::judge_from) whose expected NEES lies
  /// inside the band; verdict: consistent when at least 95% do, else optimistic (the filter claims less error than it makes:
  /// NEES above the band more often than below) or pessimistic.
  double nees_inside = 0.0;
  double nees_above = 0.0;  ///< share of the judged output times above the band
  Verdict verdict = Verdict::kConsistent;
  std::vector<std::string> notes;  ///< what the models left out (QN)
};

struct Analysis {
  Scenario scenario;
  double imu_rate = 0.0;  ///< Hz: the truth's sampling rate
  std::vector<FilterErrors> filters;
};

/// Progress in [0, 1]; return false to cancel (InputError "cancelled").
using Progress = std::function<bool(double)>;

/// The errors of each filter model against the truth, by covariance analysis. Throws InputError naming the field for an invalid
/// scenario or model.
Analysis analyse(const ImuModel& truth, const std::vector<ImuModel>& filters, const Scenario& scenario,
                 const Progress& progress = {});

/// The same by Monte Carlo: `runs` seeded runs (a stream per run, so the result does not
/// depend on the thread count); the *_rms are the runs' root-mean-square errors, the NEES
/// the runs' mean NEES.
Analysis monte_carlo(const ImuModel& truth, const std::vector<ImuModel>& filters, const Scenario& scenario, int runs,
                     std::uint64_t seed, const Progress& progress = {});

}  // namespace gmwm::nav
