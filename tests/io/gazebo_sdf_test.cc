// The Gazebo reader (io/src/gazebo_sdf.cc) and the column lookup (io/src/sim_config.cc),
// against values computed by hand from the simulators' own discretisations:
//   gz-sensors <noise>: per-sample stddev s -> WN sigma2 = s^2; precision p -> + p^2 / 12;
//   dynamic bias (driving density sigma_b, time constant T) and RotorS bias (K, T) ->
//   AR1 phi = exp(-1/(f T)), innovation variance sigma_b^2 (T/2)(1 - exp(-2/(f T)));
//   RotorS noise density N -> WN sigma2 = N^2 f.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "test_support.h"

namespace gmwm::io {
namespace {

namespace fs = std::filesystem;

// One gz-sensors <noise> block.
std::string noise(const std::string& figures, const std::string& type = "gaussian") {
  return "<noise type=\"" + type + "\">" + figures + "</noise>";
}

// An SDF model with one IMU sensor; each argument is the <noise> block (or "") of an axis.
std::string imu_sdf(const std::string& gx, const std::string& gy, const std::string& gz, const std::string& ax = "",
                    const std::string& ay = "", const std::string& az = "", const std::string& sensor_extra = "") {
  auto axis = [](const std::string& a, const std::string& n) {
    std::string out;  // appended, not concatenated: GCC 12 warns -Wrestrict wrongly on the latter
    out.append("<").append(a).append(">").append(n).append("</").append(a).append(">\n");
    return out;
  };
  return "<?xml version=\"1.0\"?>\n"
         "<sdf version=\"1.9\">\n"
         "<model name=\"m\"><link name=\"l\">\n"
         "<sensor name=\"imu_sensor\" type=\"imu\">" +
         sensor_extra +
         "\n"
         "<imu>\n"
         "<angular_velocity>\n" +
         axis("x", gx) + axis("y", gy) + axis("z", gz) +
         "</angular_velocity>\n"
         "<linear_acceleration>\n" +
         axis("x", ax) + axis("y", ay) + axis("z", az) +
         "</linear_acceleration>\n"
         "</imu></sensor>\n"
         "</link></model></sdf>\n";
}

// The RotorS defaults (rotors_gazebo_plugins, ADIS16448-like) as a plugin element.
constexpr const char* kRotors =
    "<?xml version=\"1.0\"?>\n"
    "<sdf version=\"1.6\"><model name=\"firefly\">\n"
    "<plugin filename=\"librotors_gazebo_imu_plugin.so\" name=\"rotors_gazebo_imu_plugin\">\n"
    "  <robotNamespace>firefly</robotNamespace>\n"
    "  <linkName>firefly/imu_link</linkName>\n"
    "  <imuTopic>imu</imuTopic>\n"
    "  <gyroscopeNoiseDensity>2.0e-4</gyroscopeNoiseDensity>\n"
    "  <gyroscopeRandomWalk>2.0e-5</gyroscopeRandomWalk>\n"
    "  <gyroscopeBiasCorrelationTime>1000.0</gyroscopeBiasCorrelationTime>\n"
    "  <gyroscopeTurnOnBiasSigma>0.0087</gyroscopeTurnOnBiasSigma>\n"
    "  <accelerometerNoiseDensity>4.0e-3</accelerometerNoiseDensity>\n"
    "  <accelerometerRandomWalk>6.0e-3</accelerometerRandomWalk>\n"
    "  <accelerometerBiasCorrelationTime>300.0</accelerometerBiasCorrelationTime>\n"
    "  <accelerometerTurnOnBiasSigma>0.196</accelerometerTurnOnBiasSigma>\n"
    "</plugin>\n"
    "</model></sdf>\n";

bool has_line(const std::vector<std::string>& lines, const std::string& part) {
  for (const auto& l : lines)
    if (l.find(part) != std::string::npos) return true;
  return false;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

class GazeboSdf : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("gazebo_sdf"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text, const std::string& name = "imu.sdf") {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  SimConfig read(const std::string& text, double f = 100.0, const std::string& units = "") {
    return read_gazebo_sdf(write(text), f, parse_units(units));
  }
  std::string error_of(const std::string& text, double f = 100.0) {
    try {
      read(text, f);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

// Gyro: mean 0.001, bias_mean 0.002, bias_stddev 0.003 (constants), stddev 0.009 rad/s,
// precision 0.00025 rad/s, dynamic bias sigma_b = 2e-5 rad/s^2/sqrt(Hz) with T = 400 s.
const std::string kGyroNoise = noise(
    "<mean>0.001</mean><stddev>0.009</stddev><bias_mean>0.002</bias_mean><bias_stddev>0.003</bias_stddev>"
    "<dynamic_bias_stddev>2e-5</dynamic_bias_stddev><dynamic_bias_correlation_time>400</dynamic_bias_correlation_time>"
    "<precision>0.00025</precision>",
    "gaussian_quantized");
const std::string kAccelNoise = noise("<mean>0</mean><stddev>0.02</stddev>");

TEST_F(GazeboSdf, ConvertsAlikeAxesOfAGzSensorsImuToOneModelPerKind) {
  const SimConfig c = read(imu_sdf(kGyroNoise, kGyroNoise, kGyroNoise, kAccelNoise, kAccelNoise, kAccelNoise), 100.0);
  EXPECT_NE(c.source.find("gz-sensors SDF"), std::string::npos) << c.source;
  EXPECT_TRUE(c.axis_models.empty());
  const Model& gyro = c.models.at(SensorKind::kGyro);
  ASSERT_EQ(gyro.to_string(), "AR1+WN");
  const auto v = gyro.given_values();
  // phi = exp(-1/(f T)) = exp(-1/40000) = 0.99997500031249740.
  EXPECT_NEAR(v(0), 0.9999750003124974, 1e-15);
  // Innovation variance sigma_b^2 (T/2)(1 - exp(-2/(f T))) = 4e-10 x 200 x (1 - exp(-5e-5))
  //   = 8e-8 x 4.99987500208e-5 = 3.99990000167e-12 (not sigma_b^2 T/2 = 8e-8, the stationary one).
  EXPECT_NEAR(v(1), 3.9999000016666e-12, 1e-24);
  // WN: stddev^2 + precision^2 / 12 = 8.1e-5 + 6.25e-8 / 12 = 8.1e-5 + 5.2083333e-9 = 8.10052083333e-5.
  EXPECT_NEAR(v(2), 8.100520833333333e-05, 1e-17);
  const Model& accel = c.models.at(SensorKind::kAccel);
  ASSERT_EQ(accel.to_string(), "WN");
  EXPECT_NEAR(accel.given_values()(0), 4.0e-4, 1e-18);  // 0.02^2

  const auto& lines = c.conversions.at(SensorKind::kGyro);
  const std::string all = joined(lines);
  EXPECT_TRUE(has_line(lines, "angular_velocity: the <x>, <y> and <z> noise blocks are alike")) << all;
  EXPECT_TRUE(has_line(lines,
                       "angular_velocity mean = 0.001 rad/s: a constant offset, invisible to the Haar WV: "
                       "no term"))
      << all;
  EXPECT_TRUE(has_line(lines, "bias_mean = 0.002 rad/s")) << all;
  EXPECT_TRUE(has_line(lines, "bias_stddev = 0.003 rad/s")) << all;
  EXPECT_TRUE(has_line(lines, "it decays over T = 400 s")) << all;  // gz-sensors starts the bias there
  EXPECT_TRUE(has_line(lines,
                       "stddev = 0.009 rad/s per sample (not a density) -> WN sigma2 = (s)^2 = 8.1e-05 "
                       "(rad/s)^2 per sample"))
      << all;
  EXPECT_TRUE(has_line(lines, "precision = 0.00025 rad/s")) << all;
  EXPECT_TRUE(has_line(lines,
                       "/ 12 = 5.20833e-09 (rad/s)^2 per sample, added to the WN: valid once the noise spans "
                       "a few LSBs"))
      << all;
  EXPECT_TRUE(has_line(lines, "WN sigma2 = 8.1e-05 + 5.20833e-09 = 8.10052e-05 (rad/s)^2 per sample")) << all;
  // Both variances of the bias: innovation 4e-12, stationary sigma_b^2 T/2 = 4e-10 x 200 = 8e-8.
  EXPECT_TRUE(has_line(lines,
                       "dynamic_bias_stddev = 2e-05 rad/s^2/sqrt(Hz) (a driving density, not the stationary "
                       "deviation) with dynamic_bias_correlation_time = 400 s"))
      << all;
  EXPECT_TRUE(has_line(lines, "AR1 phi = exp(-1/(f T)) = 0.9999750003")) << all;
  EXPECT_TRUE(has_line(lines,
                       "innovation variance (sigma_b)^2 (T/2)(1 - exp(-2/(f T))) = 3.9999e-12 (rad/s)^2 per "
                       "sample, stationary variance (sigma_b)^2 T/2 = 8e-08 (rad/s)^2"))
      << all;
  EXPECT_TRUE(c.notes.empty());
}

TEST_F(GazeboSdf, ConvertsToTheDataUnits) {
  const SimConfig c = read(imu_sdf(kGyroNoise, kGyroNoise, kGyroNoise, kAccelNoise, kAccelNoise, kAccelNoise), 100.0,
                           "gyro=deg/s,accel=g");
  const auto v = c.models.at(SensorKind::kGyro).given_values();
  // (0.009 x 180/pi)^2 = 0.5156620156^2 = 0.26590731435; + (0.00025 x 180/pi)^2 / 12 = 1.70979497e-5.
  EXPECT_NEAR(v(2), 0.26590731435095116 + 1.70979497396445e-05, 1e-13);
  // (2e-5 x 180/pi)^2 x 200 x (1 - exp(-5e-5)) = 1.31308971e-8; phi does not depend on units.
  EXPECT_NEAR(v(1), 1.3130897124883254e-08, 1e-19);
  EXPECT_NEAR(v(0), 0.9999750003124974, 1e-15);
  // (0.02 / 9.80665)^2 = 4.15928462e-6 g^2.
  EXPECT_NEAR(c.models.at(SensorKind::kAccel).given_values()(0), 4.1592846200401915e-06, 1e-18);
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kGyro), "(s x 57.2958 deg/s per rad/s)^2 = 0.265907 (deg/s)^2"))
      << joined(c.conversions.at(SensorKind::kGyro));
}

TEST_F(GazeboSdf, KeepsPerAxisModelsWhenTheAxesDiffer) {
  const SimConfig c = read(imu_sdf(noise("<stddev>0.01</stddev>"), noise("<stddev>0.02</stddev>"), "", kAccelNoise,
                                   kAccelNoise, kAccelNoise));
  EXPECT_FALSE(c.models.count(SensorKind::kGyro));
  EXPECT_TRUE(c.models.count(SensorKind::kAccel));                         // the accel axes are alike
  EXPECT_NEAR(c.axis_models.at("gyro_x").given_values()(0), 1e-4, 1e-19);  // 0.01^2
  EXPECT_NEAR(c.axis_models.at("gyro_y").given_values()(0), 4e-4, 1e-19);  // 0.02^2
  EXPECT_FALSE(c.axis_models.count("gyro_z"));                             // no <noise> on z
  EXPECT_TRUE(has_line(c.axis_conversions.at("gyro_z"), "angular_velocity <z>: no <noise> block: no term"));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kGyro), "noise blocks differ: one gyro model per axis"));

