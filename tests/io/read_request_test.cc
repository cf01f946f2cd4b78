// What every face reads a recording with (io::ReadRequest, issue 45) and the timing of
// stamps that come without a file (a pandas index): the same rules, the same refusals as a
// file's timestamp column.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/stamp_timing.h"
#include "log_writers.h"
#include "signal_test_util.h"
#include "test_support.h"

namespace {

using gmwm::InputError;
using gmwm::io::column_list;
using gmwm::io::ReadRequest;
using gmwm::io::timing_of_stamps;
using gmwm::test::contains;
using gmwm::test::write_text;

// Nanosecond stamps from 1.7e18 (a Unix time) with the given steps.
std::vector<std::int64_t> stamps(const std::vector<std::int64_t>& steps) {
  std::vector<std::int64_t> t{1700000000000000000};
  for (std::int64_t s : steps) t.push_back(t.back() + s);
  return t;
}

// The same stamps as a file's '#timestamp [ns]' column beside one varying signal.
std::string stamps_csv(const std::vector<std::int64_t>& t) {
  std::string s = "timestamp [ns],x\n";
  for (std::size_t i = 0; i < t.size(); ++i)
    s += std::to_string(t[i]) + "," + std::to_string(std::sin(0.37 * static_cast<double>(i))) + "\n";
  return s;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// A temporary folder removed with the test.
class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& tag) : path(gmwm::test::temp_dir(tag)) {}
  ~ScratchFolder() { std::filesystem::remove_all(path); }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::filesystem::path path;
};

// Issue 47, item 3: topics at different rates, each read with its own stamps (no resampling).
TEST(ReadRequest, SeveralTopicsAreReadAsPartsEachAtTheRateOfItsOwnStamps) {
  const std::filesystem::path dir = gmwm::test::temp_dir("io_parts");
  std::vector<gmwm::test::Ros1BagOptions> topics = gmwm::test::realsense_topics(800, 500);
  topics.push_back(topics[0]);  // a second unit's gyroscope topic
  topics.back().topic = "/imu1/gyro";
  const std::string path = (dir / "parts.bag").string();
  std::ofstream(path, std::ios::binary) << gmwm::test::ros1_bag_of_topics(topics).bytes;

  ReadRequest request;
  request.path = path;
  request.topic = "/camera/gyro/sample, /camera/accel/sample";
  const std::vector<gmwm::io::RecordPart> parts = gmwm::io::read_request_parts(request);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].topic, "/camera/gyro/sample");
  EXPECT_NEAR(parts[0].set.freq, 400.0, 1e-9);
  ASSERT_EQ(parts[0].set.signals.size(), 3u);
  EXPECT_EQ(parts[0].set.signals[0].values.size(), 800u);
  EXPECT_EQ(parts[1].topic, "/camera/accel/sample");
  EXPECT_NEAR(parts[1].set.freq, 250.0, 1e-9);
  ASSERT_EQ(parts[1].set.signals.size(), 3u);
  EXPECT_EQ(parts[1].set.signals[2].name, "accel_z");
  EXPECT_EQ(parts[1].set.signals[2].values.size(), 500u);

  // One topic: the record as read_request reads it.
  request.topic = "/camera/accel/sample";
  ASSERT_EQ(gmwm::io::read_request_parts(request).size(), 1u);

  // Names keep columns from whichever topic gives them; a topic left with none is left out.
  request.topic = "/camera/gyro/sample,/camera/accel/sample";
  request.columns = {"accel_y"};
  const auto kept = gmwm::io::read_request_parts(request);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].topic, "/camera/accel/sample");
  ASSERT_EQ(kept[0].set.signals.size(), 1u);
  EXPECT_EQ(kept[0].set.signals[0].name, "accel_y");

  const auto refused = [&](ReadRequest r, const std::vector<std::string>& words) {
    try {
      gmwm::io::read_request_parts(r);
      ADD_FAILURE() << "not refused: " << r.topic;
    } catch (const InputError& e) {
      for (const std::string& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
    }
  };
  ReadRequest two = request;
  two.columns.clear();
  two.topic = "/camera/gyro/sample,/imu1/gyro";
  refused(two, {"topic /camera/gyro/sample and topic /imu1/gyro both give gyro_x", "read each in its own run"});
  two.topic = "/camera/gyro/sample,,/imu1/gyro";
  refused(two, {"--topic '/camera/gyro/sample,,/imu1/gyro': found an empty name"});
  two.topic = "/camera/gyro/sample,/camera/accel/sample";
  two.freq = 400.0;
  refused(two, {"--freq with --topic", "rate of its own stamps"});
  std::filesystem::remove_all(dir);
}

