// Records that were misread without a word (issue 25): a change of sampling rate inside a
// record, text appended after a gzip stream, every member of a concatenated gzip file, a
// file in UTF-16 or with CR-only line endings, and jittery timestamps beyond the memory
// budget (their steps then kept in a temporary file, with the same exact median).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"
#include "signal_test_util.h"
#include "test_support.h"

using gmwm::io::read_signals;
using gmwm::io::ReadOptions;
using gmwm::io::SignalSet;
using gmwm::test::contains;
using gmwm::test::gzip_member;
using gmwm::test::read_error;
using gmwm::test::write_text;

namespace {

// A CSV of nanosecond stamps (steps as given) and one varying signal.
std::string stamps_csv(const std::vector<std::int64_t>& steps) {
  std::string s = "timestamp [ns],x\n";
  std::int64_t t = 1700000000000000000;
  for (std::size_t i = 0; i <= steps.size(); ++i) {
    s += std::to_string(t) + "," + std::to_string(std::sin(0.37 * static_cast<double>(i))) + "\n";
    if (i < steps.size()) t += steps[i];
  }
  return s;
}

// A fixed linear congruential generator's next value in [0, 1).
double uniform(std::uint64_t& state) {
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return static_cast<double>(state >> 11) / 9007199254740992.0;
}

class RecordIntegrity : public ::testing::Test {
 protected:
  std::filesystem::path dir = gmwm::test::temp_dir("records");
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string file(const std::string& content, const std::string& name = "x.csv") {
    return write_text(dir, name, content);
  }
};

TEST_F(RecordIntegrity, ARateChangeInsideARecordIsRefusedNamingBothRatesAndWhereItChanges) {
  // 4096 samples at 100 Hz, then 4096 at 200 Hz.
  std::vector<std::int64_t> steps(4096, 10000000);
  steps.insert(steps.end(), 4096, 5000000);
  const std::string p = file(stamps_csv(steps));
  const std::string e = read_error(p);
  EXPECT_TRUE(contains(e,
                       "the sampling rate changes within the record, from about 100 Hz at its start to about 200 Hz "
                       "from sample 4097"))
      << e;
  EXPECT_TRUE(contains(e, "x.csv: timestamps 'timestamp [ns]'")) << e;
  EXPECT_TRUE(contains(e, "--freq")) << e;
  // --freq takes the samples as evenly spaced: read, with the change reported.
  ReadOptions o;
  o.freq = 100.0;
  const SignalSet s = read_signals(p, o);
  ASSERT_TRUE(s.timing && s.timing->rate_change);
  EXPECT_NEAR(s.timing->rate_change->from_hz, 100.0, 1e-9);
  EXPECT_NEAR(s.timing->rate_change->to_hz, 200.0, 1e-9);
  EXPECT_EQ(s.timing->rate_change->sample, 4096);
  EXPECT_TRUE(contains(s.timing->summary(), "the sampling rate changes")) << s.timing->summary();
}

TEST_F(RecordIntegrity, AFinalStretchOfTwoBlocksAtAnotherRateIsFound) {
  // 20,000 samples at 400 Hz, the last 2100 at 500 Hz: a stretch of two blocks of steps
  // always fills one block whole, wherever the blocks fall.
  std::vector<std::int64_t> steps(20000, 2500000);
  steps.insert(steps.end(), 2100, 2000000);
  const std::string e = read_error(file(stamps_csv(steps)));
  EXPECT_TRUE(contains(e, "from about 400 Hz at its start to about 500 Hz")) << e;
}

TEST_F(RecordIntegrity, JitterRoundingAndGapsAreNotARateChange) {
  std::uint64_t state = 7;
  // Half a step of uniform jitter at 200 Hz over 300,000 samples.
  std::vector<std::int64_t> jitter;
  for (int i = 0; i < 300000; ++i)
    jitter.push_back(5000000 + static_cast<std::int64_t>((uniform(state) - 0.5) * 5000000));
  // 400 Hz stamped in whole milliseconds: steps of 2 and 3 ms in turn.
  std::vector<std::int64_t> rounded;
  for (int i = 1; i <= 100000; ++i) rounded.push_back(((i * 5 + 1) / 2 - ((i - 1) * 5 + 1) / 2) * 1000000);
  // One sample lost in every 4 (a step of two periods, a quarter of the steps).
  std::vector<std::int64_t> gappy;
  for (int i = 0; i < 100000; ++i) gappy.push_back(i % 4 == 3 ? 20000000 : 10000000);
  for (const auto* steps : {&jitter, &rounded, &gappy}) {
    const SignalSet s = read_signals(file(stamps_csv(*steps)), {});
    ASSERT_TRUE(s.timing);
    EXPECT_FALSE(s.timing->rate_change) << s.timing->summary();
  }
}

TEST_F(RecordIntegrity, EveryMemberOfAConcatenatedGzipFileIsRead) {
  std::string first = "time,x\n", second;
  for (int i = 0; i < 3000; ++i)
    (i < 1000 ? first : second) += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i)) + "\n";
  const SignalSet s = read_signals(file(gzip_member(first) + gzip_member(second), "two.csv.gz"), {});
  ASSERT_EQ(s.signals.size(), 1u);
  EXPECT_EQ(s.signals[0].values.size(), 3000u);
  // Zero padding after the last member (tape blocks) is ignored, as gzip does.
  const SignalSet padded = read_signals(file(gzip_member(first) + std::string(512, '\0'), "padded.csv.gz"), {});
  EXPECT_EQ(padded.signals[0].values.size(), 1000u);
}

