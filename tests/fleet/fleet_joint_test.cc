// The joint model of a fleet's group (fleet/fleet_joint.h): units that share one theta give
// it back and the shared-theta test does not reject; a fleet whose units differ is told
// apart; the units that stand out are left out of the typical unit's model; a group's axis
// that cannot have a joint model says why.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/fleet/fleet_joint.h"

using namespace gmwm;
using namespace gmwm::fleet;

namespace {

constexpr double kFreq = 100.0;
constexpr std::int64_t kN = std::int64_t{1} << 16;

// Unit k's row of group "IMU-X", axis gyro_x in rad/s, of n observed samples.
FleetRow unit_row(std::size_t k, std::int64_t n) {
  FleetRow r;
  r.unit = "SN" + std::to_string(k + 1);
  r.model = r.group = "IMU-X";
  r.axis = "gyro_x";
  r.data_unit = "rad/s";
  r.freq = kFreq;
  r.n = n;
  return r;
}

// A study of `specs.size()` units of group "IMU-X", axis gyro_x, each unit's WV of a series
// of `spec` (values given) with its own stream.
FleetStudy fleet_of(const std::vector<std::string>& specs, std::uint64_t seed) {
  FleetStudy s;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const Model m = parse_model(specs[k]);
    const auto x = simulate(m, m.given_values(), kN, seed, k);
    s.rows.push_back(unit_row(k, kN));
    FleetCurves c;
    c.wv = classical_wv(x.data(), kN);
    s.curves.push_back(std::move(c));
  }
  return s;
}

FleetStudyOptions options() {
  FleetStudyOptions o;
  o.model = "AR1+WN+RW";
  o.joint.enabled = true;
  o.joint.test_draws = 49;
  return o;
}

// N = sqrt(1e-4 / 100) = 1e-3 rad/s/sqrt(Hz) (the white noise dominates the Allan deviation up
// to a few seconds), a Gauss-Markov bias of correlation time 10 s and variance 1e-6, K = 1e-4.
constexpr const char* kTruth = "AR1(phi=0.999000499833375,sigma2=1.999e-9)+WN(sigma2=1e-4)+RW(gamma2=1e-10)";

TEST(FleetJoint, UnitsThatShareOneThetaGiveItBackAndTheTestDoesNotReject) {
  const FleetStudy s = fleet_of(std::vector<std::string>(6, kTruth), 7);
  const std::vector<FleetJointModel> j = fleet_joint_models(s, options());
  ASSERT_EQ(j.size(), 1u);
  const FleetJointModel& m = j.front();
  ASSERT_EQ(m.status, "ok");
  EXPECT_EQ(m.units, 6);
  EXPECT_EQ(m.recommended, "AR1+WN+RW");
  ASSERT_TRUE(m.test.has_value());
  EXPECT_EQ(m.test->calibration, ReplicateCalibration::kBootstrap);  // 6 units: the bootstrap
  EXPECT_GT(m.test->heterogeneity_p, 0.05);
  // The typical unit's N is the truth's sqrt(1e-4 / 100) = 1e-3 rad/s/sqrt(Hz), within its interval.
  ASSERT_TRUE(m.figures.has_value());
  const Readoff& n = m.figures->white.figure;
  EXPECT_LE(n.low, 1e-3);
  EXPECT_GE(n.high, 1e-3);
  EXPECT_NEAR(n.value, 1e-3, 0.02e-3);
  EXPECT_EQ(m.unit, "rad/s");
}

TEST(FleetJoint, AFleetWhoseUnitsDifferIsToldApartByTheChiSquareBeyondTwelveUnits) {
  // Twenty units whose white noise differs by up to +-40% in variance.
  std::vector<std::string> specs;
  for (int k = 0; k < 20; ++k)
    specs.push_back("AR1(phi=0.999000499833375,sigma2=1.999e-9)+WN(sigma2=" + std::to_string(1e-4 * (0.6 + 0.04 * k)) +
                    ")+RW(gamma2=1e-10)");
  const std::vector<FleetJointModel> j = fleet_joint_models(fleet_of(specs, 8), options());
  ASSERT_EQ(j.front().status, "ok");
  ASSERT_TRUE(j.front().test.has_value());
  EXPECT_EQ(j.front().test->calibration, ReplicateCalibration::kChiSquare);
  EXPECT_TRUE(j.front().test->rejects()) << j.front().test->heterogeneity_p;
}