  const auto y = baseline_for_column(c, SensorKind::kGyro, "gyro_y");
  ASSERT_TRUE(y.has_value());
  EXPECT_NEAR(y->model.given_values()(0), 4e-4, 1e-19);
  ASSERT_GE(y->conversions.size(), 2u);
  EXPECT_NE(y->conversions[0].find("differ"), std::string::npos) << joined(y->conversions);
  EXPECT_NE(y->conversions[1].find("angular_velocity <y> stddev = 0.02 rad/s"), std::string::npos)
      << joined(y->conversions);
  EXPECT_NEAR(baseline_for_column(c, SensorKind::kGyro, "w_RS_S_x")->model.given_values()(0), 1e-4, 1e-19);
  EXPECT_FALSE(baseline_for_column(c, SensorKind::kGyro, "gyro_z").has_value());
  // Alike axes: the kind's model whatever the column's name.
  EXPECT_NEAR(baseline_for_column(c, SensorKind::kAccel, "acc")->model.given_values()(0), 4e-4, 1e-19);
  try {
    baseline_for_column(c, SensorKind::kGyro, "gyro");
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("column 'gyro': gz-sensors SDF"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not end in an axis letter"), std::string::npos) << e.what();
  }
}

TEST(ColumnAxis, TakesATrailingAxisLetterAfterASeparatorOrInCamelCase) {
  EXPECT_EQ(column_axis("gyro_x"), 'x');
  EXPECT_EQ(column_axis("w_RS_S_y"), 'y');
  EXPECT_EQ(column_axis("acc.Z"), 'z');
  EXPECT_EQ(column_axis("gyro2x"), 'x');
  EXPECT_EQ(column_axis("gyroX"), 'x');
  EXPECT_EQ(column_axis("z"), 'z');
  EXPECT_EQ(column_axis("gyro"), 0);
  EXPECT_EQ(column_axis("accx"), 0);  // ambiguous: no separator
  EXPECT_EQ(column_axis("GYROX"), 0);
  EXPECT_EQ(column_axis(""), 0);
}

TEST_F(GazeboSdf, ConvertsTheRotorsImuPluginDefaults) {
  const SimConfig c = read(kRotors, 100.0);
  EXPECT_NE(c.source.find("RotorS/PX4 IMU plugin"), std::string::npos) << c.source;
  const auto g = c.models.at(SensorKind::kGyro).given_values();
  ASSERT_EQ(c.models.at(SensorKind::kGyro).to_string(), "AR1+WN");
  // phi = exp(-1/(100 x 1000)) = exp(-1e-5) = 0.99999000005;
  // innovation (2e-5)^2 x 500 x (1 - exp(-2e-5)) = 2e-7 x 1.99998e-5 = 3.99996e-12;
  // WN (2e-4)^2 x 100 = 4e-6.
  EXPECT_NEAR(g(0), 0.9999900000499998, 1e-15);
  EXPECT_NEAR(g(1), 3.999960000266666e-12, 1e-24);
  EXPECT_NEAR(g(2), 4.0e-6, 1e-20);
  const auto a = c.models.at(SensorKind::kAccel).given_values();
  // phi = exp(-1/30000) = 0.99996666722; innovation (6e-3)^2 x 150 x (1 - exp(-1/15000))
  //   = 5.4e-3 x 6.66644445e-5 = 3.59988e-7; WN (4e-3)^2 x 100 = 1.6e-3.
  EXPECT_NEAR(a(0), 0.999966667222216, 1e-15);
  EXPECT_NEAR(a(1), 3.599880002666623e-07, 1e-19);
  EXPECT_NEAR(a(2), 1.6e-3, 1e-17);
  const auto& lines = c.conversions.at(SensorKind::kGyro);
  EXPECT_TRUE(has_line(lines,
                       "gyroscopeNoiseDensity = 0.0002 rad/s/sqrt(Hz) -> WN sigma2 = (N)^2 x f = 4e-06 "
                       "(rad/s)^2 per sample at f = 100 Hz"))
      << joined(lines);
  EXPECT_TRUE(has_line(lines,
                       "gyroscopeRandomWalk = 2e-05 rad/s^2/sqrt(Hz) with gyroscopeBiasCorrelationTime = "
                       "1000 s (the driving density of a Gauss-Markov bias, not a random walk)"))
      << joined(lines);
  EXPECT_TRUE(has_line(lines, "stationary variance (K)^2 T/2 = 2e-07 (rad/s)^2"));  // 4e-10 x 500
  EXPECT_TRUE(has_line(lines,
                       "gyroscopeTurnOnBiasSigma = 0.0087 rad/s: a constant turn-on bias (drawn once), "
                       "invisible to the Haar WV: no term"));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kAccel), "accelerometerNoiseDensity = 0.004 m/s^2/sqrt(Hz)"));
}

