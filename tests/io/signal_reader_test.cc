// read_signals(): delimiters, headers, presets, column selection, timestamps, gzip.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"
#include "signal_test_util.h"
#include "test_support.h"

using gmwm::io::read_signals;
using gmwm::io::ReadOptions;
using gmwm::io::SignalSet;
using gmwm::test::contains;
using gmwm::test::csv_rows;
using gmwm::test::write_text;

namespace {

class SignalReader : public ::testing::Test {
 protected:
  std::filesystem::path dir = gmwm::test::temp_dir("reader");
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string file(const std::string& content, const std::string& name = "x.csv") {
    return write_text(dir, name, content);
  }
};

// EuRoC imu0/data.csv: ns since 1970 at 200 Hz (as in the dataset, first stamp included).
std::string euroc_rows(int rows, std::int64_t step_ns = 5000000) {
  std::string s;
  for (int i = 0; i < rows; ++i)
    s += std::to_string(1403636579758555392LL + i * step_ns) + "," + std::to_string(0.01 * (i % 5)) + "," +
         std::to_string(-0.02 * (i % 3)) + "," + std::to_string(0.03 * (i % 4)) + "," +
         std::to_string(9.0 + 0.1 * (i % 3)) + "," + std::to_string(0.1 * (i % 6)) + "," + std::to_string(i % 2) + "\n";
  return s;
}

std::string drop_first_line(const std::string& rows) { return rows.substr(rows.find('\n') + 1); }

}  // namespace

TEST_F(SignalReader, ReadsACsvWithATimeColumnInSeconds) {
  const SignalSet s = read_signals(file("time,x,y\n" + csv_rows(100)), {});
  ASSERT_EQ(s.signals.size(), 2u);
  EXPECT_EQ(s.signals[0].name, "x");
  EXPECT_EQ(s.signals[1].name, "y");
  ASSERT_EQ(s.signals[0].values.size(), 100u);
  EXPECT_EQ(s.signals[0].values[3], 0.141120);  // sin(3) to 6 decimals, parsed exactly
  EXPECT_EQ(s.signals[1].values[9], 2.0);
  EXPECT_TRUE(s.freq_known);
  EXPECT_NEAR(s.freq, 100.0, 1e-9);
  ASSERT_TRUE(s.timing);
  EXPECT_EQ(s.timing->column, "time");
  EXPECT_EQ(s.timing->unit_to_seconds, 1.0);
  EXPECT_EQ(s.timing->gaps, 0);
  EXPECT_EQ(s.timing->disorder, 0);
  EXPECT_EQ(s.delimiter, "comma");
  EXPECT_EQ(s.preset, "");
  EXPECT_FALSE(s.compressed);
}

TEST_F(SignalReader, DetectsTabSemicolonAndWhitespaceDelimiters) {
  const std::pair<char, const char*> cases[] = {{'\t', "tab"}, {';', "semicolon"}, {' ', "whitespace"}};
  for (const auto& [c, name] : cases) {
    const std::string header = std::string("time") + c + "x" + c + "y\n";
    const SignalSet s = read_signals(file(header + csv_rows(40, c)), {});
    EXPECT_EQ(s.delimiter, name);
    ASSERT_EQ(s.signals.size(), 2u) << name;
    EXPECT_EQ(s.signals[1].values[5], 5.0) << name;
  }
  // Runs of blanks, leading blanks and spaces after commas.
  const SignalSet ws = read_signals(file("  time   x  y\n  0.00   1.5\t 2\n" + drop_first_line(csv_rows(40, ' '))), {});
  EXPECT_EQ(ws.delimiter, "whitespace");
  EXPECT_EQ(ws.signals[0].values[0], 1.5);
  const SignalSet spaced = read_signals(file("time, x, y\n0.00, 1.5 , +2\n" + drop_first_line(csv_rows(40))), {});
  EXPECT_EQ(spaced.signals[0].name, "x");
  EXPECT_EQ(spaced.signals[1].values[0], 2.0);
}

