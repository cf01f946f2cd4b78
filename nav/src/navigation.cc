// The covariance analysis of a mismatched navigation filter (navigation.h) as named stages:
// models -> error systems -> exact block steps -> the filter's own gains and covariance ->
// the actual errors of the augmented [truth; filter estimate] system -> NEES and verdict.
#include "gmwm/nav/navigation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/random/normal_distribution.hpp>

#include "error_system.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/choice.h"

namespace gmwm::nav {

using detail::kAttitude;
using detail::kNavStates;
using detail::kPosition;
using detail::kVelocity;

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::kConsistent:
      return "consistent";
    case Verdict::kOptimistic:
      return "optimistic";
    case Verdict::kPessimistic:
      return "pessimistic";
  }
  return "?";
}

std::string SensorModel::Validate() const {
  if (!(freq > 0.0) || !std::isfinite(freq))
    return "the sampling rate must be positive (got " + std::to_string(freq) + ")";
  if (!(to_si > 0.0) || !std::isfinite(to_si))
    return "the unit's factor to SI must be positive (got " + std::to_string(to_si) + ")";
  if (theta.size() != model.num_parameters())
    return "the model " + model.to_string() + " has " + std::to_string(model.num_parameters()) + " parameters, " +
           std::to_string(theta.size()) + " values given";
  if (std::string why = model.validate(theta); !why.empty()) return why;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    if (!p.continuous_form({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, freq))
      return "component " + std::to_string(c + 1) + " (" + p.name() +
             ") has no continuous-time Gauss-Markov form (an AR1 needs 0 < phi < 1; SIN, MA1 and ARMA have "
             "none): navigation errors cannot be propagated through it";
  }
  return {};
}

ImuModel ImuModel::isotropic(std::string label, const SensorModel& gyro, const SensorModel& accel) {
  ImuModel m;
  m.label = std::move(label);
  m.gyro.fill(gyro);
  m.accel.fill(accel);
  return m;
}

std::string ImuModel::Validate() const {
  static const char* const kAxis[] = {"x", "y", "z"};
  const std::string who = label.empty() ? "" : label + ": ";
  for (int a = 0; a < 3; ++a) {
    if (std::string why = gyro[static_cast<std::size_t>(a)].Validate(); !why.empty())
      return who + "gyroscope " + kAxis[a] + ": " + why;
    if (std::string why = accel[static_cast<std::size_t>(a)].Validate(); !why.empty())
      return who + "accelerometer " + kAxis[a] + ": " + why;
  }
  return {};
}

std::string Scenario::Validate() const {
  auto positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (!positive(horizon)) return "horizon must be positive (s), got " + std::to_string(horizon);
  if (!(imu_rate >= 0.0) || !std::isfinite(imu_rate)) return "the IMU rate must be 0 (the truth's) or positive (Hz)";
  if (!(fix_rate >= 0.0) || !std::isfinite(fix_rate)) return "fix rate must be 0 or positive (Hz)";
  if (fix_rate > 0.0 && !positive(fix_sigma)) return "fix sigma must be positive (m)";
  if (!positive(gravity)) return "gravity must be positive (m/s^2)";
  if (!positive(initial_position) || !positive(initial_velocity) || !positive(initial_attitude))
    return "the initial errors must be positive";
  if (!positive(output_interval)) return "the output interval must be positive (s)";
  if (!(judge_from >= 0.0) || !(judge_from < horizon)) return "the judged stretch must start in [0, horizon) (s)";
  for (const Outage& o : outages)
    if (!(o.start >= 0.0 && o.end > o.start) || !std::isfinite(o.end))
      return "an outage must have 0 <= start < end (s), got [" + std::to_string(o.start) + ", " +
             std::to_string(o.end) + "]";
  return {};
}

const char* to_string(Trajectory t) {
  switch (t) {
    case Trajectory::kStatic:
      return "static";
    case Trajectory::kConstantVelocity:
      return "constant-velocity";
    case Trajectory::kManoeuvre:
      return "manoeuvre";
  }
  return "?";
}

namespace {
constexpr Trajectory kTrajectories[] = {Trajectory::kStatic, Trajectory::kConstantVelocity, Trajectory::kManoeuvre};
}  // namespace

std::optional<Trajectory> parse_trajectory(const std::string& name) { return parse_among(name, kTrajectories); }

std::vector<std::string> trajectory_names() { return names_among(kTrajectories); }

