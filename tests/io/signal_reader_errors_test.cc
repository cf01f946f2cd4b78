// Every user error of read_signals(): one line naming the file, the line and column where
// they apply, what was found and what was expected.

#include <gtest/gtest.h>

#include <filesystem>

#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"
#include "signal_test_util.h"
#include "test_support.h"

using gmwm::io::ReadOptions;
using gmwm::test::contains;
using gmwm::test::csv_rows;
using gmwm::test::read_error;
using gmwm::test::write_text;

namespace {

class SignalReaderErrors : public ::testing::Test {
 protected:
  std::filesystem::path dir = gmwm::test::temp_dir("reader_errors");
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string file(const std::string& content) { return write_text(dir, "x.csv", content); }
};

}  // namespace

TEST_F(SignalReaderErrors, RejectsAMissingFileNamingIt) {
  const std::string p = (dir / "nope.csv").string();
  EXPECT_EQ(read_error(p), p + ": file not found, expected an existing data file");
}

TEST_F(SignalReaderErrors, RejectsAFolderGivenAsTheFile) {
  EXPECT_EQ(read_error(dir.string()), dir.string() + ": is a folder, expected a data file");
}

TEST_F(SignalReaderErrors, ReportsAMissingFileOrAFolderAsSuchBeforeAnyFormatsCheck) {
  // --topic reads a log: a missing flight.ulg was told it is delimited text without topics.
  ReadOptions o;
  o.topic = "sensor_combined";
  for (const std::string name : {"flight.ulg", "run.bag", "x.csv"}) {
    const std::string p = (dir / name).string();
    EXPECT_EQ(read_error(p, o), p + ": file not found, expected an existing data file");
    try {
      gmwm::io::check_signals(p, o);
      ADD_FAILURE() << "no throw for " << p;
    } catch (const gmwm::InputError& e) {
      EXPECT_EQ(std::string(e.what()), p + ": file not found, expected an existing data file");
    }
  }
  EXPECT_EQ(read_error(dir.string(), o), dir.string() + ": is a folder, expected a data file");
  // An existing text file is still told it has no topics.
  EXPECT_TRUE(
      contains(read_error(file("time,x\n" + csv_rows(20)), o), "the file is delimited text, which has no topics"));
}

TEST_F(SignalReaderErrors, RejectsAnEmptyFile) {
  const std::string p = file("");
  EXPECT_EQ(read_error(p), p + ": found an empty file, expected a header row and data rows");
}

TEST_F(SignalReaderErrors, RejectsAGzipFileHoldingNoText) {
  // The 20-byte gzip stream of nothing: header, an empty final block, CRC 0 and length 0.
  const std::string empty_gzip("\x1f\x8b\x08\0\0\0\0\0\0\x03\x03\0\0\0\0\0\0\0\0\0", 20);
  const std::string gz = write_text(dir, "empty.csv.gz", empty_gzip);
  EXPECT_EQ(read_error(gz), gz + ": found no text, expected a header row and data rows");
}

TEST_F(SignalReaderErrors, RejectsAFileOfBlankLines) {
  const std::string p = file("\n  \n\r\n");
  EXPECT_EQ(read_error(p), p + ": found only blank lines, expected a header row and data rows");
}

TEST_F(SignalReaderErrors, RejectsAHeaderWithoutDataRows) {
  const std::string p = file("time,x,y\n\n");
  EXPECT_EQ(read_error(p), p + ":1: found a header but no data rows, expected at least 16 rows of samples");
}

TEST_F(SignalReaderErrors, RejectsAFileWithoutAHeaderRowSayingSo) {
  const std::string p = file(csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":1: found a data row '0.00,0.000000,0' where the header belongs, "
                               "expected a header row naming the columns (e.g. "
                               "'time,gyro_x,gyro_y')");
}

