// The navigation-error analysis (nav/navigation.h) against closed forms, against its own
// Monte Carlo, and its refusals (issue 28).
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/nav/navigation.h"

namespace gmwm::nav {
namespace {

constexpr double kRate = 100.0;  // Hz

SensorModel sensor(const std::string& spec) {
  const Model m = parse_model(spec);
  return {m, m.given_values(), kRate};
}

// A sensor whose error is negligible beside the one under test (a white noise of density
// 1e-15 of it: its share of a variance is ~1e-30).
SensorModel quiet() { return sensor("WN(sigma2=1e-30)"); }

// No fixes, initial errors at ~0: the free-inertial growth of one sensor's error.
Scenario free_inertial(double horizon) {
  Scenario s;
  s.horizon = horizon;
  s.fix_rate = 0.0;
  s.initial_position = s.initial_velocity = s.initial_attitude = 1e-15;
  s.output_interval = 1.0;
  return s;
}

// The last output's attitude / velocity / position root-mean-square over the three axes.
// By value: the tests bind it to a reference to a temporary Analysis, whose life ends with the
// statement (a reference into it dangled).
FilterErrors only(const Analysis& a) { return a.filters.front(); }

TEST(NavigationErrors, AWhiteGyroGivesAnAttitudeErrorOfNRootT) {
  // sigma2 = 1e-6 (rad/s)^2 per sample at 100 Hz: N^2 = 1e-8 rad^2/s. Per axis
  // Var(psi) = N^2 t; over three axes the root of the trace is sqrt(3 N^2 t).
  const ImuModel m = ImuModel::isotropic("wn", sensor("WN(sigma2=1e-6)"), quiet());
  const Analysis a = analyse(m, {m}, free_inertial(600.0));
  const FilterErrors& f = only(a);
  for (std::size_t k = 1; k < f.time.size(); k += 97) {
    const double want = std::sqrt(3.0 * 1e-8 * f.time[k]);
    EXPECT_NEAR(f.attitude_rms[k], want, 1e-9 * want) << "t = " << f.time[k];
  }
  EXPECT_EQ(f.time.back(), 600.0);
}

TEST(NavigationErrors, ARandomWalkGyroBiasGivesKTToTheThreeHalvesOverRootThree) {
  // gamma2 = 1e-12 per sample at 100 Hz: K^2 = 1e-10 (rad/s)^2/s. Var(psi) = K^2 t^3 / 3
  // per axis: the root of the trace over three axes is K t^(3/2).
  const ImuModel m = ImuModel::isotropic("rw", sensor("RW(gamma2=1e-12)"), quiet());
  const FilterErrors& f = only(analyse(m, {m}, free_inertial(600.0)));
  for (std::size_t k = 1; k < f.time.size(); k += 97) {
    const double t = f.time[k], want = std::sqrt(1e-10) * std::pow(t, 1.5);
    EXPECT_NEAR(f.attitude_rms[k], want, 1e-9 * want) << "t = " << t;
  }
}

TEST(NavigationErrors, AGaussMarkovGyroBiasGivesItsKnownIntegral) {
  // AR1(phi, sigma2) at 100 Hz: T = -1 / (f ln phi), s2 = sigma2 / (1 - phi^2). The
  // integral of a stationary Gauss-Markov bias has variance 2 s2 T^2 (t/T - 1 + e^(-t/T));
  // what the INS integrates is the samples, whose sum grows faster by the white density
  // w = s2 dt (1 + phi) / (1 - phi) - 2 s2 T (process.h, gauss_markov_form; 3e-7 of the
  // growth here), so the attitude variance is the integral's plus w t.
  const double phi = 0.999, sigma2 = 1e-8, dt = 1.0 / kRate;
  const double T = -1.0 / (kRate * std::log(phi)), s2 = sigma2 / (1.0 - phi * phi);
  const double w = s2 * dt * (1.0 + phi) / (1.0 - phi) - 2.0 * s2 * T;
  const ImuModel m = ImuModel::isotropic("gm", sensor("AR1(phi=0.999,sigma2=1e-8)"), quiet());
  const FilterErrors& f = only(analyse(m, {m}, free_inertial(600.0)));
  for (std::size_t k = 1; k < f.time.size(); k += 97) {
    const double t = f.time[k];
    const double want = std::sqrt(3.0 * (2.0 * s2 * T * T * (t / T - 1.0 + std::exp(-t / T)) + w * t));
    // w is a difference of two numbers 3e6 times larger: 1e-16 x 3e6 of it is rounding.
    EXPECT_NEAR(f.attitude_rms[k], want, 1e-9 * want) << "t = " << t;
  }
}

TEST(NavigationErrors, AWhiteAccelerometerGivesAVelocityRandomWalkAndNTToTheThreeHalvesInPosition) {
  // sigma2 = 1e-4 (m/s^2)^2 at 100 Hz: N^2 = 1e-6. Per axis Var(dv) = N^2 t and
  // Var(dp) = N^2 t^3 / 3 (no attitude error to couple in).
  const ImuModel m = ImuModel::isotropic("acc", quiet(), sensor("WN(sigma2=1e-4)"));
  const FilterErrors& f = only(analyse(m, {m}, free_inertial(600.0)));
  for (std::size_t k = 1; k < f.time.size(); k += 97) {
    const double t = f.time[k];
    const double v = std::sqrt(3.0 * 1e-6 * t), p = std::sqrt(1e-6 * t * t * t);
    EXPECT_NEAR(f.velocity_rms[k], v, 1e-9 * v) << "t = " << t;
    EXPECT_NEAR(f.position_rms[k], p, 1e-9 * p) << "t = " << t;
  }
}

TEST(NavigationErrors, AWhiteGyroOfAnyMagnitudeTiltsTheVelocityAndPositionAsItsClosedForms) {
  // At rest a tilt psi_x makes dv_y = -g psi_x (f x psi, f = (0, 0, -g)), likewise psi_y
  // dv_x: from a white gyro (N^2 = sigma2 / f) Var(dv) = g^2 N^2 t^3 / 3 and Var(dp) =
  // g^2 N^2 t^5 / 20 on each horizontal axis. The same within 1e-9 relative (the exact
  // step's rounding, as above) at every magnitude a double holds over the horizon: the
  // step's exponential once squared F dt away beside a Qc dt of 1e20 (sigma2 = 1e22 at
  // 100 Hz), leaving Phi = I and no velocity at all.
  const double g = 9.80665;
  for (double sigma2 : {1e-6, 1e22, 1e100, 1e250}) {
    const Model m = parse_model("WN");
    Eigen::VectorXd theta(1);
    theta << sigma2;
    const ImuModel model = ImuModel::isotropic("wn", SensorModel{m, theta, kRate}, quiet());
    const FilterErrors f = only(analyse(model, {model}, free_inertial(600.0)));
    const double n2 = sigma2 / kRate;
    for (std::size_t k = 1; k < f.time.size(); k += 97) {
      const double t = f.time[k];
      const double v = g * std::sqrt(2.0 * n2 * t * t * t / 3.0), p = g * std::sqrt(2.0 * n2 * std::pow(t, 5) / 20.0);
      EXPECT_NEAR(f.velocity_rms[k], v, 1e-9 * v) << "sigma2 = " << sigma2 << ", t = " << t;
      EXPECT_NEAR(f.position_rms[k], p, 1e-9 * p) << "sigma2 = " << sigma2 << ", t = " << t;
    }
  }
}

TEST(NavigationErrors, AFixHoldsThePositionErrorToItsOwnHoweverLargeTheAccelerometersNoise) {
  // Fixes every second (1 m per axis) on an accelerometer whose white noise puts P >= N^2
  // / 3 >= 3e17 m^2 into the position between two fixes: after each fix the position's
  // variance is P R / (P + R) = R (1 - R / P), so the error is sqrt(3) m to 3e-18 relative,
  // and what the right filter claims is the same (NEES 9). Taken as I - K_p the fix's
  // complement kept eps sqrt(P) of the prior: 1.5e8 m at sigma2 = 1e50, and 0 m where the
  // step's exponential had lost the dynamics.
  for (double sigma2 : {1e20, 1e50, 1e100, 1e300}) {
    const Model m = parse_model("WN");
    Eigen::VectorXd theta(1);
    theta << sigma2;
    const ImuModel model = ImuModel::isotropic("acc", quiet(), SensorModel{m, theta, kRate});
    Scenario s;
    s.horizon = 120.0;
    const FilterErrors f = only(analyse(model, {model}, s));
    for (std::size_t k = 1; k < f.time.size(); ++k) {
      EXPECT_NEAR(f.position_rms[k], std::sqrt(3.0), 1e-9) << "sigma2 = " << sigma2 << ", t = " << f.time[k];
      EXPECT_NEAR(f.position_claimed[k], std::sqrt(3.0), 1e-9) << "sigma2 = " << sigma2 << ", t = " << f.time[k];
      EXPECT_NEAR(f.nees[k], 9.0, 1e-6) << "sigma2 = " << sigma2 << ", t = " << f.time[k];
    }
    EXPECT_EQ(f.verdict, Verdict::kConsistent);
  }
}

TEST(NavigationErrors, RefusesErrorsBeyondADoubleNamingTheModelInsteadOfCallingThemConsistent) {
  // Free inertial, a white gyro of sigma2 = 1e300 at 100 Hz: the position's variance
  // g^2 N^2 t^5 / 20 passes 1.8e308 m^2 at t = 72 s. It was inf, then NaN, a NEES the
  // verdict counted inside its band: "consistent", errors printed as '-'.
  const Model m = parse_model("WN");
  Eigen::VectorXd theta(1);
  theta << 1e300;
  const ImuModel huge = ImuModel::isotropic("truth", SensorModel{m, theta, kRate}, quiet());
  try {
    analyse(huge, {huge}, free_inertial(600.0));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truth: the navigation errors it makes overflow a double"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("by t = 72 s"), std::string::npos) << e.what();
  }
  EXPECT_THROW(monte_carlo(huge, {huge}, free_inertial(600.0), 2, 1), InputError);
  // A filter model whose densities overflow once squared in SI (an inflation of 1e160).
  const ImuModel ok = ImuModel::isotropic("ok", sensor("WN(sigma2=1e-6)"), sensor("WN(sigma2=1e-4)"));
  ImuModel inflated = ok;
  inflated.label = "ok*1e160";
  for (auto& s : inflated.gyro) s.to_si = 1e160;
  try {
    analyse(ok, {inflated}, Scenario{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ok*1e160: its noise densities in SI units overflow a double"),
              std::string::npos)
        << e.what();
  }
}

TEST(NavigationErrors, ARightModelIsConsistentAndOneWithoutItsGaussMarkovBiasIsOptimistic) {
  // Position fixes every second (1 m) and a 60 s outage: the filter that knows the truth's
  // Gauss-Markov bias claims what it makes (NEES = 9 at every time: consistent); the one
  // that leaves it out claims less error than it makes.
  Scenario s;
  s.horizon = 300.0;
  s.outages = {{120.0, 180.0}};
  const ImuModel truth = ImuModel::isotropic("truth", sensor("AR1(phi=0.9999,sigma2=1e-12)+WN(sigma2=1e-8)"),
                                             sensor("AR1(phi=0.9999,sigma2=1e-8)+WN(sigma2=1e-5)"));
  const ImuModel without = ImuModel::isotropic("no GM", sensor("WN(sigma2=1e-8)"), sensor("WN(sigma2=1e-5)"));
  const Analysis a = analyse(truth, {truth, without}, s);
  const FilterErrors& right = a.filters[0];
  const FilterErrors& wrong = a.filters[1];
  for (double v : right.nees) EXPECT_NEAR(v, 9.0, 1e-6);
  EXPECT_EQ(right.verdict, Verdict::kConsistent);
  // The actual and the claimed covariance come from two recursions (the augmented 2n-state
  // one and the filter's own): equal up to rounding, which grows with the 300 fix updates
  // (each loses ~cond(S) eps ~ 1e-12 relative): 1e-7 relative is far above it and far below
  // any modelling difference (the wrong filter's differ by tens of percent).
  for (std::size_t k = 0; k < right.time.size(); ++k)
    EXPECT_NEAR(right.position_rms[k], right.position_claimed[k], 1e-7 * right.position_claimed[k]);
  EXPECT_EQ(wrong.verdict, Verdict::kOptimistic);
  // At the end of the outage (t = 180 s) the wrong filter's errors are larger than the
  // right one's and larger than what it claims.
  const std::size_t end = 180;
  ASSERT_EQ(wrong.time[end], 180.0);
  EXPECT_GT(wrong.position_rms[end], right.position_rms[end]);
  EXPECT_GT(wrong.position_rms[end], wrong.position_claimed[end]);
}

TEST(NavigationErrors, TheMethodsOwnComparisonFindsTheFilterWithoutItsGaussMarkovOptimistic) {
  // The GMWM method's motivating case (tools/bench/bench_nav.cc, docs/nav.md): WN + GM
  // (beta = 1e-4 /s) on every axis, accelerometer 70 ug/sqrt(Hz) and 50 ug, gyroscope
  // 30 deg/h/sqrt(Hz) and 10 deg/h; fixes every second, a 60 s outage. The right filter is
  // consistent; the one without the GM claims less than it makes (NEES above its band),
  // and its error at the outage's end is twice the right one's (56.8 m against 26.4 m).
  const double g = 9.80665, deg_h = 3.14159265358979323846 / 180.0 / 3600.0;
  auto model = [&](double beta) {
    auto one = [&](double n, double sigma) {
      Model m = parse_model(beta > 0.0 ? "GM+WN" : "WN", ProcessContext{kRate, true});
      Eigen::VectorXd theta(m.num_parameters());
      if (beta > 0.0)
        theta << beta, sigma * sigma, n * n * kRate;
      else
        theta << n * n * kRate;
      return SensorModel{m, theta, kRate};
    };
    return ImuModel::isotropic("beta", one(30.0 * deg_h, 10.0 * deg_h), one(70e-6 * g, 50e-6 * g));
  };
  Scenario s;
  s.outages = {{300.0, 360.0}};
  const Analysis a = analyse(model(1e-4), {model(1e-4), model(0.0)}, s);
  EXPECT_EQ(a.filters[0].verdict, Verdict::kConsistent);
  EXPECT_EQ(a.filters[1].verdict, Verdict::kOptimistic);
  EXPECT_GT(*std::max_element(a.filters[1].nees.begin(), a.filters[1].nees.end()), a.filters[1].nees_high);
  EXPECT_GT(a.filters[1].position_rms[359], 2.0 * a.filters[0].position_rms[359]);
}

TEST(NavigationErrors, StaysExactOnALongRunWithFastUpdatesWhereTheRawInertialErrorIsHuge) {
  // 25 minutes at rest with fixes at 20 Hz (5 cm): the uncorrected inertial errors reach
  // 1e5 m while the filter's stay at centimetres. The right filter's NEES is 9 at every
  // time (the closed-loop form: the open-loop difference of the two lost every digit past
  // ~1000 s, NEES jumping 6.9-12.3).
  Scenario s;
  s.horizon = 1500.0;
  s.fix_rate = 20.0;
  s.fix_sigma = 0.05;
  s.outages = {{1380.0, 1440.0}};
  s.output_interval = 10.0;
  const ImuModel truth =
      ImuModel::isotropic("truth", sensor("AR1(phi=0.99996,sigma2=1e-13)+RW(gamma2=3e-15)+WN(sigma2=1e-5)"),
                          sensor("AR1(phi=0.96,sigma2=5e-6)+RW(gamma2=5e-9)+WN(sigma2=2e-3)"));
  const FilterErrors f = only(analyse(truth, {truth}, s));
  for (std::size_t k = 0; k < f.time.size(); ++k) EXPECT_NEAR(f.nees[k], 9.0, 1e-6) << "t = " << f.time[k];
}

TEST(NavigationErrors, TheCovarianceAnalysisEqualsItsMonteCarloWithinTheMonteCarloError) {
  // 1000 runs of 10 minutes with a 60 s outage: at every output time the runs' mean squared
  // position error, a mean of 1000 values of a scaled chi-square-like quantity, lies within
  // 4 of its standard errors of the analysis' (the standard error of a mean square of a
  // Gaussian vector: at most sqrt(2 / runs) of it, 0.045 relative); likewise the mean NEES.
  // The runs step at the IMU's rate (here 10 Hz: the models at 100 Hz enter through their
  // continuous forms), the analysis by exact blocks of a second.
  Scenario s;
  s.horizon = 600.0;
  s.imu_rate = 10.0;
  s.outages = {{300.0, 360.0}};
  s.output_interval = 10.0;
  const ImuModel truth =
      ImuModel::isotropic("truth", sensor("AR1(phi=0.9995,sigma2=1e-12)+RW(gamma2=1e-14)+WN(sigma2=1e-8)"),
                          sensor("AR1(phi=0.999,sigma2=1e-9)+WN(sigma2=1e-5)"));
  const ImuModel filter = ImuModel::isotropic("WN+RW", sensor("RW(gamma2=1e-13)+WN(sigma2=1e-8)"),
                                              sensor("RW(gamma2=1e-10)+WN(sigma2=1e-5)"));
  constexpr int kRuns = 1000;
  const Analysis exact = analyse(truth, {filter}, s);
  const Analysis mc = monte_carlo(truth, {filter}, s, kRuns, 2828);
  const FilterErrors& e = exact.filters.front();
  const FilterErrors& m = mc.filters.front();
  ASSERT_EQ(e.time, m.time);
  const double tol = 4.0 * std::sqrt(2.0 / kRuns);
  int worst = 0;
  double worst_z = 0.0;
  for (std::size_t k = 1; k < e.time.size(); ++k) {
    const double rel = m.position_rms[k] * m.position_rms[k] / (e.position_rms[k] * e.position_rms[k]) - 1.0;
    EXPECT_LT(std::abs(rel), tol) << "position, t = " << e.time[k];
    const double relv = m.velocity_rms[k] * m.velocity_rms[k] / (e.velocity_rms[k] * e.velocity_rms[k]) - 1.0;
    EXPECT_LT(std::abs(relv), tol) << "velocity, t = " << e.time[k];
    EXPECT_LT(std::abs(m.nees[k] / e.nees[k] - 1.0), tol) << "NEES, t = " << e.time[k];
    if (std::abs(rel) / tol > worst_z) worst_z = std::abs(rel) / tol, worst = static_cast<int>(k);
  }
  RecordProperty("worst_position_in_tolerances", std::to_string(worst_z) + " at output " + std::to_string(worst));
}

TEST(NavigationErrors, AManoeuvreMakesTheHeadingObservableAndTheRightFilterStaysConsistent) {
  // At rest a position fix says nothing of the heading error (the yaw's error grows with
  // the gyro's as in free inertial); turns and accelerations put it into the position, so
  // the attitude error ends far smaller. The right filter claims what it makes on both
  // (NEES 9 to rounding), and the pose changes every second without losing exactness.
  Scenario s;
  s.horizon = 600.0;
  const ImuModel truth = ImuModel::isotropic("truth", sensor("RW(gamma2=1e-14)+WN(sigma2=1e-8)"),
                                             sensor("RW(gamma2=1e-10)+WN(sigma2=1e-5)"));
  const FilterErrors at_rest = only(analyse(truth, {truth}, s));
  s.trajectory = Trajectory::kManoeuvre;
  const FilterErrors moving = only(analyse(truth, {truth}, s));
  // (0.0045 rad against 0.0086 rad after 600 s; the yaw's random-walk part keeps growing
  // between turns.)
  EXPECT_LT(moving.attitude_rms.back(), 0.75 * at_rest.attitude_rms.back());
  for (double v : moving.nees) EXPECT_NEAR(v, 9.0, 1e-6);
  EXPECT_EQ(moving.verdict, Verdict::kConsistent);
}

TEST(NavigationErrors, TheManoeuvresPosesAreTheCircuitItDescribes) {
  const double g = 9.80665;
  const Pose start = pose_at(Trajectory::kManoeuvre, 0, g);
  EXPECT_DOUBLE_EQ(start.specific_force.x(), 2.0);  // 10 m/s in 5 s
  EXPECT_DOUBLE_EQ(start.heading, 0.0);
  const Pose straight = pose_at(Trajectory::kManoeuvre, 5 + 10, g);
  EXPECT_DOUBLE_EQ(straight.specific_force.head<2>().norm(), 0.0);
  // The first turn's middle second: heading 4.5 x 9 deg, centripetal v w = 10 x pi / 20
  // towards heading + 90 deg; after four sides the circuit repeats.
  const Pose turning = pose_at(Trajectory::kManoeuvre, 5 + 20 + 4, g);
  const double pi = 3.14159265358979323846;
  EXPECT_NEAR(turning.heading, 4.5 * pi / 20.0, 1e-15);
  EXPECT_NEAR(turning.specific_force.head<2>().norm(), 10.0 * pi / 20.0, 1e-12);
  EXPECT_NEAR(
      turning.specific_force.head<2>().dot(Eigen::Vector2d(std::cos(turning.heading), std::sin(turning.heading))), 0.0,
      1e-12);
  const Pose again = pose_at(Trajectory::kManoeuvre, 5 + 20 + 4 + 120, g);
  EXPECT_EQ(again.heading, turning.heading);
  EXPECT_EQ(pose_at(Trajectory::kStatic, 29, g).specific_force, Eigen::Vector3d(0.0, 0.0, -g));
  EXPECT_EQ(parse_trajectory("manoeuvre"), Trajectory::kManoeuvre);
  EXPECT_FALSE(parse_trajectory("maneuver").has_value());
}

TEST(NavigationErrors, AModelInDegreesPerSecondMeansTheSameAsItsValuesInRadians) {
  // WN(sigma2) in deg/s with to_si = pi / 180 is WN(sigma2 (pi / 180)^2) in rad/s.
  const double k = 3.14159265358979323846 / 180.0;
  SensorModel deg = sensor("WN(sigma2=1e-4)+RW(gamma2=1e-10)");
  deg.to_si = k;
  const Model m = parse_model("WN+RW");
  Eigen::VectorXd theta(2);
  theta << 1e-4 * k * k, 1e-10 * k * k;
  const SensorModel rad{m, theta, kRate};
  const FilterErrors a = only(analyse(ImuModel::isotropic("deg", deg, quiet()),
                                      {ImuModel::isotropic("deg", deg, quiet())}, free_inertial(100.0)));
  const FilterErrors b = only(analyse(ImuModel::isotropic("rad", rad, quiet()),
                                      {ImuModel::isotropic("rad", rad, quiet())}, free_inertial(100.0)));
  EXPECT_NEAR(a.attitude_rms.back(), b.attitude_rms.back(), 1e-12 * b.attitude_rms.back());
}

TEST(NavigationErrors, AModelGivenAtAnotherRateMeansTheSameThroughItsContinuousForm) {
  // WN(sigma2) at 100 Hz has the density sigma2 / 100; at 200 Hz the same density is
  // WN(2 sigma2): a filter given at 200 Hz over a 100 Hz truth is the truth itself.
  const ImuModel truth = ImuModel::isotropic("truth", sensor("WN(sigma2=1e-6)"), sensor("WN(sigma2=1e-4)"));
  ImuModel fast = ImuModel::isotropic("fast", sensor("WN(sigma2=2e-6)"), sensor("WN(sigma2=2e-4)"));
  for (auto& g : fast.gyro) g.freq = 200.0;
  for (auto& a : fast.accel) a.freq = 200.0;
  const Analysis a = analyse(truth, {fast}, Scenario{});
  for (double v : a.filters.front().nees) EXPECT_NEAR(v, 9.0, 1e-6);
  EXPECT_EQ(a.imu_rate, kRate);
}

TEST(NavigationErrors, TheMonteCarloIsTheSameWhateverTheThreadCount) {
  // A stream per run, the runs' sums in run order: one thread and all of them agree to the bit.
  Scenario s;
  s.horizon = 60.0;
  s.outages = {{20.0, 40.0}};
  const ImuModel truth = ImuModel::isotropic("truth", sensor("AR1(phi=0.999,sigma2=1e-12)+WN(sigma2=1e-8)"),
                                             sensor("RW(gamma2=1e-10)+WN(sigma2=1e-5)"));
  const Analysis all = monte_carlo(truth, {truth}, s, 64, 99);
  Analysis one;
  {
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, 1);
    one = monte_carlo(truth, {truth}, s, 64, 99);
  }
  EXPECT_EQ(all.filters[0].position_rms, one.filters[0].position_rms);
  EXPECT_EQ(all.filters[0].nees, one.filters[0].nees);
}

TEST(NavigationErrors, AnAr1ThatForgetsWithinASampleIsItsWhiteNoise) {
  // phi = 1e-300 (L = 691, e^L near the largest double): the form is the samples' white
  // density alone, the analysis finite, and equal to WN(sigma2) to rounding.
  const ImuModel ar = ImuModel::isotropic("ar", sensor("AR1(phi=1e-300,sigma2=1e-6)"), quiet());
  const ImuModel wn = ImuModel::isotropic("wn", sensor("WN(sigma2=1e-6)"), quiet());
  const FilterErrors a = only(analyse(ar, {ar}, free_inertial(60.0)));
  const FilterErrors w = only(analyse(wn, {wn}, free_inertial(60.0)));
  EXPECT_NEAR(a.attitude_rms.back(), w.attitude_rms.back(), 1e-12 * w.attitude_rms.back());
}

TEST(NavigationErrors, RefusesAModelWithoutAContinuousFormAndABadScenarioNamingTheField) {
  const ImuModel ok = ImuModel::isotropic("ok", sensor("WN(sigma2=1e-6)"), sensor("WN(sigma2=1e-4)"));
  const ImuModel sin = ImuModel::isotropic("sin", sensor("SIN(A2=1e-6,f=0.1)"), sensor("WN(sigma2=1e-4)"));
  try {
    analyse(sin, {ok}, Scenario{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sin: gyroscope x: component 1 (SIN) has no continuous-time"),
              std::string::npos)
        << e.what();
  }
  Scenario s;
  s.horizon = -1.0;
  EXPECT_THROW(analyse(ok, {ok}, s), InputError);
  s = Scenario{};
  s.output_interval = 0.0125;  // 1.25 IMU periods at 100 Hz
  try {
    analyse(ok, {ok}, s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("whole number of IMU periods"), std::string::npos) << e.what();
  }
  s = Scenario{};
  s.trajectory = Trajectory::kManoeuvre;
  s.imu_rate = 100.5;
  s.fix_rate = 0.0;
  s.output_interval = 2.0 / 100.5;
  try {
    analyse(ok, {ok}, s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("must be a whole number of Hz"), std::string::npos) << e.what();
  }
  EXPECT_THROW(analyse(ok, {}, Scenario{}), InputError);
  s = Scenario{};
  s.horizon = 1e7;
  s.fix_rate = 100.0;  // 1e9 fix periods: refused before any memory is taken
  try {
    analyse(ok, {ok}, s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shorten the horizon or lower the fix rate"), std::string::npos) << e.what();
  }
  EXPECT_THROW(monte_carlo(ok, {ok}, Scenario{}, 1, 1), InputError);
}

}  // namespace
}  // namespace gmwm::nav