TEST_F(RecordIntegrity, TextAppendedAfterAGzipStreamIsRefusedNotDropped) {
  std::string rows = "time,x\n", more;
  for (int i = 0; i < 100; ++i) rows += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i)) + "\n";
  for (int i = 100; i < 200; ++i) more += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i)) + "\n";
  const std::string member = gzip_member(rows);
  const std::string e = read_error(file(member + more, "mixed.csv.gz"));
  EXPECT_TRUE(contains(e,
                       "mixed.csv.gz: found bytes that are not gzip data after the end of the gzip stream, at byte "
                       "offset " +
                           std::to_string(member.size())))
      << e;
}

TEST_F(RecordIntegrity, Utf16AndCrOnlyLineEndingsAreNamedAsSuch) {
  std::string utf16 = "\xFF\xFE";
  for (char c : std::string("time,x\n0,1\n0.01,2\n")) utf16 += std::string(1, c) + '\0';
  EXPECT_TRUE(contains(read_error(file(utf16, "u.csv")), "u.csv:1: found a UTF-16 byte-order mark"))
      << read_error(file(utf16, "u.csv"));
  std::string no_bom;
  for (char c : std::string("time,x\n0,1\n0.01,2\n")) no_bom += std::string(1, c) + '\0';
  EXPECT_TRUE(contains(read_error(file(no_bom, "n.csv")), "n.csv:1: found NUL bytes in the header line"));
  std::string cr = "time,x\r";
  for (int i = 0; i < 100; ++i) cr += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i)) + "\r";
  const std::string e = read_error(file(cr, "mac.csv"));
  EXPECT_TRUE(contains(e, "mac.csv:1: found carriage returns (CR) inside the first line")) << e;
  // ... also when the CR-only file is longer than the line limit.
  std::string long_cr = "time,x\r";
  while (long_cr.size() <= gmwm::io::kMaxLineBytes) long_cr += "0.01,0.123456789\r";
  EXPECT_TRUE(contains(read_error(file(long_cr, "long.csv")), "carriage returns (CR)"));
  // CR LF line endings are fine.
  std::string crlf = "time,x\r\n";
  for (int i = 0; i < 100; ++i) crlf += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i)) + "\r\n";
  EXPECT_EQ(read_signals(file(crlf, "dos.csv"), {}).signals[0].values.size(), 100u);
}

TEST_F(RecordIntegrity, JitteryStampsBeyondTheMemoryBudgetKeepTheirStepsInAFileWithTheSameTiming) {
  // 150,001 stamps at 5 ms with 0.4 ms of jitter: more distinct steps than the step table
  // holds, so the steps are listed (8 bytes a row); beyond a 1 MB budget the list goes to a
  // temporary file and the median is selected from it, bit for bit the same.
  std::uint64_t state = 12345;
  std::vector<std::int64_t> steps;
  for (int i = 0; i < 150000; ++i)
    steps.push_back(i == 9000 ? 60000000 : 5000000 + static_cast<std::int64_t>((uniform(state) - 0.5) * 800000));
  const std::string p = file(stamps_csv(steps));
  const SignalSet in_memory = read_signals(p, {});
  ReadOptions o;
  o.memory_budget = 1e6;
  const SignalSet spilled = read_signals(p, o);
  ASSERT_TRUE(spilled.spilled);
  ASSERT_TRUE(in_memory.timing && spilled.timing);
  EXPECT_EQ(spilled.timing->median_step_seconds, in_memory.timing->median_step_seconds);
  EXPECT_EQ(spilled.timing->gaps, in_memory.timing->gaps);
  EXPECT_EQ(spilled.timing->largest_gap_seconds, in_memory.timing->largest_gap_seconds);
  EXPECT_EQ(spilled.freq, in_memory.freq);
  EXPECT_GE(spilled.timing->gaps, 1);
}

TEST_F(RecordIntegrity, ASimulatedFileAtAVeryLowRateReadsBackAtThatRate) {
  // Its time column says its unit: a step of 1000 s is not read as 1000 us.
  std::vector<double> x(64);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.3 * static_cast<double>(i));
  const std::string p = (dir / "slow.csv").string();
  gmwm::io::write_signals(p, {{"x", x}}, 0.001);
  const SignalSet s = read_signals(p, {});
  EXPECT_NEAR(s.freq, 0.001, 1e-15);
  EXPECT_EQ(s.timing->unit, "s");
}

}  // namespace
