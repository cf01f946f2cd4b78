// write_signals(): CSV (optionally gzip) that read_signals() reads back bit for bit.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include "gmwm/engine/check.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"
#include "signal_test_util.h"
#include "test_support.h"

using gmwm::io::read_signals;
using gmwm::io::ReadOptions;
using gmwm::io::Signal;
using gmwm::io::write_signals;

namespace {

class SignalWriter : public ::testing::Test {
 protected:
  std::filesystem::path dir = gmwm::test::temp_dir("writer");
  void TearDown() override { std::filesystem::remove_all(dir); }
};

// Doubles that are hard to print: random bit patterns over the whole exponent range,
// subnormals, extremes, negative zero, and values with long decimal expansions.
std::vector<Signal> awkward_signals(std::size_t n) {
  std::mt19937_64 rng(20240611);
  std::vector<double> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) {
    double x;
    do {
      const std::uint64_t bits = rng();
      std::memcpy(&x, &bits, sizeof x);
    } while (!std::isfinite(x));
    a[i] = x;
    b[i] = std::sin(static_cast<double>(i)) / 3.0 * std::pow(10.0, static_cast<double>(i % 40) - 20.0);
  }
  const double specials[] = {0.1,
                             1.0 / 3.0,
                             -0.0,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::max(),
                             1e-310,
                             123456789012345678.0};
  for (std::size_t i = 0; i < std::size(specials); ++i) b[i] = specials[i];
  return {{"a", a}, {"b", b}};
}

void expect_bitwise_equal(std::span<const double> got, std::span<const double> want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    ASSERT_EQ(std::memcmp(&got[i], &want[i], sizeof(double)), 0) << "row " << i << ": " << got[i] << " != " << want[i];
}

}  // namespace

TEST_F(SignalWriter, RoundTripsPlainCsvToFullDoublePrecision) {
  const auto signals = awkward_signals(3000);
  const std::string p = (dir / "out.csv").string();
  write_signals(p, signals, 100.0);
  const auto s = read_signals(p, {});
  ASSERT_EQ(s.signals.size(), 2u);
  EXPECT_FALSE(s.compressed);
  EXPECT_EQ(s.signals[0].name, "a");
  EXPECT_EQ(s.signals[1].name, "b");
  expect_bitwise_equal(s.signals[0].values, signals[0].values);
  expect_bitwise_equal(s.signals[1].values, signals[1].values);
  ASSERT_TRUE(s.timing);
  EXPECT_EQ(s.timing->column, "time [s]");
  EXPECT_EQ(s.timing->unit_source, "stated in the header");
  EXPECT_NEAR(s.freq, 100.0, 1e-9);
}

TEST_F(SignalWriter, RoundTripsGzipToFullDoublePrecision) {
  const auto signals = awkward_signals(3000);
  const std::string p = (dir / "out.csv.gz").string();
  write_signals(p, signals, 250.0);
  const auto s = read_signals(p, {});
  EXPECT_TRUE(s.compressed);
  expect_bitwise_equal(s.signals[0].values, signals[0].values);
  expect_bitwise_equal(s.signals[1].values, signals[1].values);
  EXPECT_NEAR(s.freq, 250.0, 1e-9);
  EXPECT_EQ(s.timing->gaps, 0);
}

TEST_F(SignalWriter, WritesNoTimeColumnWithoutAFreq) {
  const std::string p = (dir / "nofreq.csv").string();
  write_signals(p, {{"x", {1.5, -2.0, 0.25}}, {"y", {1, 2, 3}}}, std::nullopt);
  EXPECT_EQ(gmwm::io::format_signals_csv({{"x", {1.5, -2.0, 0.25}}, {"y", {1, 2, 3}}}, std::nullopt),
            "x,y\n1.5,1\n-2,2\n0.25,3\n");
  std::ifstream in(p);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "x,y");
}

TEST_F(SignalWriter, WritesTheTimeInSecondsFirst) {
  EXPECT_EQ(gmwm::io::format_signals_csv({{"x", {1.0, 2.0, 4.0}}}, 4.0), "time [s],x\n0,1\n0.25,2\n0.5,4\n");
}

TEST_F(SignalWriter, QuotesNamesThatNeedIt) {
  std::vector<double> v(20);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(i % 5);
  const std::string p = (dir / "names.csv").string();
  write_signals(p, {{"gyro, x \"raw\"", v}, {"y", v}}, 10.0);
  const auto s = read_signals(p, {});
  ASSERT_EQ(s.signals.size(), 2u);
  EXPECT_EQ(s.signals[0].name, "gyro, x \"raw\"");
}

TEST_F(SignalWriter, RejectsSignalsOfDifferentLengths) {
  EXPECT_THROW(write_signals((dir / "bad.csv").string(), {{"x", {1, 2}}, {"y", {1}}}, 1.0), gmwm::InvalidArgument);
  EXPECT_THROW(write_signals((dir / "bad.csv").string(), {{"x", {1, 2}}}, 0.0), gmwm::InvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.csv"));
}

TEST_F(SignalWriter, RejectsAMissingFolderWithoutLeavingAFile) {
  const std::string p = (dir / "no" / "such" / "out.csv").string();
  EXPECT_THROW(write_signals(p, {{"x", {1, 2}}}, 1.0), gmwm::InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "no"));
}
