// `gmwm nav` and `gmwm export --consistent-for` end to end: a fitted six-axis IMU as the
// truth, its filters' verdicts, the terminal's width, the report, the consistent export,
// and bad input (exit 2, one line naming what was wrong, nothing written).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::lines_of;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

class GmwmNav : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(gmwm::test::temp_dir("cli_nav"));
    // Six axes of AR1 + WN + RW at 100 Hz (a Gauss-Markov bias of T = 10 s, sd 7e-4),
    // fitted as such: the truth of every test here.
    auto r = run_gmwm({"simulate", "--model", "AR1(phi=0.999,sigma2=1e-9)+WN(sigma2=1e-6)+RW(gamma2=1e-12)", "--n",
                       "65536", "--freq", "100", "--signals", "6", "--names",
                       "gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z", "--output", "imu.csv", "--quiet"},
                      *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_gmwm({"fit", "imu.csv", "--model", "AR1+WN+RW", "--units", "gyro=rad/s,accel=m/s^2", "--json", "fit.json",
                  "--quiet"},
                 *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* GmwmNav::dir_ = nullptr;

TEST_F(GmwmNav, GivesOneLinePerFilterModelWithTheTruthConsistentAndNoLineWiderThan100Columns) {
  const auto r = run_gmwm({"nav", "--truth", "fit.json", "--outage", "300:360", "--json", "nav.json"}, *dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& line : lines_of(r.out)) EXPECT_LE(line.size(), 100u) << line;
  const json doc = read_json(*dir_ / "nav.json");
  ASSERT_EQ(doc.at("filters").size(), 2u);  // the default: truth and its WN + RW
  EXPECT_EQ(doc.at("filters")[0].at("label"), "truth");
  EXPECT_EQ(doc.at("filters")[0].at("verdict"), "consistent");
  EXPECT_EQ(doc.at("filters")[1].at("label"), "wnrw");
  // Where the outage ends: the last output before 360 s (the simulated file's rate is
  // estimated from its time column, 100 Hz to 1e-12).
  EXPECT_NEAR(doc.at("filters")[0].at("summary").at("time").get<double>(), 359.0, 1e-6);
  const json& curves = doc.at("filters")[0].at("curves");
  EXPECT_EQ(curves.at("time").size(), 601u);
  EXPECT_EQ(curves.at("nees").size(), 601u);
  EXPECT_NE(r.out.find("truth "), std::string::npos);
  EXPECT_NE(r.out.find("wnrw "), std::string::npos);
}

TEST_F(GmwmNav, TakesModelStringsAtARateAndWritesAReportWithFourPlots) {
  const auto r = run_gmwm({"nav", "--truth", "fit.json", "--filter", "truth", "--filter",
                           "gyro=WN(sigma2=1e-6)+RW(gamma2=1e-12);accel=WN(sigma2=1e-6)+RW(gamma2=1e-12)", "--filter",
                           "wnrw*2", "--rate", "100", "--horizon", "120", "--report", "nav.html", "--quiet"},
                          *dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(*dir_ / "nav.html");
  for (const char* kind : {"nav-position", "nav-velocity", "nav-attitude", "nav-nees"})
    EXPECT_NE(html.find(std::string("data-plot=\"") + kind + "\""), std::string::npos) << kind;
  EXPECT_NE(html.find("wnrw*2"), std::string::npos);
}

TEST_F(GmwmNav, PrintsALabelsControlBytesEscapedOnOneLine) {
  const auto r = run_gmwm(
      {"nav", "--truth", "fit.json", "--filter", "truth", "--label", "evil\nname\x1b[31m", "--horizon", "20"}, *dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  EXPECT_NE(r.out.find("evil name\\x1B[31m"), std::string::npos) << r.out;
}

TEST_F(GmwmNav, RefusesBadSourcesAndScenariosInOneLineWritingNothing) {
  const fs::path out = *dir_ / "bad.json";
  expect_bad_input(run_gmwm({"nav", "--truth", "fit.json", "--filter", "wnrw*0", "--json", "bad.json"}, *dir_),
                   {"wnrw*0", "positive number"}, out);
  expect_bad_input(run_gmwm({"nav", "--truth", "fit.json", "--outage", "360:300", "--json", "bad.json"}, *dir_),
                   {"--outage", "START:END"}, out);
  expect_bad_input(run_gmwm({"nav", "--truth", "truth", "--json", "bad.json"}, *dir_), {"truth", "give a file"}, out);
  expect_bad_input(run_gmwm({"nav", "--truth", "missing.json", "--json", "bad.json"}, *dir_), {"missing.json"}, out);
  expect_bad_input(run_gmwm({"nav", "--truth", "fit.json", "--trajectory", "maneuver", "--json", "bad.json"}, *dir_),
                   {"--trajectory", "manoeuvre"}, out);
  expect_bad_input(
      run_gmwm({"nav", "--truth", "fit.json", "--filter", "gyro=WN;accel=WN", "--json", "bad.json"}, *dir_),
      {"gyro=WN", "give every parameter's value"}, out);
  expect_bad_input(run_gmwm({"nav", "--truth", "gyro=WN(sigma2=1e-6)", "--json", "bad.json"}, *dir_),
                   {"give both sensors"}, out);
  // A model with more states than the analysis takes (FLICKER 14 + 32 AR1/GM per axis).
  const std::string big = "16*AR1(phi=0.5,sigma2=1e-6)+16*GM(beta=1,sigma2_gm=1e-6)+FLICKER(B2=1e-8)";
  expect_bad_input(
      run_gmwm({"nav", "--truth", "gyro=" + big + ";accel=" + big, "--rate", "100", "--json", "bad.json"}, *dir_),
      {"states, more than 240"}, out);
  // An output that is one of the model files is refused, the file untouched.
  const std::string before = gmwm::test::read_text(*dir_ / "fit.json");
  const auto same = run_gmwm({"nav", "--truth", "fit.json", "--json", "fit.json"}, *dir_);
  EXPECT_EQ(same.exit_code, 2) << same.err;
  EXPECT_NE(same.err.find("fit.json"), std::string::npos) << same.err;
  EXPECT_EQ(gmwm::test::read_text(*dir_ / "fit.json"), before);
  const auto report = run_gmwm({"nav", "--truth", "fit.json", "--filter", "imu.csv*2", "--report", "imu.csv"}, *dir_);
  EXPECT_EQ(report.exit_code, 2) << report.err;
}

TEST(GmwmNavNumbers, GivesAHugeGyroNoiseTheFixLimitedErrorItMakesAndRefusesErrorsBeyondADouble) {
  // Issue 42 item 9: a gyroscope white noise of sigma2 = 1e25 printed 0 m and
  // "pessimistic". Once the gyro's noise dwarfs a 1 m fix (the position's process noise
  // between fixes >= 1e12 m^2 here), the horizontal errors are the fixes' own and the
  // vertical the accelerometer's: the answer is the same as at sigma2 = 1e15 to the share
  // R / P < 1e-12 of the fix the prior still carries.
  const fs::path dir = gmwm::test::temp_dir("cli_nav_numbers");
  auto position = [&](const std::string& sigma2) {
    const auto r = run_gmwm({"nav", "--truth", "gyro=WN(sigma2=" + sigma2 + ")+RW(gamma2=1e-14);accel=WN(sigma2=1e-6)",
                             "--rate", "100", "--json", "n.json", "--quiet"},
                            dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const json doc = read_json(dir / "n.json");
    EXPECT_EQ(doc.at("filters")[0].at("verdict"), "consistent");
    return doc.at("filters")[0].at("curves").at("position_rms").back().get<double>();
  };
  const double moderate = position("1e15"), huge = position("1e25");
  EXPECT_GT(huge, 1.0);  // two horizontal axes at ~1 m each
  EXPECT_NEAR(huge, moderate, 1e-6 * moderate);
  // Free inertial, the position's variance passes 1.8e308 m^2 at 72 s: refused, not '-'.
  expect_bad_input(run_gmwm({"nav", "--truth", "gyro=WN(sigma2=1e300);accel=WN(sigma2=1e-6)", "--rate", "100",
                             "--fix-rate", "0", "--json", "bad.json"},
                            dir),
                   {"truth", "overflow a double", "t = 72 s", "horizon"}, dir / "bad.json");
  fs::remove_all(dir);
}

TEST_F(GmwmNav, ExportsTheSmallestInflationThatKeepsAWnRwFilterFromBeingOptimistic) {
  const auto r = run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "imu.yaml", "--consistent-for",
                           "20,60", "--json", "export.json"},
                          *dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = read_json(*dir_ / "export.json").at("consistent_for");
  // This truth's Gauss-Markov bias (T = 10 s) lies where a WN + RW filter cannot follow it:
  // no inflation makes it consistent (docs/nav.md), the smallest non-optimistic one leaves
  // it conservative, and the header says what it lacks.
  EXPECT_EQ(c.at("verdict"), "pessimistic");
  const double k = c.at("walk_factor").get<double>();
  EXPECT_GE(k, 1.0);
  // The factor is the smallest to 1%: the next smaller one is optimistic by the same verdict
  // (unless no inflation is needed at all).
  if (k > 1.0) EXPECT_EQ(c.at("smaller_factor_verdict"), "optimistic");
  // One verdict everywhere: the terminal's, the JSON's and the header's are the same word.
  EXPECT_NE(r.out.find("(" + c.at("verdict").get<std::string>() + ")"), std::string::npos) << r.out;
  EXPECT_NE(c.at("reason").get<std::string>().find("(" + c.at("verdict").get<std::string>() + ")"), std::string::npos);
  const std::string yaml = read_text(*dir_ / "imu.yaml");
  EXPECT_NE(yaml.find("the smallest factor"), std::string::npos);
  EXPECT_NE(yaml.find("what it lacks: AR1 (T "), std::string::npos);
  // The written filter, run through `gmwm nav` on the export's own setting, is not optimistic.
  const auto n =
      run_gmwm({"nav", "--truth", "fit.json", "--filter", "imu.yaml", "--fix-rate", "20", "--fix-sigma", "0.05",
                "--horizon", "720", "--outage", "600:660", "--judge-from", "540", "--json", "check.json", "--quiet"},
               *dir_);
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_NE(read_json(*dir_ / "check.json").at("filters")[0].at("verdict"), "optimistic");
}

TEST_F(GmwmNav, ConsistentForRefusesInflateASimulatorFormatAndAGyroOnlySource) {
  const fs::path out = *dir_ / "bad.json";
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "x.yaml", "--consistent-for",
                             "20,60", "--inflate", "2", "--json", "bad.json"},
                            *dir_),
                   {"--consistent-for", "--inflate"}, out);
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "gz-sdf", "--output", "x.sdf", "--consistent-for",
                             "20,60", "--json", "bad.json"},
                            *dir_),
                   {"--consistent-for", "gz-sdf"}, out);
  expect_bad_input(run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "x.yaml", "--consistent-for", "20",
                             "--json", "bad.json"},
                            *dir_),
                   {"--consistent-for", "RATE,HORIZON"}, out);
  EXPECT_FALSE(fs::exists(*dir_ / "x.yaml"));
}

}  // namespace
