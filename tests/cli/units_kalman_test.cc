// `fit` and `select` with --units and --kf-rate: each parameter also as the continuous
// quantity a navigation engineer uses, in the declared unit, and the Kalman-filter table
// (issue 6, items 2 and 4), checked against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

class GmwmUnits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_units");
    // The EuRoC ADIS16448 gyro white noise: N = 1.6968e-04 rad/s/sqrt(Hz) at 200 Hz is a
    // per-sample variance N^2 x 200 = 5.7583e-06 (rad/s)^2; a small random walk beside it.
    auto r = run_gmwm({"simulate", "--model", "WN(sigma2=5.7583e-06)+RW(gamma2=1e-12)", "--n", "131072", "--freq",
                       "200", "--names", "gyro_x", "--output", "g.csv", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const json* find(const json& rows, const std::string& process, const std::string& name) {
  for (const json& r : rows)
    if (r.at("process") == process && r.at(r.contains("role") ? "role" : "name") == name) return &r;
  return nullptr;
}

TEST_F(GmwmUnits, FitGivesTheNoiseDensityInTheDeclaredUnitAndTheFilterTerms) {
  auto r =
      run_gmwm({"fit", "g.csv", "--model", "WN+RW", "--units", "gyro=rad/s", "--verbose", "--json", "f.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = read_json(dir_ / "f.json").at("columns").at(0);
  EXPECT_EQ(c.at("unit"), "rad/s");
  const json* n = find(c.at("continuous"), "WN", "noise density");
  ASSERT_NE(n, nullptr) << c.at("continuous").dump();
  EXPECT_EQ(n->at("unit"), "rad/s/sqrt(Hz)");
  // sqrt(sigma2_hat / 200) within 2% of 1.6968e-04 (sigma2_hat's relative SE at N = 2^17
  // is about sqrt(2 / N) ~ 0.4%), and the interval brackets the value.
  EXPECT_NEAR(n->at("value").get<double>(), 1.6968e-04, 0.02 * 1.6968e-04);
  EXPECT_LT(n->at("ci_low").get<double>(), n->at("value").get<double>());
  EXPECT_GT(n->at("ci_high").get<double>(), n->at("value").get<double>());
  const json* k = find(c.at("continuous"), "RW", "random walk");
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->at("unit"), "rad/s^2/sqrt(Hz)");
  // Kalman terms at the data's rate: R = sigma2 (5.7583e-06), the RW's Q_d = gamma2.
  const json& kal = c.at("kalman");
  EXPECT_NEAR(kal.at("filter_rate").get<double>(), 200.0, 1e-6);  // from the time column
  const json* R = find(kal.at("terms"), "WN", "measurement noise R");
  ASSERT_NE(R, nullptr) << kal.dump();
  EXPECT_NEAR(R->at("discrete").get<double>(), 5.7583e-06, 0.04 * 5.7583e-06);
  EXPECT_EQ(R->at("discrete_unit"), "(rad/s)^2");
  EXPECT_EQ(R->at("q_unit"), "(rad/s)^2/Hz");
  // A filter at 100 Hz: R halves (q f_k with q = sigma2 / 200).
  auto half = run_gmwm(
      {"fit", "g.csv", "--model", "WN+RW", "--units", "gyro=rad/s", "--kf-rate", "100", "--json", "h.json"}, dir_);
  ASSERT_EQ(half.exit_code, 0) << half.err;
  const json h = read_json(dir_ / "h.json");
  const json* R2 = find(h.at("columns").at(0).at("kalman").at("terms"), "WN", "measurement noise R");
  ASSERT_NE(R2, nullptr);
  EXPECT_NEAR(R2->at("discrete").get<double>(), 0.5 * R->at("discrete").get<double>(), 1e-12);
  // The terminal shows both tables.
  EXPECT_NE(r.out.find("rad/s/sqrt(Hz)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Kalman filter at 200"), std::string::npos) << r.out;
}

TEST_F(GmwmUnits, DegreesPerSecondDataGiveDensitiesInDegreesAndSelectReportsTheBestModelsTerms) {
  auto r =
      run_gmwm({"select", "g.csv", "--model", "WN+RW", "--units", "gyro=deg/s", "--verbose", "--json", "s.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = read_json(dir_ / "s.json").at("columns").at(0);
  EXPECT_EQ(c.at("unit"), "deg/s");
  const json* n = find(c.at("best_continuous"), "WN", "noise density");
  ASSERT_NE(n, nullptr) << c.at("best_continuous").dump();
  EXPECT_EQ(n->at("unit"), "deg/s/sqrt(Hz)");
  EXPECT_FALSE(c.at("best_kalman").at("terms").empty());
}

TEST_F(GmwmUnits, RejectsABadUnitAndANonPositiveFilterRateWithOneLine) {
  expect_bad_input(run_gmwm({"fit", "g.csv", "--model", "WN", "--units", "gyro=furlong", "--json", "x.json"}, dir_),
                   {"furlong"}, dir_ / "x.json");
  expect_bad_input(run_gmwm({"fit", "g.csv", "--model", "WN", "--kf-rate", "-5", "--json", "x.json"}, dir_),
                   {"--kf-rate"}, dir_ / "x.json");
}

}  // namespace