TEST_F(SignalReader, HandlesCrlfAByteOrderMarkAndTrailingBlankLines) {
  std::string rows = csv_rows(30), crlf;
  for (char ch : rows) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  const SignalSet s = read_signals(file("\xEF\xBB\xBFtime,x,y\r\n" + crlf + "\r\n\n  \n"), {});
  EXPECT_EQ(s.signals[0].name, "x");
  EXPECT_EQ(s.signals[1].values.size(), 30u);
  EXPECT_EQ(s.signals[1].values[29], 29 % 7);
  // No final line break.
  const SignalSet t = read_signals(file("time,x,y\n" + rows + "0.30,1,2"), {});
  EXPECT_EQ(t.signals[1].values.size(), 31u);
  EXPECT_EQ(t.signals[1].values.back(), 2.0);
  // Blank last lines of every form, the very last without a line break (a lone CR, spaces).
  for (const std::string tail : {"\n \t\n\r\n\r", "\n\n  ", "\r\n\t\r\n"}) {
    const SignalSet u = read_signals(file("time,x,y\n" + rows + tail), {});
    EXPECT_EQ(u.signals[1].values.size(), 30u) << tail;
  }
}

TEST_F(SignalReader, RecognisesTheEurocLayoutAndRenamesItsColumns) {
  const SignalSet s = read_signals(file("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                                        "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n" +
                                        euroc_rows(200)),
                                   {});
  EXPECT_EQ(s.preset, "euroc");
  ASSERT_EQ(s.signals.size(), 6u);
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(s.signals[i].name, names[i]);
  EXPECT_EQ(s.signals[0].unit, "rad/s");
  EXPECT_EQ(s.signals[5].unit, "m/s^2");
  ASSERT_TRUE(s.timing);
  EXPECT_EQ(s.timing->column, "timestamp [ns]");
  EXPECT_EQ(s.timing->unit_to_seconds, 1e-9);
  // Integer nanoseconds since 1970 exceed 2^53; the steps must still be exact.
  EXPECT_EQ(s.timing->median_step_seconds, 5e6 * 1e-9);
  EXPECT_DOUBLE_EQ(s.freq, 200.0);
  EXPECT_EQ(s.timing->gaps, 0);
  // The original names stay valid in --columns.
  ReadOptions o;
  o.columns = {"a_RS_S_z", "gyro_y"};
  const SignalSet picked = read_signals(s.path, o);
  ASSERT_EQ(picked.signals.size(), 2u);
  EXPECT_EQ(picked.signals[0].name, "accel_z");
  EXPECT_EQ(picked.signals[1].name, "gyro_y");
}

TEST_F(SignalReader, RecognisesTheKalibrLayoutWithNanosecondTimestamps) {
  const SignalSet s =
      read_signals(file("timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n" + euroc_rows(100, 2500000)), {});
  EXPECT_EQ(s.preset, "kalibr");
  EXPECT_EQ(s.signals[3].name, "accel_x");
  EXPECT_EQ(s.timing->unit, "ns");
  EXPECT_EQ(s.timing->unit_source, "kalibr layout");
  EXPECT_DOUBLE_EQ(s.freq, 400.0);
}

TEST_F(SignalReader, TreatsEarlierHashLinesAsCommentsBeforeATextHeader) {
  const SignalSet s = read_signals(file("# recorded 2024-01-01\n# rig 3\n\ntime,x,y\n" + csv_rows(20)), {});
  EXPECT_EQ(s.signals[0].name, "x");
  EXPECT_EQ(s.signals[0].values.size(), 20u);
  // A '#' header followed by data (EuRoC style), with an earlier comment line.
  const SignalSet h = read_signals(file("# comment\n# time x y\n" + csv_rows(20, ' ')), {});
  EXPECT_EQ(h.signals[1].name, "y");
}

