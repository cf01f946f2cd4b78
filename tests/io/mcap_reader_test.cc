// MCAP input: ROS 2 bags written by the reference MCAP writer (@mcap/core, with @foxglove/cdr;
// tools/fixtures/mcap/write_imu_mcap.mjs, committed under tests/data/mcap), zstd, lz4,
// uncompressed chunks and no chunks: the values equal the same values in CSV to the last
// bit; and the bad-file paths (one line naming the file, topic, message index or byte).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"
#include "input_file.h"
#include "log_writers.h"
#include "signal_test_util.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::InputError;
using gmwm::io::read_signals;
using gmwm::io::ReadOptions;

namespace {

const fs::path kFixtures = fs::path(GMWM_SOURCE_DIR) / "tests" / "data" / "mcap";

std::vector<char> bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

class Mcap : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("mcap"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::vector<char>& bytes, const std::string& name = "bag.mcap") {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p.string();
  }
  static std::string error_of(const std::string& path, const std::string& topic = {}) {
    ReadOptions o;
    o.topic = topic;
    try {
      read_signals(path, o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

// The CSV's first n rows, read through the CSV reader.
gmwm::io::SignalSet csv_rows(const fs::path& dir, std::size_t n) {
  std::ifstream in(kFixtures / "imu.csv");
  std::ofstream out(dir / "head.csv");
  std::string line;
  for (std::size_t k = 0; k <= n && std::getline(in, line); ++k) out << line << '\n';
  out.close();
  ReadOptions o;
  o.freq = 200.0;
  return read_signals((dir / "head.csv").string(), o);
}

struct Layout {
  const char* file;
  std::size_t messages;
};

class McapLayouts : public Mcap, public ::testing::WithParamInterface<Layout> {};

TEST_P(McapLayouts, GivesTheSameValuesAsTheSameDataInCsvToTheLastBitAtTheRateOfTheStamps) {
  const Layout l = GetParam();
  const auto bag = read_signals((kFixtures / l.file).string(), {});
  const auto csv = csv_rows(dir_, l.messages);
  ASSERT_EQ(bag.signals.size(), 6u);
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(bag.signals[k].name, names[k]);
    EXPECT_EQ(bag.signals[k].unit, k < 3 ? "rad/s" : "m/s^2");
    EXPECT_EQ(bag.signals[k].values, csv.signals[k].values) << names[k];  // bit for bit
  }
  EXPECT_TRUE(bag.freq_known);
  EXPECT_DOUBLE_EQ(bag.freq, 200.0);
  ASSERT_TRUE(bag.timing.has_value());
  EXPECT_EQ(bag.timing->gaps, 0);
  EXPECT_EQ(bag.preset, "mcap:/imu/data");
}

INSTANTIATE_TEST_SUITE_P(EveryChunkLayout, McapLayouts,
                         ::testing::Values(Layout{"imu_zstd.mcap", 2048}, Layout{"imu_lz4.mcap", 2048},
                                           Layout{"imu_chunks_uncompressed.mcap", 512},
                                           Layout{"imu_no_chunks.mcap", 256}),
                         [](const ::testing::TestParamInfo<Layout>& p) {
                           std::string name = p.param.file;  // "imu_lz4.mcap" -> "imulz4"
                           name = name.substr(0, name.find('.'));
                           std::erase(name, '_');
                           return name;
                         });

TEST_F(Mcap, ColumnsPickAxesOfTheNamedTopic) {
  ReadOptions o;
  o.topic = "/imu/data";
  o.columns = {"gyro_z", "accel_x"};
  const auto set = read_signals((kFixtures / "two_imu_topics.mcap").string(), o);
  ASSERT_EQ(set.signals.size(), 2u);
  EXPECT_EQ(set.signals[0].name, "gyro_z");
  EXPECT_EQ(set.signals[1].name, "accel_x");
  EXPECT_EQ(set.signals[1].values.size(), 64u);
}

TEST_F(Mcap, RefusesATopicWithTooFewMessages) {
  // /imu2 carries every 10th of 64 messages: 7.
  const std::string p = (kFixtures / "two_imu_topics.mcap").string();
  EXPECT_EQ(error_of(p, "/imu2"), p + ": topic /imu2 has 7 messages, expected at least 16");
}

TEST_F(Mcap, RefusesTwoImuTopicsWithoutANameAndNamesThem) {
  EXPECT_EQ(error_of((kFixtures / "two_imu_topics.mcap").string()),
            (kFixtures / "two_imu_topics.mcap").string() +
                ": several sensor_msgs/msg/Imu topics (/imu/data, /imu2): name one with --topic");
}

TEST_F(Mcap, RefusesAnAbsentTopicAndATopicOfAnotherTypeNamingTheTopics) {
  const std::string p = (kFixtures / "imu_lz4.mcap").string();
  EXPECT_EQ(error_of(p, "/nothere"), p + ": no topic /nothere in this bag (it has /imu/data (sensor_msgs/msg/Imu), "
                                         "/imu/temperature (sensor_msgs/msg/Temperature))");
  EXPECT_EQ(error_of(p, "/imu/temperature"),
            p + ": topic /imu/temperature is sensor_msgs/msg/Temperature, expected sensor_msgs/msg/Imu messages");
}

TEST_F(Mcap, RefusesUnsortedStampsNamingTheMessage) {
  const std::string p = (kFixtures / "unsorted.mcap").string();
  EXPECT_EQ(error_of(p), p + ": topic /imu/data message 12: header stamp 1700000000.050000000 s is not after the "
                             "previous message's: unsorted stamps");
}

TEST_F(Mcap, RefusesATruncatedFileNamingWhereItEnds) {
  std::vector<char> b = bytes_of(kFixtures / "imu_zstd.mcap");
  b.resize(b.size() / 2);
  const std::string e = error_of(write(b));
  EXPECT_NE(e.find("bag.mcap: record at byte "), std::string::npos) << e;
  EXPECT_NE(e.find("runs past the end of the file: truncated (an interrupted recording? 'mcap recover'"),
            std::string::npos)
      << e;
}

TEST_F(Mcap, RefusesAFileCutAtARecordBoundaryWithoutItsFooter) {
  // The unchunked file cut right after its 100th record: no DataEnd, no footer.
  std::vector<char> b = bytes_of(kFixtures / "imu_no_chunks.mcap");
  std::size_t at = 8;
  for (int k = 0; k < 100; ++k) {
    std::uint64_t len;
    std::memcpy(&len, b.data() + at + 1, 8);
    at += 9 + len;
  }
  b.resize(at);
  EXPECT_EQ(error_of(write(b)), (dir_ / "bag.mcap").string() + ": the file ends at byte " + std::to_string(at) +
                                    " without a DataEnd or footer record: truncated (an interrupted recording? "
                                    "'mcap recover' rewrites it)");
}

TEST_F(Mcap, RefusesAChunkWhoseRecordsFailTheirCrc) {
  // A byte of a message inside the first uncompressed chunk changed: the chunk's CRC-32 fails.
  std::vector<char> b = bytes_of(kFixtures / "imu_chunks_uncompressed.mcap");
  b[2000] = static_cast<char>(b[2000] ^ 0x40);
  const std::string e = error_of(write(b));
  EXPECT_NE(e.find("bag.mcap: chunk at byte "), std::string::npos) << e;
  EXPECT_NE(e.find(": CRC-32 of the records is "), std::string::npos) << e;
  EXPECT_NE(e.find(": a damaged file"), std::string::npos) << e;
}

TEST_F(Mcap, RefusesAZstdChunkThatDoesNotDecompress) {
  std::vector<char> b = bytes_of(kFixtures / "imu_zstd.mcap");
  const std::string zstd_magic = "\x28\xb5\x2f\xfd";
  const std::size_t at = std::string(b.begin(), b.end()).find(zstd_magic);
  ASSERT_NE(at, std::string::npos);
  for (std::size_t k = at + 40; k < at + 120; ++k) b[k] = 0x55;
  const std::string e = error_of(write(b));
  EXPECT_NE(e.find("bag.mcap: chunk at byte "), std::string::npos) << e;
  EXPECT_NE(e.find("zstd data does not decompress to its "), std::string::npos) << e;
}

// Issue 25: the file was mapped, and a file truncated while it was read killed the process
// with SIGBUS. Read with pread(), a file that shrinks is one line naming the byte where it
// now ends. Deterministic: the reader's hook truncates the file once the reading has passed
// its first megabyte.
TEST_F(Mcap, AFileThatShrinksWhileItIsReadIsAnErrorLineNotASignal) {
  gmwm::test::McapOptions o;
  o.messages = 20000;  // about 7 MB in uncompressed chunks
  const std::string bytes = gmwm::test::mcap_file(o).bytes;
  const std::string p = write(std::vector<char>(bytes.begin(), bytes.end()));
  constexpr std::uint64_t kCut = 1u << 19;
  bool cut = false;
  gmwm::io::detail::testing::set_read_hook([&](const std::string& path, std::uint64_t offset) {
    if (!cut && path == p && offset > (1u << 20)) {
      fs::resize_file(p, kCut);
      cut = true;
    }
  });
  const std::string e = error_of(p);
  gmwm::io::detail::testing::set_read_hook(nullptr);
  EXPECT_TRUE(cut);
  EXPECT_EQ(e.rfind(p + ": the file ends at byte " + std::to_string(kCut) + ", expected ", 0), 0u) << e;
  EXPECT_NE(e.find("bytes when opened: it shrank while being read)"), std::string::npos) << e;
}

// The same file read whole: the values the writer put, at its rate.
TEST_F(Mcap, ReadsTheTestWritersFileInEveryChunkCompression) {
  for (const char* compression : {"", "lz4", "zstd"}) {
    gmwm::test::McapOptions o;
    o.messages = 1000;
    o.compression = compression;
    const std::string bytes = gmwm::test::mcap_file(o).bytes;
    const auto set = read_signals(write(std::vector<char>(bytes.begin(), bytes.end())), {});
    ASSERT_EQ(set.signals.size(), 6u);
    for (std::size_t k = 0; k < 6; ++k)
      for (int i = 0; i < 1000; i += 97)
        EXPECT_EQ(set.signals[k].values[static_cast<std::size_t>(i)], gmwm::test::imu_values(i)[k]);
    EXPECT_DOUBLE_EQ(set.freq, 200.0) << compression;
  }
}

}  // namespace
