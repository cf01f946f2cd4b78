// The error policy end to end (docs/design.md section 3): every bad input or option gives exit code 2,
// ONE line on stderr naming the input, the place (line/column where it applies) and what
// was expected, and no output file.

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/io/signal_writer.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::run_gmwm;
using gmwm::test::write_text;

namespace {

class GmwmCliBadInput : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_bad"); }
  void TearDown() override { fs::remove_all(dir_); }

  /// `gmwm wv FILE --freq 100 --json out.json` on a file with `content`.
  gmwm::test::CliRun wv_on(const std::string& file, const std::string& content) {
    write_text(dir_ / file, content);
    return run_gmwm({"wv", file, "--freq", "100", "--json", "out.json"}, dir_);
  }
  /// `gmwm fit noise.csv --freq 100 --model SPEC --json out.json`.
  gmwm::test::CliRun fit_with_model(const std::string& spec) {
    gmwm::test::write_noise_csv(dir_ / "noise.csv", 256);
    return run_gmwm({"fit", "noise.csv", "--freq", "100", "--model", spec, "--json", "out.json"}, dir_);
  }
  fs::path json() const { return dir_ / "out.json"; }

  fs::path dir_;
};

std::string rows(int n, const std::string& header = "a,b") {
  std::string s = header + "\n";
  for (int i = 0; i < n; ++i) s += std::to_string(0.5 * i * i - 3.0 * i) + "," + std::to_string(i % 7) + "\n";
  return s;
}

}  // namespace

