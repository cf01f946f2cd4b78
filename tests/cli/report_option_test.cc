// `--report PATH` on wv, fit, select and gap without a browser: a bad path fails before
// any work (exit 2, one line, nothing written), and a good one gives PATH and PATH.svg
// once everything else succeeded. The rendering is checked in html_report_browser_test.cc.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/report/html_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;

namespace {

class ReportOption : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_report"); }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string example() { return std::string(GMWM_SOURCE_DIR) + "/data/example_imu6.csv.gz"; }
  // The four commands, each on one column, quick.
  static std::vector<std::vector<std::string>> commands() {
    return {{"wv", example(), "--columns", "gyro_x"},
            {"fit", example(), "--columns", "gyro_x", "--model", "AR1+WN"},
            {"select", example(), "--columns", "gyro_x", "--model", "AR1+WN"},
            {"gap", example(), "--columns", "gyro_x", "--fit", "WN+RW", "--replicates", "40"}};
  }
  fs::path dir_;
};

TEST_F(ReportOption, FailsEarlyWithOneLineWhenTheReportsFolderIsMissing) {
  for (auto args : commands()) {
    args.insert(args.end(), {"--json", "out.json", "--report", "no_such_folder/r.html"});
    const auto r = run_gmwm(args, dir_);
    SCOPED_TRACE(args[0]);
    expect_bad_input(r, {"--report", "no_such_folder"}, dir_ / "out.json");
    EXPECT_FALSE(fs::exists(dir_ / "no_such_folder"));
  }
}

TEST_F(ReportOption, RefusesStandardOutputAsTheReportsPath) {
  const auto r = run_gmwm({"wv", example(), "--report", "-", "--json", "out.json"}, dir_);
  expect_bad_input(r, {"--report", "expected a file path"}, dir_ / "out.json");
}

TEST_F(ReportOption, WritesTheReportAndItsSvgForEveryCommand) {
  if (const std::string why = gmwm::report::vega_missing_reason(); !why.empty()) {
    const char* req = std::getenv("GMWM_REQUIRE_BROWSER");
    if (req && std::string(req) == "1") FAIL() << "Vega is required (CI): " << why;
    GTEST_SKIP() << "Vega (Debian libjs-vega) not available: " << why;
  }
  for (auto args : commands()) {
    const std::string name = args[0] + ".html";
    args.insert(args.end(), {"--report", name, "--quiet"});
    const auto r = run_gmwm(args, dir_);
    SCOPED_TRACE(args[0]);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string html = read_text(dir_ / name);
    EXPECT_NE(html.find("<h2>gyro_x</h2>"), std::string::npos);
    EXPECT_NE(html.find("data-plot=\"wv\""), std::string::npos);
    EXPECT_EQ(read_text(dir_ / (name + ".svg")).rfind("<svg", 0), 0u);
    if (args[0] == "gap") {
      EXPECT_NE(html.find("data-plot=\"gap-levels\""), std::string::npos);
    }
    if (args[0] == "select") {
      EXPECT_NE(html.find("<tr class=\"chosen\">"), std::string::npos);
    }
    if (args[0] == "fit") {
      EXPECT_NE(html.find("<table class=\"continuous\">"), std::string::npos);
    }
  }
}

}  // namespace
