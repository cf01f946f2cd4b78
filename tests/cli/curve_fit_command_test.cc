// gmwm fit --curve (issue 48, item 5): a model fitted to a given Allan deviation curve on the
// command line, the document in fit's shape with its "curve", the terminal summary, and the
// refusals (exit 2, one line naming the file, line and column or the option, nothing written).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

// The acceptance bar's record (pipeline's CurveStudy): AR1 of 2 s, white noise and a random
// walk at 100 Hz.
constexpr const char* kTruth = "AR1(phi=0.995,sigma2=3e-4)+WN(sigma2=1)+RW(gamma2=1e-7)";

class CurveFitCommand : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("curve_fit_cli"); }
  void TearDown() override { fs::remove_all(dir_); }

  // A record of the truth (2^17 samples, seed 48) and its Allan deviation as gmwm writes it.
  void write_record_and_its_curve() {
    const auto sim = run_gmwm({"simulate", "--model", kTruth, "--n", "131072", "--freq", "100", "--names", "gyro_x",
                               "--seed", "48", "--output", "rec.csv"},
                              dir_);
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto wv = run_gmwm({"wv", "rec.csv", "--adev", "--adev-csv", "adev.csv", "-q"}, dir_);
    ASSERT_EQ(wv.exit_code, 0) << wv.err;
  }

  // The run's exit code 2, its one line holding `why`, nothing written.
  void expect_refused(const std::vector<std::string>& args, const std::string& why) {
    std::vector<std::string> with_json = args;
    with_json.insert(with_json.end(), {"--json", "out.json"});
    const auto r = run_gmwm(with_json, dir_);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("gmwm: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  }

  fs::path dir_;
};

TEST_F(CurveFitCommand, RecoversTheRecordsOwnFitFromTheAllanDeviationCsvWritten) {
  // The bar end to end: each parameter of the curve's fit within the record fit's 95%
  // interval widened 1.5 times about its estimate.
  write_record_and_its_curve();
  ASSERT_EQ(run_gmwm({"fit", "rec.csv", "--model", "WN+RW+AR1", "--json", "raw.json", "-q"}, dir_).exit_code, 0);
  const auto r = run_gmwm({"fit", "--curve", "adev.csv", "--model", "WN+RW+AR1", "--json", "curve.json", "-q"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // edf given: no warning
  const json raw = read_json(dir_ / "raw.json")["columns"][0]["parameters"];
  const json curve = read_json(dir_ / "curve.json")["columns"][0]["parameters"];
  ASSERT_EQ(raw.size(), curve.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const double v = raw[k]["value"], lo = raw[k]["ci_low"], hi = raw[k]["ci_high"];
    const double c = curve[k]["value"];
    EXPECT_EQ(curve[k]["name"], raw[k]["name"]);
    EXPECT_GE(c, v - 1.5 * (v - lo)) << raw[k]["process"] << " " << raw[k]["name"];
    EXPECT_LE(c, v + 1.5 * (hi - v)) << raw[k]["process"] << " " << raw[k]["name"];
  }
}

TEST_F(CurveFitCommand, WritesFitsDocumentWithTheCurveAndItsTerminalSummary) {
  write_record_and_its_curve();
  const auto r = run_gmwm({"fit", "--curve", "adev.csv", "--model", "WN+RW+AR1", "--units", "rad/s", "--exclude-taus",
                           ":0.015", "--json", "out.json"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "out.json");
  EXPECT_EQ(doc["command"], "fit");
  EXPECT_EQ(doc["input"], "adev.csv");
  EXPECT_EQ(doc["model_spec"], "WN+RW+AR1");
  const json& c = doc["columns"][0];
  EXPECT_EQ(c["name"], "gyro_x");
  EXPECT_EQ(c["freq"], 100.0);
  EXPECT_EQ(c["estimator"], "curve");
  EXPECT_EQ(c["unit"], "rad/s");
  EXPECT_TRUE(c["gof"]["p_value"].is_null());
  EXPECT_EQ(c["quality"]["rejected"], false);
  EXPECT_EQ(c["curve"]["value"], "adev");
  EXPECT_EQ(c["curve"]["weights"], "edf");
  EXPECT_EQ(c["curve"]["rate"], "curve");
  EXPECT_EQ(c["curve"]["excluded"], ":0.015");
  EXPECT_EQ(c["curve"]["fitted"][0], false);  // 0.01 s left out
  EXPECT_EQ(c["curve"]["fitted"][1], true);
  EXPECT_EQ(c["implied_wv"].size(), c["levels"].size());
  EXPECT_EQ(c["levels"][0]["tau"], 2.0);  // the Haar scale of an averaging time of one sample
  EXPECT_EQ(c["allan"]["tau"].size() + 1, c["curve"]["tau"].size());
  EXPECT_GT(c["noise_figures"]["white"]["value"].get<double>(), 0.0);
  EXPECT_NE(r.out.find("gyro_x: AR1+WN+RW; no goodness-of-fit test"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("N white noise"), std::string::npos) << r.out;
  const auto v = run_gmwm({"fit", "--curve", "adev.csv", "--model", "WN+RW+AR1", "-v"}, dir_);
  EXPECT_NE(gmwm::test::flowed(v.out).find("a curve of " + std::to_string(c["curve"]["tau"].size()) +
                                           " points (adev, adev.csv); 100 Hz (its finest tau one sample), weights "
                                           "from edf, Omega model"),
            std::string::npos)
      << v.out;
}

TEST_F(CurveFitCommand, FitsEveryCurveOfAFileAndColumnsPicksThem) {
  gmwm::test::write_text(dir_ / "two.csv",
                         "column,tau_seconds,avar\n"
                         "a,0.01,2\na,0.02,1\na,0.04,0.5\na,0.08,0.25\n"
                         "b,0.01,8\nb,0.02,4\nb,0.04,2\nb,0.08,1\n");
  const auto all = run_gmwm({"fit", "--curve", "two.csv", "--model", "WN", "--json", "all.json", "-q"}, dir_);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const json doc = read_json(dir_ / "all.json");
  ASSERT_EQ(doc["columns"].size(), 2u);
  // AVAR(m) = sigma2 / m for white noise, m = 1 at the finest tau: sigma2 = 2 and 8.
  EXPECT_NEAR(doc["columns"][0]["parameters"][0]["value"].get<double>(), 2.0, 1e-6);
  EXPECT_NEAR(doc["columns"][1]["parameters"][0]["value"].get<double>(), 8.0, 1e-6);
  // No interval, edf or record: weighed as the shortest record, and the warning says so.
  EXPECT_EQ(doc["columns"][0]["curve"]["weights"], "shortest-record");
  EXPECT_NE(all.err.find("gmwm: warning: two.csv: curve 'a': no interval, edf or record length"), std::string::npos)
      << all.err;
  const auto b = run_gmwm(
      {"fit", "--curve", "two.csv", "--columns", "b", "--model", "WN", "--record", "100", "--json", "b.json", "-q"},
      dir_);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(b.err.empty()) << b.err;
  const json one = read_json(dir_ / "b.json");
  ASSERT_EQ(one["columns"].size(), 1u);
  EXPECT_EQ(one["columns"][0]["name"], "b");
  EXPECT_EQ(one["columns"][0]["curve"]["weights"], "record");
  EXPECT_EQ(one["columns"][0]["curve"]["record_seconds"], 100.0);
}

TEST_F(CurveFitCommand, RefusesHostileCurvesInOneLineNamingTheFileLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"tau,adev\n1,0.1\n2,nan\n", "bad.csv:3:2: found 'nan', expected the adev (a finite decimal number)"},
      {"tau,adev\n1,0.1\n2,-0.1\n", "bad.csv:3:2: found -0.1, expected a positive finite adev"},
      {"tau,adev\n1,0.1\n0.5,0.09\n", "bad.csv:3:1: found tau 0.5 s after 1 s, expected taus increasing"},
      {"tau,adev\n1,0.1\n1,0.09\n", "bad.csv:3:1: found tau 1 s again (line 2), expected each tau once, increasing"},
      {"tau,adev\n1,0.1\n2,0.09\n4,0.08\n",
       "bad.csv: curve 'adev': found 3 points to fit, expected at least 4 for the 4 parameters of WN+RW+AR1"},
      {"tau,value\n1,0.1\n", "bad.csv:1: found a value column (the header: tau, value), expected --value adev, avar"},
      {"tau,adev,ci_low,ci_high\n1,0.1,0.11,0.2\n",
       "bad.csv:2:3: found the interval 0.11 .. 0.2 for 0.1, expected low < high holding the value"},
      {"", "bad.csv: found no header, expected a header row naming tau and the values"}};
  for (const auto& [text, why] : cases) {
    gmwm::test::write_text(dir_ / "bad.csv", text);
    expect_refused({"fit", "--curve", "bad.csv", "--model", "WN+RW+AR1"}, why);
  }
  gmwm::test::write_text(dir_ / "ok.csv", "tau,adev\n0.01,0.1\n0.02,0.07\n0.04,0.05\n0.08,0.035\n");
  expect_refused({"fit", "--curve", "ok.csv", "--model", "WN", "--freq", "10"},
                 "ok.csv:2:1: found tau 0.01 s, 0.1 samples at 10 Hz, expected at least one sample");
  expect_refused({"fit", "--curve", "ok.csv", "--model", "WN", "--record", "0.1"},
                 "--record: found 0.1 s, expected at least the longest window of ok.csv (0.16 s");
  expect_refused({"fit", "--curve", "ok.csv", "--model", "WN", "--value", "wv"},
                 "ok.csv:1: found no wv column (the header: tau, adev), expected one named wv or value (--value wv)");
  expect_refused({"fit", "--curve", "missing.csv", "--model", "WN"}, "missing.csv");
}

TEST_F(CurveFitCommand, RefusesTheOptionsThatReadARecordBesideACurve) {
  gmwm::test::write_text(dir_ / "ok.csv", "tau,adev\n0.01,0.1\n0.02,0.07\n0.04,0.05\n0.08,0.035\n");
  gmwm::test::write_noise_csv(dir_ / "rec.csv", 1024);
  const std::vector<std::string> curve = {"fit", "--curve", "ok.csv", "--model", "WN"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> a = curve;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  expect_refused(with({"rec.csv"}), "INPUT with --curve: a curve has no record to read (give one or the other)");
  expect_refused(with({"--robust"}), "--robust with --curve: a curve has no record to read");
  expect_refused(with({"--first-level", "2"}), "--first-level with --curve");
  expect_refused(with({"--report", "r.html"}), "--report with --curve: a curve fit writes no HTML report yet");
  expect_refused(with({"--omega", "full"}),
                 "--omega: found 'full', expected model or diag (a curve has no record to simulate or to take a "
                 "covariance from)");
  expect_refused(with({"--exclude-taus", "2:1"}), "--exclude-taus: found '2:1', expected taus in seconds");
  expect_refused(with({"--curve-confidence", "1"}), "--curve-confidence: found '1', expected a confidence level");
  expect_refused({"fit", "--model", "WN"}, "INPUT is required (a record to fit, or --curve FILE)");
}

}  // namespace
