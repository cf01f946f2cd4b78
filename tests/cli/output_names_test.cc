// Column names from a file reach every output of the program as text of that output, never
// as its syntax (issue 25): the terminal table (no escape sequence), the CSV (quoted, and
// no formula), the JSON (the name itself, read back with a JSON parser) and the HTML
// report (escaped text). The export formats are checked in tests/io/export_hostile_names_test.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "gmwm/report/html_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;

namespace {

// An escape sequence that clears the screen and sets the window title, a C1 CSI, and a
// spreadsheet formula.
const std::string kEscapeName =
    "gyro\x1b[2J\x1b]0;pwned\x07\xC2\x9B"
    "31mx";
const std::string kFormulaName = "=HYPERLINK(\"http://evil\";\"click\")+0";
const std::string kMarkupName = "</script><script>alert(1)</script>";

class GmwmOutputNames : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_names");
    // The header's quotes are the CSV's own: the names are the text between them.
    std::string csv = "time,\"" + kEscapeName + "\",\"" +
                      std::string("=HYPERLINK(\"\"http://evil\"\";\"\"click\"\")+0") + "\",\"" + kMarkupName + "\"\n";
    for (int i = 0; i < 4096; ++i)
      csv += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i * 0.37)) + "," +
             std::to_string(std::cos(i * 0.1)) + "," + std::to_string(std::sin(i * 0.05) + (i % 3) * 0.01) + "\n";
    gmwm::test::write_text(dir_ / "names.csv", csv);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

bool has_control_bytes(const std::string& text) {
  for (unsigned char c : text)
    if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7F) return true;
  return text.find("\xC2\x9B") != std::string::npos;
}

TEST_F(GmwmOutputNames, TheTerminalShowsEscapesAsTextAndTheJsonKeepsTheNames) {
  const auto r = run_gmwm({"wv", "names.csv", "--json", "wv.json", "--csv", "wv.csv"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(has_control_bytes(r.out)) << r.out;
  EXPECT_FALSE(has_control_bytes(r.err)) << r.err;
  EXPECT_NE(r.out.find("gyro\\x1B[2J\\x1B]0;pwned\\x07\\xC2\\x9B31mx"), std::string::npos) << r.out;
  const auto doc = gmwm::test::read_json(dir_ / "wv.json");
  ASSERT_EQ(doc["columns"].size(), 3u);
  EXPECT_EQ(doc["columns"][0]["name"], kEscapeName);
  EXPECT_EQ(doc["columns"][1]["name"], kFormulaName);
  EXPECT_EQ(doc["columns"][2]["name"], kMarkupName);
}

TEST_F(GmwmOutputNames, TheCsvQuotesEveryNameAndDisarmsFormulas) {
  const auto r = run_gmwm({"wv", "names.csv", "--csv", "wv.csv", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(dir_ / "wv.csv");
  // The formula's cell is text to a spreadsheet: quoted, with a leading '.
  EXPECT_NE(csv.find("\n\"'=HYPERLINK(\"\"http://evil\"\";\"\"click\"\")+0\",1,"), std::string::npos)
      << csv.substr(0, 600);
  // No line starts with a formula character.
  for (std::size_t p = csv.find('\n'); p != std::string::npos && p + 1 < csv.size(); p = csv.find('\n', p + 1))
    EXPECT_EQ(std::string("=+-@").find(csv[p + 1]), std::string::npos) << csv.substr(p + 1, 80);
}

TEST_F(GmwmOutputNames, TheReportHoldsTheNamesAsEscapedText) {
  if (!gmwm::report::vega_missing_reason().empty()) GTEST_SKIP() << gmwm::report::vega_missing_reason();
  const auto r = run_gmwm({"wv", "names.csv", "--report", "r.html", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(dir_ / "r.html");
  EXPECT_EQ(html.find(kMarkupName), std::string::npos) << "the name's markup reached the page as markup";
  EXPECT_NE(html.find("&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_EQ(html.find("\x1b"), std::string::npos);
}

}  // namespace
