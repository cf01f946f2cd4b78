// gmwm stability --hat (issue 48, item 7): the three-cornered hat of three columns recorded
// together on the command line: each column's own deviation separated from a common input a
// hundred times larger, in the JSON ("hat") and the terminal; a negative variance flagged and
// kept; the refusals (exit 2, one line naming the option, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

// Three sensors a, b, c at 100 Hz: white rate noise of 1e-3 times `levels` each, plus a common
// input (white 0.3, a random walk and a slow sine: a platform's rotation) whose deviation is
// a hundred times the largest.
std::string three_sensors_csv(int n, const std::vector<double>& levels, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::string csv = "time [s],a,b,c\n";
  double walk = 0.0;
  for (int i = 0; i < n; ++i) {
    walk += 3e-4 * g(rng);
    const double common = 0.3 * g(rng) + walk + 0.5 * std::sin(2.0 * 3.141592653589793 * i / 6000.0);
    char line[160];
    const double a = common + 1e-3 * levels[0] * g(rng), b = common + 1e-3 * levels[1] * g(rng),
                 c = common + 1e-3 * levels[2] * g(rng);
    std::snprintf(line, sizeof line, "%.2f,%.17g,%.17g,%.17g\n", i * 0.01, a, b, c);
    csv += line;
  }
  return csv;
}

class StabilityHatCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("stability_hat_cli");
    gmwm::test::write_text(dir_ / "three.csv", three_sensors_csv(20000, {1.0, 2.0, 3.0}, 11));
  }
  void TearDown() override { fs::remove_all(dir_); }

  void expect_refused(const std::vector<std::string>& args, const std::string& why) {
    const auto r = run_gmwm(args, dir_);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  }

  fs::path dir_;
};

