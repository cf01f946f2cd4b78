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
  const gmwm::test::TempFolder folder("cli_log_memory");
  const fs::path& dir = folder.path;
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
}

// A gyroscope-only topic (RealSense's /camera/gyro/sample carries linear_acceleration 0 in
// every message) was refused for a constant axis, so neither of a RealSense bag's topics
// could be read: the axes that are 0 throughout are left out with a warning (and a report
// note), the gyroscope read; an axis asked for by --columns is still refused.
TEST(GmwmBinaryLogs, AGyroscopeOnlyTopicIsReadWithTheAxesItDoesNotCarryLeftOutAndSaid) {
  const gmwm::test::TempFolder folder("cli_gyro_topic");
  const fs::path& dir = folder.path;
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
}

// Issue 47, item 3: RealSense's bag carries the gyroscope and the accelerometer on separate
// topics at different rates; both are read in one run, each at its own rate, no resampling.
TEST(GmwmBinaryLogs, TwoTopicsAtDifferentRatesAreReadInOneRunEachAtItsOwnRate) {
  const gmwm::test::TempFolder folder("cli_two_topics");
  const fs::path& dir = folder.path;
  std::ofstream(dir / "d435i.bag", std::ios::binary)
      << gmwm::test::ros1_bag_of_topics(gmwm::test::realsense_topics(1600, 1000)).bytes;
  const std::string topics = "/camera/gyro/sample,/camera/accel/sample";
  const auto r = run_gmwm(
      {"wv", "d435i.bag", "--topic", topics, "--json", "wv.json", "--csv", "wv.csv", "--report", "wv.html"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = read_json(dir / "wv.json");
  ASSERT_EQ(doc["columns"].size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    const bool is_gyro = k < 3;
    EXPECT_EQ(doc["columns"][k]["name"].get<std::string>().rfind(is_gyro ? "gyro_" : "accel_", 0), 0u);
    EXPECT_NEAR(doc["columns"][k]["freq"].get<double>(), is_gyro ? 400.0 : 250.0, 1e-6);
    EXPECT_EQ(doc["columns"][k]["n"].get<int>(), is_gyro ? 1600 : 1000);
    // The first level's tau in seconds is each topic's own: 2 samples at its own rate.
    EXPECT_NEAR(doc["columns"][k]["levels"][0]["tau_seconds"].get<double>(), is_gyro ? 2.0 / 400 : 2.0 / 250, 1e-12);
  }
  ASSERT_EQ(doc["parts"].size(), 2u);
  EXPECT_EQ(doc["parts"][0]["topic"], "/camera/gyro/sample");
  EXPECT_EQ(doc["parts"][1]["topic"], "/camera/accel/sample");
  EXPECT_EQ(doc["parts"][1]["samples"].get<int>(), 1000);
  EXPECT_NEAR(doc["parts"][1]["timing"]["estimated_freq"].get<double>(), 250.0, 1e-6);
  EXPECT_FALSE(doc.contains("timing"));  // a record-wide timing would speak for one topic only
  const std::string csv = gmwm::test::read_text(dir / "wv.csv");
  EXPECT_EQ(csv.find("column,level"), 0u);
  EXPECT_EQ(csv.find("column,level", 1), std::string::npos);  // one header
  EXPECT_NE(csv.find("\naccel_z,1,2,0.008,"), std::string::npos) << csv.substr(0, 400);
  EXPECT_NE(csv.find("\ngyro_x,1,2,0.005,"), std::string::npos);
  const std::string html = gmwm::test::read_text(dir / "wv.html");
  EXPECT_NE(html.find("topic /camera/accel/sample (250 Hz)"), std::string::npos);
  EXPECT_NE(r.out.find("topic /camera/gyro/sample (400 Hz):"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("topic /camera/accel/sample (250 Hz):"), std::string::npos);

  // --columns names the axes to keep from whichever topic gives them.
  const auto some = run_gmwm({"wv", "d435i.bag", "--topic", topics, "--columns", "accel_y,gyro_z", "--json", "-"}, dir);
  ASSERT_EQ(some.exit_code, 0) << some.err;
  const auto picked = nlohmann::json::parse(some.out);
  ASSERT_EQ(picked["columns"].size(), 2u);
  EXPECT_EQ(picked["columns"][0]["name"], "gyro_z");
  EXPECT_EQ(picked["columns"][1]["name"], "accel_y");

  // Refused with one line, nothing written: a rate for both, an index, a name no topic gives,
  // a command that reads one topic.
  expect_bad_input(run_gmwm({"wv", "d435i.bag", "--topic", topics, "--freq", "400", "--json", "x.json"}, dir),
                   {"--freq with --topic", "each part is read at the rate of its own stamps"}, dir / "x.json");
  expect_bad_input(run_gmwm({"wv", "d435i.bag", "--topic", topics, "--columns", "2", "--json", "x.json"}, dir),
                   {"--columns 2", "found an index, expected the names"}, dir / "x.json");
  expect_bad_input(
      run_gmwm({"wv", "d435i.bag", "--topic", topics, "--columns", "mag_x", "--json", "x.json"}, dir),
      {"--columns mag_x: found in none of the parts", "topic /camera/accel/sample (accel_x, accel_y, accel_z)"},
      dir / "x.json");
  expect_bad_input(run_gmwm({"wv", "d435i.bag", "--topic", "/camera/gyro/sample,/camera/gyro/sample"}, dir),
                   {"found /camera/gyro/sample twice"}, dir / "x.json");
  expect_bad_input(run_gmwm({"gap", "d435i.bag", "--topic", topics, "--kalibr", "k.yaml", "--json", "x.json"}, dir),
                   {"found several topics where one record is read", "wv, fit and select"}, dir / "x.json");
}

}  // namespace
