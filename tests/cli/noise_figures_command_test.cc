// The noise figures end to end: wv --adev (terminal, JSON, CSV), fit/select with their
// N, K, B, and exports that never write 0 for a density the data show (issue 13).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::flowed;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using json = nlohmann::json;

namespace {

class GmwmNoiseFigures : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_figures"); }
  void TearDown() override { fs::remove_all(dir_); }
  void simulate(const std::string& model, const std::string& names, int n = 262144) {
    const auto r = run_gmwm({"simulate", "--model", model, "--n", std::to_string(n), "--freq", "100", "--signals",
                             std::to_string(std::count(names.begin(), names.end(), ',') + 1), "--names", names,
                             "--output", "sim.csv.gz", "--quiet"},
                            dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  fs::path dir_;
};

// "Value: ..." of a YAML line.
double yaml_value(const std::string& text, const std::string& key) {
  const auto at = text.find("\n" + key + ":");
  if (at == std::string::npos) return NAN;
  return std::stod(text.substr(at + key.size() + 2));
}

}  // namespace

TEST_F(GmwmNoiseFigures, WvAdevGivesTheAllanDeviationAndItsReadOffsInTheDeclaredUnit) {
  // N = sqrt(0.01 / 100) = 0.01 deg/s/sqrt(Hz), K = sqrt(1e-8 x 100) = 0.001 deg/s^2/sqrt(Hz).
  simulate("WN(sigma2=0.01)+RW(gamma2=1e-8)", "gyro_x");
  const auto r = run_gmwm(
      {"wv", "sim.csv.gz", "--adev", "--units", "gyro=deg/s", "--json", "wv.json", "--adev-csv", "adev.csv"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find("overlapping Allan deviation"), std::string::npos) << r.out;
  EXPECT_NE(flowed(r.out).find("N white noise"), std::string::npos) << r.out;
  const json col = read_json(dir_ / "wv.json").at("columns").at(0);
  EXPECT_EQ(col.at("unit"), "deg/s");
  const json& n = col.at("noise_figures").at("white");
  EXPECT_EQ(n.at("unit"), "deg/s/sqrt(Hz)");
  EXPECT_EQ(n.at("source"), "data");
  EXPECT_NEAR(n.at("value").get<double>() / 0.01, 1.0, 0.03);
  EXPECT_LT(n.at("low").get<double>(), 0.01);
  EXPECT_GT(n.at("high").get<double>(), 0.01);
  const json& k = col.at("noise_figures").at("walk");
  EXPECT_EQ(k.at("unit"), "deg/s^2/sqrt(Hz)");
  EXPECT_NEAR(k.at("value").get<double>() / 0.001, 1.0, 0.25) << k.at("how");
  const json& a = col.at("allan");
  ASSERT_EQ(a.at("tau").size(), a.at("adev").size());
  EXPECT_TRUE(a.at("model").is_null()) << "no model in wv";
  // The CSV: a header and one row per averaging time.
  const std::string csv = read_text(dir_ / "adev.csv");
  EXPECT_EQ(csv.rfind("column,m,tau_seconds,adev,ci_low,ci_high,edf\ngyro_x,1,", 0), 0u) << csv.substr(0, 120);
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), a.at("tau").size() + 1);
}

TEST_F(GmwmNoiseFigures, WvAdevRejectsItsOptionsWithoutAdevAndBadPointsPerOctave) {
  simulate("WN(sigma2=1)", "x", 4096);
  expect_bad_input(run_gmwm({"wv", "sim.csv.gz", "--adev-csv", "a.csv", "--json", "o.json"}, dir_),
                   {"--adev-csv", "only meaningful with --adev"}, dir_ / "o.json");
  expect_bad_input(run_gmwm({"wv", "sim.csv.gz", "--adev", "--adev-points", "0", "--json", "o.json"}, dir_),
                   {"--adev-points: found '0', expected an integer from 1 to 64"}, dir_ / "o.json");
  expect_bad_input(run_gmwm({"wv", "sim.csv.gz", "--adev", "--units", "gyro=furlong", "--json", "o.json"}, dir_),
                   {"furlong"}, dir_ / "o.json");
  EXPECT_FALSE(fs::exists(dir_ / "a.csv"));
}