TEST_F(GazeboSdf, SaysWhichRotorsParametersAreNotGivenAndLeavesTheirTermsOut) {
  const SimConfig c = read(
      "<plugin name=\"imu\" filename=\"libgazebo_imu_plugin.so\">"
      "<gyroscopeNoiseDensity>1e-3</gyroscopeNoiseDensity>"
      "<accelerometerRandomWalk>0</accelerometerRandomWalk></plugin>");
  EXPECT_EQ(c.models.at(SensorKind::kGyro).to_string(), "WN");
  EXPECT_FALSE(c.models.count(SensorKind::kAccel));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kGyro),
                       "gyroscopeRandomWalk not given (the plugin then uses its "
                       "built-in default): no term here"));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kAccel), "accelerometerRandomWalk = 0: no bias process"));
}

TEST_F(GazeboSdf, LeavesOutZeroFiguresNoneTypesAndPrecisionsGzSensorsIgnores) {
  const SimConfig c = read(imu_sdf(
      noise("<stddev>0</stddev><precision>5e-7</precision>"), noise("<stddev>0</stddev><precision>5e-7</precision>"),
      noise("<stddev>0</stddev><precision>5e-7</precision>"), noise("<stddev>0.1</stddev>", "none"),
      noise("<stddev>0.1</stddev>", "none"), noise("<stddev>0.1</stddev>", "none")));
  EXPECT_TRUE(c.models.empty());
  EXPECT_TRUE(c.axis_models.empty());
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kGyro),
                       "gz-sensors treats a precision within 1e-6 of zero as "
                       "none"));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kGyro), "no nonzero stddev, precision or dynamic bias: no term"));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kAccel), "<noise type=\"none\">: gz-sensors adds no noise"));
}