// A table whose stamp columns each stamp the columns to their right, a sensor's cells empty in
// the other's rows ("gyro_timestamp,gyro_x,accel_timestamp,accel_x"): `gyro` rows at 400 Hz
// and `accel` rows at 250 Hz over the same second, merged by time.
std::string stamped_table(int gyro, int accel) {
  std::string s = "gyro_timestamp [ns],gyro_x,gyro_y,accel_timestamp [ns],accel_x\n";
  const std::int64_t t0 = 1700000000000000000;
  int g = 0, a = 0;
  while (g < gyro || a < accel) {
    const std::int64_t tg = g < gyro ? t0 + g * 2500000LL : INT64_MAX, ta = a < accel ? t0 + a * 4000000LL : INT64_MAX;
    const bool with_gyro = tg <= ta, with_accel = ta <= tg;
    s += with_gyro ? std::to_string(tg) + "," + std::to_string(std::sin(g * 0.7) * 1e-3) + "," +
                         std::to_string(std::cos(g * 1.3) * 1e-3) + ","
                   : std::string(",,,");
    s += with_accel ? std::to_string(ta) + "," + std::to_string(9.81 + std::sin(a * 0.9) * 1e-2) : std::string(",");
    s += "\n";
    g += with_gyro;
    a += with_accel;
  }
  return s;
}

TEST(ReadRequest, ATableWhoseStampColumnsEachStampTheirOwnIsReadAsPartsEachAtItsRate) {
  const std::filesystem::path dir = gmwm::test::temp_dir("io_stamp_parts");
  const std::string path = write_text(dir, "mixed.csv", stamped_table(800, 500));
  ReadRequest request;
  request.path = path;
  const auto parts = gmwm::io::read_request_parts(request);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].stamps, "gyro_timestamp [ns]");
  EXPECT_EQ(parts[0].label(), "stamps gyro_timestamp [ns]");
  EXPECT_NEAR(parts[0].set.freq, 400.0, 1e-9);
  ASSERT_EQ(parts[0].set.signals.size(), 2u);
  EXPECT_EQ(parts[0].set.signals[1].name, "gyro_y");
  EXPECT_EQ(parts[0].set.signals[1].values.size(), 800u);
  EXPECT_EQ(parts[0].set.timing->gaps, 0);  // the accelerometer's rows are not the gyroscope's gaps
  EXPECT_NEAR(parts[1].set.freq, 250.0, 1e-9);
  ASSERT_EQ(parts[1].set.signals.size(), 1u);
  EXPECT_EQ(parts[1].set.signals[0].values.size(), 500u);
  EXPECT_NEAR(parts[1].set.signals[0].values[1], 9.81 + std::sin(0.9) * 1e-2, 1e-6);

  // One part's columns read alone take their own stamps; columns of both, or none named, are
  // refused by the one-record read (each would be timed by the other sensor's clock).
  request.columns = {"accel_x"};
  const gmwm::io::SignalSet accel = gmwm::io::read_request(request);
  EXPECT_NEAR(accel.freq, 250.0, 1e-9);
  EXPECT_EQ(accel.signals.at(0).values.size(), 500u);
  request.columns = {"gyro_x", "accel_x"};
  EXPECT_TRUE(contains(message_of([&] { gmwm::io::read_request(request); }),
                       "--columns: found columns of 2 timestamp columns"));
  request.columns.clear();
  EXPECT_TRUE(contains(message_of([&] { gmwm::io::read_request(request); }),
                       "mixed.csv:1: found 2 timestamp columns, each stamping the columns to its right "
                       "(gyro_timestamp [ns] (gyro_x, gyro_y); accel_timestamp [ns] (accel_x))"));
  request.freq = 100.0;
  EXPECT_TRUE(
      contains(message_of([&] { gmwm::io::read_request_parts(request); }), "--freq with the timestamp columns of"));
  std::filesystem::remove_all(dir);
}

TEST(ReadRequest, AStampColumnWithTooFewSamplesIsRefusedNamingItAndItsColumns) {
  // The accelerometer stamps only 10 rows of the table: the refusal names which part of the
  // file is short, not only the file.
  const std::filesystem::path dir = gmwm::test::temp_dir("io_stamp_parts_short");
  ReadRequest request;
  request.path = write_text(dir, "short.csv", stamped_table(800, 10));
  const std::string message = message_of([&] { gmwm::io::read_request_parts(request); });
  EXPECT_EQ(message, request.path +
                         ": the columns stamped by 'accel_timestamp [ns]' (accel_x): found 10 samples, expected at "
                         "least 16 (the wavelet variance needs 4 levels, 2^4 samples)");
  std::filesystem::remove_all(dir);
}

TEST(ReadRequest, ASensorsLabelledStampIsATimestampColumnButALetterTWithALabelIsNot) {
  for (const std::string name : {"gyro_timestamp", "timestamp_accel", "accel_time [ns]", "imu_stamp"})
    EXPECT_TRUE(gmwm::io::is_timestamp_column_name(name)) << name;
  for (const std::string name : {"x_t", "t_gyro", "lifetime", "timestamp_"})
    EXPECT_FALSE(gmwm::io::is_timestamp_column_name(name)) << name;
}

}  // namespace

TEST(ReadRequest, AColumnListIsSplitAtCommasWithBlanksTrimmed) {
  EXPECT_EQ(column_list("a, b ,3"), (std::vector<std::string>{"a", "b", "3"}));
  EXPECT_EQ(gmwm::io::comma_list(""), std::vector<std::string>{});
}