TEST_F(GmwmCliBadInput, RejectsAMissingFileWithExitCode2AndNoOutput) {
  auto r = run_gmwm({"wv", "missing.csv", "--freq", "100", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"missing.csv", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnEmptyFileWithExitCode2AndNoOutput) {
  expect_bad_input(wv_on("empty.csv", ""), {"empty.csv", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAHeaderOnlyFileWithExitCode2AndNoOutput) {
  expect_bad_input(wv_on("header.csv", "a,b\n"), {"header.csv:1", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsANonNumericCellNamingLineAndColumn) {
  std::string content = rows(40);
  content += "1,oops\n";
  expect_bad_input(wv_on("text.csv", content), {"text.csv:42:2", "oops", "expected a number"}, json());
}

TEST_F(GmwmCliBadInput, RejectsANaNCellNamingLineAndColumn) {
  std::string content = rows(20);
  content += "nan,1\n";
  expect_bad_input(wv_on("nan.csv", content), {"nan.csv:22:1", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnInfiniteCellNamingLineAndColumn) {
  std::string content = rows(20);
  content += "3,-inf\n";
  expect_bad_input(wv_on("inf.csv", content), {"inf.csv:22:2", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsARaggedRowWithExitCode2AndNoOutput) {
  std::string content = rows(30);
  content += "7\n";
  content += rows(5, "").substr(1);
  expect_bad_input(wv_on("ragged.csv", content), {"ragged.csv:32", "expected 2"}, json());
}

TEST_F(GmwmCliBadInput, RejectsFewerThan16SamplesWithExitCode2AndNoOutput) {
  expect_bad_input(wv_on("short.csv", rows(15)), {"short.csv", "16"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAConstantColumnWithExitCode2AndNoOutput) {
  std::string content = "a,b\n";
  for (int i = 0; i < 64; ++i) content += "2.5," + std::to_string(i % 5) + "\n";
  expect_bad_input(wv_on("constant.csv", content), {"constant.csv", "'a'", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsATruncatedGzipStreamWithExitCode2AndNoOutput) {
  std::vector<gmwm::io::Signal> signals(1);
  signals[0].name = "x";
  std::mt19937_64 rng(7);
  std::normal_distribution<double> z;
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) x.push_back(z(rng));
  signals[0].values = std::move(x);
  gmwm::io::write_signals((dir_ / "cut.csv.gz").string(), signals, std::nullopt);
  fs::resize_file(dir_ / "cut.csv.gz", fs::file_size(dir_ / "cut.csv.gz") / 2);
  auto r = run_gmwm({"wv", "cut.csv.gz", "--freq", "100", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"cut.csv.gz", "gzip", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAMissingFreqWhenThereIsNoTimestampColumn) {
  gmwm::test::write_noise_csv(dir_ / "notime.csv", 64);
  auto r = run_gmwm({"wv", "notime.csv", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"notime.csv", "--freq"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnUnknownColumnName) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 64);
  auto r = run_gmwm({"wv", "noise.csv", "--freq", "100", "--columns", "zz", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"noise.csv", "zz", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnUnknownProcessInTheModelNamingTheColumn) {
  expect_bad_input(fit_with_model("AR1+XYZ"), {"AR1+XYZ", "XYZ", "column 5"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnUnknownParameterNameInTheModel) {
  // The message names the model, the bad name and the parameters the process has.
  expect_bad_input(fit_with_model("AR1(rho=0.5)+WN"), {"AR1(rho=0.5)+WN", "rho", "phi"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAMalformedModelStringNamingTheColumn) {
  expect_bad_input(fit_with_model("AR1++WN"), {"AR1++WN", "column 5", "expected"}, json());
  expect_bad_input(fit_with_model("AR1+WN("), {"AR1+WN(", "column", "expected"}, json());
}

TEST_F(GmwmCliBadInput, RejectsANegativeVarianceGivenAsAStartingValue) {
  expect_bad_input(fit_with_model("AR1+WN(sigma2=-1)"), {"WN(sigma2=-1)", "sigma2", "positive"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAModelWithMoreParametersThanLevels) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 256);
  auto r = run_gmwm(
      {"fit", "noise.csv", "--freq", "100", "--levels", "3", "--model", "AR1+WN+RW", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"AR1+WN+RW", "levels"}, json());
}

TEST_F(GmwmCliBadInput, RejectsBadRobustOptionsWithOneLine) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 64);
  struct Case {
    std::vector<std::string> opts;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {{"--robust", "--eff", "0"}, {"--eff: found 0, expected", "between 0 and 1"}},
      {{"--robust", "--eff", "1"}, {"--eff: found 1, expected", "between 0 and 1"}},
      {{"--robust", "--eff", "1.5"}, {"--eff: found 1.5, expected", "between 0 and 1"}},
      {{"--robust", "--estimator", "tukey"}, {"--estimator: found 'tukey', expected huber or bisquare"}},
      {{"--eff", "0.6"}, {"--eff 0.6", "only meaningful with --robust"}},
      {{"--estimator", "huber"}, {"--estimator huber", "only meaningful with --robust"}},
      {{"--no-spike-screen"}, {"--no-spike-screen", "only meaningful with --robust"}},
  };
  for (const auto& c : cases)
    for (const char* cmd : {"wv", "fit"}) {
      std::vector<std::string> args = {cmd, "noise.csv", "--freq", "100", "--json", "out.json"};
      if (std::string(cmd) == "fit") args.insert(args.end(), {"--model", "WN"});
      args.insert(args.end(), c.opts.begin(), c.opts.end());
      std::string trace = cmd;
      for (const auto& o : c.opts) trace += " " + o;
      SCOPED_TRACE(trace);
      expect_bad_input(run_gmwm(args, dir_), c.expect, json());
    }
}

TEST_F(GmwmCliBadInput, RejectsBadOptionValuesWithOneLine) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 64);
  expect_bad_input(run_gmwm({"wv", "noise.csv", "--freq", "-5", "--json", "out.json"}, dir_), {"--freq"}, json());
  expect_bad_input(run_gmwm({"wv", "noise.csv", "--freq", "100", "--alpha", "1.5", "--json", "out.json"}, dir_),
                   {"--alpha"}, json());
  expect_bad_input(run_gmwm({"wv", "noise.csv", "--freq", "100", "--threads", "0", "--json", "out.json"}, dir_),
                   {"--threads"}, json());
  expect_bad_input(run_gmwm({"wv", "noise.csv", "--freq", "100", "--no-such-option", "--json", "out.json"}, dir_),
                   {"--no-such-option"}, json());
  expect_bad_input(run_gmwm({"fit", "noise.csv", "--freq", "100", "--json", "out.json"}, dir_), {"--model"}, json());
  expect_bad_input(
      run_gmwm({"fit", "noise.csv", "--freq", "100", "--model", "WN", "--omega", "weird", "--json", "out.json"}, dir_),
      {"--omega"}, json());
}

TEST_F(GmwmCliBadInput, RejectsAnOutputPathInAMissingFolderBeforeAnyWork) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 64);
  auto r = run_gmwm({"wv", "noise.csv", "--freq", "100", "--json", "out.json", "--csv", "nowhere/wv.csv"}, dir_);
  expect_bad_input(r, {"nowhere", "--csv"}, json());
}

TEST_F(GmwmCliBadInput, RejectsASimulationModelWithoutEveryValue) {
  auto r = run_gmwm(
      {"simulate", "--model", "AR1(phi=0.9)+WN(sigma2=1)", "--n", "100", "--output", "sim.csv", "--json", "out.json"},
      dir_);
  expect_bad_input(r, {"AR1(phi=0.9)+WN(sigma2=1)", "sigma2", "expected"}, json());
  EXPECT_FALSE(fs::exists(dir_ / "sim.csv"));
}

TEST_F(GmwmCliBadInput, RejectsAMissingCommandWithExitCode2) {
  auto r = run_gmwm({}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
}