namespace {
// The built-in manoeuvre (navigation.h): speed 10 m/s reached in 5 s, sides of 20 s, turns
// of 10 s through 90 degrees. A coordinated turn at speed v and yaw rate w has a
// centripetal acceleration v w towards the turn's centre.
constexpr std::int64_t kAccelerateSeconds = 5, kStraightSeconds = 20, kTurnSeconds = 10;
constexpr double kSpeed = 10.0;  // m/s
constexpr double kPi = 3.14159265358979323846;
}  // namespace

Pose pose_at(Trajectory trajectory, std::int64_t second, double gravity) {
  Pose p;
  p.specific_force = Eigen::Vector3d(0.0, 0.0, -gravity);
  if (trajectory != Trajectory::kManoeuvre) return p;
  if (second < kAccelerateSeconds) {
    p.specific_force.x() = kSpeed / static_cast<double>(kAccelerateSeconds);
    return p;
  }
  const std::int64_t side = kStraightSeconds + kTurnSeconds;
  const std::int64_t in_cycle = (second - kAccelerateSeconds) % (4 * side);
  const std::int64_t k = in_cycle / side, s = in_cycle % side;
  const double rate = (kPi / 2.0) / static_cast<double>(kTurnSeconds);  // rad/s
  p.heading = static_cast<double>(k) * kPi / 2.0;
  if (s >= kStraightSeconds) {
    p.heading += rate * (static_cast<double>(s - kStraightSeconds) + 0.5);
    const double towards = p.heading + kPi / 2.0;  // a right turn's centre
    p.specific_force.x() = kSpeed * rate * std::cos(towards);
    p.specific_force.y() = kSpeed * rate * std::sin(towards);
  }
  return p;
}

