// A datasheet's figures as a gap baseline (sim_config.h, read_datasheet_yaml): the unit
// conversions against hand-computed values, the bias conventions against IEEE 952's
// closed forms, the refusals with their line, and the corrected datasheet's round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"

namespace {

using gmwm::io::SensorKind;
using gmwm::io::SimConfig;

constexpr double kF = 100.0;  // Hz
const double kDeg = std::numbers::pi / 180.0;

SimConfig parse(const std::string& text, const std::map<SensorKind, gmwm::io::Unit>& units = {}) {
  return gmwm::io::parse_datasheet_yaml(text, "sheet.yaml", kF, units);
}

const std::map<SensorKind, gmwm::io::Unit> kDegG = gmwm::io::parse_units("gyro=deg/s,accel=g");

// The model's value of a parameter, by component name and parameter index.
double value(const SimConfig& c, SensorKind kind, const std::string& process, int index = 0) {
  const gmwm::Model& m = c.models.at(kind);
  const Eigen::VectorXd theta = m.given_values();
  for (int k = 0; k < m.num_components(); ++k)
    if (m.components()[static_cast<std::size_t>(k)].process->name() == process) return theta(m.offset(k) + index);
  ADD_FAILURE() << "no " << process << " in " << m.to_string(theta);
  return NAN;
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const gmwm::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(DatasheetYaml, ADensityPerRootHertzAnAngleRandomWalkPerRootHourAndDegreesPerHourAgree) {
  // 0.05 deg/s/sqrt(Hz) = 3 deg/sqrt(h) (sqrt(3600 s) = 60) = 180 deg/h/sqrt(Hz).
  for (const std::string fig : {"noise_density: 0.05 deg/s/sqrt(Hz)", "angle_random_walk: 3 deg/sqrt(h)",
                                "noise_density: 180 deg/h/sqrt(Hz)", "angle_random_walk: 3 \xC2\xB0/\xE2\x88\x9Ahr",
                                "angle_random_walk: 3 deg/hr^0.5", "noise_density: 0.05 dps/rtHz"}) {
    const SimConfig c = parse("gyroscope:\n  " + fig + "\n", kDegG);
    // sigma2 = N^2 f in (deg/s)^2: 0.05^2 x 100 = 0.25.
    EXPECT_NEAR(value(c, SensorKind::kGyro, "WN"), 0.25, 1e-12) << fig;
  }
}

TEST(DatasheetYaml, AccelerometerFiguresInMicroGAndVelocityRandomWalkConvertToSi) {
  const SimConfig a = parse("accelerometer:\n  noise_density: 150 ug/sqrt(Hz)\n");
  const double n = 150e-6 * 9.80665;  // m/s^2/sqrt(Hz)
  EXPECT_NEAR(value(a, SensorKind::kAccel, "WN") / (n * n * kF), 1.0, 1e-12);
  const SimConfig v = parse("accel:\n  velocity_random_walk: 0.2 m/s/sqrt(h)\n");
  const double nv = 0.2 / 60.0;  // m/s/sqrt(s) = m/s^2/sqrt(Hz)
  EXPECT_NEAR(value(v, SensorKind::kAccel, "WN") / (nv * nv * kF), 1.0, 1e-12);
  // In g: the same density over 9.80665.
  const SimConfig g = parse("accelerometer:\n  noise_density: 150 ug/sqrt(Hz)\n", kDegG);
  EXPECT_NEAR(value(g, SensorKind::kAccel, "WN") / (150e-6 * 150e-6 * kF), 1.0, 1e-12);
}

TEST(DatasheetYaml, ARateRandomWalkPerRootHourIsKSquaredOverF) {
  const SimConfig c = parse("gyroscope:\n  noise_density: 0.01 deg/s/sqrt(Hz)\n  rate_random_walk: 10 deg/h/sqrt(h)\n");
  const double K = 10.0 * kDeg / 3600.0 / 60.0;  // rad/s/sqrt(s) = rad/s^2/sqrt(Hz)
  EXPECT_NEAR(value(c, SensorKind::kGyro, "RW") / (K * K / kF), 1.0, 1e-12);
  const SimConfig k = parse("gyroscope:\n  random_walk: 2e-5 rad/s^2/sqrt(Hz)\n");
  EXPECT_NEAR(value(k, SensorKind::kGyro, "RW") / (2e-5 * 2e-5 / kF), 1.0, 1e-12);
}

TEST(DatasheetYaml, ABiasInstabilityWithoutCorrelationTimeIsAFlickerOfCoefficientB) {
  const SimConfig c = parse("gyroscope:\n  bias_instability: 25 deg/h\n", kDegG);
  const double B = 25.0 / 3600.0;  // deg/s
  EXPECT_NEAR(value(c, SensorKind::kGyro, "FLICKER") / (B * B), 1.0, 1e-12);
}

TEST(DatasheetYaml, ABiasInstabilityWithACorrelationTimeIsAGaussMarkovPeakingAtTheFlickerFloor) {
  const SimConfig c = parse("gyroscope:\n  bias_instability: 25 deg/h\n  bias_correlation_time: 100 s\n", kDegG);
  const double phi = value(c, SensorKind::kGyro, "AR1", 0), s2 = value(c, SensorKind::kGyro, "AR1", 1);
  EXPECT_NEAR(phi, std::exp(-1.0 / (kF * 100.0)), 1e-15);
  // IEEE 952 Annex C: a Gauss-Markov's Allan deviation peaks at 0.61736 sigma (T f = 1e4
  // samples: the discrete AR1 is the continuous process to ~1e-4); the peak is 0.664 B.
  const double sigma = std::sqrt(s2 / (1.0 - phi * phi));
  EXPECT_NEAR(0.61736 * sigma / (0.6642824702679600 * 25.0 / 3600.0), 1.0, 2e-3);
}

TEST(DatasheetYaml, AnInRunStabilityIsTheMinimumOfTheWholeAllanDeviation) {
  // White noise + flicker: the Allan variance sigma2/m + 2 B2 ln2/pi falls to its least at
  // the search's longest time (1e5 s = 1e7 samples), where the flicker is flat.
  const SimConfig c =
      parse("gyroscope:\n  noise_density: 0.05 deg/s/sqrt(Hz)\n  in_run_bias_stability: 0.007 deg/s\n", kDegG);
  const double s2 = value(c, SensorKind::kGyro, "WN"), b2 = value(c, SensorKind::kGyro, "FLICKER");
  const double m_max = 1e5 * kF;
  const double minimum = std::sqrt(s2 / m_max + 2.0 * b2 * std::numbers::ln2 / std::numbers::pi);
  EXPECT_NEAR(minimum / 0.007, 1.0, 1e-3);
  // The same figure read as IEEE 952's B gives a flicker 0.664 lower in deviation: not the same.
  const SimConfig b = parse("gyroscope:\n  bias_instability: 0.007 deg/s\n", kDegG);
  EXPECT_GT(value(c, SensorKind::kGyro, "FLICKER") / value(b, SensorKind::kGyro, "FLICKER"), 2.0);
}

TEST(DatasheetYaml, AStabilityBelowWhatTheWhiteNoiseAndWalkAllowGivesNoBiasAndSaysSo) {
  const SimConfig c = parse(
      "gyroscope:\n  noise_density: 1 deg/s/sqrt(Hz)\n  rate_random_walk: 1000 deg/h/sqrt(h)\n"
      "  in_run_bias_stability: 1e-6 deg/s\n",
      kDegG);
  EXPECT_EQ(c.models.at(SensorKind::kGyro).num_components(), 2);
  bool said = false;
  for (const auto& l : c.conversions.at(SensorKind::kGyro)) said |= l.find("no bias term") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(DatasheetYaml, EveryConversionIsWrittenOutWithItsUnits) {
  const SimConfig c = parse("name: ADIS16405\ngyroscope:\n  noise_density: 0.05 deg/s/sqrt(Hz)\n", kDegG);
  ASSERT_EQ(c.conversions.at(SensorKind::kGyro).size(), 1u);
  const std::string& l = c.conversions.at(SensorKind::kGyro)[0];
  EXPECT_NE(l.find("noise_density = 0.05 deg/s/sqrt(Hz) = 0.000872665 rad/s/sqrt(Hz)"), std::string::npos) << l;
  EXPECT_NE(l.find("0.25 (deg/s)^2 per sample at f = 100 Hz"), std::string::npos) << l;
  EXPECT_NE(c.source.find("ADIS16405"), std::string::npos);
  EXPECT_EQ(c.format, gmwm::io::SimFormat::kDatasheet);
  EXPECT_EQ(c.fields.at(0).name, "gyroscope/noise_density");
  EXPECT_EQ(c.fields.at(0).unit, "deg/s/sqrt(Hz)");
}

TEST(DatasheetYaml, RefusesWhatItCannotReadNamingTheLineAndWhatWasExpected) {
  EXPECT_NE(error_of("gyroscope:\n  noise_density: 0.05\n")
                .find("sheet.yaml:2: gyroscope.noise_density: found 0.05 "
                      "without a unit"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  noise_density: 25 deg/h\n")
                .find("sheet.yaml:2: gyroscope.noise_density: 'deg/h' is not a unit of a white noise density"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  bias_instabilty: 25 deg/h\n")
                .find("sheet.yaml:2: unknown figure 'gyroscope.bias_instabilty' (expected one of"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  noise_density: 0.05 deg/s/sqrt(Hz)\n  angle_random_walk: 3 deg/sqrt(h)\n")
                .find("sheet.yaml:3: gyroscope.angle_random_walk and gyroscope.noise_density (sheet.yaml:2) give the "
                      "same figure twice"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  bias_correlation_time: 100 s\n")
                .find("sheet.yaml:2: gyroscope.bias_correlation_time "
                      "without a bias figure"),
            std::string::npos);
  EXPECT_NE(error_of("accelerometer:\n  noise_density: -1 ug/sqrt(Hz)\n").find("expected a non-negative figure"),
            std::string::npos);
  EXPECT_NE(error_of("magnetometer:\n  noise_density: 1 uT\n").find("sheet.yaml:1: unknown key 'magnetometer'"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  noise_density: 0.05 deg/s/sqrt(Hz)\ngyro:\n  noise_density: 1 deg/s/sqrt(Hz)\n")
                .find("given twice"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope: [1, 2]\n").find("expected a map of figures"), std::string::npos);
  EXPECT_NE(error_of("name: x\n").find("no gyroscope or accelerometer figures"), std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  noise_density: 0x1p3 deg/s/sqrt(Hz)\n").find("expected a number and a unit"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope:\n  noise_density: [0.05\n").find("sheet.yaml:"), std::string::npos);
}

TEST(DatasheetYaml, RefusesAFigureThatLeavesTheRangeOfADoubleInSiUnitsInsteadOfDroppingIt) {
  // 1e-320 deg/h is 4.8e-326 rad/s: it underflowed to 0 and the bias term was left out
  // without a word; 1e-320 ug/sqrt(Hz) the same for the white noise.
  auto expect_error = [](const std::string& text, const std::string& part) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "' in: " << e;
  };
  expect_error("gyroscope:\n  noise_density: 1e-3 rad/s/sqrt(Hz)\n  bias_instability: 1e-320 deg/h\n",
               "sheet.yaml:3: gyroscope.bias_instability: found 1e-320 deg/h, which is 0 in SI units (rad/s), outside "
               "the range of a double (expected a figure near the sensor's)");
  expect_error("accelerometer:\n  noise_density: 1e-320 ug/sqrt(Hz)\n",
               "sheet.yaml:2: accelerometer.noise_density: found 1e-320 ug/sqrt(Hz), which is 0 in SI units "
               "(m/s^2/sqrt(Hz))");
  expect_error("gyroscope:\n  noise_density: 1e-3 rad/s/sqrt(Hz)\n  rate_random_walk: 1e-320 deg/h/sqrt(h)\n",
               "sheet.yaml:3: gyroscope.rate_random_walk: found 1e-320 deg/h/sqrt(h), which is 0 in SI units");
  // A subnormal figure has lost its precision: 1e-320 s as a correlation time.
  expect_error("gyroscope:\n  bias_instability: 10 deg/h\n  bias_correlation_time: 1e-320 s\n",
               "sheet.yaml:3: gyroscope.bias_correlation_time: found 1e-320 s, which is 9.99989e-321 in SI units (s)");
  // 1e308 g is 9.8e308 m/s^2, beyond a double.
  expect_error("accelerometer:\n  bias_instability: 1e308 g\n",
               "sheet.yaml:2: accelerometer.bias_instability: found 1e308 g, which is inf in SI units (m/s^2)");
}

TEST(DatasheetYaml, ACorrectedDatasheetKeepsTheInputsKeysAndUnitsAndReadsBackToItsFigures) {
  const SimConfig input = parse(
      "gyroscope:\n  angle_random_walk: 3 deg/sqrt(h)\n  in_run_bias_stability: 0.007 deg/s\n"
      "accelerometer:\n  noise_density: 0.5 mg/sqrt(Hz)\n");
  gmwm::io::DatasheetFigures gyro;
  gyro.white = 0.03 * kDeg;                // rad/s/sqrt(Hz): 1.8 deg/sqrt(h)
  gyro.instability = 0.006 * kDeg;         // rad/s
  gyro.walk = 5.0 * kDeg / 3600.0 / 60.0;  // 5 deg/h/sqrt(h), not in the input: added in that unit
  const std::string text = gmwm::io::write_datasheet_yaml(input, {{SensorKind::kGyro, gyro}}, kF);
  EXPECT_NE(text.find("  angle_random_walk: 1.8 deg/sqrt(h)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  rate_random_walk: 5 deg/h/sqrt(h)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("accelerometer:\n  noise_density: 0.5 mg/sqrt(Hz)\n"), std::string::npos) << text;  // kept
  // Read back (SI data): the in-run stability written gives the flicker of B again.
  const SimConfig back = parse(text);
  EXPECT_NEAR(value(back, SensorKind::kGyro, "FLICKER") / (gyro.instability * gyro.instability), 1.0, 2e-3);
  EXPECT_NEAR(value(back, SensorKind::kGyro, "WN") / (gyro.white * gyro.white * kF), 1.0, 1e-3);
}

}  // namespace