TEST_F(GazeboSdf, NotesARateMismatchAndTheSourcesItDidNotUse) {
  const std::string gz = imu_sdf(kAccelNoise, kAccelNoise, kAccelNoise, "", "", "", "<update_rate>200</update_rate>");
  // The plugin after the sensor's model, inside the same <sdf>.
  const std::string both = gz.substr(0, gz.rfind("</sdf>")) +
                           "<model name=\"r\"><plugin name=\"rotors\" filename=\"librotors_gazebo_imu_plugin.so\">"
                           "<gyroscopeNoiseDensity>1e-3</gyroscopeNoiseDensity></plugin></model></sdf>\n";
  const SimConfig c = read(both, 100.0);
  EXPECT_NE(c.source.find("gz-sensors"), std::string::npos);
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(0), 4e-4, 1e-19);
  EXPECT_FALSE(c.models.count(SensorKind::kAccel));
  EXPECT_TRUE(has_line(c.conversions.at(SensorKind::kAccel), "linear_acceleration: no <noise> block"));
  ASSERT_EQ(c.notes.size(), 2u) << joined(c.notes);
  EXPECT_NE(c.notes[0].find("update_rate 200 Hz differs from the data's 100 Hz"), std::string::npos) << c.notes[0];
  EXPECT_NE(c.notes[1].find("2 IMU noise sources: the baseline is the first, <sensor name=\"imu_sensor\" type=\"imu\"> "
                            "at line 4; not used: <plugin name=\"rotors\""),
            std::string::npos)
      << c.notes[1];
  // The notes follow the column's conversions.
  const auto b = baseline_for_column(c, SensorKind::kGyro, "gyro_x");
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->conversions.back(), c.notes.back());
}

