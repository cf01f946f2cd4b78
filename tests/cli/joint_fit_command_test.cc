// `gmwm fit INPUT --joint FILE[:COLUMN] ...`: one joint (multi-signal) model per axis from
// replicates of a sensor, end to end, and its bad-input paths (exit 2, one line naming the
// replicate, nothing written).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/report/html_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::flowed;
using gmwm::test::run_gmwm;

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  return cells;
}

constexpr const char* kTruth = "AR1(phi=0.99,sigma2=1e-4)+WN(sigma2=1e-2)+RW(gamma2=1e-8)";

class GmwmCliJointFit : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_joint");
    // Three recordings of a two-axis sensor, 2^12, 2^13 and 2^14 samples at 100 Hz.
    for (int k = 1; k <= 3; ++k) simulate("r" + std::to_string(k) + ".csv", 1 << (11 + k), "100", k);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void simulate(const std::string& file, int n, const std::string& freq, int seed, const std::string& names = "gx,gy") {
    const auto r = run_gmwm({"simulate", "--model", kTruth, "--n", std::to_string(n), "--freq", freq, "--signals",
                             std::to_string(std::count(names.begin(), names.end(), ',') + 1), "--names", names,
                             "--seed", std::to_string(seed), "-o", file, "--quiet"},
                            dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  gmwm::test::CliRun fit(std::vector<std::string> extra) {
    std::vector<std::string> args = {"fit", "r1.csv", "--model", "AR1+WN+RW", "--json", "out.json", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_gmwm(args, dir_);
  }
  fs::path json() const { return dir_ / "out.json"; }
  fs::path dir_;
};

TEST_F(GmwmCliJointFit, ThreeFilesGiveOneJointModelPerAxisWithEveryReplicateBesideIt) {
  const auto r = fit({"--joint", "r2.csv", "r3.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = gmwm::test::read_json(json());
  EXPECT_TRUE(doc["joint"].get<bool>());
  ASSERT_EQ(doc["columns"].size(), 2u);
  for (const auto& col : doc["columns"]) {
    ASSERT_EQ(col["replicates"].size(), 3u);
    EXPECT_EQ(col["replicates"][0]["source"], "r1.csv:" + col["name"].get<std::string>());
    EXPECT_EQ(col["replicates"][2]["n"], 1 << 14);
    EXPECT_EQ(col["status"], "converged");
    EXPECT_EQ(col["parameters"].size(), 4u);
    EXPECT_EQ(col["agmwm"].size(), 4u);
    // df = (12 + 13 + 14) levels - 4 parameters.
    EXPECT_EQ(col["gof"]["df"].get<double>(), 35.0);
    double shares = 0.0;
    for (const auto& rep : col["replicates"]) shares += rep["objective_share"].get<double>();
    EXPECT_NEAR(shares / col["objective"].get<double>(), 1.0, 1e-9);
  }
}

TEST_F(GmwmCliJointFit, FileColonColumnAddsOneColumnAsAReplicateOfTheSelectedOne) {
  const auto r = fit({"--columns", "gx", "--joint", "r1.csv:gy", "r2.csv:gx"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = gmwm::test::read_json(json());
  ASSERT_EQ(doc["columns"].size(), 1u);
  const auto& reps = doc["columns"][0]["replicates"];
  ASSERT_EQ(reps.size(), 3u);
  EXPECT_EQ(reps[1]["source"], "r1.csv:gy");
  EXPECT_EQ(reps[2]["source"], "r2.csv:gx");
}

TEST_F(GmwmCliJointFit, RejectsAReplicateWithoutOneOfTheInputsColumns) {
  simulate("one_axis.csv", 1 << 12, "100", 9, "gx");
  expect_bad_input(fit({"--joint", "one_axis.csv"}), {"one_axis.csv", "gy"}, json());
}

TEST_F(GmwmCliJointFit, RejectsAReplicateTooShortForTheModelsLevels) {
  simulate("short.csv", 8, "100", 9);
  expect_bad_input(fit({"--joint", "short.csv"}), {"short.csv"}, json());
}

TEST_F(GmwmCliJointFit, RejectsARecordingGivenTwice) {
  expect_bad_input(fit({"--joint", "r2.csv", "r1.csv"}), {"r1.csv", "given twice"}, json());
}

TEST_F(GmwmCliJointFit, RejectsAColumnEntryWhenSeveralInputColumnsAreSelected) {
  expect_bad_input(fit({"--joint", "r2.csv:gx"}), {"r2.csv:gx", "--columns"}, json());
}

TEST_F(GmwmCliJointFit, RejectsAReplicateAtAnotherRate) {
  simulate("fast.csv", 1 << 12, "200", 9);
  expect_bad_input(fit({"--joint", "fast.csv"}), {"fast.csv", "200 Hz", "100 Hz"}, json());
}

TEST_F(GmwmCliJointFit, NeverWritesOverAReplicateNamedWithItsColumn) {
  const std::string before = gmwm::test::read_text(dir_ / "r2.csv");
  const auto r = run_gmwm(
      {"fit", "r1.csv", "--columns", "gx", "--joint", "r2.csv:gx", "--model", "WN+RW", "--json", "r2.csv"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("r2.csv"), std::string::npos) << r.err;
  EXPECT_EQ(gmwm::test::read_text(dir_ / "r2.csv"), before);
}

TEST_F(GmwmCliJointFit, SelectRanksEverySubModelByItsWvicCrossValidatedOverTheReplicates) {
  const auto r = run_gmwm({"select", "r1.csv", "--columns", "gx", "--joint", "r2.csv", "r3.csv", "--model", "AR1+WN+RW",
                           "--optimism", "replicates", "--json", "out.json", "--quiet"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = gmwm::test::read_json(json());
  ASSERT_EQ(doc["columns"].size(), 1u);
  const auto& col = doc["columns"][0];
  EXPECT_EQ(col["training"].size(), 3u);
  ASSERT_EQ(col["ranking"].size(), 7u);
  EXPECT_EQ(col["ranking"][0]["rank"], 1);
  EXPECT_TRUE(col["ranking"][0]["equivalent"].get<bool>());
  EXPECT_EQ(col["ranking"][0]["split_loss"].size(), 3u);
  EXPECT_FALSE(col["recommended"].get<std::string>().empty());
}

TEST_F(GmwmCliJointFit, ARobustJointFitResistsSpikesInEveryReplicate) {
  // One spike of 5 (50 white-noise sd) every 100 samples of each recording's gx.
  for (const char* file : {"r1.csv", "r2.csv", "r3.csv"}) {
    std::istringstream in(gmwm::test::read_text(dir_ / file));
    std::ostringstream out;
    std::string line;
    std::getline(in, line);
    out << line << '\n';
    const auto header = split(line);
    const std::size_t gx = static_cast<std::size_t>(std::find(header.begin(), header.end(), "gx") - header.begin());
    ASSERT_LT(gx, header.size());
    for (int i = 0; std::getline(in, line); ++i) {
      auto cells = split(line);
      if (i % 100 == 0) cells[gx] = std::to_string(std::stod(cells[gx]) + 5.0);
      for (std::size_t c = 0; c < cells.size(); ++c) out << (c ? "," : "") << cells[c];
      out << '\n';
    }
    gmwm::test::write_text(dir_ / file, out.str());
  }
  const auto wn = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"--columns", "gx", "--joint", "r2.csv", "r3.csv"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = fit(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto doc = gmwm::test::read_json(json());
    EXPECT_EQ(doc["estimator"], extra.empty() ? "classical" : "robust");
    for (const auto& p : doc["columns"][0]["parameters"])
      if (p["process"] == "WN") return p["value"].get<double>();
    return -1.0;
  };
  const double classical = wn({}), robust = wn({"--robust"});
  // The spikes add 25 / 100 = 0.25 to the variance: the classical joint WN is pulled far
  // above the truth 1e-2; the robust one stays within 20% of it.
  EXPECT_GT(classical, 3e-2);
  EXPECT_NEAR(robust, 1e-2, 2e-3);
}

TEST_F(GmwmCliJointFit, SelectWithOptimismAllGivesTheThreeWvicsSideBySide) {
  const auto r = run_gmwm({"select", "r1.csv", "--columns", "gx", "--joint", "r2.csv", "r3.csv", "--model", "WN+RW",
                           "--optimism", "all", "--replicates", "20", "--json", "out.json"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find("bootstrap WVIC"), std::string::npos) << r.out;
  EXPECT_NE(flowed(r.out).find("smallest bootstrap WVIC"), std::string::npos) << r.out;
  const auto doc = gmwm::test::read_json(json());
  EXPECT_EQ(doc["optimism"], "all");
  const auto& col = doc["columns"][0];
  EXPECT_TRUE(col["chosen_bootstrap"].is_string());
  ASSERT_EQ(col["ranking"].size(), 3u);
  for (const auto& row : col["ranking"]) {
    EXPECT_TRUE(row["cv_wvic"].is_number()) << row.dump();
    EXPECT_TRUE(row["analytic_wvic"].is_number()) << row.dump();
    EXPECT_TRUE(row["bootstrap_wvic"].is_number()) << row.dump();
    EXPECT_TRUE(row["rank_bootstrap"].is_number()) << row.dump();
  }
}

TEST_F(GmwmCliJointFit, RejectsTheBootstrapOptimismAloneWithReplicates) {
  const auto r = run_gmwm({"select", "r1.csv", "--columns", "gx", "--joint", "r2.csv", "--model", "WN+RW", "--optimism",
                           "bootstrap", "--json", "out.json"},
                          dir_);
  expect_bad_input(r, {"--joint with --optimism bootstrap", "--optimism all"}, json());
}

TEST_F(GmwmCliJointFit, FitAndSelectWriteAReportOfTheReplicates) {
  if (!gmwm::report::vega_missing_reason().empty()) GTEST_SKIP() << gmwm::report::vega_missing_reason();
  auto r = fit({"--joint", "r2.csv", "r3.csv", "--columns", "gx", "--report", "fit.html"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string html = gmwm::test::read_text(dir_ / "fit.html");
  EXPECT_NE(html.find("joint fit over the replicates"), std::string::npos);
  EXPECT_NE(html.find("r3.csv:gx"), std::string::npos);
  EXPECT_NE(html.find("shared theta?"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "fit.html.svg"));
  r = run_gmwm({"select", "r1.csv", "--columns", "gx", "--joint", "r2.csv", "r3.csv", "--model", "WN+RW", "--report",
                "select.html", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  html = gmwm::test::read_text(dir_ / "select.html");
  EXPECT_NE(html.find("model selection over the replicates"), std::string::npos);
  EXPECT_NE(html.find("recommended model, fitted jointly over the replicates"), std::string::npos);
}

TEST_F(GmwmCliJointFit, RejectsTheReplicateOptimismWithoutReplicates) {
  const auto r =
      run_gmwm({"select", "r1.csv", "--model", "WN+RW", "--optimism", "replicates", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"--optimism replicates", "--joint"}, json());
}

// Issue 25: a joint result said nothing of its unit, and export took it as SI (a deg/s
// fit written as rad/s/sqrt(Hz), 57x too large).
TEST_F(GmwmCliJointFit, UnitsGiveTheJointModelItsUnitAndNoiseFiguresAndExportConvertsThemToSi) {
  for (int k = 1; k <= 3; ++k)
    simulate("g" + std::to_string(k) + ".csv", 1 << (11 + k), "100", 10 + k, "gyro_x,gyro_y");
  auto r = run_gmwm({"fit", "g1.csv", "--joint", "g2.csv", "g3.csv", "--model", "AR1+WN+RW", "--units", "gyro=deg/s",
                     "--json", "out.json", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = gmwm::test::read_json(json());
  ASSERT_EQ(doc["columns"].size(), 2u);
  const auto& col = doc["columns"][0];
  EXPECT_EQ(col["unit"], "deg/s");
  ASSERT_TRUE(col["noise_figures"].is_object()) << col.dump();
  const double n_deg = col["noise_figures"]["white"]["value"].get<double>();
  EXPECT_GT(n_deg, 0.0);
  EXPECT_EQ(col["noise_figures"]["white"]["unit"], "deg/s/sqrt(Hz)");
  EXPECT_FALSE(col["continuous"].empty());
  EXPECT_FALSE(col["kalman"]["terms"].empty());

  r = run_gmwm({"export", "out.json", "--format", "kalibr", "--output", "imu.yaml", "--partial", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = gmwm::test::read_text(dir_ / "imu.yaml");
  const auto at = yaml.find("gyroscope_noise_density:");
  ASSERT_NE(at, std::string::npos) << yaml;
  // The mean over the two axes, in rad/s/sqrt(Hz).
  const double n_deg_y = doc["columns"][1]["noise_figures"]["white"]["value"].get<double>();
  const double written = std::stod(yaml.substr(at + 24));
  EXPECT_NEAR(written, 0.5 * (n_deg + n_deg_y) * 3.14159265358979323846 / 180.0, 1e-6 * written) << yaml;
}

TEST_F(GmwmCliJointFit, SelectGivesTheRecommendedModelFittedJointlyWithItsUnitForExport) {
  for (int k = 1; k <= 3; ++k) simulate("g" + std::to_string(k) + ".csv", 1 << (11 + k), "100", 10 + k, "gyro_x");
  auto r = run_gmwm({"select", "g1.csv", "--joint", "g2.csv", "g3.csv", "--model", "AR1+WN+RW", "--units", "gyro=deg/s",
                     "--json", "out.json"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find("recommended, fitted jointly: "), std::string::npos) << r.out;
  EXPECT_NE(flowed(r.out).find("deg/s/sqrt(Hz)"), std::string::npos) << r.out;
  const auto doc = gmwm::test::read_json(json());
  const auto& col = doc["columns"][0];
  EXPECT_EQ(col["unit"], "deg/s");
  ASSERT_TRUE(col["best_model"].is_string()) << col.dump();
  EXPECT_EQ(col["best_fit"]["model"], col["recommended"]);
  EXPECT_TRUE(col["noise_figures"].is_object());
  r = run_gmwm({"export", "out.json", "--format", "kalibr", "--output", "imu.yaml", "--partial", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(gmwm::test::read_text(dir_ / "imu.yaml").find("deg/s"), std::string::npos);
}

TEST_F(GmwmCliJointFit, ExportRefusesAJointResultWhoseUnitItCannotTell) {
  for (int k = 1; k <= 2; ++k) simulate("g" + std::to_string(k) + ".csv", 1 << 12, "100", 10 + k, "gyro_x");
  auto r = run_gmwm({"fit", "g1.csv", "--joint", "g2.csv", "--model", "WN+RW", "--json", "out.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(gmwm::test::read_json(json())["columns"][0]["unit"].is_null());
  r = run_gmwm({"export", "out.json", "--format", "kalibr", "--output", "imu.yaml"}, dir_);
  expect_bad_input(r, {"out.json", "column 'gyro_x'", "does not say the data's unit", "--units gyro="},
                   dir_ / "imu.yaml");
  // Told the unit, it converts.
  r = run_gmwm({"export", "out.json", "--format", "kalibr", "--units", "gyro=deg/s", "--output", "imu.yaml",
                "--partial", "--quiet"},
               dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(GmwmCliJointFit, RejectsBadUnitsBeforeAnyWork) {
  expect_bad_input(fit({"--joint", "r2.csv", "--units", "gyro=furlong/s"}), {"--units", "furlong/s"}, json());
}

}  // namespace

namespace {

// The progress bars of the joint commands (issue 26, item 6): drawn on a terminal (run
// under script(1), which gives the command a pseudo-terminal), absent off one and with
// --quiet.
class GmwmCliJointProgress : public GmwmCliJointFit {
 protected:
  // stdout and stderr of `gmwm ARGS` run on a pseudo-terminal, or "" when script(1) is missing.
  std::string on_terminal(const std::vector<std::string>& args) {
    if (std::system("command -v script > /dev/null 2>&1") != 0) return {};
    std::string cmd = std::string("'") + gmwm::test::gmwm_cli_path() + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    const fs::path log = dir_ / "tty.log";
    const std::string shell =
        "cd '" + dir_.string() + "' && script -qec \"" + cmd + "\" /dev/null > '" + log.string() + "' 2>&1";
    EXPECT_EQ(std::system(shell.c_str()), 0) << shell;
    return gmwm::test::read_text(log);
  }
};

TEST_F(GmwmCliJointProgress, FitAndSelectJointShowProgressOnATerminalAndNotOffOne) {
  const std::vector<std::string> fit_args = {"fit",    "r1.csv", "--model",      "AR1+WN+RW", "--joint",
                                             "r2.csv", "r3.csv", "--replicates", "20"};
  const std::vector<std::string> select_args = {"select", "r1.csv", "--model", "WN+RW", "--joint", "r2.csv", "r3.csv"};
  const std::string fit_tty = on_terminal(fit_args);
  if (fit_tty.empty()) GTEST_SKIP() << "script(1) (bsdutils) is not installed: no pseudo-terminal to test on";
  EXPECT_NE(fit_tty.find("fit --joint: bootstrap draws"), std::string::npos) << fit_tty;
  EXPECT_NE(on_terminal(select_args).find("select --joint: selections"), std::string::npos);
  // Off a terminal (the captured stderr of run_gmwm), and --quiet: no bar.
  auto r = run_gmwm(fit_args, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("bootstrap draws"), std::string::npos) << r.err;
  r = run_gmwm(select_args, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("selections"), std::string::npos) << r.err;
  std::vector<std::string> quiet = fit_args;
  quiet.push_back("--quiet");
  EXPECT_EQ(on_terminal(quiet).find("bootstrap draws"), std::string::npos);
}

TEST_F(GmwmCliJointProgress, GapShowsProgressOnATerminalAndNotOffOneOrWithQuiet) {
  const std::vector<std::string> gap_args = {"gap", "r3.csv", "--model", "WN(sigma2=1e-4)", "--replicates", "40"};
  const std::string tty = on_terminal(gap_args);
  if (tty.empty()) GTEST_SKIP() << "script(1) (bsdutils) is not installed: no pseudo-terminal to test on";
  EXPECT_NE(tty.find("gap: columns x steps"), std::string::npos) << tty;
  const auto r = run_gmwm(gap_args, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("columns x steps"), std::string::npos) << r.err;
  std::vector<std::string> quiet = gap_args;
  quiet.push_back("--quiet");
  EXPECT_EQ(on_terminal(quiet).find("columns x steps"), std::string::npos);
}

}  // namespace
