// A fleet's spec mask (io/fleet_spec.h): limits per sensor model in the datasheet yaml's own
// figures and units, each converted to SI; one datasheet for every model; the refusals with
// their file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/fleet_spec.h"

using gmwm::InputError;
using gmwm::io::parse_fleet_spec;
using gmwm::io::SensorKind;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(FleetSpec, ReadsEachModelsLimitsInSiWithTheTextAsWritten) {
  const auto spec = parse_fleet_spec(
      "ADIS16405:\n"
      "  gyroscope:\n"
      "    angle_random_walk: 2 deg/sqrt(h)\n"
      "    in_run_bias_stability: 0.007 deg/s\n"
      "  accelerometer:\n"
      "    velocity_random_walk: 0.2 m/s/sqrt(h)\n"
      "    bias_instability: 0.2 mg\n"
      "BMI088:\n"
      "  gyroscope: {noise_density: 0.014 deg/s/sqrt(Hz), rate_random_walk: 10 deg/h/sqrt(h)}\n",
      "spec.yaml");
  const auto* g = spec.limits("ADIS16405", SensorKind::kGyro);
  ASSERT_NE(g, nullptr);
  ASSERT_TRUE(g->white && g->instability);
  EXPECT_FALSE(g->walk);
  // 2 deg/sqrt(h) = 2 (pi/180) / 60 rad/s/sqrt(Hz).
  EXPECT_NEAR(g->white->si, 2.0 * kDeg / 60.0, 1e-15);
  EXPECT_EQ(g->white->written, "2 deg/sqrt(h)");
  EXPECT_EQ(g->white->unit, "deg/sqrt(h)");
  EXPECT_EQ(g->white->value, 2.0);
  EXPECT_EQ(g->white->where, "spec.yaml:3");
  EXPECT_TRUE(g->instability_is_minimum);
  EXPECT_NEAR(g->instability->si, 0.007 * kDeg, 1e-15);
  const auto* a = spec.limits("ADIS16405", SensorKind::kAccel);
  ASSERT_NE(a, nullptr);
  EXPECT_FALSE(a->instability_is_minimum);
  EXPECT_NEAR(a->instability->si, 0.2e-3 * 9.80665, 1e-15);
  const auto* b = spec.limits("BMI088", SensorKind::kGyro);
  ASSERT_NE(b, nullptr);
  EXPECT_NEAR(b->walk->si, 10.0 * kDeg / 3600.0 / 60.0, 1e-18);  // deg/h/sqrt(h) -> rad/s^2/sqrt(Hz)
  EXPECT_EQ(spec.limits("BMI088", SensorKind::kAccel), nullptr);
  EXPECT_EQ(spec.limits("MPU6050", SensorKind::kGyro), nullptr);
}

TEST(FleetSpec, OneDatasheetAppliesToEveryModel) {
  const auto spec = parse_fleet_spec("name: generic\ngyroscope:\n  noise_density: 0.01 deg/s/sqrt(Hz)\n", "one.yaml");
  ASSERT_NE(spec.limits("anything", SensorKind::kGyro), nullptr);
  EXPECT_EQ(spec.limits("anything", SensorKind::kAccel), nullptr);
}

TEST(FleetSpec, RefusesWhatADatasheetRefusesNamingTheFileAndLine) {
  for (const auto& [text, mention] : std::vector<std::pair<std::string, std::string>>{
           {"ADIS16405:\n  gyroscope:\n    angle_random_walk: 2\n",
            "spec.yaml:3: gyroscope.angle_random_walk: found 2 without a unit"},
           {"ADIS16405:\n  gyroscope:\n    angle_random_walk: 2 deg/h\n",
            "spec.yaml:3: gyroscope.angle_random_walk: 'deg/h' is not a unit"},
           {"ADIS16405:\n  gyroscope:\n    noise: 2 deg/sqrt(h)\n", "spec.yaml:3: unknown figure 'gyroscope.noise'"},
           {"ADIS16405: 3\n", "spec.yaml:1: ADIS16405: expected the model's datasheet map"},
           {"ADIS16405:\n  gyro: {noise_density: 1 deg/s/sqrt(Hz)}\nADIS16405:\n  gyro: {}\n", "spec.yaml:3"},
           {"- a\n- b\n", "spec.yaml: expected a spec yaml"},
           {"a: [\n", "spec.yaml:"}}) {
    try {
      parse_fleet_spec(text, "spec.yaml");
      FAIL() << "took: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  }
}

}  // namespace
