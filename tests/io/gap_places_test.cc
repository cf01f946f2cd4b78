// Where the timestamps show missing samples (issue 47, item 1): TimingReport::missing places
// each gap on the grid of the record's samples with the missing ones between them, so that a
// run starts at the index the first missing sample would have had, whatever block of steps
// it falls in; a step that is not a whole number of periods is a gap of unknown length.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/io/stamp_timing.h"
#include "signal_test_util.h"
#include "test_support.h"

namespace {

using gmwm::MissingRun;
using gmwm::io::timing_of_stamps;
using gmwm::io::TimingReport;

constexpr std::int64_t kOrigin = 1700000000000000000;  // a Unix time in ns
constexpr std::int64_t kPeriod = 10000000;             // 10 ms: 100 Hz

// The stamps of grid samples 0..n-1 but those in `dropped`.
std::vector<std::int64_t> stamps_without(std::int64_t n, const std::set<std::int64_t>& dropped) {
  std::vector<std::int64_t> t;
  for (std::int64_t k = 0; k < n; ++k)
    if (!dropped.count(k)) t.push_back(kOrigin + k * kPeriod);
  return t;
}

std::set<std::int64_t> range(std::int64_t first, std::int64_t count) {
  std::set<std::int64_t> s;
  for (std::int64_t k = first; k < first + count; ++k) s.insert(k);
  return s;
}

void expect_runs(const TimingReport& r, const std::vector<MissingRun>& want) {
  ASSERT_EQ(r.missing.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k) {
    EXPECT_EQ(r.missing[k].start, want[k].start) << "run " << k;
    EXPECT_EQ(r.missing[k].length, want[k].length) << "run " << k;
  }
}

TEST(GapPlaces, EachRunStartsWhereItsFirstMissingSampleWouldHaveBeen) {
  // Gaps in the first block of 1024 steps, in a middle one, and in the last short block.
  std::set<std::int64_t> dropped = range(10, 3);
  dropped.insert(500);
  for (std::int64_t k : range(4000, 50)) dropped.insert(k);
  dropped.insert(5098);
  const TimingReport r = timing_of_stamps(stamps_without(5100, dropped), "data.index", "t", std::nullopt);
  EXPECT_EQ(r.gaps, 4);
  EXPECT_TRUE(r.gap_positions_known);
  EXPECT_EQ(r.uncertain_gaps, 0);
  expect_runs(r, {{10, 3}, {500, 1}, {4000, 50}, {5098, 1}});
}

TEST(GapPlaces, FindsEveryTenthSampleDroppedAsPx4LogsDropThem) {
  std::set<std::int64_t> dropped;
  for (std::int64_t k = 9; k < 20000; k += 10) dropped.insert(k);
  // Grid sample 20000 is recorded: a sample missing at the very end shows in no step.
  const TimingReport r = timing_of_stamps(stamps_without(20001, dropped), "data.index", "t", std::nullopt);
  EXPECT_DOUBLE_EQ(r.estimated_freq, 100.0);  // 8 of 9 steps are one period
  ASSERT_EQ(r.missing.size(), 2000u);
  for (std::size_t k = 0; k < r.missing.size(); ++k) {
    ASSERT_EQ(r.missing[k].start, 9 + 10 * static_cast<std::int64_t>(k));
    ASSERT_EQ(r.missing[k].length, 1);
  }
}

TEST(GapPlaces, AStepThatIsNotAWholeNumberOfPeriodsIsAGapOfUnknownLength) {
  std::vector<std::int64_t> t = stamps_without(3000, {});
  for (std::size_t k = 1500; k < t.size(); ++k) t[k] += 3 * kPeriod / 2;  // a step of 2.5 periods
  for (std::size_t k = 2500; k < t.size(); ++k) t[k] += 2 * kPeriod;      // and one of 3: 2 missing
  const TimingReport r = timing_of_stamps(t, "data.index", "t", std::nullopt);
  EXPECT_EQ(r.gaps, 2);
  EXPECT_EQ(r.uncertain_gaps, 1);
  ASSERT_TRUE(r.first_uncertain_gap.has_value());
  EXPECT_EQ(r.first_uncertain_gap->sample, 1500);
  EXPECT_NEAR(r.first_uncertain_gap->step_seconds, 0.025, 1e-12);
  expect_runs(r, {{2500, 2}});  // the known gap is placed; the uncertain one adds nothing
}

TEST(GapPlaces, AFilesTimestampColumnGivesTheSameRunsAsItsStamps) {
  std::set<std::int64_t> dropped = range(100, 7);
  dropped.insert(2222);
  const std::vector<std::int64_t> t = stamps_without(3000, dropped);
  std::string csv = "timestamp [ns],x\n";
  for (std::size_t i = 0; i < t.size(); ++i)
    csv += std::to_string(t[i]) + "," + std::to_string(std::sin(0.37 * static_cast<double>(i))) + "\n";
  const std::string dir = gmwm::test::temp_dir("gap_places");
  gmwm::io::ReadOptions o;
  const gmwm::io::SignalSet set = gmwm::io::read_signals(gmwm::test::write_text(dir, "g.csv", csv), o);
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(set.timing.has_value());
  expect_runs(*set.timing, {{100, 7}, {2222, 1}});
  expect_runs(timing_of_stamps(t, "data.index", "t", std::nullopt), {{100, 7}, {2222, 1}});
}

TEST(GapPlaces, ARecordWithoutGapsHasNoRuns) {
  const TimingReport r = timing_of_stamps(stamps_without(4096, {}), "data.index", "t", std::nullopt);
  EXPECT_EQ(r.gaps, 0);
  EXPECT_TRUE(r.missing.empty());
  EXPECT_EQ(r.uncertain_gaps, 0);
}

}  // namespace