TEST_F(StabilityHatCommand, SeparatesEachColumnFromACommonInputAHundredTimesLargerInTheJsonAndTheTable) {
  const auto r = run_gmwm(
      {"stability", "three.csv", "--hat", "--kind", "oadev,mdev", "--units", "rad/s", "--json", "out.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "out.json");
  const json& hat = doc["hat"];
  EXPECT_EQ(hat["sensors"], json({"a", "b", "c"}));
  ASSERT_EQ(hat["pairs"].size(), 3u);
  EXPECT_EQ(hat["pairs"][0]["name"], "a - b");
  EXPECT_EQ(hat["pairs"][2]["name"], "c - a");
  // Each column read alone: the common input, 0.3 rad/s at 0.01 s; each pair: two sensors.
  EXPECT_GT(doc["columns"][0]["deviations"]["oadev"]["value"][0].get<double>(), 0.29);
  EXPECT_NEAR(hat["pairs"][0]["deviations"]["oadev"]["value"][0].get<double>(), std::sqrt(5.0) * 1e-3, 5e-5);
  for (const std::string kind : {"oadev", "mdev"}) {
    const json& k = hat["deviations"][kind];
    EXPECT_EQ(k["m"], hat["pairs"][0]["deviations"][kind]["m"]) << kind;
    EXPECT_EQ(k["unit"], "rad/s");
    ASSERT_EQ(k["sensors"].size(), 3u);
    for (std::size_t s = 0; s < 3; ++s) {
      const json& sensor = k["sensors"][s];
      EXPECT_EQ(sensor["name"], std::string(1, static_cast<char>('a' + s)));
      // At 0.01 s (20000 samples: 15650 degrees of freedom for oadev), each within 3% of its
      // level (the spread of the variance: sqrt((2 + 13 + 36) / 15650) = 6% for a, 3% of the
      // deviation at 3 spreads).
      EXPECT_NEAR(sensor["value"][0].get<double>(), 1e-3 * (s + 1.0), 0.03e-3 * (s + 1.0) * (s == 0 ? 3 : 1))
          << kind << " " << s;
      EXPECT_LT(sensor["ci_low"][0].get<double>(), sensor["value"][0].get<double>());
      EXPECT_GT(sensor["ci_high"][0].get<double>(), sensor["value"][0].get<double>());
      EXPECT_EQ(sensor["negative"].size(), k["m"].size());
      for (std::size_t i = 0; i < k["m"].size(); ++i)
        if (sensor["negative"][i].get<bool>()) {
          EXPECT_TRUE(sensor["value"][i].is_null());
          EXPECT_LT(sensor["variance"][i].get<double>(), 0.0);
        } else {
          EXPECT_NEAR(sensor["value"][i].get<double>(), std::sqrt(sensor["variance"][i].get<double>()),
                      1e-12 * sensor["value"][i].get<double>());
        }
    }
  }
  // The terminal: the hat's table per kind, three rows per tau.
  const std::string out = gmwm::test::flowed(r.out);
  EXPECT_NE(out.find("three-cornered hat of a, b, c: each column's own deviation, separated from what the three "
                     "share"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("oadev [rad/s]"), std::string::npos) << r.out;
  EXPECT_NE(out.find("score interval of each separated variance from edf, the smallest of the three pairs' degrees "
                     "of freedom"),
            std::string::npos)
      << r.out;
  // --three-cornered-hat is --hat.
  ASSERT_EQ(run_gmwm({"stability", "three.csv", "--three-cornered-hat", "--kind", "oadev,mdev", "--units", "rad/s",
                      "--json", "long.json", "--quiet"},
                     dir_)
                .exit_code,
            0);
  EXPECT_EQ(read_json(dir_ / "long.json")["hat"], hat);
}

TEST_F(StabilityHatCommand, ANegativeVarianceIsFlaggedAndKeptNotClamped) {
  // a is the common input alone: its true deviation is 0 and its estimate as often below as
  // above it.
  gmwm::test::write_text(dir_ / "quiet.csv", three_sensors_csv(20000, {0.0, 2.0, 3.0}, 5));
  const auto r = run_gmwm({"stability", "quiet.csv", "--hat", "--json", "out.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json a = read_json(dir_ / "out.json")["hat"]["deviations"]["oadev"]["sensors"][0];
  int negative = 0;
  for (std::size_t i = 0; i < a["negative"].size(); ++i)
    if (a["negative"][i].get<bool>()) {
      ++negative;
      EXPECT_TRUE(a["value"][i].is_null());
      EXPECT_LT(a["variance"][i].get<double>(), 0.0);
      // Its interval, where one fits, is a bound from 0.
      if (!a["ci_low"][i].is_null()) EXPECT_EQ(a["ci_low"][i].get<double>(), 0.0);
    }
  EXPECT_GE(negative, 3) << a.dump();
  EXPECT_NE(r.out.find("[var -"), std::string::npos) << r.out;
  EXPECT_NE(gmwm::test::flowed(r.out).find("the separated variance V (in the unit squared) is negative: no deviation"),
            std::string::npos)
      << r.out;
}

TEST_F(StabilityHatCommand, RefusesWhatIsNotThreeColumnsOfOneRecordInOneLineWritingNothing) {
  expect_refused({"stability", "three.csv", "--hat", "--columns", "a,b", "--json", "out.json"},
                 "three.csv: --hat: the three-cornered hat reads three columns recorded together (--columns A,B,C), "
                 "found 2 (a, b)");
  std::string four = "x,y,z,w\n";
  for (int i = 0; i < 100; ++i)
    four += std::to_string(i % 3) + "," + std::to_string(i % 5) + "," + std::to_string(i % 7) + "," +
            std::to_string(i % 11) + "\n";
  gmwm::test::write_text(dir_ / "four.csv", four);
  expect_refused({"stability", "four.csv", "--freq", "10", "--hat", "--json", "out.json"},
                 "four.csv: --hat: the three-cornered hat reads three columns recorded together (--columns A,B,C), "
                 "found 4 (x, y, z, w)");
  expect_refused({"stability", "three.csv", "--hat", "--kind", "oadev,mtie", "--json", "out.json"},
                 "--hat: mtie is a maximum, not a variance: the three-cornered hat separates every kind but mtie");
}

}  // namespace
