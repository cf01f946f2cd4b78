// `gmwm export` end to end: from a `gmwm fit --json` result and directly from a data file
// (fitted first with --model), the declared units, Basalt's sidecar, and bad input (exit 2,
// exactly one line on stderr, no file written).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The value of "key: value  # comment" in a YAML text.
double yaml_value(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1));
  ADD_FAILURE() << "no " << key << " in\n" << text;
  return std::nan("");
}

// A parameter's value in a fit column of the JSON.
double parameter(const json& column, const std::string& name) {
  for (const json& p : column.at("parameters"))
    if (p.at("name") == name) return p.at("value").get<double>();
  ADD_FAILURE() << "no parameter " << name;
  return std::nan("");
}

class GmwmExport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_export");
    // Three gyro axes with the EuRoC ADIS16448 figures at 200 Hz (N = 1.6968e-4, K = 1.9393e-5).
    ASSERT_NO_FATAL_FAILURE(gmwm::test::write_adis_gyro_fit(dir_, 32768));
    fit_ = read_json(dir_ / "fit.json");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Mean over the three columns of N = sqrt(sigma2 / f) and K = sqrt(gamma2 f), from the
  // fit's own parameter table (engine/physical.h conventions), in the data's unit.
  std::pair<double, double> mean_n_k() const {
    double n = 0.0, k = 0.0;
    for (const json& c : fit_.at("columns")) {
      const double f = c.at("freq").get<double>();
      n += std::sqrt(parameter(c, "sigma2") / f) / 3.0;
      k += std::sqrt(parameter(c, "gamma2") * f) / 3.0;
    }
    return {n, k};
  }

  fs::path dir_;
  json fit_;
};

