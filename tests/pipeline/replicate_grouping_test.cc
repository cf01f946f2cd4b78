// The replicate grouping (pipeline::group_replicates): what `fit --joint` and `select
// --joint` and Python's fit_joint / select_joint hand to the joint studies.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/pipeline/replicate_study.h"

namespace gmwm::pipeline {
namespace {

io::SignalSet recording(const std::string& path, std::vector<std::string> names, double freq, double offset) {
  io::SignalSet set;
  set.path = path;
  set.freq = freq;
  set.freq_known = true;
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::vector<double> x(64);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = offset + static_cast<double>(k * 1000 + i);
    set.signals.push_back({names[k], std::move(x), ""});
  }
  return set;
}

std::string refusal(const io::SignalSet& primary, std::vector<ReplicateRecording> rest) {
  try {
    group_replicates(primary, "INPUT", std::move(rest));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GroupReplicates, PutsEachRecordingsColumnUnderTheAxisOfTheSameName) {
  const io::SignalSet a = recording("a.csv", {"gx", "gy"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back({"--joint b.csv", recording("b.csv", {"gx", "gy"}, 100.0, 0.5), false});
  rest.push_back({"--joint c.csv", recording("c.csv", {"gx", "gy"}, 100.0, 0.25), false});
  const std::vector<ReplicateGroup> g = group_replicates(a, "INPUT", std::move(rest));
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[1].axis, "gy");
  EXPECT_EQ(g[1].sources, (std::vector<std::string>{"a.csv:gy", "b.csv:gy", "c.csv:gy"}));
  ASSERT_EQ(g[1].series.size(), 3u);
  EXPECT_EQ(g[1].series[1][0], 1000.5);  // b's second column, not its first
}

TEST(GroupReplicates, TakesOneColumnAsAReplicateOfTheSingleAxis) {
  const io::SignalSet a = recording("a.csv", {"gx"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back({"--joint b.csv:other", recording("b.csv", {"other"}, 100.0, 0.5), true});
  const std::vector<ReplicateGroup> g = group_replicates(a, "INPUT", std::move(rest));
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].sources, (std::vector<std::string>{"a.csv:gx", "b.csv:other"}));
}

TEST(GroupReplicates, RefusesARateThatDiffersNamingTheRecordingAndBothRates) {
  const io::SignalSet a = recording("a.csv", {"gx"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back({"--joint b.csv", recording("b.csv", {"gx"}, 200.0, 0.5), false});
  EXPECT_EQ(refusal(a, std::move(rest)),
            "--joint b.csv: sampled at 200 Hz, INPUT at 100 Hz; replicates must share the rate");
}

TEST(GroupReplicates, AcceptsRatesThatDifferInTheirLastDigits) {
  const io::SignalSet a = recording("a.csv", {"gx"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back(
      {"--joint b.csv", recording("b.csv", {"gx"}, 100.0 * (1.0 + kReplicateRateTolerance / 2), 0.5), false});
  EXPECT_EQ(refusal(a, std::move(rest)), "");
}

TEST(GroupReplicates, RefusesARecordingGivenTwiceNamingBothSources) {
  const io::SignalSet a = recording("a.csv", {"gx"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back({"--joint copy.csv", recording("copy.csv", {"gx"}, 100.0, 0.0), false});
  EXPECT_EQ(refusal(a, std::move(rest)),
            "--joint copy.csv: copy.csv:gx is the same recording as a.csv:gx (a replicate given twice)");
}

TEST(GroupReplicates, RefusesAColumnCountThatDiffersFromThePrimarys) {
  const io::SignalSet a = recording("a.csv", {"gx", "gy"}, 100.0, 0.0);
  std::vector<ReplicateRecording> rest;
  rest.push_back({"replicates[1]", recording("replicates[1]", {"gx"}, 100.0, 0.5), false});
  EXPECT_EQ(refusal(a, std::move(rest)), "replicates[1]: has 1 columns, expected 2 (those of INPUT)");
  std::vector<ReplicateRecording> one;
  one.push_back({"--joint b.csv:gx", recording("b.csv", {"gx"}, 100.0, 0.5), true});
  EXPECT_EQ(refusal(a, std::move(one)),
            "--joint b.csv:gx: one column, a replicate of one column, but INPUT has 2 columns");
}

// A replicate whose samples are held (read so: io::find_repeated_samples) keeps that reading
// in its group, and its robust WV goes without the spike screen (the copies' zero steps
// deflate the scale the screen measures spikes against), said in its screening note; the
// other replicate keeps the screen.
TEST(GroupReplicates, AHeldReplicatesRobustWvGoesWithoutTheSpikeScreenAndSaysWhy) {
  const Model m = parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-10)");
  const std::int64_t n = 1 << 13;
  const std::vector<double> measured = simulate(m, m.given_values(), n / 2, 31, 0);
  std::vector<double> held(static_cast<std::size_t>(n));
  for (std::int64_t t = 0; t < n; ++t) held[static_cast<std::size_t>(t)] = measured[static_cast<std::size_t>(t / 2)];
  io::SignalSet a, b;
  for (io::SignalSet* s : {&a, &b}) {
    s->freq = 100.0;
    s->freq_known = true;
  }
  a.path = "a.csv";
  b.path = "b.csv";
  a.signals.push_back({"gx", simulate(m, m.given_values(), n, 32, 0), ""});
  b.signals.push_back({"gx", std::move(held), ""});
  io::find_repeated_samples(a);
  io::find_repeated_samples(b);
  ASSERT_TRUE(b.signals[0].repeated.held());
  std::vector<ReplicateRecording> rest;
  rest.push_back({"--joint b.csv", std::move(b), false});
  const std::vector<ReplicateGroup> groups = group_replicates(a, "a.csv", std::move(rest));
  ASSERT_EQ(groups.front().repeated.size(), 2u);
  EXPECT_FALSE(groups.front().repeated[0].held());
  EXPECT_TRUE(groups.front().repeated[1].held());
  const std::vector<WaveletVariance> wvs = replicate_wvs(groups.front(), m, {}, robust::RobustWvOptions{});
  ASSERT_EQ(wvs.size(), 2u);
  EXPECT_EQ(wvs[0].screening.rfind("spike screen: ", 0), 0u) << wvs[0].screening;
  EXPECT_EQ(wvs[1].screening.rfind("spike screen off: 50% of the samples copy the one before (held)", 0), 0u)
      << wvs[1].screening;
  EXPECT_TRUE(wvs[1].replaced.empty());
}

}  // namespace
}  // namespace gmwm::pipeline
