// `--topic` and PX4 ULog input end to end: the WV of a log's IMU topic equals, to the last
// bit, the WV of the same values read from CSV; bad logs exit 2 with one line, writing nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "log_writers.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;

namespace {

class GmwmUlog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_ulog");
    fixture_.samples = 4096;
    const auto bytes = gmwm::test::ulog_bytes(fixture_);
    std::ofstream(dir_ / "log.ulg", std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  gmwm::test::UlogFixture fixture_;
  fs::path dir_;
};

TEST_F(GmwmUlog, GivesTheSameWvAsTheSameValuesInCsvToTheLastBit) {
  auto r = run_gmwm({"wv", "log.ulg", "--topic", "sensor_combined", "--json", "ulog.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto v = gmwm::test::ulog_expected(fixture_);
  std::ofstream csv(dir_ / "same.csv");
  csv << "gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n";
  char cell[40];
  for (std::size_t i = 0; i < v[0].size(); ++i)
    for (std::size_t k = 0; k < 6; ++k) {
      std::snprintf(cell, sizeof cell, "%.17g", v[k][i]);
      csv << cell << (k == 5 ? "\n" : ",");
    }
  csv.close();
  r = run_gmwm({"wv", "same.csv", "--freq", "200", "--json", "csv.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto a = read_json(dir_ / "ulog.json"), b = read_json(dir_ / "csv.json");
  ASSERT_EQ(a["columns"].size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(a["columns"][k]["name"], b["columns"][k]["name"]);
    EXPECT_EQ(a["columns"][k]["levels"], b["columns"][k]["levels"]) << k;  // doubles compared exactly
  }
  EXPECT_EQ(a["columns"][0]["freq"].get<double>(), 200.0);  // from the 5000 us stamps
}

TEST_F(GmwmUlog, ABadLogExitsTwoWithOneLineAndWritesNothing) {
  auto bytes = gmwm::test::ulog_bytes(fixture_);
  bytes.resize(bytes.size() / 2 + 7);
  std::ofstream(dir_ / "cut.ulg", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  expect_bad_input(run_gmwm({"wv", "cut.ulg", "--json", "x.json"}, dir_), {"cut.ulg: message ", "truncated"},
                   dir_ / "x.json");
  expect_bad_input(run_gmwm({"wv", "log.ulg", "--topic", "sensor_mag", "--json", "x.json"}, dir_),
                   {"log.ulg", "--topic sensor_mag", "expected an IMU topic"}, dir_ / "x.json");
}

// Issue 25: `--memory MB` holds for the binary logs too; beyond it their axes go to temporary
// files and the WV is the same to the last bit (140,000 messages: 6.7 MB of values, past a
// budget of 1 MB from the first check on).
TEST(GmwmBinaryLogs, MemoryGivesTheSameWvToTheLastBitForEveryBinaryLog) {
  const fs::path dir = gmwm::test::temp_dir("cli_log_memory");
  gmwm::test::Ros1BagOptions bag;
  bag.messages = 140000;
  bag.per_chunk = 2000;
  bag.compression = "lz4";
  gmwm::test::McapOptions mcap;
  mcap.messages = 140000;
  mcap.per_chunk = 3000;
  mcap.compression = "zstd";
  std::ofstream(dir / "log.ulg", std::ios::binary) << gmwm::test::ulog_sensor_combined(140000);
  std::ofstream(dir / "log.bag", std::ios::binary) << gmwm::test::ros1_bag(bag).bytes;
  std::ofstream(dir / "log.mcap", std::ios::binary) << gmwm::test::mcap_file(mcap).bytes;
  for (const char* log : {"log.ulg", "log.bag", "log.mcap"}) {
    auto r = run_gmwm({"wv", log, "--json", "memory.json", "--quiet"}, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_gmwm({"wv", log, "--memory", "1", "--json", "files.json", "--quiet"}, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto a = read_json(dir / "memory.json"), b = read_json(dir / "files.json");
    ASSERT_EQ(a["columns"].size(), 6u) << log;
    for (std::size_t k = 0; k < 6; ++k)
      EXPECT_EQ(a["columns"][k]["levels"], b["columns"][k]["levels"]) << log << " " << k;
  }
  fs::remove_all(dir);
}

// A gyroscope-only topic (RealSense's /camera/gyro/sample carries linear_acceleration 0 in
// every message) was refused for a constant axis, so neither of a RealSense bag's topics
// could be read: the axes that are 0 throughout are left out with a warning (and a report
// note), the gyroscope read; an axis asked for by --columns is still refused.
TEST(GmwmBinaryLogs, AGyroscopeOnlyTopicIsReadWithTheAxesItDoesNotCarryLeftOutAndSaid) {
  const fs::path dir = gmwm::test::temp_dir("cli_gyro_topic");
  gmwm::test::Ros1BagOptions bag;
  bag.messages = 512;
  bag.zero_accel = true;
  bag.topic = "/camera/gyro/sample";
  std::ofstream(dir / "gyro.bag", std::ios::binary) << gmwm::test::ros1_bag(bag).bytes;
  const auto r = run_gmwm({"wv", "gyro.bag", "--json", "wv.json", "--report", "wv.html"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = read_json(dir / "wv.json");
  ASSERT_EQ(doc["columns"].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(doc["columns"][k]["name"].get<std::string>().rfind("gyro_", 0), 0u);
  const std::string said =
      "accel_x, accel_y, accel_z are 0 in every one of its 512 messages (a sensor the topic "
      "does not carry): left out";
  EXPECT_NE(gmwm::test::flowed(r.err).find(said), std::string::npos) << r.err;
  EXPECT_NE(gmwm::test::read_text(dir / "wv.html").find(said), std::string::npos);
  expect_bad_input(run_gmwm({"wv", "gyro.bag", "--columns", "gyro_x,accel_x", "--json", "x.json"}, dir),
                   {"gyro.bag", "accel_x: found all 512 values equal to 0"}, dir / "x.json");
  fs::remove_all(dir);
}

}  // namespace