TEST_F(GmwmExport, RefusesAGyroscopeOnlyResultForAFileWithAccelerometerFieldsUnlessPartial) {
  // A 0 for the accelerometer (or its fields left out, which VINS's FileStorage reads as 0)
  // would be a perfect accelerometer: refused, nothing written, naming --partial.
  for (const std::string format : {"kalibr", "openvins", "vins", "orbslam3", "basalt", "gz-sdf", "rotors"}) {
    const auto r = run_gmwm({"export", "fit.json", "--format", format, "--output", "out"}, dir_);
    EXPECT_EQ(r.exit_code, 2) << format << ": " << r.err;
    EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("no accelerometer column in the source"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("give --partial"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << format;
    // With --partial: the gyroscope's fields, none of the accelerometer's.
    const auto p = run_gmwm({"export", "fit.json", "--format", format, "--output", "out", "--partial"}, dir_);
    ASSERT_EQ(p.exit_code, 0) << format << ": " << p.err;
    const std::string text = read_text(dir_ / "out");
    for (const std::string accel : {"accelerometer_noise_density:", "acc_n:", "acc_w:", "IMU.NoiseAcc:",
                                    "\"accel_noise_std\"", "<linear_acceleration>", "<accelerometerNoiseDensity>"})
      EXPECT_EQ(text.find(accel), std::string::npos) << format << ": " << accel;
    EXPECT_NE(p.err.find("gmwm: warning: No accelerometer column in the source (--partial)"), std::string::npos)
        << p.err;
    fs::remove(dir_ / "out");
    fs::remove(dir_ / "out.txt");
  }
}

TEST_F(GmwmExport, WritesAKalibrYamlFromAFitResult) {
  auto r = run_gmwm(
      {"export", "fit.json", "--format", "kalibr", "--output", "imu.yaml", "--json", "e.json", "--partial"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "imu.yaml");
  const auto [n, k] = mean_n_k();
  EXPECT_NEAR(yaml_value(yaml, "gyroscope_noise_density"), n, 1e-12 * n);
  EXPECT_NEAR(yaml_value(yaml, "gyroscope_random_walk"), k, 1e-12 * k);
  // ... close to the simulated figures.
  EXPECT_NEAR(n, 1.6968e-4, 0.05 * 1.6968e-4);
  EXPECT_EQ(yaml_value(yaml, "update_rate"), 200.0);
  EXPECT_NE(yaml.find("# Source: gmwm fit result fit.json (data sim.csv)"), std::string::npos) << yaml;
  // No accelerometer column: warned on stderr, its fields left out (--partial).
  EXPECT_NE(r.err.find("gmwm: warning: No accelerometer column"), std::string::npos) << r.err;
  EXPECT_EQ(yaml.find("accelerometer_noise_density:"), std::string::npos) << yaml;
  EXPECT_NE(r.out.find("wrote kalibr noise parameters to imu.yaml"), std::string::npos) << r.out;
  const json e = read_json(dir_ / "e.json");
  EXPECT_EQ(e.at("command"), "export");
  EXPECT_EQ(e.at("format"), "kalibr");
  EXPECT_NEAR(e.at("written").at("gyro").at("combined").at("noise_density").get<double>(), n, 1e-12 * n);
}

TEST_F(GmwmExport, FitsADataFileFirstWhenGivenAModel) {
  // The same fit as `gmwm fit` (classical WV, its default model-based diagonal Omega): the
  // same figures.
  auto r = run_gmwm({"export", "sim.csv", "--model", "WN+RW", "--units", "gyro=rad/s", "--format", "orbslam3",
                     "--output", "orb.yaml", "--partial", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "orb.yaml");
  const auto [n, k] = mean_n_k();
  EXPECT_NEAR(yaml_value(yaml, "IMU.NoiseGyro"), n, 1e-9 * n);
  EXPECT_NEAR(yaml_value(yaml, "IMU.GyroWalk"), k, 1e-9 * k);
  EXPECT_NE(yaml.find("IMU.Frequency: 200.0"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("# Source: data sim.csv fitted with WN+RW"), std::string::npos) << yaml;
  EXPECT_TRUE(r.out.empty()) << "--quiet";
}

TEST_F(GmwmExport, ConvertsDeclaredDegreesPerSecondToRadians) {
  // A result fitted without --units, exported as deg/s data: the same numbers are pi/180
  // times smaller in rad/s.
  auto r = run_gmwm({"fit", "sim.csv", "--model", "WN+RW", "--json", "plain.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_gmwm({"export", "plain.json", "--format", "vins", "--units", "gyro=deg/s", "--output", "vins.yaml",
                "--partial", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "vins.yaml");
  const auto [n, k] = mean_n_k();
  // VINS: gyr_n = N sqrt(200) per sample, gyr_w = K sqrt(200).
  EXPECT_NEAR(yaml_value(yaml, "gyr_n"), n * kPi / 180.0 * std::sqrt(200.0), 1e-12 * n);
  EXPECT_NEAR(yaml_value(yaml, "gyr_w"), k * kPi / 180.0 * std::sqrt(200.0), 1e-12 * k);
  EXPECT_NE(yaml.find("gyro data in deg/s -> rad/s"), std::string::npos) << yaml;
}

TEST_F(GmwmExport, BasaltWritesItsHeaderToASidecarAndPerAxisVectors) {
  auto r = run_gmwm({"export", "fit.json", "--format", "basalt", "--aggregate", "per-axis", "--output", "calib.json",
                     "--partial", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json calib = read_json(dir_ / "calib.json");
  const json& cols = fit_.at("columns");
  for (std::size_t i = 0; i < 3; ++i) {
    const double n = std::sqrt(parameter(cols[i], "sigma2") / 200.0);
    EXPECT_NEAR(calib.at("value0").at("gyro_noise_std")[i].get<double>(), n, 1e-12 * n) << i;
  }
  const std::string sidecar = read_text(dir_ / "calib.json.txt");
  EXPECT_NE(sidecar.find("Generated by gmwm"), std::string::npos);
  EXPECT_NE(sidecar.find("Aggregation: per-axis"), std::string::npos);
}

TEST_F(GmwmExport, WritesAGazeboSdfThatTheGapCommandReads) {
  auto r = run_gmwm({"export", "fit.json", "--format", "gz-sdf", "--output", "imu.sdf", "--partial", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string sdf = read_text(dir_ / "imu.sdf");
  EXPECT_NE(sdf.find("<sensor name=\"imu\" type=\"imu\">"), std::string::npos);
  EXPECT_EQ(sdf.find("<linear_acceleration>", sdf.find("-->")), std::string::npos);
  r = run_gmwm({"gap", "sim.csv", "--columns", "gyro_x", "--gazebo", "imu.sdf", "--replicates", "40", "--json",
                "g.json", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json column = read_json(dir_ / "g.json").at("columns")[0];
  const std::string baseline = column.at("baseline_model");
  // The random walk, exported as a bias with T = 1000 x the record, reads back as a random
  // walk over the record (RW-like), as a Kalibr file of the same figures gives.
  EXPECT_EQ(baseline.find("AR1("), std::string::npos) << baseline;
  EXPECT_NE(baseline.find("RW(gamma2="), std::string::npos) << baseline;
  EXPECT_NE(column.at("conversions").dump().find("is RW-like"), std::string::npos) << column.at("conversions").dump();
}

// Issue 25: a result or a data file that does not say its unit is refused, never taken as SI.
TEST_F(GmwmExport, RefusesAResultOrDataWithoutAUnitAndAUnitContradictingTheResult) {
  auto r = run_gmwm({"fit", "sim.csv", "--model", "WN+RW", "--json", "plain.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_bad_input(run_gmwm({"export", "plain.json", "--format", "kalibr", "--output", "out.yaml"}, dir_),
                   {"plain.json: column 'gyro_x': the result does not say the data's unit", "--units gyro=UNIT"},
                   dir_ / "out.yaml");
  // --units naming the other sensor only does not say this one's.
  expect_bad_input(
      run_gmwm({"export", "plain.json", "--format", "kalibr", "--units", "accel=g", "--output", "out.yaml"}, dir_),
      {"column 'gyro_x'", "--units gyro=UNIT"}, dir_ / "out.yaml");
  expect_bad_input(
      run_gmwm({"export", "fit.json", "--format", "kalibr", "--units", "gyro=deg/s", "--output", "out.yaml"}, dir_),
      {"--units says gyro=deg/s, but the result was fitted on rad/s data"}, dir_ / "out.yaml");
  expect_bad_input(
      run_gmwm({"export", "sim.csv", "--model", "WN+RW", "--format", "kalibr", "--output", "out.yaml"}, dir_),
      {"sim.csv: column 'gyro_x': the file does not say its unit; give --units gyro=UNIT"}, dir_ / "out.yaml");
}

TEST_F(GmwmExport, RejectsBadInputWithOneLineAndNoFile) {
  const fs::path out = dir_ / "out.yaml";
  expect_bad_input(
      run_gmwm({"export", "fit.json", "--format", "kalibr", "--inflate", "0", "--output", "out.yaml"}, dir_),
      {"--inflate 0", "expected a positive factor"}, out);
  expect_bad_input(
      run_gmwm({"export", "fit.json", "--format", "kalibr", "--aggregate", "per-axis", "--output", "out.yaml"}, dir_),
      {"--aggregate per-axis", "kalibr", "mean or worst"}, out);
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "kalibr2", "--output", "out.yaml"}, dir_),
                   {"--format 'kalibr2'", "expected one of kalibr, openvins"}, out);
  expect_bad_input(run_gmwm({"export", "sim.csv", "--format", "kalibr", "--output", "out.yaml"}, dir_),
                   {"sim.csv", "give --model SPEC"}, out);
  expect_bad_input(
      run_gmwm({"export", "fit.json", "--model", "WN", "--format", "kalibr", "--output", "out.yaml"}, dir_),
      {"--model", "only for a data file"}, out);
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "kalibr", "--rate", "-1", "--output", "out.yaml"}, dir_),
                   {"--rate: found '-1', expected a sampling rate in Hz"}, out);
  expect_bad_input(
      run_gmwm({"export", "fit.json", "--format", "kalibr", "--columns", "gyro_q", "--output", "out.yaml"}, dir_),
      {"fit.json", "no column 'gyro_q'"}, out);
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "no_such_dir/out.yaml"}, dir_),
                   {"--output", "no_such_dir"}, out);
  auto wv = run_gmwm({"wv", "sim.csv", "--columns", "gyro_x", "--json", "wv.json", "--quiet"}, dir_);
  ASSERT_EQ(wv.exit_code, 0) << wv.err;
  expect_bad_input(run_gmwm({"export", "wv.json", "--format", "kalibr", "--output", "out.yaml"}, dir_),
                   {"wv.json", "holds no fitted model"}, out);
  // Basalt: neither the file nor its sidecar.
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "basalt", "--aggregate", "per-axis", "--columns",
                             "gyro_x,gyro_y", "--output", "calib.json"},
                            dir_),
                   {"--aggregate per-axis", "gyro_x, gyro_y"}, dir_ / "calib.json");
  EXPECT_FALSE(fs::exists(dir_ / "calib.json.txt"));
}

}  // namespace