namespace {

// Limits of a scenario's grid: 1e6 fix periods (14 h at 20 Hz, 11 days at 1 Hz; a gain of
// ~1 kB each) and 2e5 output times (56 h at 1 s; 0.65 kB each).
constexpr std::int64_t kMaxBlocks = 1000000;
constexpr std::int64_t kMaxOutputs = 200000;

// The analysis' time grid: blocks of `block` IMU steps (the largest that divides the fix
// period, the output interval and, for the manoeuvre, the second its pose is held for),
// a fix (where one is due) at the end of a block, an output every `per_output` blocks,
// and the pose each block is flown at (an index into `poses`).
struct Grid {
  double dt = 0.0;
  std::int64_t block = 1, blocks = 0, per_output = 1, per_fix = 0;  // per_fix 0: no fixes
  std::vector<Pose> poses;
  std::vector<int> pose_of_block;
};

// n steps of length dt in a duration, or -1 when it is not a whole number of them.
std::int64_t whole_steps(double duration, double dt) {
  const double k = duration / dt;
  const double r = std::round(k);
  return std::abs(k - r) <= 1e-6 * std::max(1.0, r) && r >= 1.0 ? static_cast<std::int64_t>(r) : -1;
}

double imu_rate_of(const Scenario& s, const ImuModel& truth) {
  return s.imu_rate > 0.0 ? s.imu_rate : truth.gyro[0].freq;
}

Grid grid_of(const Scenario& s, double freq) {
  Grid g;
  g.dt = 1.0 / freq;
  const std::int64_t out = whole_steps(s.output_interval, g.dt);
  if (out < 0)
    throw InputError("the output interval (" + std::to_string(s.output_interval) +
                     " s) must be a whole number of IMU periods (1/" + std::to_string(freq) + " s)");
  std::int64_t block = out, fix = 0;
  if (s.fix_rate > 0.0) {
    fix = whole_steps(1.0 / s.fix_rate, g.dt);
    if (fix < 0)
      throw InputError("the fix period (1/" + std::to_string(s.fix_rate) + " s) must be a whole number of IMU periods");
    block = std::gcd(block, fix);
  }
  std::int64_t second = 0;
  if (s.trajectory == Trajectory::kManoeuvre) {
    second = whole_steps(1.0, g.dt);
    if (second < 0)
      throw InputError("the manoeuvre holds each pose for a second: the IMU rate (" + std::to_string(freq) +
                       " Hz) must be a whole number of Hz");
    block = std::gcd(block, second);
  }
  g.block = block;
  g.per_output = out / block;
  g.per_fix = fix / block;
  g.blocks = static_cast<std::int64_t>(std::floor(s.horizon / (static_cast<double>(g.block) * g.dt) + 1e-9));
  g.blocks -= g.blocks % g.per_output;  // end on an output
  if (g.blocks < 1) throw InputError("the horizon is shorter than one output interval");
  // Memory: a filter gain per block (states x 3 doubles) and a 9 x 9 covariance per output.
  if (g.blocks > kMaxBlocks)
    throw InputError("the scenario has " + std::to_string(g.blocks) +
                     " analysis steps (one per fix period or output "
                     "interval), more than " +
                     std::to_string(kMaxBlocks) + ": shorten the horizon or lower the fix rate");
  if (g.blocks / g.per_output > kMaxOutputs)
    throw InputError("the scenario has " + std::to_string(g.blocks / g.per_output) + " output times, more than " +
                     std::to_string(kMaxOutputs) + ": lengthen the output interval");
  g.pose_of_block.resize(static_cast<std::size_t>(g.blocks));
  for (std::int64_t b = 0; b < g.blocks; ++b) {
    const Pose p = pose_at(s.trajectory, second > 0 ? b * g.block / second : 0, s.gravity);
    std::size_t k = 0;
    while (k < g.poses.size() && !(g.poses[k].heading == p.heading && g.poses[k].specific_force == p.specific_force))
      ++k;
    if (k == g.poses.size()) g.poses.push_back(p);
    g.pose_of_block[static_cast<std::size_t>(b)] = static_cast<int>(k);
  }
  return g;
}

// Whether a fix comes at the end of block b.
bool fix_at(const Scenario& s, const Grid& g, std::int64_t b) {
  if (g.per_fix == 0 || (b + 1) % g.per_fix != 0) return false;
  const double t = static_cast<double>((b + 1) * g.block) * g.dt;
  for (const Outage& o : s.outages)
    if (t >= o.start && t < o.end) return false;
  return true;
}

// A system and its exact block step at each of the grid's poses.
struct Propagation {
  detail::ErrorSystem sys;
  std::vector<detail::Step> steps;  // per pose
  const detail::Step& at(const Grid& g, std::int64_t b) const {
    return steps[static_cast<std::size_t>(g.pose_of_block[static_cast<std::size_t>(b)])];
  }
};

Propagation propagation(const ImuModel& model, const Scenario& s, const Grid& g) {
  Propagation p;
  p.sys = detail::error_system(model, s);
  Eigen::MatrixXd F, Qc;
  for (const Pose& pose : g.poses) {
    detail::at_pose(p.sys, pose, F, Qc);
    p.steps.push_back(detail::repeat(detail::discretise(F, Qc, g.dt), g.block));
    if (!p.steps.back().Phi.allFinite() || !p.steps.back().Q.allFinite())
      throw InputError((model.label.empty() ? std::string("a model") : model.label) +
                       ": the errors its noise adds over one step (" + std::to_string(g.block) +
                       " IMU periods) overflow a double (beyond 1.8e308): expected smaller noise figures");
  }
  return p;
}

// Rows of the position fix H (3 x n): the position errors.
Eigen::MatrixXd fix_rows(int n) {
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(3, n);
  h.leftCols(3).setIdentity();
  return h;
}

// sqrt of the trace of a 3x3 block.
double root_trace(const Eigen::MatrixXd& m, int at) { return std::sqrt(std::max(m.block(at, at, 3, 3).trace(), 0.0)); }

// The band of the mean NEES of n states over kNeesRuns runs.
std::pair<double, double> nees_band(int n) {
  const boost::math::chi_squared chi(static_cast<double>(n * kNeesRuns));
  return {boost::math::quantile(chi, 0.025) / kNeesRuns, boost::math::quantile(chi, 0.975) / kNeesRuns};
}

void finish_verdict(FilterErrors& f, double judge_from) {
  int inside = 0, above = 0, below = 0;
  for (std::size_t k = 0; k < f.nees.size(); ++k) {
    if (f.time[k] < judge_from - 1e-9) continue;
    const double v = f.nees[k];
    if (v > f.nees_high)
      ++above;
    else if (v < f.nees_low)
      ++below;
    else
      ++inside;
  }
  const int judged = inside + above + below;
  f.nees_inside = judged == 0 ? 0.0 : static_cast<double>(inside) / static_cast<double>(judged);
  f.nees_above = judged == 0 ? 0.0 : static_cast<double>(above) / static_cast<double>(judged);
  f.verdict = f.nees_inside >= 0.95 ? Verdict::kConsistent
              : above >= below      ? Verdict::kOptimistic
                                    : Verdict::kPessimistic;
}

// What the covariance analysis and the Monte Carlo share for one filter: its system's
// block steps and its gains and covariance along the grid (the gains do not depend on the
// data: a linear filter's are the same in every run).
struct FilterPlan {
  Propagation prop;
  std::vector<Eigen::MatrixXd> gain;            // per block (empty where no fix)
  std::vector<Eigen::Matrix3d> kept;            // per block with a fix: I - K_p = R S^-1
  std::vector<Eigen::MatrixXd> nav_covariance;  // per output: the filter's own 9 x 9
};

FilterPlan plan_filter(const ImuModel& model, const Scenario& s, const Grid& g) {
  FilterPlan f;
  f.prop = propagation(model, s, g);
  const int n = f.prop.sys.states();
  const Eigen::MatrixXd H = fix_rows(n);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(3, 3) * (s.fix_sigma * s.fix_sigma);
  Eigen::MatrixXd P = f.prop.sys.P0;
  f.nav_covariance.push_back(P.topLeftCorner(kNavStates, kNavStates));
  f.gain.resize(static_cast<std::size_t>(g.blocks));
  f.kept.resize(static_cast<std::size_t>(g.blocks));
  for (std::int64_t b = 0; b < g.blocks; ++b) {
    const detail::Step& step = f.prop.at(g, b);
    P = step.Phi * P * step.Phi.transpose() + step.Q;
    if (fix_at(s, g, b)) {
      const Eigen::MatrixXd S = H * P * H.transpose() + R;
      const Eigen::MatrixXd S_inv = S.ldlt().solve(Eigen::MatrixXd::Identity(3, 3));
      const Eigen::MatrixXd K = P * H.transpose() * S_inv;
      // The share of the position error a fix keeps, I - K_p = I - P_pp S^-1 = R S^-1
      // (S = P_pp + R), taken in the second form: as a difference it kept rounding's
      // eps * sqrt(P_pp) of it, 1.5e8 m of a position known to 1 m where the process noise
      // of one fix period is 1e48 m^2 (an accelerometer white noise of sigma2 = 1e50).
      const Eigen::Matrix3d kept = R * S_inv;
      Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(n, n) - K * H;
      I_KH.topLeftCorner(3, 3) = kept;
      P = I_KH * P * I_KH.transpose() + K * R * K.transpose();  // Joseph form
      f.gain[static_cast<std::size_t>(b)] = K;
      f.kept[static_cast<std::size_t>(b)] = kept;
    }
    P = 0.5 * (P + P.transpose());
    if ((b + 1) % g.per_output == 0) f.nav_covariance.push_back(P.topLeftCorner(kNavStates, kNavStates));
  }
  return f;
}

// The checks both methods start with; the grid at the scenario's IMU rate.
Grid checked_grid(const ImuModel& truth, const std::vector<ImuModel>& filters, const Scenario& scenario) {
  if (const std::string why = scenario.Validate(); !why.empty()) throw InputError("scenario: " + why);
  if (const std::string why = truth.Validate(); !why.empty()) throw InputError(why);
  for (const ImuModel& m : filters)
    if (const std::string why = m.Validate(); !why.empty()) throw InputError(why);
  if (filters.empty()) throw InputError("no filter model to analyse");
  return grid_of(scenario, imu_rate_of(scenario, truth));
}

void report(const Progress& progress, double share) {
  if (progress && !progress(share)) throw InputError("cancelled");
}

// A double holds variances up to 1.8e308 (m^2, (m/s)^2, rad^2): past it the propagation
// overflows to inf, then NaN (inf - inf), which the verdict's comparisons counted inside
// the NEES band and the table printed as '-' under "consistent". `whose` says whether the
// model's errors are the truth's ("it makes") or what a filter claims ("it claims").
void check_representable(double value, const std::string& label, const char* whose, double t, double horizon) {
  if (std::isfinite(value)) return;
  auto num = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return std::string(buf);
  };
  throw InputError((label.empty() ? std::string("a model") : label) + ": the navigation errors " + whose +
                   " overflow a double (beyond 1.8e308) by t = " + num(t) +
                   " s: expected noise figures whose errors a double holds over the " + num(horizon) +
                   " s horizon (smaller ones, or a shorter horizon)");
}

}  // namespace

