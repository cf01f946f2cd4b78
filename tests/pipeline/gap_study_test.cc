// The gap study's columns: each diagnosed as it would be alone, columns with one baseline
// sharing one simulated reference (pipeline/src/gap_study.cc, gap::ReferenceCache).

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/gap/gap.h"
#include "gmwm/pipeline/gap_study.h"

namespace gmwm::pipeline {
namespace {

constexpr std::int64_t kN = 1 << 14;
constexpr int kReplicates = 40;  // the fewest whose global test can reject at alpha = 0.05
// The data: the baseline plus, in the second column, a sinusoid it lacks (a gap to find).
constexpr const char* kBaseline = "WN(sigma2=1e-2)+RW(gamma2=1e-8)";
constexpr const char* kWithGap = "WN(sigma2=1e-2)+RW(gamma2=1e-8)+SIN(A2=4e-2,f=0.05)";

// Column k of the record: gyro_x, gyro_y (the one with the gap), gyro_z, each its own draw.
io::SignalSet signal_set(const std::vector<int>& columns) {
  static const char* const kNames[] = {"gyro_x", "gyro_y", "gyro_z"};
  io::SignalSet set;
  set.path = "<array>";
  set.freq = 100.0;
  set.freq_known = true;
  for (int k : columns) {
    const Model m = parse_model(k == 1 ? kWithGap : kBaseline);
    set.signals.push_back({kNames[k], simulate(m, m.given_values(), kN, 11, static_cast<std::uint64_t>(k)), ""});
  }
  return set;
}

GapStudyOptions options() {
  GapStudyOptions o;
  o.baseline = ModelBaseline{kBaseline};
  o.gap.replicates = kReplicates;
  o.gap.seed = 5;
  return o;
}

// Every figure of a column's diagnosis, bit for bit.
void expect_same_diagnosis(const gap::GapResult& a, const gap::GapResult& b) {
  EXPECT_EQ(a.headline, b.headline);
  EXPECT_EQ(a.detected, b.detected);
  EXPECT_EQ(a.statistic, b.statistic);
  EXPECT_EQ(a.p_value, b.p_value);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t j = 0; j < a.levels.size(); ++j) {
    EXPECT_EQ(a.levels[j].ratio, b.levels[j].ratio) << "level " << j + 1;
    EXPECT_EQ(a.levels[j].z, b.levels[j].z) << "level " << j + 1;
  }
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.shrinkage.p_value_after, b.shrinkage.p_value_after);
}

TEST(GapStudy, DiagnosesAColumnAsItWouldAloneWhicheverColumnsComeWithIt) {
  io::SignalSet three = signal_set({0, 1, 2});
  io::SignalSet alone = signal_set({1});  // gyro_y, the column with the gap, listed alone
  const GapStudy all = study_gap(three, options());
  const GapStudy one = study_gap(alone, options());
  ASSERT_EQ(all.columns.size(), 3u);
  ASSERT_EQ(one.columns.size(), 1u);
  EXPECT_TRUE(all.columns[1].result.detected) << all.columns[1].result.headline;
  expect_same_diagnosis(all.columns[1].result, one.columns[0].result);
}

TEST(GapStudy, SimulatesOneReferenceForTheColumnsThatShareABaselineAndLength) {
  io::SignalSet three = signal_set({0, 1, 2});
  GapStudyOptions o = options();
  o.gap.references = gap::make_reference_cache();
  const GapStudy all = study_gap(three, o);
  // One full-length reference and one time-window reference (gap_windows.cc), not three each.
  EXPECT_EQ(gap::cached_references(*o.gap.references), 2u);
  // Another seed is another draw: kept beside the first.
  o.gap.seed = 6;
  study_gap(three, o);
  EXPECT_EQ(gap::cached_references(*o.gap.references), 4u);
}

TEST(GapReferenceCache, GivesEachDiagnosisTheReferenceItWouldDrawWithoutIt) {
  io::SignalSet set = signal_set({0, 1});
  GapStudyOptions shared = options();
  shared.gap.references = gap::make_reference_cache();
  const GapStudy with = study_gap(set, shared);
  for (std::size_t k = 0; k < set.signals.size(); ++k) {
    io::SignalSet own = signal_set({static_cast<int>(k)});
    const GapStudy without = study_gap(own, options());  // a fresh cache: its own draw
    expect_same_diagnosis(with.columns[k].result, without.columns[0].result);
  }
}

}  // namespace
}  // namespace gmwm::pipeline
