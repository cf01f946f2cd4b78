// PX4 ULog input: the IMU topics of a log written byte by byte from the published format
// (tests/support: ulog_bytes), their values, rate and units, and the bad-file paths (one
// line naming the file, message index and what was expected).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"
#include "signal_test_util.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::InputError;
using gmwm::io::read_signals;
using gmwm::io::ReadOptions;

namespace {

class Ulog : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("ulog"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::vector<unsigned char>& bytes, const std::string& name = "log.ulg") {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return p.string();
  }
  static std::string error_of(const std::string& path, const std::string& topic = {}) {
    ReadOptions o;
    o.topic = topic;
    return gmwm::test::read_error(path, o);
  }
  fs::path dir_;
};

TEST_F(Ulog, ReadsSensorCombinedAsSixAxesAtTheRateOfItsTimestamps) {
  const gmwm::test::UlogFixture f;
  const auto set = read_signals(write(gmwm::test::ulog_bytes(f)), {});
  ASSERT_EQ(set.signals.size(), 6u);
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  const auto expected = gmwm::test::ulog_expected(f);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(set.signals[k].name, names[k]);
    EXPECT_EQ(set.signals[k].values, expected[k]) << names[k];  // the floats, exactly
    EXPECT_EQ(set.signals[k].unit, k < 3 ? "rad/s" : "m/s^2");
  }
  EXPECT_TRUE(set.freq_known);
  EXPECT_DOUBLE_EQ(set.freq, 200.0);  // 5000 us steps
  ASSERT_TRUE(set.timing.has_value());
  EXPECT_EQ(set.timing->unit, "us");
  EXPECT_EQ(set.timing->samples, f.samples);
  EXPECT_EQ(set.timing->gaps, 0);
  EXPECT_EQ(set.preset, "ulog:sensor_combined");
}