// The estimation error's system, closed loop (the filter's corrections fed back to the
// navigation solution, as an error-state filter runs): y = [e, the navigation errors after
// the corrections (9); the truth's sensor states; the filter's estimates of its own sensor
// states]. The open-loop form [x_truth; x_hat] carries the raw inertial errors, which grow
// without bound (10^5 m after 20 min at rest), and takes e as the difference of two such
// numbers: its variance lost every digit past ~1000 s at 20 Hz updates. Closed loop, e's
// dynamics need only the truth's and the filter's sensor couplings: both share the
// kinematic block Phi_nn (the same trajectory), so x_hat's navigation part drops out.
struct ClosedLoop {
  int nt = 0, nf = 0;
  int size() const { return nt + nf - kNavStates; }
  int truth_sensors() const { return nt - kNavStates; }
  int filter_sensors() const { return nf - kNavStates; }
  // Phi of y from the truth's and the filter's transition over the same interval.
  Eigen::MatrixXd phi(const Eigen::MatrixXd& pt, const Eigen::MatrixXd& pf) const {
    const int st = truth_sensors(), sf = filter_sensors();
    Eigen::MatrixXd p = Eigen::MatrixXd::Zero(size(), size());
    p.topLeftCorner(kNavStates, kNavStates) = pt.topLeftCorner(kNavStates, kNavStates);
    p.block(0, kNavStates, kNavStates, st) = pt.block(0, kNavStates, kNavStates, st);
    p.block(0, kNavStates + st, kNavStates, sf) = -pf.block(0, kNavStates, kNavStates, sf);
    p.block(kNavStates, kNavStates, st, st) = pt.bottomRightCorner(st, st);
    p.block(kNavStates + st, kNavStates + st, sf, sf) = pf.bottomRightCorner(sf, sf);
    return p;
  }
  // A fix's correction y <- y + G (H e + v), G = [-K_nav; 0; K_sensors] (size x 3).
  Eigen::MatrixXd correction(const Eigen::MatrixXd& K) const {
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(size(), 3);
    G.topRows(kNavStates) = -K.topRows(kNavStates);
    G.bottomRows(filter_sensors()) = K.bottomRows(filter_sensors());
    return G;
  }
};