TEST_F(SignalReader, PicksColumnsByNameOrIndexInTheGivenOrder) {
  const std::string p = file("time,x,y,z\n" + std::string("0,1,2,3\n0.01,2,3,5\n") + [] {
    std::string r;
    for (int i = 2; i < 20; ++i)
      r += std::to_string(i * 0.01) + "," + std::to_string(i) + "," + std::to_string(i % 3) + "," + std::to_string(-i) +
           "\n";
    return r;
  }());
  ReadOptions o;
  o.columns = {" 4", "X"};  // an index (blanks trimmed), a name matched regardless of case
  const SignalSet s = read_signals(p, o);
  ASSERT_EQ(s.signals.size(), 2u);
  EXPECT_EQ(s.signals[0].name, "z");
  EXPECT_EQ(s.signals[0].values[1], 5.0);
  EXPECT_EQ(s.signals[1].name, "x");
}

TEST_F(SignalReader, SkipsTextColumnsUnlessAskedFor) {
  std::string rows;
  for (int i = 0; i < 20; ++i) rows += std::to_string(i) + ",ok," + std::to_string(i % 4) + "\n";
  const std::string p = file("t,status,x\n" + rows);
  const SignalSet s = read_signals(p, {});
  ASSERT_EQ(s.signals.size(), 1u);
  EXPECT_EQ(s.signals[0].name, "x");
  ReadOptions o;
  o.columns = {"status"};
  EXPECT_EQ(gmwm::test::read_error(p, o), p + ":2:2: found 'ok' in column 'status', expected a number");
}

TEST_F(SignalReader, SplitsAUnitOffTheHeaderName) {
  const SignalSet s = read_signals(file("time (s),\"gyro_x [deg/s]\",y\n" + csv_rows(20)), {});
  EXPECT_EQ(s.signals[0].name, "gyro_x");
  EXPECT_EQ(s.signals[0].unit, "deg/s");
  EXPECT_EQ(s.timing->unit_source, "stated in the header");
}

TEST_F(SignalReader, DecidesTheTimeUnitFromTheNameOrTheStep) {
  struct Case {
    const char* header;
    double scale;
    double unit;
  };
  const Case cases[] = {
      {"time_ms", 10.0, 1e-3},        // suffix
      {"Timestamp [us]", 1e4, 1e-6},  // bracket
      {"stamp", 1e7, 1e-9},           // step 1e7: ns
      {"t", 1e4, 1e-6},               // step 1e4: us
      {"time", 10.0, 1e-3},           // step 10: ms
      {"time", 0.01, 1.0},            // step 0.01: s
  };
  for (const Case& c : cases) {
    std::string rows;
    for (int i = 0; i < 20; ++i) rows += std::to_string(i * c.scale) + "," + std::to_string(i % 3) + "\n";
    const SignalSet s = read_signals(file(std::string(c.header) + ",x\n" + rows), {});
    ASSERT_TRUE(s.timing) << c.header;
    EXPECT_EQ(s.timing->unit_to_seconds, c.unit) << c.header;
    EXPECT_NEAR(s.freq, 100.0, 1e-6) << c.header;
  }
  // A Unix time in ms at 1 kHz (step 1) is recognised by its magnitude.
  std::string rows;
  for (int i = 0; i < 20; ++i) rows += std::to_string(1700000000000LL + i) + "," + std::to_string(i % 3) + "\n";
  const SignalSet ms = read_signals(file("time,x\n" + rows), {});
  EXPECT_EQ(ms.timing->unit, "ms");
  EXPECT_NEAR(ms.freq, 1000.0, 1e-9);
}

