// Records whose timestamps show missing samples (issue 47, item 1) on the command line: each
// scale reads the complete windows (the WV, the Allan deviation, fit and select), the terminal
// and the JSON say how many windows each scale lost, --gaps join keeps the samples end to end,
// a gap of unknown length is refused, the robust WV reads the windows without a gap, the joint
// fit reads each replicate through its own gaps, and a study without a complete-window form
// refuses the record instead of joining it silently.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/robust/robust_wv.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::flowed;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr int kN = 1 << 14;
constexpr double kFreq = 100.0;

class GapsCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("gaps_cli");
    const gmwm::Model m = gmwm::parse_model("WN(sigma2=1)+RW(gamma2=1e-4)", gmwm::ProcessContext{kFreq, true});
    full_ = gmwm::simulate(m, m.given_values(), kN, 4711);
    // 3 gaps: 40 samples at 1000, 1 at 5000, 300 at 9000.
    for (int k = 1000; k < 1040; ++k) dropped_.insert(k);
    dropped_.insert(5000);
    for (int k = 9000; k < 9300; ++k) dropped_.insert(k);
    std::string csv = "time [s],gyro_x\n";
    for (int k = 0; k < kN; ++k) {
      if (dropped_.count(k)) continue;
      csv += std::to_string(k / kFreq) + "," + std::to_string(full_[static_cast<std::size_t>(k)]) + "\n";
      observed_.push_back(std::stod(std::to_string(full_[static_cast<std::size_t>(k)])));
    }
    gmwm::test::write_text(dir_ / "gappy.csv", csv);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::vector<double> full_, observed_;
  std::set<int> dropped_;
};