TEST_F(GazeboSdf, ShippedExampleMatchesTheKalibrExampleAtOneHundredHertz) {
  const std::string root = GMWM_SOURCE_DIR;
  const SimConfig sdf = read_gazebo_sdf(root + "/data/adis16405_gz.sdf", 100.0, parse_units("gyro=deg/s,accel=g"));
  const SimConfig yaml =
      read_kalibr_imu_yaml(root + "/data/adis16405_imu.yaml", 100.0, parse_units("gyro=deg/s,accel=g"));
  for (SensorKind k : {SensorKind::kGyro, SensorKind::kAccel}) {
    ASSERT_EQ(sdf.models.at(k).to_string(), "AR1+WN");
    const auto s = sdf.models.at(k).given_values();
    const auto y = yaml.models.at(k).given_values();  // WN, RW
    // stddev = N sqrt(100): the SDF's WN is Kalibr's plus the precision's p^2/12
    // (gyro: (8.73e-4)^2/12 / (8.73e-3)^2 = 0.083%; accel: (3.27e-2)^2/12 / (4.9e-2)^2 = 3.7%).
    EXPECT_GT(s(2), y(0));
    EXPECT_LT(s(2), y(0) * 1.04);
    // Over T the Gauss-Markov bias has the random walk's innovation: sigma2 ~ gamma2 = K^2/f.
    EXPECT_NEAR(s(1) / y(1), 1.0, 1e-3);
  }
}

