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

#include "gmwm/engine/error.h"
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

// A CSV of the grid's samples but those dropped, stamped in ns.
std::string csv_without(std::int64_t n, const std::set<std::int64_t>& dropped, std::int64_t extra_at = -1,
                        std::int64_t extra = 0) {
  std::vector<std::int64_t> t = stamps_without(n, dropped);
  if (extra_at >= 0)
    for (std::size_t k = static_cast<std::size_t>(extra_at); k < t.size(); ++k) t[k] += extra;
  std::string csv = "timestamp [ns],x\n";
  for (std::size_t i = 0; i < t.size(); ++i)
    csv += std::to_string(t[i]) + "," + std::to_string(std::sin(0.37 * static_cast<double>(i))) + "\n";
  return csv;
}

gmwm::io::SignalSet read_csv(const std::string& csv, gmwm::io::GapHandling gaps) {
  const std::string dir = gmwm::test::temp_dir("gap_read");
  gmwm::io::ReadOptions o;
  o.gaps = gaps;
  try {
    gmwm::io::SignalSet set = gmwm::io::read_signals(gmwm::test::write_text(dir, "g.csv", csv), o);
    std::filesystem::remove_all(dir);
    return set;
  } catch (...) {
    std::filesystem::remove_all(dir);
    throw;
  }
}

TEST(GapReading, TheRecordCarriesTheMissingRunsItsStampsShowAndSaysSo) {
  const gmwm::io::SignalSet set = read_csv(csv_without(3000,
                                                       [] {
                                                         std::set<std::int64_t> d = range(100, 7);
                                                         d.insert(2222);
                                                         return d;
                                                       }()),
                                           gmwm::io::GapHandling::kCompleteWindows);
  ASSERT_EQ(set.missing.size(), 2u);
  EXPECT_EQ(set.missing[1].start, 2222);
  EXPECT_EQ(set.missing_samples(), 8);
  EXPECT_EQ(set.signals.front().values.size(), 2992u);
  EXPECT_EQ(gmwm::io::gaps_summary(set),
            "8 of the record's 3000 samples missing in 2 gaps (the largest 7 samples); each scale reads the "
            "windows that hold no missing sample, or those missing at most a tenth of each half (the Allan deviation "
            "from 10 samples a half, the WV where complete windows are scarce)");
}

TEST(GapReading, GapsJoinLeavesTheSamplesEndToEndAsBefore) {
  const gmwm::io::SignalSet set = read_csv(csv_without(3000, range(100, 7)), gmwm::io::GapHandling::kJoin);
  EXPECT_TRUE(set.missing.empty());
  EXPECT_EQ(set.gaps, gmwm::io::GapHandling::kJoin);
  EXPECT_EQ(set.timing->gaps, 1);
  EXPECT_EQ(gmwm::io::gaps_summary(set), "");
}

TEST(GapReading, AGapOfUnknownLengthIsRefusedWithTheStampsAroundIt) {
  // A step of 2.5 periods after sample 1500 (15.00 s to 15.025 s from the first stamp).
  const std::string csv = csv_without(3000, {}, 1500, 3 * kPeriod / 2);
  try {
    read_csv(csv, gmwm::io::GapHandling::kCompleteWindows);
    FAIL() << "a gap of 2.5 periods was read";
  } catch (const gmwm::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("g.csv: timestamps 'timestamp [ns]': a gap of unknown length before sample 1500: from 14.99 s "
                     "to 15.015 s after the first stamp, a step of 25 ms = 2.5 periods of 10 ms, expected a whole "
                     "number of periods (to 0.25); give --gaps join to join the samples end to end"),
              std::string::npos)
        << m;
  }
  EXPECT_NO_THROW(read_csv(csv, gmwm::io::GapHandling::kJoin));
}

TEST(GapReading, StampsTooJitteryToPlaceALostSampleAreReadEndToEnd) {
  // Uniform jitter of half a period either side (a host clock stamping a USB IMU): steps of
  // up to 1.5 periods are late stamps, not lost samples; no gap can be placed to a sample.
  std::vector<std::int64_t> t;
  std::uint64_t state = 11;
  for (std::int64_t k = 0; k < 20000; ++k) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const double u = static_cast<double>(state >> 11) / 9007199254740992.0;
    t.push_back(kOrigin + k * kPeriod + static_cast<std::int64_t>((u - 0.5) * kPeriod));
  }
  const TimingReport jittery = timing_of_stamps(t, "data.index", "t", std::nullopt);
  // A step is the difference of two jitters, triangular over +-1 period: its 10th percentile
  // is 1 - sqrt(0.2) = 0.553 periods short of the median (a block's sampling error ~0.03).
  EXPECT_NEAR(jittery.jitter, 1.0 - std::sqrt(0.2), 0.04);
  std::string csv = "timestamp [ns],x\n";
  for (std::size_t i = 0; i < t.size(); ++i)
    csv += std::to_string(t[i]) + "," + std::to_string(std::sin(0.37 * static_cast<double>(i))) + "\n";
  const gmwm::io::SignalSet set = read_csv(csv, gmwm::io::GapHandling::kCompleteWindows);
  EXPECT_TRUE(set.missing.empty());
  // A regular clock that loses every fourth sample (a third of its steps are gaps): the
  // lower tail of the steps is one period, the jitter 0, and every gap is placed.
  std::set<std::int64_t> quarter;
  for (std::int64_t k = 3; k < 7998; k += 4) quarter.insert(k);  // not the last sample: no stamp after it
  const TimingReport lossy = timing_of_stamps(stamps_without(8000, quarter), "data.index", "t", std::nullopt);
  EXPECT_EQ(lossy.jitter, 0.0);
  EXPECT_EQ(lossy.missing.size(), quarter.size());
}

TEST(GapReading, TheGapsOptionTakesWindowsOrJoinAndNamesBothOtherwise) {
  EXPECT_EQ(gmwm::io::gap_handling_of("windows"), gmwm::io::GapHandling::kCompleteWindows);
  EXPECT_EQ(gmwm::io::gap_handling_of("join"), gmwm::io::GapHandling::kJoin);
  try {
    gmwm::io::gap_handling_of("fill");
    FAIL() << "--gaps fill was taken";
  } catch (const gmwm::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "--gaps: found 'fill', expected 'windows' (each scale from the windows without a missing sample) or "
                 "'join' (the samples end to end)");
  }
}

}  // namespace