TEST_F(Ulog, PicksATopicItsInstanceAndColumns) {
  const std::string path = write(gmwm::test::ulog_bytes());
  ReadOptions o;
  o.topic = "sensor_gyro:1";
  o.columns = {"gyro_x"};  // y and z are constant in the fixture
  const auto set = read_signals(path, o);
  ASSERT_EQ(set.signals.size(), 1u);
  EXPECT_DOUBLE_EQ(set.signals[0].values[3], 1.0 + 3.0 / 512.0);  // instance 1: x = 1 + i / 512
  o.topic = "sensor_gyro";
  EXPECT_DOUBLE_EQ(read_signals(path, o).signals[0].values[3], 3.0 / 512.0);
  o.columns = {"accel_x"};
  try {
    read_signals(path, o);
    ADD_FAILURE() << "accel_x of sensor_gyro accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--columns accel_x: topic sensor_gyro gives gyro_x, gyro_y, gyro_z"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(Ulog, RejectsATruncatedLogNamingTheMessage) {
  auto bytes = gmwm::test::ulog_bytes();
  bytes.resize(bytes.size() - 20);
  const std::string why = error_of(write(bytes));
  EXPECT_NE(why.find("log.ulg: message "), std::string::npos) << why;
  EXPECT_NE(why.find("truncated: a 'D' message of 50 bytes with 30 left"), std::string::npos) << why;
}

TEST_F(Ulog, RejectsAnAbsentTopicAnInstanceAndANonImuTopic) {
  const std::string path = write(gmwm::test::ulog_bytes());
  EXPECT_NE(
      error_of(path, "sensor_accel").find("no topic sensor_accel in this log (it has sensor_combined, sensor_gyro)"),
      std::string::npos)
      << error_of(path, "sensor_accel");
  EXPECT_NE(error_of(path, "sensor_gyro:2").find("no topic sensor_gyro instance 2"), std::string::npos);
  EXPECT_NE(error_of(path, "vehicle_status").find("--topic vehicle_status: expected an IMU topic"), std::string::npos);
}

TEST_F(Ulog, RejectsUnsortedStampsWithTheMessageIndex) {
  gmwm::test::UlogFixture f;
  f.gyro_instances = 0;
  for (int i = 0; i < f.samples; ++i) f.stamps.push_back(1000000 + 5000 * static_cast<std::uint64_t>(i));
  std::swap(f.stamps[10], f.stamps[11]);
  const std::string why = error_of(write(gmwm::test::ulog_bytes(f)));
  EXPECT_NE(why.find("is not after the previous one"), std::string::npos) << why;
  EXPECT_NE(why.find("unsorted stamps"), std::string::npos) << why;
  EXPECT_NE(why.find("message 17 "), std::string::npos) << why;  // B, I, 2 F, A, then D 1..11 (+1 for the swap)
}

// Issue 25, a fuzzer's finding: stamps near 2^64 round, as doubles, to 2^64, and naming them
// through the double was undefined behaviour; the message names the stamps as read.
TEST_F(Ulog, NamesStampsNear2To64AsTheyAreWritten) {
  gmwm::test::UlogFixture f;
  f.gyro_instances = 0;
  for (int i = 0; i < f.samples; ++i) f.stamps.push_back(~std::uint64_t{0} - 64 + static_cast<std::uint64_t>(i));
  const std::string why = error_of(write(gmwm::test::ulog_bytes(f)));
  EXPECT_NE(why.find("timestamp 18446744073709551552 us is not after the previous one (18446744073709551551 us)"),
            std::string::npos)
      << why;
}

TEST_F(Ulog, RefusesAConstantAxisAsTheCsvReaderDoes) {
  // sensor_gyro's y axis is 0 in every message.
  ReadOptions o;
  o.topic = "sensor_gyro";
  o.columns = {"gyro_y"};
  try {
    read_signals(write(gmwm::test::ulog_bytes()), o);
    ADD_FAILURE() << "a constant axis accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("topic sensor_gyro gyro_y: found all 64 values equal to 0"), std::string::npos)
        << e.what();
  }
}

// Issue 25: a topic subscribed again (a logger restart: its format defined again and a new
// 'A' under another msg_id) lost every message before the second subscription.
TEST_F(Ulog, ReadsEveryMessageOfATopicSubscribedTwiceInOrder) {
  gmwm::test::UlogFixture f;
  f.resubscribe_at = 40;
  const auto set = read_signals(write(gmwm::test::ulog_bytes(f)), {});
  const auto expected = gmwm::test::ulog_expected(f);
  ASSERT_EQ(set.signals.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(set.signals[k].values, expected[k]) << set.signals[k].name;
  ASSERT_TRUE(set.timing.has_value());
  EXPECT_EQ(set.timing->samples, f.samples);
  EXPECT_EQ(set.timing->gaps, 0);
  EXPECT_DOUBLE_EQ(set.freq, 200.0);
}

// A msg_id that another topic's subscription takes over no longer gives the topic's data.
TEST_F(Ulog, AMsgIdTakenOverByAnotherTopicStopsCounting) {
  gmwm::test::UlogFixture f;
  f.gyro_instances = 0;
  f.samples = 40;
  auto bytes = gmwm::test::ulog_bytes(f);
  // sensor_gyro subscribed under sensor_combined's msg_id 7, then one message of 48 bytes
  // that is not sensor_combined's: a stamp from the past would be refused as unsorted.
  const std::string gyro_format =
      "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;"
      "float temperature;uint32_t error_count;uint8_t[3] clip_counter;uint8_t samples;uint8_t[4] _padding0;";
  const auto message = [&](char type, const std::vector<unsigned char>& payload) {
    bytes.push_back(static_cast<unsigned char>(payload.size() & 0xff));
    bytes.push_back(static_cast<unsigned char>(payload.size() >> 8));
    bytes.push_back(static_cast<unsigned char>(type));
    bytes.insert(bytes.end(), payload.begin(), payload.end());
  };
  message('F', std::vector<unsigned char>(gyro_format.begin(), gyro_format.end()));
  std::vector<unsigned char> a = {0, 7, 0};
  a.insert(a.end(), {'s', 'e', 'n', 's', 'o', 'r', '_', 'g', 'y', 'r', 'o'});
  message('A', a);
  std::vector<unsigned char> d(50, 0);
  d[0] = 7;  // msg_id 7, timestamp 1 us
  d[2] = 1;
  message('D', d);
  const auto set = read_signals(write(bytes), {});
  EXPECT_EQ(set.signals[0].values.size(), 40u);
}

TEST_F(Ulog, RefusesATopicForADelimitedTextFile) {
  const fs::path p = dir_ / "x.csv";
  std::ofstream(p) << "a\n1\n2\n";
  EXPECT_NE(error_of(p.string(), "sensor_combined").find("the file is delimited text, which has no topics"),
            std::string::npos);
}

}  // namespace