Analysis analyse(const ImuModel& truth, const std::vector<ImuModel>& filters, const Scenario& scenario,
                 const Progress& progress) {
  const Grid g = checked_grid(truth, filters, scenario);
  Analysis out;
  out.scenario = scenario;
  out.imu_rate = 1.0 / g.dt;
  const Propagation tp = propagation(truth, scenario, g);
  const int nt = tp.sys.states();
  const auto [low, high] = nees_band(kNavStates);
  for (std::size_t fi = 0; fi < filters.size(); ++fi) {
    const FilterPlan fp = plan_filter(filters[fi], scenario, g);
    const ClosedLoop cl{nt, fp.prop.sys.states()};
    const int ny = cl.size();
    std::vector<detail::Step> step(g.poses.size());
    for (std::size_t k = 0; k < g.poses.size(); ++k) {
      step[k].Phi = cl.phi(tp.steps[k].Phi, fp.prop.steps[k].Phi);
      step[k].Q = Eigen::MatrixXd::Zero(ny, ny);
      step[k].Q.topLeftCorner(nt, nt) = tp.steps[k].Q;
    }
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(ny, ny);  // Cov(y); the estimates start at 0
    A.topLeftCorner(nt, nt) = tp.sys.P0;
    const double r = scenario.fix_sigma * scenario.fix_sigma;
    FilterErrors fe;
    fe.label = filters[fi].label;
    fe.nees_low = low;
    fe.nees_high = high;
    fe.notes = fp.prop.sys.notes;
    auto record = [&](double t, std::size_t output) {
      const Eigen::MatrixXd actual = A.topLeftCorner(kNavStates, kNavStates);
      const Eigen::MatrixXd& claimed = fp.nav_covariance[output];
      fe.time.push_back(t);
      fe.position_rms.push_back(root_trace(actual, kPosition));
      fe.velocity_rms.push_back(root_trace(actual, kVelocity));
      fe.attitude_rms.push_back(root_trace(actual, kAttitude));
      fe.position_claimed.push_back(root_trace(claimed, kPosition));
      fe.velocity_claimed.push_back(root_trace(claimed, kVelocity));
      fe.attitude_claimed.push_back(root_trace(claimed, kAttitude));
      fe.nees.push_back(claimed.ldlt().solve(actual).trace());
      check_representable(actual.trace(), truth.label, "it makes", t, scenario.horizon);
      check_representable(claimed.trace(), fe.label, "it claims", t, scenario.horizon);
      check_representable(fe.nees.back(), fe.label, "it claims", t, scenario.horizon);
    };
    record(0.0, 0);
    std::size_t output = 0;
    for (std::int64_t b = 0; b < g.blocks; ++b) {
      const detail::Step& s = step[static_cast<std::size_t>(g.pose_of_block[static_cast<std::size_t>(b)])];
      A = s.Phi * A * s.Phi.transpose() + s.Q;
      const Eigen::MatrixXd& K = fp.gain[static_cast<std::size_t>(b)];
      if (K.size() > 0) {
        const Eigen::MatrixXd G = cl.correction(K);
        Eigen::MatrixXd M = Eigen::MatrixXd::Identity(ny, ny);
        // H selects e's position: y + G H y, with I - K_p as the plan keeps it (R S^-1).
        M.leftCols(3) += G;
        M.topLeftCorner(3, 3) = fp.kept[static_cast<std::size_t>(b)];
        A = M * A * M.transpose() + r * G * G.transpose();
      }
      A = 0.5 * (A + A.transpose());
      if ((b + 1) % g.per_output == 0) record(static_cast<double>((b + 1) * g.block) / out.imu_rate, ++output);
      if ((b & 63) == 0)
        report(progress, (static_cast<double>(fi) + static_cast<double>(b + 1) / static_cast<double>(g.blocks)) /
                             static_cast<double>(filters.size()));
    }
    finish_verdict(fe, scenario.judge_from);
    out.filters.push_back(std::move(fe));
  }
  report(progress, 1.0);
  return out;
}

}  // namespace gmwm::nav