// The case: a model without WN (the white noise is a fast AR1) once exported 0.
TEST_F(GmwmNoiseFigures, AnExportFromAModelWithoutWhiteNoiseWritesTheDensityTheDataShow) {
  // Fast AR1 (phi = 0.16, the ADIS gyro filter) + slow AR1; N = sqrt(0.12 / 0.84^2 / 100).
  simulate("AR1(phi=0.16,sigma2=0.12)+AR1(phi=0.9999,sigma2=2e-8)", "gyro_x,gyro_y,gyro_z");
  auto r = run_gmwm(
      {"fit", "sim.csv.gz", "--model", "2*AR1", "--units", "gyro=deg/s", "--verbose", "--json", "fit.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find("N white noise"), std::string::npos) << r.out;
  EXPECT_NE(flowed(r.out).find("white measurement noise R (from N)"), std::string::npos)
      << "the Kalman table's R from N";
  const double n_true = std::sqrt(0.12 / (0.84 * 0.84) / 100.0);
  const json doc = read_json(dir_ / "fit.json");  // a range over a temporary's member would dangle
  for (const json& c : doc.at("columns")) {
    const json& n = c.at("noise_figures").at("white");
    EXPECT_NEAR(n.at("value").get<double>() / n_true, 1.0, 0.02) << c.at("name");
    EXPECT_FALSE(n.at("components").empty());
  }
  r = run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "imu.yaml", "--partial", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "imu.yaml");
  const double kPi = 3.14159265358979323846;
  EXPECT_NEAR(yaml_value(yaml, "gyroscope_noise_density") / (n_true * kPi / 180.0), 1.0, 0.02) << yaml;
  EXPECT_GT(yaml_value(yaml, "gyroscope_random_walk"), 0.0);
  EXPECT_NE(yaml.find("part of N (faster than 1 s)"), std::string::npos) << "the fast AR1 is named in N's sources";
  EXPECT_NE(yaml.find("gyro_x (deg/s data): N from the model"), std::string::npos) << yaml;
}

TEST_F(GmwmNoiseFigures, SelectReportsTheFiguresOfItsChosenModel) {
  simulate("WN(sigma2=0.01)+RW(gamma2=1e-8)", "accel_x", 131072);
  const auto r = run_gmwm({"select", "sim.csv.gz", "--model", "AR1+WN+RW", "--json", "s.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json col = read_json(dir_ / "s.json").at("columns").at(0);
  EXPECT_EQ(col.at("best"), "WN+RW");
  const json& n = col.at("noise_figures").at("white");
  EXPECT_EQ(n.at("source"), "model") << n.at("note");
  EXPECT_NEAR(n.at("value").get<double>() / 0.01, 1.0, 0.03);
  EXPECT_EQ(n.at("unit"), "U/sqrt(Hz)") << "the data unit is not declared without --units";
  EXPECT_EQ(col.at("allan").at("model").size(), col.at("allan").at("adev").size());
}

TEST_F(GmwmNoiseFigures, FitReportsQAndRBesideNKBOnEveryFaceWithTheirUnits) {
  // QN(Q2 = 1) at 100 Hz: Q = sqrt(Q2) / f = 0.01 deg (the angle quantum of a deg/s gyro);
  // DR(omega = 1e-5 per sample): R = omega f = 1e-3 deg/s^2; white noise between them.
  simulate("QN(Q2=1)+WN(sigma2=0.01)+DR(omega=1e-5)", "gyro_x");
  const auto r = run_gmwm(
      {"fit", "sim.csv.gz", "--model", "QN+WN+DR", "--units", "gyro=deg/s", "--json", "f.json", "--report", "f.html"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string out = flowed(r.out);
  EXPECT_NE(out.find("Q quantization"), std::string::npos) << r.out;
  EXPECT_NE(out.find("R rate ramp"), std::string::npos) << r.out;
  EXPECT_NE(out.find("arcsec"), std::string::npos) << r.out;
  EXPECT_NE(out.find("deg/h^2"), std::string::npos) << r.out;
  const json col = read_json(dir_ / "f.json").at("columns").at(0);
  const json& q = col.at("noise_figures").at("quantization");
  EXPECT_EQ(q.at("unit"), "deg");
  EXPECT_EQ(q.at("source"), "model") << q.at("note");
  EXPECT_NEAR(q.at("value").get<double>() / 0.01, 1.0, 0.05) << q.at("how");
  EXPECT_EQ(q.at("components").at(0).at("component").get<std::string>().rfind("QN(", 0), 0u);
  const json& ramp = col.at("noise_figures").at("ramp");
  EXPECT_EQ(ramp.at("unit"), "deg/s^2");
  EXPECT_EQ(ramp.at("source"), "model") << ramp.at("note");
  EXPECT_NEAR(ramp.at("value").get<double>() / 1e-3, 1.0, 0.1) << ramp.at("how");
  EXPECT_EQ(ramp.at("data").at("status"), "extrapolated") << ramp.at("data").at("how");
  // The Kalman table: the quantization's measurement noise from Q (R = 2 Q^2 f_k^2), none from R.
  bool from_q = false;
  for (const json& t : col.at("kalman").at("terms")) {
    from_q = from_q || t.at("process") == "Q";
    EXPECT_EQ(t.at("role").get<std::string>().find("(from R)"), std::string::npos);
  }
  EXPECT_TRUE(from_q);
  const std::string html = read_text(dir_ / "f.html");
  EXPECT_NE(html.find("<td>Q quantization</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>R rate ramp</td>"), std::string::npos);
}
