// The memory budget of the binary log readers (issue 25): beyond it the axes of a PX4 ULog,
// ROS 1 bag, MCAP or rosbag2 topic go on in temporary files as the text reader's columns do
// (ColumnSink), and what is read is the same to the last bit as in memory: the values, the
// timing report, the rate. Logs of 140,000 messages (70,000 for bz2, slow to write), past two
// checks of the budget, read with the default budget and with one of one byte.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"
#include "log_writers.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::io::read_signals;
using gmwm::io::ReadOptions;
using gmwm::io::SignalSet;

namespace {

struct LogCase {
  const char* name;
  const char* file;
  int messages;
  std::string (*write)(int n);
};

std::string ros1(int n, const char* codec) {
  gmwm::test::Ros1BagOptions o;
  o.messages = n;
  o.per_chunk = 2000;
  o.compression = codec;
  return gmwm::test::ros1_bag(o).bytes;
}

std::string mcap(int n, const char* codec) {
  gmwm::test::McapOptions o;
  o.messages = n;
  o.per_chunk = 3000;
  o.compression = codec;
  return gmwm::test::mcap_file(o).bytes;
}

const LogCase kCases[] = {
    {"ulog", "log.ulg", 140000, gmwm::test::ulog_sensor_combined},
    {"ros1_none", "bag.bag", 140000, [](int n) { return ros1(n, "none"); }},
    {"ros1_lz4", "bag.bag", 140000, [](int n) { return ros1(n, "lz4"); }},
    {"ros1_bz2", "bag.bag", 70000, [](int n) { return ros1(n, "bz2"); }},
    {"mcap_none", "bag.mcap", 140000, [](int n) { return mcap(n, ""); }},
    {"mcap_lz4", "bag.mcap", 140000, [](int n) { return mcap(n, "lz4"); }},
    {"mcap_zstd", "bag.mcap", 140000, [](int n) { return mcap(n, "zstd"); }},
    {"rosbag2", "bag.db3", 140000, nullptr},
};

class LogBudget : public ::testing::TestWithParam<LogCase> {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("log_budget");
    const LogCase c = GetParam();
    path_ = (dir_ / c.file).string();
    if (c.write) {
      std::ofstream(path_, std::ios::binary) << c.write(c.messages);
    } else {
      gmwm::test::Rosbag2Options o;
      o.messages = c.messages;
      gmwm::test::rosbag2_db(path_, o);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  std::string path_;
};

void expect_same_bits(const SignalSet& a, const SignalSet& b) {
  ASSERT_EQ(a.signals.size(), b.signals.size());
  for (std::size_t k = 0; k < a.signals.size(); ++k) {
    const auto& x = a.signals[k].values;
    const auto& y = b.signals[k].values;
    EXPECT_EQ(a.signals[k].name, b.signals[k].name);
    EXPECT_EQ(a.signals[k].unit, b.signals[k].unit);
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(double)), 0) << a.signals[k].name;
  }
  ASSERT_TRUE(a.timing && b.timing);
  EXPECT_EQ(a.timing->samples, b.timing->samples);
  EXPECT_EQ(a.timing->median_step_seconds, b.timing->median_step_seconds);
  EXPECT_EQ(a.timing->gaps, b.timing->gaps);
  EXPECT_EQ(a.timing->disorder, b.timing->disorder);
  EXPECT_EQ(a.timing->unit, b.timing->unit);
  EXPECT_EQ(a.freq, b.freq);
  EXPECT_EQ(a.preset, b.preset);
}

TEST_P(LogBudget, BeyondTheBudgetTheAxesGoToFilesAndReadTheSameToTheLastBit) {
  const SignalSet memory = read_signals(path_, {});
  ReadOptions tiny;
  tiny.memory_budget = 1.0;  // from the first check (message 65,536) on, in files
  const SignalSet files = read_signals(path_, tiny);
  EXPECT_FALSE(memory.spilled);
  EXPECT_TRUE(files.spilled);
  ASSERT_EQ(files.signals.size(), 6u);
  for (const auto& s : files.signals) EXPECT_TRUE(s.values.in_file()) << s.name;
  for (const auto& s : memory.signals) EXPECT_FALSE(s.values.in_file()) << s.name;
  EXPECT_EQ(memory.signals[0].values.size(), static_cast<std::size_t>(GetParam().messages));
  expect_same_bits(memory, files);
  EXPECT_DOUBLE_EQ(files.freq, 200.0);
  // The values the writer put (floats in the ULog).
  for (int i : {0, 65535, 65536, GetParam().messages - 1}) {
    const std::vector<double> v = gmwm::test::imu_values(i);
    for (std::size_t k = 0; k < 6; ++k) {
      const double expected =
          std::string(GetParam().name) == "ulog" ? static_cast<double>(static_cast<float>(v[k])) : v[k];
      EXPECT_EQ(files.signals[k].values[static_cast<std::size_t>(i)], expected) << k << " " << i;
    }
  }
}

TEST_P(LogBudget, ColumnsPickTheAxesKeptWithinTheBudget) {
  ReadOptions o;
  o.columns = {"accel_z", "gyro_x"};
  o.memory_budget = 1.0;
  const SignalSet files = read_signals(path_, o);
  o.memory_budget = 0.0;
  const SignalSet memory = read_signals(path_, o);
  ASSERT_EQ(files.signals.size(), 2u);
  EXPECT_EQ(files.signals[0].name, "accel_z");
  EXPECT_TRUE(files.spilled);
  expect_same_bits(memory, files);
}

TEST_P(LogBudget, WithoutSpillingTheLogIsRefusedWithOneLineNamingTheMessage) {
  ReadOptions o;
  o.memory_budget = 1.0;
  o.spill = false;
  try {
    read_signals(path_, o);
    ADD_FAILURE() << "read beyond the budget";
  } catch (const gmwm::InputError& e) {
    const std::string why = e.what();
    EXPECT_EQ(why.rfind(path_ + ": ", 0), 0u) << why;
    // The 65,536th message of the topic: in a ULog file its index among all messages (after
    // the format and the subscription) and its byte.
    const bool ulog = std::string(GetParam().name) == "ulog";
    EXPECT_NE(why.find(ulog ? ": message 65538 at byte " : " message 65536: "), std::string::npos) << why;
    EXPECT_NE(why.find("found more than 0 messages of 6 axes"), std::string::npos) << why;
    EXPECT_NE(why.find("read fewer axes with --columns"), std::string::npos) << why;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryBinaryReader, LogBudget, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