TEST_F(SignalReader, CountsGapsAndDisorderInTheTimestamps) {
  std::string rows;
  const double times[] = {0, 1, 2, 3, 5, 6, 7, 7, 8, 9, 8.5, 10, 11, 12, 16, 17, 18, 19, 20, 21};
  for (int i = 0; i < 20; ++i) rows += std::to_string(times[i] * 0.01) + "," + std::to_string(i % 3) + "\n";
  const SignalSet s = read_signals(file("time,x\n" + rows), {});
  ASSERT_TRUE(s.timing);
  EXPECT_EQ(s.timing->gaps, 2);  // 3->5 and 12->16; 8.5->10 is 1.5 steps, not a gap
  EXPECT_NEAR(s.timing->largest_gap_seconds, 0.04, 1e-12);
  EXPECT_EQ(s.timing->disorder, 2);  // 7->7 and 9->8.5
  EXPECT_NEAR(s.freq, 100.0, 1e-9);
  EXPECT_TRUE(contains(s.timing->summary(), "2 gaps (largest 40 ms), 2 out of order")) << s.timing->summary();
  // Which ones and where: the stamp 7 repeated (sample 7), 8.5 after 9 (sample 10).
  EXPECT_EQ(s.timing->duplicated, 1);
  EXPECT_EQ(s.timing->first_duplicated, 7);
  EXPECT_EQ(s.timing->last_duplicated, 7);
  EXPECT_EQ(s.timing->first_backward, 10);
  EXPECT_TRUE(contains(s.timing->summary(),
                       "2 out of order (1 repeats the stamp before (5% of the samples, at sample 7), 1 goes backwards "
                       "(first at sample 10))"))
      << s.timing->summary();
}

// A stream whose stamps repeat (a driver that sends a message twice, a clock that did not
// advance) says how many, what share of the samples and from where to where; an ordered
// stream says nothing more than "0 out of order".
TEST_F(SignalReader, SaysTheShareOfDuplicatedStampsAndWhereTheyAre) {
  std::string rows;
  int sample = 0;
  for (int i = 0; i < 200; ++i) {
    rows += std::to_string(i * 0.01) + "," + std::to_string(i % 7) + "\n";
    ++sample;
    if (i == 50 || i == 120 || i == 150) {  // the same stamp again
      rows += std::to_string(i * 0.01) + "," + std::to_string(i % 5) + "\n";
      ++sample;
    }
  }
  const SignalSet s = read_signals(file("time,x\n" + rows), {});
  ASSERT_TRUE(s.timing);
  EXPECT_EQ(s.timing->disorder, 3);
  EXPECT_EQ(s.timing->duplicated, 3);
  EXPECT_EQ(s.timing->first_duplicated, 51);  // the 52nd row repeats the 51st's stamp
  EXPECT_EQ(s.timing->last_duplicated, 153);  // two rows added before it
  EXPECT_EQ(s.timing->first_backward, -1);
  EXPECT_TRUE(contains(s.timing->summary(),
                       "3 out of order (3 repeat the stamp before (1.48% of the samples, from sample 51 to 153))"))
      << s.timing->summary();
  const SignalSet ordered = read_signals(file("time,x,y\n" + csv_rows(50)), {});
  EXPECT_TRUE(contains(ordered.timing->summary(), "0 out of order")) << ordered.timing->summary();
  EXPECT_FALSE(contains(ordered.timing->summary(), "repeat")) << ordered.timing->summary();
  EXPECT_EQ(ordered.timing->disorder_text(), "");
}

TEST_F(SignalReader, LetsFreqOverrideTheTimestampsAndReportsADisagreement) {
  const std::string p = file("time,x,y\n" + csv_rows(50));
  ReadOptions o;
  o.freq = 50.0;
  const SignalSet s = read_signals(p, o);
  EXPECT_EQ(s.freq, 50.0);
  ASSERT_TRUE(s.timing);
  EXPECT_NEAR(s.timing->estimated_freq, 100.0, 1e-9);
  EXPECT_TRUE(contains(s.timing->summary(), "--freq 50 Hz disagrees with them by 100%")) << s.timing->summary();
  o.freq = 100.5;  // within 1%: no remark
  EXPECT_FALSE(contains(read_signals(p, o).timing->summary(), "disagrees"));
}

