// --decimate K and --data increment on the command line (issue 47, items 4 and 5): decimating
// white noise without a filter keeps its variance a sample (so its density N grows sqrt(K)
// times: the band above the new Nyquist frequency folds in), the mean of each K samples
// divides it by K (N unchanged), and the note and the JSON say which; increments are rates
// times the rate.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::flowed;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

class DecimateCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("decimate_cli");
    // White noise sigma2 = 1 at 400 Hz, 2^17 samples.
    const auto r = run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "131072", "--freq", "400", "--names",
                             "gyro_x", "--seed", "3", "--output", "wn.csv", "--quiet"},
                            dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // sigma2 of the WN fit and the white-noise figure N of `gmwm fit` with `extra` options.
  std::pair<json, json> fit(const std::vector<std::string>& extra, std::string* err = nullptr) {
    std::vector<std::string> args = {"fit", "wn.csv", "--model", "WN", "--json", "fit.json", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_gmwm(args, dir_);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (err) *err = r.err;
    const json doc = read_json(dir_ / "fit.json");
    const json& col = doc.at("columns").at(0);
    return {col.at("parameters").at(0), col.at("noise_figures").at("white")};
  }

  fs::path dir_;
};

bool inside(const json& p, double truth, const char* low = "ci_low", const char* high = "ci_high") {
  return p.at(low).get<double>() <= truth && truth <= p.at(high).get<double>();
}

TEST_F(DecimateCommand, WhiteNoiseDecimatedWithoutAFilterKeepsItsVarianceAndTheAverageDividesItByK) {
  constexpr int kK = 4;
  const auto [full_sigma2, full_n] = fit({});
  EXPECT_TRUE(inside(full_sigma2, 1.0));
  // N = sigma sqrt(dt) = sqrt(1 / 400) = 0.05.
  EXPECT_NEAR(full_n.at("value").get<double>(), 0.05, 0.002);

  std::string note;
  const auto [none_sigma2, none_n] = fit({"--decimate", std::to_string(kK), "--decimate-filter", "none"}, &note);
  EXPECT_TRUE(inside(none_sigma2, 1.0)) << none_sigma2.dump();  // the variance a sample: unchanged
  EXPECT_NEAR(none_n.at("value").get<double>() / full_n.at("value").get<double>(), 2.0, 0.1);  // sqrt(4)
  EXPECT_NE(flowed(note).find("decimated by 4 (every 4-th sample, no filter) from 400 Hz to 100 Hz"), std::string::npos)
      << note;

  const auto [mean_sigma2, mean_n] = fit({"--decimate", std::to_string(kK)}, &note);
  EXPECT_TRUE(inside(mean_sigma2, 1.0 / kK)) << mean_sigma2.dump();                             // sigma2 / K
  EXPECT_NEAR(mean_n.at("value").get<double>() / full_n.at("value").get<double>(), 1.0, 0.05);  // N unchanged
  const json doc = read_json(dir_ / "fit.json");
  EXPECT_EQ(doc.at("conditioning").at("decimation"), kK);
  EXPECT_EQ(doc.at("conditioning").at("decimation_filter"), "average");
  // The stamps' rate (decimal seconds), within 1e-9.
  EXPECT_NEAR(doc.at("conditioning").at("freq_before_decimation").get<double>(), 400.0, 4e-7);
  EXPECT_NEAR(doc.at("columns").at(0).at("freq").get<double>(), 100.0, 1e-7);
}

TEST_F(DecimateCommand, IncrementsAreFittedAsTheRatesTheyIntegrate) {
  // The same white noise as increments over 1/400 s: rates of 400 x the values, sigma2 x 400^2.
  const auto [rate_sigma2, rate_n] = fit({});
  const auto [inc_sigma2, inc_n] = fit({"--data", "increment"});
  EXPECT_NEAR(inc_sigma2.at("value").get<double>() / rate_sigma2.at("value").get<double>(), 160000.0, 1e-6 * 160000);
  const auto bad = run_gmwm({"wv", "wn.csv", "--data", "delta"}, dir_);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("expected 'rate' (angular rates, specific forces), 'increment'"), std::string::npos)
      << bad.err;
}

}  // namespace