TEST(ReadRequest, AnEmptyColumnNameOrListIsRefusedNamingTheOption) {
  EXPECT_EQ(message_of([] { column_list("a,,b"); }),
            "--columns 'a,,b': found an empty name, expected names or 1-based indices separated by commas");
  EXPECT_EQ(message_of([] { column_list(""); }),
            "--columns: found an empty list, expected names or 1-based indices separated by commas");
}

TEST(ReadRequest, AMemoryOutsideOneMegabyteToATerabyteIsRefusedAsTheCommandLineRefusesIt) {
  ReadRequest r;
  r.path = "x.csv";
  r.memory_mb = 0.5;
  EXPECT_EQ(message_of([&] { (void)r.options(); }), "--memory: found '0.5', expected a number of MB from 1 to 1e12");
  r.memory_mb = 64.0;
  EXPECT_DOUBLE_EQ(r.options().memory_budget, 64e6);
  EXPECT_EQ(gmwm::io::memory_problem(2e12, "2e12"), "found '2e12', expected a number of MB from 1 to 1e12");
}

TEST(ReadRequest, ARecordingWithoutTimestampsOrFreqIsRefusedAndFreqGivesItsRate) {
  const ScratchFolder scratch("read_request");
  const auto& dir = scratch.path;
  const std::string p = write_text(dir, "plain.csv", "x,y\n" + gmwm::test::csv_rows(64, ',', false));
  ReadRequest r;
  r.path = p;
  r.columns = {"1"};
  EXPECT_TRUE(contains(message_of([&] { gmwm::io::read_request(r); }), "give the sampling rate with --freq HZ"));
  r.freq = 50.0;
  EXPECT_DOUBLE_EQ(gmwm::io::read_request(r).freq, 50.0);
}

TEST(StampTiming, StampsGiveTheRateGapsAndDisorderTheirFileColumnGives) {
  std::vector<std::int64_t> steps(3000, 5000000);  // 200 Hz
  steps[1000] = 15000000;                          // a gap of three steps
  steps[2000] = -1000;                             // one out of order
  const std::vector<std::int64_t> t = stamps(steps);
  const ScratchFolder scratch("stamp_timing");
  const auto& dir = scratch.path;
  gmwm::io::ReadOptions o;
  const gmwm::io::SignalSet set = gmwm::io::read_signals(write_text(dir, "s.csv", stamps_csv(t)), o);
  const gmwm::io::TimingReport file = *set.timing;
  const gmwm::io::TimingReport index = timing_of_stamps(t, "data.index", "timestamp [ns]", std::nullopt);
  EXPECT_DOUBLE_EQ(index.estimated_freq, 200.0);
  EXPECT_DOUBLE_EQ(index.estimated_freq, file.estimated_freq);
  EXPECT_DOUBLE_EQ(index.median_step_seconds, file.median_step_seconds);
  EXPECT_EQ(index.gaps, 1);
  EXPECT_EQ(index.gaps, file.gaps);
  EXPECT_DOUBLE_EQ(index.largest_gap_seconds, file.largest_gap_seconds);
  EXPECT_EQ(index.disorder, 1);
  EXPECT_EQ(index.disorder, file.disorder);
  EXPECT_EQ(index.samples, file.samples);
}

TEST(StampTiming, ARateChangeIsRefusedInTheFileReadersWordsUnlessFreqIsGiven) {
  std::vector<std::int64_t> steps(4096, 10000000);                       // 100 Hz
  for (std::size_t i = 2048; i < steps.size(); ++i) steps[i] = 5000000;  // then 200 Hz
  const std::vector<std::int64_t> t = stamps(steps);
  const ScratchFolder scratch("stamp_timing_change");
  const auto& dir = scratch.path;
  const std::string p = write_text(dir, "c.csv", stamps_csv(t));
  const std::string file = gmwm::test::read_error(p);
  const std::string index = message_of([&] { timing_of_stamps(t, p, "timestamp [ns]", std::nullopt); });
  EXPECT_TRUE(contains(index, "the sampling rate changes within the record, from about 100 Hz")) << index;
  EXPECT_EQ(index, file);
  EXPECT_TRUE(timing_of_stamps(t, p, "timestamp [ns]", 100.0).rate_change.has_value());
}

TEST(StampTiming, StampsThatNeverIncreaseAreRefusedAsAFilesAre) {
  const std::vector<std::int64_t> t(64, 1700000000000000000);
  EXPECT_EQ(message_of([&] { timing_of_stamps(t, "data.index", "when", std::nullopt); }),
            "data.index: found timestamps in column 'when' that never increase, expected increasing times; give "
            "the sampling rate with --freq HZ");
  EXPECT_NO_THROW(timing_of_stamps(t, "data.index", "when", 100.0));
}

TEST(StampTiming, StampsTooFarApartForNanosecondsAreRefusedNotWrapped) {
  const std::vector<std::int64_t> t = {std::numeric_limits<std::int64_t>::min() + 1, 0,
                                       std::numeric_limits<std::int64_t>::max()};
  EXPECT_TRUE(contains(message_of([&] { timing_of_stamps(t, "data.index", "index", std::nullopt); }),
                       "expected times within 292 years of the first"));
}