TEST_F(SignalReader, DetectsGzipByContentNotByName) {
  std::vector<double> x(40);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::cos(static_cast<double>(i));
  const std::string gz = (dir / "a.csv.gz").string();
  gmwm::io::write_signals(gz, {{"x", x}}, 100.0);
  const std::string renamed = (dir / "a.txt").string();
  std::filesystem::rename(gz, renamed);
  const SignalSet s = read_signals(renamed, {});
  EXPECT_TRUE(s.compressed);
  EXPECT_EQ(s.signals[0].values, x);
  // Plain text named .gz is read as plain text.
  const SignalSet plain = read_signals(file("time,x,y\n" + csv_rows(20), "plain.csv.gz"), {});
  EXPECT_FALSE(plain.compressed);
  EXPECT_EQ(plain.signals.size(), 2u);
}

TEST_F(SignalReader, ReadsTheAdisRecordingAsSixColumnsOfAMillionRows) {
  GMWM_REQUIRE_SHARED_DATA();
  ReadOptions o;
  o.freq = 100.0;
  const SignalSet s = read_signals(gmwm::test::shared_data_file("adis_16405_imu1.csv.gz"), o);
  ASSERT_EQ(s.signals.size(), 6u);
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(s.signals[i].name, names[i]);
    EXPECT_EQ(s.signals[i].values.size(), 1000000u);
  }
  EXPECT_EQ(s.signals[0].values[0], -0.05);
  EXPECT_EQ(s.signals[5].values[1], -1.01898);
  EXPECT_EQ(s.freq, 100.0);
  EXPECT_TRUE(s.compressed);
  EXPECT_FALSE(s.timing);
}

namespace {

// The reader's timing from steps it never stores must equal what the list of all steps
// gives: the median (mean of the two middle ones for an even count), the gaps and the
// disorder. `stamps` are integer nanoseconds, so each offset (and step) is exact.
struct ListTiming {
  double median_step_s = 0.0;
  std::int64_t gaps = 0, disorder = 0;
  double largest_gap_s = 0.0;
};
ListTiming timing_of_list(const std::vector<std::int64_t>& stamps) {
  std::vector<double> steps;
  ListTiming t;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    const double d = static_cast<double>(stamps[i] - stamps[0]) - static_cast<double>(stamps[i - 1] - stamps[0]);
    if (d > 0)
      steps.push_back(d);
    else
      ++t.disorder;
  }
  std::vector<double> sorted = steps;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  const double median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  t.median_step_s = median * 1e-9;
  for (double d : steps)
    if (d > gmwm::io::TimingReport::kGapFactor * median) {
      ++t.gaps;
      t.largest_gap_s = std::max(t.largest_gap_s, d * 1e-9);
    }
  return t;
}

std::string ns_csv(const std::vector<std::int64_t>& stamps) {
  std::string s = "timestamp [ns],x\n";
  for (std::size_t i = 0; i < stamps.size(); ++i)
    s += std::to_string(stamps[i]) + "," + std::to_string(std::sin(0.1 * static_cast<double>(i))) + "\n";
  return s;
}

}  // namespace

class StepTiming : public SignalReader {
 protected:
  // Reads the stamps as a CSV and expects the reader's timing to equal the list's.
  ListTiming expect_timing_of_list(const std::vector<std::int64_t>& stamps) {
    const ListTiming want = timing_of_list(stamps);
    const SignalSet s = read_signals(file(ns_csv(stamps)), {});
    EXPECT_TRUE(s.timing);
    if (!s.timing) return want;
    EXPECT_EQ(s.timing->median_step_seconds, want.median_step_s);
    EXPECT_EQ(s.timing->gaps, want.gaps);
    EXPECT_EQ(s.timing->largest_gap_seconds, want.largest_gap_s);
    EXPECT_EQ(s.timing->disorder, want.disorder);
    return want;
  }
};