TEST_F(SignalReaderErrors, RejectsANonNumericCellNamingLineAndColumn) {
  const std::string p = file("time,x,y\n" + csv_rows(3) + "0.03,abc,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":5:2: found 'abc' in column 'x', expected a number");
}

TEST_F(SignalReaderErrors, RejectsAnEmptyCell) {
  const std::string p = file("time,x,y\n" + csv_rows(3) + "0.03,,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":5:2: found an empty cell in column 'x', expected a number");
}

TEST_F(SignalReaderErrors, HintsAtTheDecimalSeparatorInASemicolonFile) {
  const std::string p = file("time;x\n0;1\n0,01;2\n");
  EXPECT_EQ(read_error(p), p + ":3:1: found '0,01' in column 'time', expected a number (with "
                               "'.' as the decimal separator)");
}

TEST_F(SignalReaderErrors, RejectsNanAndInfCells) {
  for (const std::string bad : {"nan", "NaN", "inf", "-Infinity"}) {
    const std::string p = file("time,x,y\n" + csv_rows(3) + "0.03,1," + bad + "\n" + csv_rows(20));
    EXPECT_EQ(read_error(p), p + ":5:3: found '" + bad +
                                 "' in column 'y', expected a finite number (NaN and Inf are "
                                 "not allowed)");
  }
}

TEST_F(SignalReaderErrors, RejectsANumberOutsideTheRangeOfADouble) {
  const std::string p = file("time,x,y\n" + csv_rows(3) + "0.03,1e999,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":5:2: found '1e999' in column 'x', expected a number within the "
                               "range of a double");
}

TEST_F(SignalReaderErrors, RejectsARaggedRowNamingLineAndColumn) {
  const std::string few = file("time,x,y\n" + csv_rows(3) + "0.03,0.5\n" + csv_rows(20));
  EXPECT_EQ(read_error(few), few +
                                 ":5:3: found 2 fields, expected 3 like the header (no value "
                                 "for column 'y')");
  const std::string many = file("time,x,y\n" + csv_rows(3) + "0.03,0.5,1,9\n" + csv_rows(20));
  EXPECT_EQ(read_error(many), many +
                                  ":5:4: found 4 fields, expected 3 like the header (extra "
                                  "value '9')");
}

TEST_F(SignalReaderErrors, RejectsARaggedRowInAWhitespaceSeparatedFile) {
  const std::string p = file("time x y\n" + csv_rows(3, ' ') + "0.03  0.5\n" + csv_rows(20, ' '));
  EXPECT_EQ(read_error(p), p + ":5:3: found 2 fields, expected 3 like the header (no value for "
                               "column 'y')");
}

TEST_F(SignalReaderErrors, RejectsABlankLineBetweenDataRows) {
  const std::string p = file("time,x,y\n" + csv_rows(3) + "\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":5: found an empty line, expected a data row (blank lines are "
                               "allowed only at the end of the file)");
}

TEST_F(SignalReaderErrors, NamesTheFirstOfARunOfBlankLinesOfEveryFormBeforeAnotherRow) {
  // Spaces, tabs, CR LF: each form a blank line; the rows after them are refused at the first.
  const std::string p = file("time,x,y\n" + csv_rows(3) + "\n  \n\t\r\n \r\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":5: found an empty line, expected a data row (blank lines are "
                               "allowed only at the end of the file)");
  // A line of a space and a lone CR before text is not blank: it is the row after the blank.
  const std::string q = file("time,x,y\n" + csv_rows(3) + "\n \rx\n");
  EXPECT_EQ(read_error(q), q + ":5: found an empty line, expected a data row (blank lines are "
                               "allowed only at the end of the file)");
}

TEST_F(SignalReaderErrors, CountsTheBlankLinesBeforeTheHeaderInTheLineItNames) {
  const std::string p = file("\n \t\n\r\ntime,x,y\n" + csv_rows(3) + "0.03,abc,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(p), p + ":8:2: found 'abc' in column 'x', expected a number");
}

TEST_F(SignalReaderErrors, NamesTheFirstBlankLineOfARunLongerThanTheReadersBuffer) {
  // 300 000 blank lines of three bytes (0.9 MB) cross the 256 KiB text chunks at every offset
  // of a line, its CR included.
  std::string blanks;
  for (int i = 0; i < 300000; ++i) blanks += " \r\n";
  const std::string p = file("time,x,y\n" + csv_rows(20) + blanks + "0.2,1,2\n");
  EXPECT_EQ(read_error(p), p + ":22: found an empty line, expected a data row (blank lines are "
                               "allowed only at the end of the file)");
  const std::string q = file("time,x,y\n" + csv_rows(20) + blanks + " \t");
  EXPECT_EQ(read_error(q), "no error");
  const std::string h = file(blanks + "time,x,y\n" + csv_rows(3) + "0.03,abc,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(h), h + ":300005:2: found 'abc' in column 'x', expected a number");
  // Bare line breaks (read eight at a time) across the chunks, an odd count of them, then a
  // row: the line numbers after them are still exact.
  const std::string bare(300001, '\n');
  const std::string r = file("time,x,y\n" + csv_rows(20) + bare + "0.2,abc,2\n");
  EXPECT_EQ(read_error(r), r + ":22: found an empty line, expected a data row (blank lines are "
                               "allowed only at the end of the file)");
  const std::string e = file(bare + "time,x,y\n" + csv_rows(3) + "0.03,abc,1\n" + csv_rows(20));
  EXPECT_EQ(read_error(e), e + ":300006:2: found 'abc' in column 'x', expected a number");
  EXPECT_EQ(read_error(file("time,x,y\n" + csv_rows(20) + bare)), "no error");
}

TEST_F(SignalReaderErrors, RejectsFewerThanSixteenSamples) {
  static_assert(gmwm::io::kMinSamples == 16);
  const std::string p = file("time,x,y\n" + csv_rows(15));
  EXPECT_EQ(read_error(p), p + ": found 15 samples, expected at least 16 (the wavelet variance "
                               "needs 4 levels, 2^4 samples)");
  EXPECT_EQ(read_error(file("time,x,y\n" + csv_rows(16))), "no error");
}

TEST_F(SignalReaderErrors, RejectsAConstantColumn) {
  std::string rows;
  for (int i = 0; i < 20; ++i) rows += std::to_string(i) + "," + std::to_string(i % 3) + ",2.5\n";
  const std::string p = file("time,x,y\n" + rows);
  EXPECT_EQ(read_error(p), p + ": column 3 'y': found all 20 values equal to 2.5, expected a "
                               "varying signal (a constant has a wavelet variance of zero)");
  ReadOptions only_x;
  only_x.columns = {"x"};
  EXPECT_EQ(read_error(p, only_x), "no error");
}

TEST_F(SignalReaderErrors, RejectsATruncatedGzipStream) {
  const std::string gz = (dir / "full.csv.gz").string();
  gmwm::io::write_signals(gz, {{"x", std::vector<double>(5000, 0.0)}}, 100.0);
  const auto size = std::filesystem::file_size(gz);
  std::filesystem::resize_file(gz, size / 2);
  const std::string msg = read_error(gz);
  EXPECT_EQ(msg.rfind(gz + ": gzip stream ends early after ", 0), 0u) << msg;
  EXPECT_TRUE(contains(msg, "bytes of text (truncated file?), expected a complete gzip stream")) << msg;
  // Cut inside the 8-byte trailer (CRC and length): the text is whole, the stream is not.
  gmwm::io::write_signals(gz, {{"x", std::vector<double>(5000, 0.0)}}, 100.0);
  std::filesystem::resize_file(gz, std::filesystem::file_size(gz) - 3);
  EXPECT_TRUE(contains(read_error(gz), ": gzip stream ends early")) << read_error(gz);
}

TEST_F(SignalReaderErrors, RejectsCorruptGzipData) {
  const std::string gz = (dir / "bad.csv.gz").string();
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(static_cast<double>(i));
  gmwm::io::write_signals(gz, {{"x", x}}, 100.0);
  std::string bytes;
  {
    std::ifstream in(gz, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  for (std::size_t i = 100; i < 140; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  write_text(dir, "bad.csv.gz", bytes);
  const std::string msg = read_error(gz);
  EXPECT_EQ(msg.rfind(gz + ": corrupt gzip data", 0), 0u) << msg;
  EXPECT_TRUE(contains(msg, "expected a valid gzip stream")) << msg;
}

TEST_F(SignalReaderErrors, RejectsAnUnknownColumnNameOrIndex) {
  const std::string p = file("time,x,y\n" + csv_rows(20));
  ReadOptions by_name;
  by_name.columns = {"x", "z"};
  EXPECT_EQ(read_error(p, by_name), p + ": --columns: found no column named 'z', expected one "
                                        "of: time, x, y (or a 1-based index)");
  ReadOptions by_index;
  by_index.columns = {"4"};
  EXPECT_EQ(read_error(p, by_index), p + ": --columns: found index 4, expected 1..3 (the file "
                                         "has 3 columns: time, x, y)");
  by_index.columns = {"0"};
  EXPECT_TRUE(contains(read_error(p, by_index), "found index 0, expected 1..3"));
}

TEST_F(SignalReaderErrors, RejectsAnEmptyColumnsEntry) {
  ReadOptions o;
  o.columns = {"x", " "};
  EXPECT_EQ(o.Validate(),
            "--columns: found an empty entry, expected column names or 1-based "
            "indices separated by commas");
  EXPECT_EQ(read_error(file("time,x,y\n" + csv_rows(20)), o), o.Validate());
}

TEST_F(SignalReaderErrors, RejectsTheTimestampOrARepeatedColumnInColumns) {
  const std::string p = file("time,x,y\n" + csv_rows(20));
  ReadOptions o;
  o.columns = {"1"};
  EXPECT_EQ(read_error(p, o), p + ": --columns: found '1', the timestamp column 'time', "
                                  "expected a signal column");
  o.columns = {"x", "2"};
  EXPECT_EQ(read_error(p, o), p + ": --columns: found column 'x' twice, expected each column once");
}

TEST_F(SignalReaderErrors, RejectsANonPositiveFreq) {
  const std::string p = file("x,y\n" + csv_rows(20, ',', false));
  for (const double bad : {0.0, -5.0, std::nan("")}) {
    ReadOptions o;
    o.freq = bad;
    EXPECT_FALSE(o.Validate().empty());
    EXPECT_EQ(read_error(p, o), o.Validate());
  }
  ReadOptions o;
  o.freq = -5.0;
  EXPECT_EQ(o.Validate(), "--freq: found -5, expected a sampling rate in Hz from 1e-09 to 1e+09");
  o.freq = 1e-320;  // subnormal: its reciprocal overflows
  EXPECT_EQ(o.Validate(), "--freq: found 9.99989e-321, expected a sampling rate in Hz from 1e-09 to 1e+09");
  o.freq = 100.0;
  EXPECT_EQ(o.Validate(), "");
}

TEST_F(SignalReaderErrors, RejectsAFileWithoutTimestampsWhenNoFreqIsGiven) {
  const std::string p = file("x,y\n" + csv_rows(20, ',', false));
  EXPECT_EQ(read_error(p), p + ": no timestamp column found; give the sampling rate with --freq HZ");
}

TEST_F(SignalReaderErrors, RejectsTimestampsThatNeverIncreaseWhenNoFreqIsGiven) {
  std::string rows;
  for (int i = 0; i < 20; ++i) rows += "5," + std::to_string(i % 4) + "\n";
  const std::string p = file("t,x\n" + rows);
  EXPECT_EQ(read_error(p), p + ": found timestamps in column 't' that never increase, expected "
                               "increasing times; give the sampling rate with --freq HZ");
  ReadOptions o;
  o.freq = 10.0;
  EXPECT_EQ(read_error(p, o), "no error");
}

TEST_F(SignalReaderErrors, RejectsTimestampsWhoseRateIsBeyondTheRateEveryOptionAccepts) {
  // The same rule as --freq (sampling_rate_problem): stamps 0.1 ns apart give 10 GHz.
  std::string rows;
  char buf[64];
  for (int i = 0; i < 20; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g,%d\n", i * 1e-10, i % 4);
    rows += buf;
  }
  const std::string p = file("time [s],x\n" + rows);
  EXPECT_EQ(read_error(p), p + ": timestamps 'time [s]' in s (stated in the header): median step 0.0001 us = "
                               "1e+10 Hz, expected a sampling rate in Hz from 1e-09 to 1e+09; give --freq HZ to set "
                               "the rate");
  ReadOptions o;
  o.freq = 1e9;  // the rate given: the stamps are not used for it
  EXPECT_EQ(read_error(p, o), "no error");
  // 1e10 s apart (one sample in 317 years) is as far below the slowest rate.
  rows.clear();
  for (int i = 0; i < 20; ++i) rows += std::to_string(i) + "e10," + std::to_string(i % 4) + "\n";
  const std::string slow = read_error(file("time [s],x\n" + rows));
  EXPECT_TRUE(contains(slow, "x.csv: timestamps 'time [s]' in s")) << slow;
  EXPECT_TRUE(contains(slow, "= 1e-10 Hz, expected a sampling rate in Hz from 1e-09 to 1e+09")) << slow;
  // The largest rate itself, integer nanoseconds one apart, is read.
  rows.clear();
  for (int i = 0; i < 20; ++i) rows += std::to_string(i) + "," + std::to_string(i % 4) + "\n";
  EXPECT_DOUBLE_EQ(gmwm::io::read_signals(file("time [ns],x\n" + rows), {}).freq, 1e9);
}

namespace {

// Stamps in seconds since 1970 written to the nanosecond, `step_ns` apart.
std::string epoch_rows(int rows, std::int64_t step_ns) {
  std::string s;
  char buf[64];
  for (int i = 0; i < rows; ++i) {
    const std::int64_t ns = i * step_ns;
    std::snprintf(buf, sizeof buf, "%lld.%09lld,%d\n", 1700000000LL + static_cast<long long>(ns / 1000000000),
                  static_cast<long long>(ns % 1000000000), i % 4);
    s += buf;
  }
  return s;
}

}  // namespace

TEST_F(SignalReaderErrors, RejectsStampsTooCoarseAsDoublesToResolveTheirRate) {
  // 1 GHz on an epoch in seconds: a double holds 1.7e9 only to 2^-22 s = 0.2384 us, so the
  // stamps repeat or jump by that much and gave 4.1943 MHz.
  const std::string p = file("time,x\n" + epoch_rows(4096, 1));
  EXPECT_EQ(read_error(p), p + ": timestamps 'time' in s (guessed from the median step; state it in the header, e.g. "
                               "'time [s]'): median step 0.2384 us = 4.1943e+06 Hz, but doubles hold stamps near "
                               "1.7e+09 s only to 0.2384 us, too coarse to resolve the sampling rate (to 1% it needs "
                               "steps of at least 23.84 us); give --freq HZ, or write the stamps relative to the start "
                               "or as integer nanoseconds");
  // 1 MHz: steps of 4 or 5 units in the last place, a rate up to 25% wrong.
  EXPECT_TRUE(contains(read_error(file("time,x\n" + epoch_rows(64, 1000))), "too coarse to resolve the sampling rate"));
  ReadOptions o;
  o.freq = 1e6;  // the rate given: the stamps are not used for it
  EXPECT_EQ(read_error(p, o), "no error");
  // 1 kHz on the same epoch (4194 units in the last place a step), and 1 GHz as integer
  // nanoseconds (subtracted exactly), are read.
  EXPECT_NEAR(gmwm::io::read_signals(file("time,x\n" + epoch_rows(64, 1000000)), {}).freq, 1000.0, 1000.0 * 1e-3);
  std::string ns;
  for (int i = 0; i < 64; ++i) ns += std::to_string(1700000000000000000LL + i) + "," + std::to_string(i % 4) + "\n";
  EXPECT_DOUBLE_EQ(gmwm::io::read_signals(file("time [ns],x\n" + ns), {}).freq, 1e9);
}

TEST_F(SignalReaderErrors, RejectsATextTimestampColumnWhenNoFreqIsGiven) {
  std::string rows;
  for (int i = 0; i < 20; ++i) rows += "12:00:" + std::to_string(10 + i) + "," + std::to_string(i % 4) + "\n";
  const std::string p = file("time,x\n" + rows);
  EXPECT_EQ(read_error(p), p + ":2:1: found '12:00:10' in timestamp column 'time', expected a "
                               "number; give the sampling rate with --freq HZ");
}

TEST_F(SignalReaderErrors, RejectsALineLongerThanTheLimitNamingIt) {
  const std::string row(gmwm::io::kMaxLineBytes + 10, '1');
  const std::string msg = gmwm::test::read_error(file("time,x\n0,1\n0.01,2\n0.02," + row + "\n0.03,3\n"));
  EXPECT_TRUE(contains(msg, "x.csv:4: found a line longer than 1048576 bytes")) << msg;
  EXPECT_TRUE(contains(msg, "at most 1 MiB")) << msg;
}

TEST_F(SignalReaderErrors, RejectsAHeaderWithMoreColumnsThanTheLimit) {
  std::string header, row;
  for (std::size_t k = 0; k <= gmwm::io::kMaxColumns; ++k) {
    header += (k ? ",c" : "c") + std::to_string(k);
    row += k ? ",1" : "1";
  }
  const std::string msg = gmwm::test::read_error(file(header + "\n" + row + "\n"));
  EXPECT_TRUE(contains(msg, "x.csv:1: found 4097 columns, expected at most 4096")) << msg;
}

TEST_F(SignalReaderErrors, RefusesMoreRowsThanTheMemoryBudgetBeforeReadingThemAll) {
  // A budget of 1 MB holds 20,833 rows of two columns and a timestamp column (whose steps
  // jittery stamps keep) at 16 bytes a value: the file's 70,000 rows are refused at the
  // first check past it (row 65,536), naming the line.
  gmwm::io::ReadOptions o;
  o.memory_budget = 1e6;
  o.spill = false;  // the default goes on in temporary files (signal_reader_test.cc)
  const std::string msg = gmwm::test::read_error(file("time,x,y\n" + csv_rows(70000)), o);
  EXPECT_TRUE(contains(msg, "x.csv:65537: found more than 20833 rows of 2 column(s) and a timestamp column")) << msg;
  EXPECT_TRUE(contains(msg, "memory budget of 1 MB; read fewer columns with --columns")) << msg;
  o.memory_budget = -1.0;
  EXPECT_TRUE(contains(gmwm::test::read_error(file("time,x,y\n" + csv_rows(20)), o), "memory_budget: found -1"));
}
