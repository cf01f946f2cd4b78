// The robust WV's account of what it did, end to end (issue 43 item 9): where the spike
// screen replaced samples, on the terminal (wv and fit) and as a strip in the HTML report;
// and a robust estimator without a value at a level refused by saying so, not as an overflow.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using gmwm::test::write_text;
using nlohmann::json;

namespace {

class GmwmRobust : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_robust"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// Occurrences of `what` in `text`.
std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size())) ++n;
  return n;
}

TEST_F(GmwmRobust, SaysOnTheTerminalAndInTheReportWhereTheSpikeScreenReplacedSamples) {
  // White noise at 100 Hz with 12 single-sample spikes of 60 sd, 9 of them in the record's
  // first tenth and 3 in its last: the screen replaces them (its JSON lists the ranges) and
  // the terminal and the report say where, not only the JSON (213 samples in 159 ranges of
  // cont_imu1 were shown nowhere else).
  constexpr int kN = 20000;
  std::mt19937_64 rng(4242);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(kN);
  for (double& v : x) v = g(rng);
  const std::vector<int> spikes = {100, 300, 500, 700, 900, 1100, 1300, 1500, 1700, 18500, 19000, 19500};
  for (const int s : spikes) x[static_cast<std::size_t>(s)] += 60.0;
  std::string csv = "gyro_x\n";
  for (const double v : x) csv += std::to_string(v) + "\n";
  write_text(dir_ / "spiky.csv", csv);
  const auto r =
      run_gmwm({"wv", "spiky.csv", "--freq", "100", "--robust", "--json", "w.json", "--report", "w.html"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json s = read_json(dir_ / "w.json").at("columns")[0].at("screening");
  const std::size_t ranges = s.at("replaced_ranges").size();
  ASSERT_EQ(ranges, spikes.size()) << s.dump();
  const std::string text = gmwm::test::flowed(r.out);
  EXPECT_NE(text.find("spike screen: 12 samples in 12 ranges replaced by interpolation (0.06% of the record), from 1 s "
                      "to 195 s; the longest 1 sample at 1 s"),
            std::string::npos)
      << r.out;
  EXPECT_NE(text.find("ranges in each tenth of the record: 9 0 0 0 0 0 0 0 0 3"), std::string::npos) << r.out;
  // The report: the same summary over a strip with a mark per range.
  const std::string html = read_text(dir_ / "w.html");
  const auto strip = html.find("class=\"screening-strip\"");
  ASSERT_NE(strip, std::string::npos);
  EXPECT_EQ(count_of(html.substr(strip, html.find("</svg>", strip) - strip), "<title>"), ranges);
  EXPECT_NE(html.find("ranges in each tenth of the record: 9 0 0 0 0 0 0 0 0 3"), std::string::npos);
  // A robust fit says it too, on its summary screen.
  const auto f = run_gmwm({"fit", "spiky.csv", "--freq", "100", "--robust", "--model", "WN"}, dir_);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_NE(gmwm::test::flowed(f.out).find("gyro_x: spike screen: 12 samples in 12 ranges"), std::string::npos)
      << f.out;
}

TEST_F(GmwmRobust, AWvWithoutAValueAtALevelIsRefusedByTheFitSayingWhyAndWhatWorks) {
  // Precipitation-like data (39% exact zeros, amounts rounded to 0.1): the bisquare equation
  // has no root at level 1, which `wv` says ("no root"); the fit said the sums of squares
  // overflow a double and asked to rescale.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::exponential_distribution<double> amount(0.2);
  std::string csv = "precip\n";
  for (int k = 0; k < 2000; ++k)
    csv += u(rng) < 0.39 ? "0\n" : std::to_string(std::round(10.0 * amount(rng)) / 10.0) + "\n";
  write_text(dir_ / "precip.csv", csv);
  const auto w = run_gmwm({"wv", "precip.csv", "--freq", "1", "--robust", "--estimator", "bisquare"}, dir_);
  ASSERT_EQ(w.exit_code, 0) << w.err;
  ASSERT_NE(w.out.find("no root"), std::string::npos) << w.out;
  const auto f = run_gmwm({"fit", "precip.csv", "--freq", "1", "--robust", "--estimator", "bisquare", "--model",
                           "AR1+WN", "--json", "f.json"},
                          dir_);
  EXPECT_EQ(f.exit_code, 2) << f.err;
  EXPECT_EQ(gmwm::test::lines_of(f.err).size(), 1u) << f.err;
  EXPECT_NE(f.err.find("the bisquare wavelet variance has no value at level 1 (no root"), std::string::npos) << f.err;
  EXPECT_NE(f.err.find("--estimator huber"), std::string::npos) << f.err;
  EXPECT_EQ(f.err.find("overflow"), std::string::npos) << f.err;
  EXPECT_FALSE(fs::exists(dir_ / "f.json"));
}

}  // namespace