TEST_F(StepTiming, TimesWithFewDistinctStepsGiveTheListsExactMedianForAnEvenCount) {
  // Steps 4.9, 5.0 and 5.1 ms (plus one gap and one repeat): 2000 steps whose two middle
  // ones differ, so the median is their mean.
  std::vector<std::int64_t> stamps = {1700000000000000000};
  for (int i = 0; i < 2000; ++i) {
    const std::int64_t step = i == 700 ? 0 : i == 1300 ? 40000000 : (i < 1000 ? 4900000 : 5100000);
    stamps.push_back(stamps.back() + step);
  }
  const ListTiming want = expect_timing_of_list(stamps);
  EXPECT_EQ(want.disorder, 1);
  EXPECT_EQ(want.gaps, 1);
}

TEST_F(StepTiming, JitteryTimesWithMoreDistinctStepsThanTheTableGiveTheListsExactMedian) {
  // 150001 stamps at 5 ms +- 0.4 ms of jitter (a fixed LCG): about 150,000 distinct steps,
  // more than the 2^16 the step table counts before it spills to a list.
  std::vector<std::int64_t> stamps = {1700000000000000000};
  std::uint64_t state = 12345;
  for (int i = 0; i < 150000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto jitter = static_cast<std::int64_t>((state >> 33) % 800001) - 400000;
    stamps.push_back(stamps.back() + (i == 9000 ? 60000000 : 5000000 + jitter));
  }
  const ListTiming want = expect_timing_of_list(stamps);
  EXPECT_EQ(want.disorder, 0);
  EXPECT_GE(want.gaps, 1);
}

TEST_F(SignalReader, APlainFileLargerThanItsReadChunkIsReadWhole) {
  // 60000 rows (about 1.4 MB): lines cross the reader's chunk boundaries.
  std::string text = "time,x\n";
  std::vector<double> want;
  char buf[64];
  for (int i = 0; i < 60000; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g", std::sin(0.37 * i) * 1e-3 + i * 1e-9);
    want.push_back(std::strtod(buf, nullptr));
    text += std::to_string(i * 0.01) + "," + buf + "\n";
  }
  const SignalSet s = read_signals(file(text), {});
  ASSERT_EQ(s.signals.size(), 1u);
  EXPECT_EQ(s.signals[0].values, want);
}

TEST_F(SignalReader, ARecordBeyondTheMemoryBudgetGoesOnInTemporaryFilesWithTheSameValuesAndWv) {
  // A budget of 1 MB holds 20,833 rows of two columns and a timestamp column: 200,000 rows go to temporary files
  // (from the first check past the budget, row 65,536), value for value the same as in
  // memory, and so is the classical WV (the Haar prefix sums then live in a file too).
  const std::string p = file("time,x,y\n" + csv_rows(200000));
  const SignalSet in_memory = read_signals(p, {});
  ReadOptions o;
  o.memory_budget = 1e6;
  const SignalSet spilled = read_signals(p, o);
  EXPECT_FALSE(in_memory.spilled);
  ASSERT_TRUE(spilled.spilled);
  ASSERT_EQ(spilled.signals.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(spilled.signals[k].values.in_file());
    EXPECT_FALSE(in_memory.signals[k].values.in_file());
    EXPECT_TRUE(spilled.signals[k].values == in_memory.signals[k].values);
    const auto a = gmwm::classical_wv(in_memory.signals[k].values.data(), 200000);
    const auto b = gmwm::classical_wv(spilled.signals[k].values.data(), 200000);
    EXPECT_EQ(a.wv, b.wv);
    EXPECT_EQ(a.ci_low, b.ci_low);
  }
  EXPECT_EQ(spilled.freq, in_memory.freq);
  ASSERT_TRUE(spilled.timing);
  EXPECT_EQ(spilled.timing->median_step_seconds, in_memory.timing->median_step_seconds);
}