TEST(FleetJoint, LeavesOutTheUnitsThatStandOutOfTheTypicalUnitsModel) {
  std::vector<std::string> specs(6, kTruth);
  specs[2] =
      "AR1(phi=0.999000499833375,sigma2=1.999e-9)+WN(sigma2=9e-4)+RW(gamma2=1e-10)";  // N three times the others'
  FleetStudy s = fleet_of(specs, 9);
  s.rows[2].flags = {"N: 3x the fleet's median"};
  const FleetJointModel m = fleet_joint_models(s, options()).front();
  ASSERT_EQ(m.status, "ok");
  EXPECT_EQ(m.units, 5);
  EXPECT_EQ(m.left_out, std::vector<std::string>{"SN3"});
  EXPECT_NEAR(m.figures->white.figure.value, 1e-3, 0.02e-3);
}

TEST(FleetJoint, SaysWhyAGroupsAxisHasNoJointModel) {
  FleetStudy one = fleet_of({kTruth}, 10);
  EXPECT_EQ(fleet_joint_models(one, options()).front().status,
            "a joint model needs 2 units or more with a result, found 1");
  FleetStudy rates = fleet_of({kTruth, kTruth}, 11);
  rates.rows[1].freq = 200.0;
  EXPECT_NE(fleet_joint_models(rates, options()).front().status.find("the units' rates differ"), std::string::npos);
  // Units declared in deg/s and rad/s: converted to SI, one model.
  FleetStudy mixed = fleet_of({kTruth, kTruth, kTruth}, 12);
  mixed.rows[1].data_unit = "deg/s";
  for (double& x : mixed.curves[1].wv.wv) x *= std::pow(180.0 / M_PI, 2);
  for (double& x : mixed.curves[1].wv.variance) x *= std::pow(180.0 / M_PI, 4);
  const FleetJointModel m = fleet_joint_models(mixed, options()).front();
  ASSERT_EQ(m.status, "ok");
  EXPECT_EQ(m.unit, "rad/s");
  EXPECT_NEAR(m.figures->white.figure.value, 1e-3, 0.03e-3);
}

TEST(FleetJoint, UnitsWithGapsHaveTheTestsSimulatedUnitsReadThroughTheirOwnGaps) {
  // Three units, each missing its own samples: the shared-theta test's draws of unit k go
  // through unit k's gaps. Its p-values are those of replicate_test run here with each unit's
  // own estimator, bit for bit (the same streams), and not those of the classical WV of
  // whole grids the fleet used to draw.
  constexpr std::int64_t kGrid = std::int64_t{1} << 13;
  // A third to a half of each unit missing: its WV varies far more than a whole grid's.
  const std::vector<std::vector<MissingRun>> gaps = {
      {{1000, 1500}, {5000, 1500}}, {{2000, 3000}}, {{500, 1000}, {4000, 1000}, {6500, 800}}};
  FleetStudy s;
  std::vector<std::unique_ptr<GappyWvEstimator>> own;
  const Model truth = parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-10)");
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    own.push_back(std::make_unique<GappyWvEstimator>(gaps[k]));
    const auto x = simulate(truth, truth.given_values(), kGrid, 13, k);
    s.rows.push_back(unit_row(k, kGrid - missing_samples(gaps[k])));
    FleetCurves c;
    c.wv = own.back()->compute(x.data(), kGrid, 9, 0.05);
    c.missing = gaps[k];
    s.curves.push_back(std::move(c));
  }
  FleetStudyOptions o = options();
  o.model = "WN+RW";
  o.joint.test_draws = 19;
  const FleetJointModel m = fleet_joint_models(s, o).front();
  ASSERT_EQ(m.status, "ok");
  ASSERT_TRUE(m.test.has_value());
  EXPECT_EQ(m.n, kGrid);  // the figures' averaging factors span the grid, not the observed samples
  std::vector<WaveletVariance> wvs;
  for (const FleetCurves& c : s.curves) wvs.push_back(c.wv);
  ReplicateTestOptions to;
  to.seed = o.select.seed;
  to.fit = o.select.fit;
  to.fit.inference = false;
  to.bootstrap = 19;
  to.estimators = {own[0].get(), own[1].get(), own[2].get()};
  const ReplicateTest mine = replicate_test(wvs, m.fit, to);
  EXPECT_EQ(m.test->heterogeneity_p, mine.heterogeneity_p);
  EXPECT_EQ(m.test->p_value, mine.p_value);
  to.estimators.clear();
  const ReplicateTest whole = replicate_test(wvs, m.fit, to);
  EXPECT_TRUE(whole.heterogeneity_p != mine.heterogeneity_p || whole.p_value != mine.p_value);
}

}  // namespace