TEST_F(GapsCommand, TheWvReadsTheCompleteWindowsAndTheTerminalSaysWhatEachScaleLost) {
  const auto r = run_gmwm({"wv", "gappy.csv", "--json", "wv.json", "--adev"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.err).find("341 of the record's 16384 samples missing in 3 gaps (the largest 300 samples); each "
                               "scale reads the windows that hold no missing sample, or those missing at most a tenth "
                               "of each half (the Allan deviation from 10 samples a half, the WV where complete "
                               "windows are scarce)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("N = 16043 observed of 16384 (341 missing in 3 gaps)"), std::string::npos) << r.out;
  // Gaps that leave no window of half the record say how the long scales are read.
  EXPECT_NE(flowed(r.err).find("the longest stretch between gaps holds 7084 samples (70.84 s) of the record's 16384: "
                               "the longer scales are read from the windows whose halves each miss at most a tenth of "
                               "their samples"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("partial"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lost"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("partial: those of them missing some samples"), std::string::npos) << r.out;
  EXPECT_NE(
      flowed(r.out).find("complete: the windows of 2m samples without a missing sample; partial: those read that miss "
                         "some"),
      std::string::npos)
      << r.out;
  // The library's gappy WV, level by level, and the windows lost (level 1: 41 + 2 + 301).
  const std::vector<gmwm::MissingRun> runs = {{1000, 40}, {5000, 1}, {9000, 300}};
  gmwm::WaveletVariance want = gmwm::classical_wv_with_gaps(observed_, runs);
  gmwm::drop_incomplete_levels(want);
  const json doc = read_json(dir_ / "wv.json");
  EXPECT_EQ(doc.at("timing").at("missing_samples"), 341);
  EXPECT_EQ(doc.at("timing").at("gap_handling"), "windows");
  EXPECT_EQ(doc.at("timing").at("gaps_read_as_missing"), true);
  const json& levels = doc.at("columns").at(0).at("levels");
  ASSERT_EQ(levels.size(), static_cast<std::size_t>(want.levels()));
  for (std::size_t k = 0; k < levels.size(); ++k) {
    EXPECT_NEAR(levels[k].at("wv").get<double>(), want.wv[k], 1e-12 * want.wv[k]) << "level " << k + 1;
    EXPECT_EQ(levels[k].at("coefficients").get<std::int64_t>(), want.coefficients[k]);
    EXPECT_EQ(levels[k].at("partial").get<std::int64_t>(), want.partial[k]) << "level " << k + 1;
  }
  // The deepest level has no window of its width between the 300-sample gap and the ends
  // (7084 samples at most): it reads windows missing samples, and says how many.
  ASSERT_GT(want.partial.back(), 0);
  EXPECT_EQ(levels[0].at("note"), "16039 of 16383 windows of 2 samples complete (344 hold a missing sample)");
  // The Allan deviation is the gap-resistant one.
  const json& allan = doc.at("columns").at(0).at("allan");
  ASSERT_TRUE(allan.is_object());
  // Each point's windows: those holding no missing sample and those read missing some, as
  // the library counts them.
  const gmwm::AllanDeviation adev = gmwm::allan_deviation_with_gaps(observed_, runs, kFreq);
  ASSERT_EQ(allan.at("complete").size(), adev.size());
  for (std::size_t k = 0; k < adev.size(); ++k) {
    EXPECT_EQ(allan.at("complete")[k].get<std::int64_t>(), adev.complete[k]) << "point " << k;
    EXPECT_EQ(allan.at("partial")[k].get<std::int64_t>(), adev.partial[k]) << "point " << k;
  }
  EXPECT_GT(adev.partial.back(), 0) << "the longest windows are read missing some samples";
}

TEST_F(GapsCommand, GapsJoinKeepsTheSamplesEndToEndAndSaysSo) {
  const auto r = run_gmwm({"wv", "gappy.csv", "--json", "wv.json", "--gaps", "join"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.err).find("3 gap(s) in its timestamps (largest 3.01 s), joined end to end (--gaps join)"),
            std::string::npos)
      << r.err;
  const json doc = read_json(dir_ / "wv.json");
  EXPECT_EQ(doc.at("timing").at("gap_handling"), "join");
  EXPECT_EQ(doc.at("timing").at("gaps_read_as_missing"), false);
  EXPECT_EQ(doc.at("columns").at(0).at("levels").at(0).at("coefficients"), 16042);  // N - 1 of the joined
}

TEST_F(GapsCommand, FitAndSelectReadTheGapsAndRecoverTheWhiteNoise) {
  json levels[2];
  int i = 0;
  for (const char* command : {"fit", "select"}) {
    const auto r = run_gmwm({command, "gappy.csv", "--model", "WN+RW", "--json", "out.json", "--quiet"}, dir_);
    ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
    const json doc = read_json(dir_ / "out.json");
    EXPECT_EQ(doc.at("timing").at("gaps_read_as_missing"), true) << command;
    levels[i++] = doc.at("columns").at(0).at("levels");
    if (std::string(command) == "fit") {
      // WN sigma2 = 1 inside its 95% interval (16043 samples: a relative sd of about 1.2%).
      const json& p = doc.at("columns").at(0).at("parameters").at(0);
      EXPECT_EQ(p.at("process"), "WN");
      EXPECT_LE(p.at("ci_low").get<double>(), 1.0);
      EXPECT_GE(p.at("ci_high").get<double>(), 1.0);
    }
  }
  // Both read the same gap-resistant WV: every level of floor(log2 16384) = 14, though the
  // longest stretch between gaps holds 7084 samples (levels 13 and 14 from the windows whose
  // halves each miss at most a tenth of their samples, as their notes say).
  EXPECT_EQ(levels[0], levels[1]);
  ASSERT_EQ(levels[0].size(), 14u);
  for (const std::size_t j : {12u, 13u})
    EXPECT_NE(levels[0].at(j).at("note").get<std::string>().find("each miss at most"), std::string::npos)
        << levels[0].at(j).dump();
}

TEST_F(GapsCommand, AGapOfUnknownLengthIsRefusedWithItsStampsAndNothingWritten) {
  std::string csv = "time [s],gyro_x\n";
  for (int k = 0; k < 4000; ++k) {
    const double t = k / kFreq + (k >= 2000 ? 0.015 : 0.0);  // a step of 2.5 periods before sample 2000
    csv += std::to_string(t) + "," + std::to_string(full_[static_cast<std::size_t>(k)]) + "\n";
  }
  gmwm::test::write_text(dir_ / "odd.csv", csv);
  const auto r = run_gmwm({"fit", "odd.csv", "--model", "WN", "--json", "out.json"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("odd.csv: timestamps 'time [s]': a gap of unknown length before sample 2000: from 19.99 s to "
                       "20.015 s after the first stamp, a step of 25 ms = 2.5 periods of 10 ms"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  EXPECT_EQ(run_gmwm({"fit", "odd.csv", "--model", "WN", "--gaps", "join", "--quiet"}, dir_).exit_code, 0);
}

TEST_F(GapsCommand, TheRobustWvReadsTheWindowsWithoutAGapAndTheRobustFitFitsIt) {
  const auto r = run_gmwm({"wv", "gappy.csv", "--robust", "--json", "wv.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json column = read_json(dir_ / "wv.json")["columns"][0];
  EXPECT_EQ(column["estimator"], "huber");
  const std::vector<gmwm::MissingRun> runs = {{1000, 40}, {5000, 1}, {9000, 300}};
  gmwm::WaveletVariance w = gmwm::robust::robust_wv_with_gaps(observed_, runs);
  gmwm::drop_incomplete_levels(w);
  const json& levels = column["levels"];
  ASSERT_EQ(levels.size(), static_cast<std::size_t>(w.levels()));
  for (int j = 0; j < w.levels(); ++j) {
    const auto i = static_cast<std::size_t>(j);
    EXPECT_NEAR(levels[i]["wv"].get<double>(), w.wv[i], 1e-9 * w.wv[i]) << "level " << j + 1;
    EXPECT_EQ(levels[i]["coefficients"].get<std::int64_t>(), w.coefficients[i]) << "level " << j + 1;
  }
  // The fit, weighted by the model's covariance and by bootstrap draws read through the same gaps.
  for (const char* omega : {"model", "bootstrap"}) {
    const auto fit = run_gmwm({"fit", "gappy.csv", "--robust", "--model", "WN+RW", "--omega", omega, "--replicates",
                               "20", "--json", "fit.json"},
                              dir_);
    ASSERT_EQ(fit.exit_code, 0) << fit.err;
    const json c = read_json(dir_ / "fit.json")["columns"][0];
    EXPECT_EQ(c["estimator"], "huber") << omega;
    EXPECT_EQ(c["levels"].size(), static_cast<std::size_t>(w.levels())) << omega;
  }
}

TEST_F(GapsCommand, GapDiagnosisReadsTheWindowsWithoutAGapAndSaysWhatItLeftOut) {
  // Against the truth: no gap; against white noise alone: an excess at the long scales (the
  // walk; which effect explains it over one short record, a drift, a slow tone or the walk,
  // is the attribution's business). Both compared with replicates read through the gaps.
  const auto truth = run_gmwm({"gap", "gappy.csv", "--model", "WN(sigma2=1)+RW(gamma2=1e-4)", "--replicates", "60",
                               "--json", "truth.json", "--quiet"},
                              dir_);
  ASSERT_EQ(truth.exit_code, 0) << truth.err;
  const json t = read_json(dir_ / "truth.json")["columns"][0];
  EXPECT_FALSE(t["gap"]["detected"].get<bool>()) << t["headline"];
  EXPECT_NE(t["notes"].dump().find("the record misses 341 samples in 3 gaps: the WV and its reference read the "
                                   "windows without a gap"),
            std::string::npos)
      << t["notes"].dump();
  const auto wn = run_gmwm(
      {"gap", "gappy.csv", "--model", "WN(sigma2=1)", "--replicates", "60", "--json", "wn.json", "--quiet"}, dir_);
  ASSERT_EQ(wn.exit_code, 0) << wn.err;
  const json w = read_json(dir_ / "wn.json")["columns"][0];
  EXPECT_TRUE(w["gap"]["detected"].get<bool>()) << w["headline"];
  ASSERT_FALSE(w["gap"]["bands"].empty()) << w["headline"];
  EXPECT_EQ(w["gap"]["bands"][0]["direction"], "excess") << w["headline"];
  EXPECT_GE(w["gap"]["bands"][0]["tau_to"].get<double>(), 1024.0) << "the walk shows at the long scales";
}

TEST_F(GapsCommand, AStudyThatSimulatesAGridFarLongerThanTheRecordRefusesItNamingTheLongestGap) {
  // 2000 samples, 100 000 missing (a stamp 1000 s later), 2000 more: the grid is 26 times
  // the observed samples. The WV and a fit weighted by the model read the windows; the gap
  // diagnosis and a bootstrap Omega, which simulate the whole grid, refuse it.
  std::string csv = "time [s],gyro_x\n";
  for (int k = 0; k < 4000; ++k) {
    const int at = k < 2000 ? k : k + 100000;
    csv += std::to_string(at / kFreq) + "," + std::to_string(full_[static_cast<std::size_t>(k)]) + "\n";
  }
  gmwm::test::write_text(dir_ / "far.csv", csv);
  EXPECT_EQ(run_gmwm({"fit", "far.csv", "--model", "WN+RW", "--quiet"}, dir_).exit_code, 0);
  const std::string why =
      " simulates the record's whole grid of 104000 samples, 26 times its 4000 observed ones (at most 4): cut the "
      "record at its longest gap (100000 samples missing from grid sample 2000), or give --gaps join to join the "
      "samples end to end";
  for (const auto& [args, what] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"gap", "far.csv", "--model", "WN(sigma2=1)", "--json", "out.json"}, "gap diagnosis"},
           {{"fit", "far.csv", "--model", "WN+RW", "--omega", "bootstrap", "--json", "out.json"},
            "--omega bootstrap"}}) {
    const auto r = run_gmwm(args, dir_);
    EXPECT_EQ(r.exit_code, 2) << what;
    EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("far.csv: " + what + why), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  }
}

TEST_F(GapsCommand, TheJointFitReadsEachReplicateThroughItsOwnGapsAndSaysWhatEachMisses) {
  // A second unit with other gaps (205 samples in 2): each replicate's WV reads its own
  // complete windows, its own fit is the one `fit` gives on its file alone, and the
  // shared-theta test's draws are read through each replicate's gaps.
  const gmwm::Model m = gmwm::parse_model("WN(sigma2=1)+RW(gamma2=1e-4)", gmwm::ProcessContext{kFreq, true});
  const std::vector<double> other = gmwm::simulate(m, m.given_values(), kN, 4712);
  std::string csv = "time [s],gyro_x\n";
  for (int k = 0; k < kN; ++k)
    if (!(k >= 3000 && k < 3200) && !(k >= 12000 && k < 12005))
      csv += std::to_string(k / kFreq) + "," + std::to_string(other[static_cast<std::size_t>(k)]) + "\n";
  gmwm::test::write_text(dir_ / "gappy2.csv", csv);
  const auto r = run_gmwm(
      {"fit", "gappy.csv", "--model", "WN+RW", "--joint", "gappy2.csv", "--replicates", "19", "--json", "joint.json"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find("gappy.csv:gyro_x, N = 16043 (+341 missing in 3 gaps: each scale reads the windows "
                               "without one)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(flowed(r.out).find("gappy2.csv:gyro_x, N = 16179 (+205 missing in 2 gaps"), std::string::npos) << r.out;
  const json joint = read_json(dir_ / "joint.json");
  const json& reps = joint["columns"][0]["replicates"];
  ASSERT_EQ(reps.size(), 2u);
  EXPECT_EQ(reps[0]["missing_samples"], 341);
  EXPECT_EQ(reps[0]["gaps"], 3);
  EXPECT_EQ(reps[1]["missing_samples"], 205);
  EXPECT_EQ(reps[1]["gaps"], 2);
  EXPECT_EQ(joint["columns"][0]["replicate_test"]["draws"], 19);
  for (const auto& [file, k] : std::vector<std::pair<std::string, int>>{{"gappy.csv", 0}, {"gappy2.csv", 1}}) {
    ASSERT_EQ(run_gmwm({"fit", file, "--model", "WN+RW", "--json", "one.json", "--quiet"}, dir_).exit_code, 0);
    const json one = read_json(dir_ / "one.json")["columns"][0]["parameters"];
    const json& own = reps[static_cast<std::size_t>(k)]["fit"]["parameters"];
    ASSERT_EQ(own.size(), one.size());
    for (std::size_t i = 0; i < one.size(); ++i)
      EXPECT_NEAR(own[i]["value"].get<double>() / one[i]["value"].get<double>(), 1.0, 1e-6) << file << " " << i;
  }
  // The selection over replicates with the joint fit's bootstrap WVIC draws them alike.
  const auto sel = run_gmwm({"select", "gappy.csv", "--model", "WN+RW", "--joint", "gappy2.csv", "--optimism", "all",
                             "--json", "select.json", "--quiet"},
                            dir_);
  ASSERT_EQ(sel.exit_code, 0) << sel.err;
  EXPECT_TRUE(read_json(dir_ / "select.json")["columns"][0].contains("recommended"));
}

TEST_F(GapsCommand, AStudyWithoutACompleteWindowFormRefusesTheRecordNamingGapsJoin) {
  const auto r =
      run_gmwm({"gap", "gappy.csv", "--model", "WN(sigma2=1)", "--temperature", "temp", "--json", "out.json"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("gappy.csv: 341 samples missing in 3 gaps of the timestamps 'time [s]'; --temperature "
                       "reads a regular record: give --gaps join to join the samples end to end"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  const auto bad = run_gmwm({"wv", "gappy.csv", "--gaps", "fill"}, dir_);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("expected 'windows' (each scale from the windows without a missing sample) or 'join'"),
            std::string::npos)
      << bad.err;
}

}  // namespace
