// The stability study (pipeline/stability_study.h): its progress counts every step it does,
// and a progress that throws stops it (the web app's and Python's cancellation).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/pipeline/stability_study.h"

namespace gmwm::pipeline {
namespace {

io::SignalSet three_columns(std::size_t n) {
  io::SignalSet set;
  set.path = "<array>";
  set.freq = 10.0;
  set.freq_known = true;
  std::mt19937_64 rng(25);
  std::normal_distribution<double> normal;
  for (const char* name : {"a", "b", "c"}) {
    std::vector<double> y(n);
    for (double& v : y) v = normal(rng);
    set.signals.push_back({name, Samples(std::move(y)), ""});
  }
  return set;
}

TEST(StabilityStudy, TellsItsProgressAfterEachFactorAndEachKindsIntervalsUpToTheTotal) {
  const io::SignalSet set = three_columns(4096);
  StabilityStudyOptions o;
  o.kinds = {stability::DeviationKind::kOadev, stability::DeviationKind::kMdev};
  o.three_cornered_hat = true;
  std::vector<std::pair<int, int>> told;
  o.progress = [&](int done, int total) { told.emplace_back(done, total); };
  const StabilityStudy study = study_stability(set, o);
  // 4097 phase points: OADEV's octaves 1 .. 2048 (12), MDEV's 1 .. 1024 (11), each kind's
  // intervals one step more: 25 steps a column, three columns and the hat's three pairs.
  const int total = 6 * (12 + 1 + 11 + 1);
  ASSERT_EQ(told.size(), static_cast<std::size_t>(total));
  for (std::size_t i = 0; i < told.size(); ++i) {
    EXPECT_EQ(told[i].first, static_cast<int>(i) + 1);
    EXPECT_EQ(told[i].second, total);
  }
  EXPECT_EQ(study.columns.size(), 3u);
}

TEST(StabilityStudy, StopsWithTheExceptionItsProgressThrows) {
  const io::SignalSet set = three_columns(1 << 17);
  StabilityStudyOptions o;
  o.kinds = {stability::DeviationKind::kOadev, stability::DeviationKind::kTotdev};
  int told = 0;
  o.progress = [&](int done, int) {
    told = done;
    if (done == 3) throw Cancelled();
  };
  EXPECT_THROW(study_stability(set, o), Cancelled);
  EXPECT_LE(told, 4) << "the factors running beside the third finish at most";
}

}  // namespace
}  // namespace gmwm::pipeline
