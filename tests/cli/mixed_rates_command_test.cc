// Sensors at different rates in one recording (issue 47, item 3): a table whose timestamp
// columns each stamp the columns to their right, each sensor's rows leaving the other's cells
// empty, is read as parts, each at the rate of its own stamps, in one run and one result (the
// topics of a bag: ulog_input_test.cc). No resampling: each column's WV and figures are those
// of its own samples at its own rate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;

namespace {

constexpr double kGyroRate = 400.0, kAccelRate = 250.0;
constexpr double kGyroSigma = 1e-3, kAccelSigma = 2e-2;  // white noise a sample

// White noise at each rate over the same span, rows merged by time (a row of both when the
// stamps coincide), the other sensor's cells empty.
std::string mixed_table(int gyro_rows, int accel_rows) {
  std::mt19937_64 rng(47);
  std::normal_distribution<double> normal;
  std::string s = "gyro_timestamp [ns],gyro_x,accel_timestamp [ns],accel_x\n";
  const std::int64_t t0 = 1700000000000000000, gyro_step = 2500000, accel_step = 4000000;
  int g = 0, a = 0;
  char cell[64];
  while (g < gyro_rows || a < accel_rows) {
    const std::int64_t tg = g < gyro_rows ? t0 + g * gyro_step : INT64_MAX;
    const std::int64_t ta = a < accel_rows ? t0 + a * accel_step : INT64_MAX;
    const bool with_gyro = tg <= ta, with_accel = ta <= tg;
    if (with_gyro) {
      std::snprintf(cell, sizeof cell, "%.9g", kGyroSigma * normal(rng));
      s += std::to_string(tg) + "," + cell + ",";
    } else {
      s += ",,";
    }
    if (with_accel) {
      std::snprintf(cell, sizeof cell, "%.9g", 9.81 + kAccelSigma * normal(rng));
      s += std::to_string(ta) + "," + cell;
    } else {
      s += ",";
    }
    s += "\n";
    g += with_gyro;
    a += with_accel;
  }
  return s;
}

TEST(MixedRatesCommand, ATableWhoseStampColumnsEachStampTheirOwnIsFittedInOneRunEachColumnAtItsRate) {
  const fs::path dir = gmwm::test::temp_dir("cli_mixed_rates");
  gmwm::test::write_text(dir / "mixed.csv", mixed_table(1 << 14, 10240));
  const auto r = run_gmwm({"fit", "mixed.csv", "--model", "WN", "--json", "fit.json", "--report", "fit.html"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = read_json(dir / "fit.json");
  ASSERT_EQ(doc["columns"].size(), 2u);
  ASSERT_EQ(doc["parts"].size(), 2u);
  EXPECT_TRUE(doc["parts"][0]["topic"].is_null());
  EXPECT_EQ(doc["parts"][0]["stamps"], "gyro_timestamp [ns]");
  EXPECT_EQ(doc["parts"][1]["stamps"], "accel_timestamp [ns]");
  EXPECT_EQ(doc["parts"][1]["timing"]["gaps"], 0);  // the gyroscope's rows are not the accelerometer's gaps
  // Each column at its own rate, with its own samples; the white-noise density N = sigma /
  // sqrt(rate) of each inside its 95% interval (fixed seed).
  const struct {
    const char* name;
    double rate, sigma;
    int n;
  } expected[] = {{"gyro_x", kGyroRate, kGyroSigma, 1 << 14}, {"accel_x", kAccelRate, kAccelSigma, 10240}};
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& c = doc["columns"][k];
    EXPECT_EQ(c["name"], expected[k].name);
    EXPECT_EQ(c["n"].get<int>(), expected[k].n);
    EXPECT_NEAR(c["freq"].get<double>(), expected[k].rate, 1e-9);
    const auto& n = c["noise_figures"]["white"];
    const double truth = expected[k].sigma / std::sqrt(expected[k].rate);
    EXPECT_LE(n["low"].get<double>(), truth) << expected[k].name;
    EXPECT_GE(n["high"].get<double>(), truth) << expected[k].name;
  }
  EXPECT_NE(r.out.find("stamps accel_timestamp [ns] (250 Hz):"), std::string::npos) << r.out;
  EXPECT_NE(gmwm::test::read_text(dir / "fit.html").find("stamps gyro_timestamp [ns] (400 Hz): columns gyro_x"),
            std::string::npos);

  // A command that reads one record takes one stamp column's columns, at their stamps' rate;
  // without --columns it says why it cannot take both (exit 2, nothing written).
  const auto one = run_gmwm({"wv", "mixed.csv", "--columns", "accel_x", "--json", "-"}, dir);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NEAR(nlohmann::json::parse(one.out)["columns"][0]["freq"].get<double>(), kAccelRate, 1e-9);
  gmwm::test::expect_bad_input(
      run_gmwm({"gap", "mixed.csv", "--kalibr", "k.yaml", "--json", "x.json"}, dir),
      {"mixed.csv:1: found 2 timestamp columns, each stamping the columns to its right", "--columns"}, dir / "x.json");
  fs::remove_all(dir);
}

}  // namespace