namespace gmwm::nav {

Analysis monte_carlo(const ImuModel& truth, const std::vector<ImuModel>& filters, const Scenario& scenario, int runs,
                     std::uint64_t seed, const Progress& progress) {
  if (runs < 2) throw InputError("Monte Carlo needs at least 2 runs, got " + std::to_string(runs));
  const Grid g = checked_grid(truth, filters, scenario);
  // Runs step at the IMU's rate (the analysis' block steps are composed from these, so the
  // runs check the composition too), each pose's one-step transition and noise root.
  const detail::ErrorSystem ts = detail::error_system(truth, scenario);
  std::vector<detail::Step> truth_step;
  std::vector<Eigen::MatrixXd> noise_root;
  for (const Pose& pose : g.poses) {
    Eigen::MatrixXd F, Qc;
    detail::at_pose(ts, pose, F, Qc);
    truth_step.push_back(detail::discretise(F, Qc, g.dt));
    noise_root.push_back(detail::square_root(truth_step.back().Q));
  }
  const Eigen::MatrixXd start_root = detail::square_root(ts.P0);
  const int nt = ts.states();
  const std::size_t outputs = static_cast<std::size_t>(g.blocks / g.per_output) + 1;
  const auto [low, high] = nees_band(kNavStates);
  Analysis out;
  out.scenario = scenario;
  out.imu_rate = 1.0 / g.dt;
  for (std::size_t fi = 0; fi < filters.size(); ++fi) {
    const FilterPlan fp = plan_filter(filters[fi], scenario, g);
    const ClosedLoop cl{nt, fp.prop.sys.states()};
    std::vector<Eigen::MatrixXd> y_step;  // one IMU step of y, per pose
    for (std::size_t k = 0; k < g.poses.size(); ++k) {
      Eigen::MatrixXd F, Qc;
      detail::at_pose(fp.prop.sys, g.poses[k], F, Qc);
      y_step.push_back(cl.phi(truth_step[k].Phi, detail::discretise(F, Qc, g.dt).Phi));
    }
    std::vector<Eigen::LLT<Eigen::MatrixXd>> claimed_inverse;
    for (const auto& c : fp.nav_covariance) claimed_inverse.emplace_back(c);
    // Per run and output: the squared errors of the three quantities and the NEES (stored
    // per run, summed in run order: the same result whatever the thread count).
    std::vector<Eigen::Matrix<double, 4, Eigen::Dynamic>> per_run(static_cast<std::size_t>(runs));
    const double r = scenario.fix_sigma;
    gmwm::parallel_for(0, runs, [&](int run) {
      // One stream per run, the same for every filter: each filter meets the same truths.
      Rng rng = make_stream(seed, {static_cast<std::uint64_t>(run)});
      boost::random::normal_distribution<double> z(0.0, 1.0);
      auto normals = [&](int n) {
        Eigen::VectorXd v(n);
        for (int k = 0; k < n; ++k) v(k) = z(rng);
        return v;
      };
      Eigen::VectorXd y = Eigen::VectorXd::Zero(cl.size());  // closed loop, as analyse
      y.head(nt) = start_root * normals(nt);
      auto& acc = per_run[static_cast<std::size_t>(run)];
      acc.resize(4, static_cast<Eigen::Index>(outputs));
      auto record = [&](std::size_t o) {
        const Eigen::VectorXd e = y.head(kNavStates);
        acc(0, static_cast<Eigen::Index>(o)) = e.segment(kPosition, 3).squaredNorm();
        acc(1, static_cast<Eigen::Index>(o)) = e.segment(kVelocity, 3).squaredNorm();
        acc(2, static_cast<Eigen::Index>(o)) = e.segment(kAttitude, 3).squaredNorm();
        acc(3, static_cast<Eigen::Index>(o)) = e.dot(claimed_inverse[o].solve(e));
      };
      record(0);
      std::size_t o = 0;
      for (std::int64_t b = 0; b < g.blocks; ++b) {
        const auto pose = static_cast<std::size_t>(g.pose_of_block[static_cast<std::size_t>(b)]);
        for (std::int64_t k = 0; k < g.block; ++k) {
          y = y_step[pose] * y;
          y.head(nt) += noise_root[pose] * normals(nt);
        }
        const Eigen::MatrixXd& K = fp.gain[static_cast<std::size_t>(b)];
        if (K.size() > 0) {
          const Eigen::Vector3d noise = r * normals(3);
          const Eigen::Vector3d innovation = y.head(3) + noise;  // the fix minus the corrected solution
          // The position error left, (I - K_p) e_p - K_p v, with I - K_p as the plan keeps it.
          const Eigen::Vector3d position = fp.kept[static_cast<std::size_t>(b)] * y.head(3) - K.topRows(3) * noise;
          y += cl.correction(K) * innovation;
          y.head(3) = position;
        }
        if ((b + 1) % g.per_output == 0) record(++o);
      }
    });
    report(progress, static_cast<double>(fi + 1) / static_cast<double>(filters.size()));
    Eigen::Matrix<double, 4, Eigen::Dynamic> sum =
        Eigen::Matrix<double, 4, Eigen::Dynamic>::Zero(4, static_cast<Eigen::Index>(outputs));
    for (const auto& a : per_run) sum += a;
    sum /= static_cast<double>(runs);
    FilterErrors fe;
    fe.label = filters[fi].label;
    fe.nees_low = low;
    fe.nees_high = high;
    fe.notes = fp.prop.sys.notes;
    for (std::size_t k = 0; k < outputs; ++k) {
      const auto c = static_cast<Eigen::Index>(k);
      fe.time.push_back(static_cast<double>(static_cast<std::int64_t>(k) * g.per_output * g.block) / out.imu_rate);
      check_representable(sum.col(c).head(3).sum(), truth.label, "it makes", fe.time.back(), scenario.horizon);
      check_representable(fp.nav_covariance[k].trace(), fe.label, "it claims", fe.time.back(), scenario.horizon);
      check_representable(sum(3, c), fe.label, "it claims", fe.time.back(), scenario.horizon);
      fe.position_rms.push_back(std::sqrt(sum(0, c)));
      fe.velocity_rms.push_back(std::sqrt(sum(1, c)));
      fe.attitude_rms.push_back(std::sqrt(sum(2, c)));
      fe.position_claimed.push_back(root_trace(fp.nav_covariance[k], kPosition));
      fe.velocity_claimed.push_back(root_trace(fp.nav_covariance[k], kVelocity));
      fe.attitude_claimed.push_back(root_trace(fp.nav_covariance[k], kAttitude));
      fe.nees.push_back(sum(3, c));
    }
    finish_verdict(fe, scenario.judge_from);
    out.filters.push_back(std::move(fe));
  }
  return out;
}

}  // namespace gmwm::nav