TEST_F(GazeboSdf, RejectsBadFilesWithTheElementAndLine) {
  auto expect_error = [&](const std::string& text, const std::string& part) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "' in: " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  try {
    read_gazebo_sdf((dir_ / "absent.sdf").string(), 100.0, parse_units(""));
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.sdf: file not found, expected a Gazebo SDF file"), std::string::npos)
        << e.what();
  }
  // tinyxml2 gives the line of the element whose end tag does not match (<model>).
  expect_error("<sdf>\n<model>\n</sdf>\n", "imu.sdf:2: XML parse error (mismatched element)");
  expect_error("", "imu.sdf: XML parse error (empty document)");
  // A camera's <noise> is not an IMU's.
  expect_error(
      "<sdf><model><link><sensor type=\"camera\"><camera><noise type=\"gaussian\"><stddev>0.007</stddev>"
      "</noise></camera></sensor></link></model></sdf>",
      "imu.sdf: no IMU <noise> block or RotorS/PX4 IMU plugin parameters found");
  expect_error(imu_sdf(noise("<stddev>-0.01</stddev>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/stddev: found -0.01, expected a non-negative noise figure");
  expect_error(imu_sdf("", noise("\n<stddev>abc</stddev>"), ""),
               "imu.sdf:9: angular_velocity/y/noise/stddev: found 'abc', expected a number");
  expect_error(imu_sdf("", "", noise("<precision></precision>")),
               "imu.sdf:9: angular_velocity/z/noise/precision: found an empty element, expected a number");
  expect_error(imu_sdf(noise("<dynamic_bias_stddev>2e-5</dynamic_bias_stddev>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/dynamic_bias_stddev = 2e-05 needs a positive "
               "dynamic_bias_correlation_time (the time constant T, in s, of the Gauss-Markov bias it drives), "
               "found none");
  expect_error(imu_sdf(noise("<dynamic_bias_stddev>2e-5</dynamic_bias_stddev>"
                             "<dynamic_bias_correlation_time>0</dynamic_bias_correlation_time>"),
                       "", ""),
               "found 0");
  expect_error(imu_sdf(noise("<stddev>0.01</stddev>", "uniform"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise: found type 'uniform', expected type=\"gaussian\"");
  expect_error(imu_sdf("<noise><stddev>0.01</stddev></noise>", "", ""),
               "imu.sdf:7: angular_velocity/x/noise: found no type, expected type=\"gaussian\"");
  expect_error("<plugin name=\"imu\">\n<accelerometerRandomWalk>6e-3</accelerometerRandomWalk>\n</plugin>",
               "imu.sdf:2: accelerometerRandomWalk = 0.006 needs a positive accelerometerBiasCorrelationTime");
  expect_error("<plugin name=\"imu\">\n<gyroscopeTurnOnBiasSigma>-1</gyroscopeTurnOnBiasSigma>\n</plugin>",
               "imu.sdf:2: gyroscopeTurnOnBiasSigma: found -1, expected a non-negative noise figure");
  // Negative means are offsets, not noise figures: accepted.
  expect_error(imu_sdf(noise("<mean>-0.5</mean><bias_mean>-1</bias_mean>"), "", ""), "no error");
}

TEST_F(GazeboSdf, RefusesFiguresADoubleCannotHoldOrSquareNamingTheFileLineAndElement) {
  auto expect_error = [&](const std::string& text, const std::string& part) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "' in: " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.find("model '"), std::string::npos) << e;  // never the internal model string
  };
  // A figure whose variance overflows or underflows: the figure's place, not 'WN(sigma2=inf)'.
  expect_error(imu_sdf(noise("<stddev>1e308</stddev>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/stddev: 1e+308 rad/s gives WN sigma2 = inf per sample, outside "
               "the range of a double (expected a figure near the sensor's)");
  expect_error(imu_sdf("", "", "", noise("<stddev>1e-170</stddev>")),
               "imu.sdf:12: linear_acceleration/x/noise/stddev: 1e-170 m/s^2 gives WN sigma2 = 0 per sample");
  expect_error(imu_sdf(noise("<precision>1e200</precision>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/precision: 1e+200 rad/s gives a rounding variance p^2 / 12 = inf");
  expect_error(imu_sdf(noise("<dynamic_bias_stddev>1e200</dynamic_bias_stddev>"
                             "<dynamic_bias_correlation_time>400</dynamic_bias_correlation_time>"),
                       "", ""),
               "imu.sdf:7: angular_velocity/x/noise/dynamic_bias_stddev: 1e+200 rad/s^2/sqrt(Hz) gives AR1 sigma2 "
               "(with dynamic_bias_correlation_time 400 s) = inf per sample");
  expect_error(imu_sdf(noise("<dynamic_bias_stddev>2e-5</dynamic_bias_stddev>"
                             "<dynamic_bias_correlation_time>1e308</dynamic_bias_correlation_time>"),
                       "", ""),
               "imu.sdf:7: angular_velocity/x/noise/dynamic_bias_correlation_time: 1e+308 s is beyond what a double "
               "tells from a random walk at 100 Hz (phi = exp(-1/(f T)) rounds to 1)");
  // A figure beyond a double's normal numbers, huge or tiny.
  expect_error(imu_sdf(noise("<stddev>1e400</stddev>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/stddev: found 1e400, beyond the range of a double");
  expect_error(imu_sdf(noise("<stddev>1e-320</stddev>"), "", ""),
               "imu.sdf:7: angular_velocity/x/noise/stddev: found 1e-320, beyond the range of a double");
  // RotorS parameters the same way.
  expect_error("<plugin name=\"imu\">\n<gyroscopeNoiseDensity>1e308</gyroscopeNoiseDensity>\n</plugin>",
               "imu.sdf:2: gyroscopeNoiseDensity: 1e+308 rad/s/sqrt(Hz) gives WN sigma2 = inf per sample");
  expect_error(
      "<plugin name=\"imu\">\n<accelerometerRandomWalk>1e200</accelerometerRandomWalk>\n"
      "<accelerometerBiasCorrelationTime>300</accelerometerBiasCorrelationTime>\n</plugin>",
      "imu.sdf:2: accelerometerRandomWalk: 1e+200 m/s^3/sqrt(Hz) gives AR1 sigma2 (with "
      "accelerometerBiasCorrelationTime 300 s) = inf per sample");
  expect_error(
      "<plugin name=\"imu\">\n<gyroscopeRandomWalk>2e-5</gyroscopeRandomWalk>\n"
      "<gyroscopeBiasCorrelationTime>1e308</gyroscopeBiasCorrelationTime>\n</plugin>",
      "imu.sdf:3: gyroscopeBiasCorrelationTime: 1e+308 s is beyond what a double tells from a random walk");
  // In the data's units: 1e154 rad/s squares to 1e308, but as 5.7e155 deg/s its square overflows.
  try {
    read(imu_sdf(noise("<stddev>1e154</stddev>"), "", ""), 100.0, "gyro=deg/s");
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("imu.sdf:7: angular_velocity/x/noise/stddev: 1e+154 rad/s gives WN sigma2 = "
                                         "inf per sample"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace gmwm::io
