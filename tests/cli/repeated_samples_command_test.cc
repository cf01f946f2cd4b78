// Held and interpolated samples on the command line (issue 47, item 2): a RealSense-like
// record (a 400 Hz gyroscope's stamps, its accelerometer measured at 200 Hz and put on them by
// copying, accel_x, or by linear interpolation at a phase of 0.37 of a measurement, accel_y)
// is said on the terminal, in the JSON and in the report with the share, where and the
// scales smoothed; the gyroscope's own samples are not; N read at 1 s, far above the
// smoothed scales, is the measured white noise's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::flowed;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr double kGyroRate = 400.0, kAccelRate = 200.0;
constexpr int kN = 1 << 16;  // 164 s at 400 Hz
// The accelerometer's white noise a 200 Hz measurement: N = sqrt(4e-4 / 200) = 1.414e-3.
constexpr double kAccelSigma2 = 4e-4;

std::vector<double> series(const char* spec, double rate, int n, unsigned seed) {
  const gmwm::Model m = gmwm::parse_model(spec, gmwm::ProcessContext{rate, true});
  return gmwm::simulate(m, m.given_values(), n, seed);
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

class RepeatedSamplesCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("repeated_cli");
    const std::vector<double> gyro = series("WN(sigma2=1e-6)+RW(gamma2=1e-12)", kGyroRate, kN, 11);
    const std::string accel_spec = "WN(sigma2=" + number(kAccelSigma2) + ")+RW(gamma2=1e-10)";
    const std::vector<double> copied = series(accel_spec.c_str(), kAccelRate, kN / 2 + 2, 12);
    const std::vector<double> joined = series(accel_spec.c_str(), kAccelRate, kN / 2 + 2, 13);
    std::string csv = "time [s],gyro_x,accel_x,accel_y\n";
    for (int t = 0; t < kN; ++t) {
      const double u = t / 2.0 + 0.37;  // the accelerometer's time in measurements
      const auto k = static_cast<std::size_t>(u);
      const double f = u - static_cast<double>(k);
      csv += number(t / kGyroRate) + "," + number(gyro[static_cast<std::size_t>(t)]) + "," +
             number(copied[static_cast<std::size_t>(t / 2)]) + "," +
             number(joined[k] + f * (joined[k + 1] - joined[k])) + "\n";
    }
    gmwm::test::write_text(dir_ / "realsense.csv", csv);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(RepeatedSamplesCommand, TheTerminalAndTheJsonSayWhichColumnsRepeatWhereAndTheScalesSmoothed) {
  const auto r = run_gmwm({"wv", "realsense.csv", "--adev", "--json", "wv.json", "--report", "wv.html"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string err = flowed(r.err);
  EXPECT_NE(err.find("accel_x: 50% of the samples copy the one before (held; 50% of the steps are zero), from sample "
                     "0 to 65535: about 2 samples a measurement at most; the WV below tau = 32 samples (0.08 s) is "
                     "smoothed (levels 1-4): read N above it"),
            std::string::npos)
      << r.err;
  EXPECT_NE(err.find("accel_y: 100% of the samples are an exact linear combination of their neighbours "
                     "(interpolated, a pattern every 2 samples)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(err.find("the WV below tau = 64 samples (0.16 s) is smoothed (levels 1-5)"), std::string::npos) << r.err;
  EXPECT_EQ(err.find("gyro_x:"), std::string::npos) << r.err;

  const json doc = read_json(dir_ / "wv.json");
  const json& rep = doc.at("repeated_samples");
  ASSERT_EQ(rep.size(), 2u) << rep.dump();
  EXPECT_EQ(rep[0].at("column"), "accel_x");
  // Read from 16 blocks of 2048 samples end to end: a join in 2048 steps may be either kind.
  EXPECT_NEAR(rep[0].at("held_share").get<double>(), 0.5, 1e-3);
  EXPECT_EQ(rep[0].at("interpolated_share").get<double>(), 0.0);
  EXPECT_EQ(rep[0].at("first_clean_level"), 5);
  // At the stamps' rate (400 Hz to the 12 digits they are printed with).
  EXPECT_NEAR(rep[0].at("first_clean_tau_seconds").get<double>(), 32 / kGyroRate, 1e-9);
  EXPECT_EQ(rep[1].at("column"), "accel_y");
  EXPECT_EQ(rep[1].at("period"), 2);
  EXPECT_EQ(rep[1].at("held_share").get<double>(), 0.0);
  EXPECT_EQ(rep[1].at("first_clean_level"), 6);
  EXPECT_EQ(rep[1].at("summary").get<std::string>().rfind("accel_y: 100% of the samples are", 0), 0u);

  // The report's header says it too.
  EXPECT_NE(read_text(dir_ / "wv.html").find("copy the one before (held"), std::string::npos);

  // N at 1 s (400 samples, where holding biases the WV by 0.4%) is the measured white
  // noise's: within 5% of sqrt(sigma2 / 200 Hz) for both ways of filling.
  for (int c : {1, 2}) {
    const json& n = doc.at("columns").at(c).at("noise_figures").at("white");
    const double ratio = n.at("value").get<double>() / std::sqrt(kAccelSigma2 / kAccelRate);
    EXPECT_NEAR(ratio, 1.0, 0.05) << doc.at("columns").at(c).at("name") << " " << n.dump();
    std::printf("[ realsense-like ] %s: N read / measured N = %.4f\n",
                doc.at("columns").at(c).at("name").get<std::string>().c_str(), ratio);
  }
}

TEST_F(RepeatedSamplesCommand, ARecordWithoutRepeatsSaysNothingAndItsDocumentHasNoKey) {
  const auto r = run_gmwm({"wv", "realsense.csv", "--columns", "gyro_x", "--json", "wv.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("copy the one before"), std::string::npos) << r.err;
  EXPECT_FALSE(read_json(dir_ / "wv.json").contains("repeated_samples"));
}

// --first-level auto fits each repeating column above the levels its repetition biases and
// every level of the others: the fit of WN+RW on every level is rejected by its goodness of
// fit (the smoothed fine scales), above them it is not, and its N (the model's, read on the
// -1/2 slope) is within 5% of the measured white noise's, its interval covering it.
TEST_F(RepeatedSamplesCommand, FirstLevelAutoFitsAboveTheSmoothedScalesAndTheFitIsNoLongerRejected) {
  const auto all = run_gmwm({"fit", "realsense.csv", "--model", "WN+RW", "--json", "all.json"}, dir_);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const auto r = run_gmwm({"fit", "realsense.csv", "--model", "WN+RW", "--first-level", "auto", "--json", "auto.json",
                           "--report", "auto.html"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json before = read_json(dir_ / "all.json"), after = read_json(dir_ / "auto.json");
  const double truth = std::sqrt(kAccelSigma2 / kAccelRate);
  EXPECT_EQ(after.at("columns").at(0).at("first_level"), 1);
  EXPECT_EQ(before.at("columns").at(1).at("first_level"), 1);
  for (int c : {1, 2}) {
    const json& col = after.at("columns").at(c);
    const std::string name = col.at("name");
    EXPECT_LT(before.at("columns").at(c).at("gof").at("p_value").get<double>(), 0.05) << name;
    EXPECT_GT(col.at("gof").at("p_value").get<double>(), 0.05) << name;
    const int first = col.at("first_level");
    EXPECT_GE(first, 5) << name;
    // Every level is still shown, the model's WV beside it; the fit's degrees of freedom
    // are those of the fitted levels.
    EXPECT_EQ(col.at("implied_wv").size(), col.at("levels").size()) << name;
    EXPECT_EQ(col.at("gof").at("df").get<double>(), static_cast<double>(col.at("levels").size()) - (first - 1) - 2)
        << name;
    EXPECT_EQ(
        col.at("notes").at(0).get<std::string>().rfind("fitted from level " + std::to_string(first) + " (tau = ", 0),
        0u)
        << col.at("notes");
    const json& n = col.at("noise_figures").at("white");
    EXPECT_NEAR(n.at("value").get<double>() / truth, 1.0, 0.05) << name << " " << n.dump();
    EXPECT_LE(n.at("low").get<double>(), truth) << name;
    EXPECT_GE(n.at("high").get<double>(), truth) << name;
    std::printf("[ first level ] %s: from level %d, GoF p %.3g (every level: %.3g), N / measured N = %.4f\n",
                name.c_str(), first, col.at("gof").at("p_value").get<double>(),
                before.at("columns").at(c).at("gof").at("p_value").get<double>(), n.at("value").get<double>() / truth);
  }
  EXPECT_NE(read_text(dir_ / "auto.html").find("shown, not fitted"), std::string::npos);
}

TEST_F(RepeatedSamplesCommand, AFirstLevelThatLeavesTooFewLevelsIsRefusedNamingTheColumnAndNothingIsWritten) {
  const auto r =
      run_gmwm({"fit", "realsense.csv", "--model", "WN+RW", "--first-level", "16", "--json", "fit.json"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "gmwm: error: gyro_x: first level 16 leaves 1 of the WV's levels 1..16, fewer than the model's 2 "
            "parameters: a lower first level or a smaller model\n");
  EXPECT_FALSE(fs::exists(dir_ / "fit.json"));
  const auto bad = run_gmwm({"fit", "realsense.csv", "--model", "WN+RW", "--first-level", "0"}, dir_);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--first-level: found '0', expected auto or a whole number from 1 to 62"), std::string::npos)
      << bad.err;
}

// select --first-level auto ranks every sub-model on the same fitted levels as fit does, and
// its chosen model's N is the measured white noise's.
TEST_F(RepeatedSamplesCommand, SelectWithFirstLevelAutoRanksTheModelsOnTheLevelsFitTakes) {
  const auto r = run_gmwm({"select", "realsense.csv", "--columns", "accel_x", "--model", "AR1+WN+RW", "--first-level",
                           "auto", "--json", "select.json"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto f = run_gmwm({"fit", "realsense.csv", "--columns", "accel_x", "--model", "WN+RW", "--first-level", "auto",
                           "--json", "fit.json"},
                          dir_);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const json selected = read_json(dir_ / "select.json"), fitted = read_json(dir_ / "fit.json");
  const json& col = selected.at("columns").at(0);
  const json& fit = fitted.at("columns").at(0);
  EXPECT_EQ(col.at("first_level"), fit.at("first_level"));
  EXPECT_GE(col.at("first_level").get<int>(), 5);
  const json& n = col.at("noise_figures").at("white");
  EXPECT_NEAR(n.at("value").get<double>() / std::sqrt(kAccelSigma2 / kAccelRate), 1.0, 0.05) << n.dump();
  EXPECT_GT(col.at("best_fit").at("gof").at("p_value").get<double>(), 0.05) << col.at("best_fit").dump();
  const auto joint = run_gmwm(
      {"select", "realsense.csv", "--model", "WN+RW", "--first-level", "auto", "--joint", "realsense.csv"}, dir_);
  EXPECT_EQ(joint.exit_code, 2);
  EXPECT_EQ(joint.err,
            "gmwm: error: --joint with --first-level: the joint selection takes every level of each replicate\n");
}

// gmwm gap against the accelerometer's true model finds a deficit at the scales its held
// samples smooth and names effects for it; the headline and the first note say that the
// gap there is the repetition's, not the sensor's. The gyroscope, measured at its own rate,
// gets no such note.
// By default the gap study compares each column from its first level auto: above the
// scales held or interpolated samples smooth, where the accelerometer's true model (its
// 200 Hz white noise and walk at 400 Hz) is not rejected and no effect is named; every level
// compared (--first-level 1), the deficit the copies make there would be explained by
// effects the sensor does not have (an AR1 of 2.5 ms and a 63 Hz tone, before the note).
TEST_F(RepeatedSamplesCommand, GapComparesAboveTheSmoothedScalesByDefaultAndNamesNoEffectForThem) {
  const std::string truth = "WN(sigma2=" + number(2.0 * kAccelSigma2) + ")+RW(gamma2=5e-11)";
  const auto r = run_gmwm({"gap", "realsense.csv", "--columns", "accel_x,accel_y,gyro_x", "--model", truth,
                           "--replicates", "60", "--json", "g.json", "--report", "g.html"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "g.json");
  for (int k : {0, 1}) {
    const json& accel = doc.at("columns").at(k);
    const int first = accel.at("gap").at("first_level").get<int>();
    EXPECT_GE(first, k == 0 ? 5 : 6) << accel.at("name");  // above the detection's smoothed levels
    EXPECT_EQ(accel.at("gap").at("levels").size(), 16u - static_cast<std::size_t>(first) + 1u);
    EXPECT_EQ(accel.at("gap").at("levels").at(0).at("tau").get<double>(), std::ldexp(1.0, first));
    EXPECT_FALSE(accel.at("gap").at("detected").get<bool>()) << accel.at("headline");
    EXPECT_TRUE(accel.at("attribution").at("steps").empty()) << accel.at("headline");
    const std::string reason = "compared from level " + std::to_string(first) + " (tau = ";
    ASSERT_FALSE(accel.at("notes").empty());
    EXPECT_EQ(accel.at("notes").at(0).get<std::string>().rfind(reason, 0), 0u) << accel.at("notes");
    EXPECT_NE(accel.at("headline").get<std::string>().find(reason), std::string::npos);
    EXPECT_NE(accel.at("headline").get<std::string>().find("shown, not compared"), std::string::npos);
  }
  EXPECT_EQ(doc.at("columns").at(2).at("gap").at("first_level").get<int>(), 1);  // the gyroscope's own samples
  EXPECT_NE(flowed(r.out).find("accel_x: no gap"), std::string::npos) << r.out;
  EXPECT_NE(read_text(dir_ / "g.html").find("not compared"), std::string::npos);
}

TEST_F(RepeatedSamplesCommand, GapWithEveryLevelComparedSaysADeficitWithinTheSmoothedScalesIsTheRepetitions) {
  const std::string truth = "WN(sigma2=" + number(2.0 * kAccelSigma2) + ")+RW(gamma2=5e-11)";
  const auto r = run_gmwm({"gap", "realsense.csv", "--columns", "accel_x,gyro_x", "--model", truth, "--replicates",
                           "60", "--first-level", "1", "--json", "g.json"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "g.json");
  const json& accel = doc.at("columns").at(0);
  const std::string said =
      "the gap below tau = 32 samples (0.08 s) (levels 1-4) is where held samples smooth the WV: the repetition's, "
      "not the sensor's";
  ASSERT_FALSE(accel.at("notes").empty());
  EXPECT_EQ(accel.at("notes").at(0).get<std::string>().rfind(said, 0), 0u) << accel.at("notes");
  EXPECT_NE(accel.at("headline").get<std::string>().find(said), std::string::npos) << accel.at("headline");
  EXPECT_NE(flowed(r.out).find(said), std::string::npos) << r.out;
  const json& gyro = doc.at("columns").at(1);
  EXPECT_EQ(gyro.at("headline").get<std::string>().find("the repetition's"), std::string::npos);
}

// The robust WV's spike screen measures spikes against the level-1 robust scale, which the
// copies' steps of exactly zero deflate: on the held column it replaced 46750 of 65536
// samples. It is off there, said in the screening note; the gyroscope's own samples keep it.
TEST_F(RepeatedSamplesCommand, TheRobustWvLeavesAHeldColumnUnscreenedAndSaysWhy) {
  const auto r = run_gmwm({"wv", "realsense.csv", "--columns", "accel_x,gyro_x", "--robust", "--json", "w.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "w.json");
  const json& held = doc.at("columns").at(0).at("screening");
  EXPECT_EQ(held.at("replaced_samples").get<int>(), 0);
  EXPECT_EQ(
      held.at("note").get<std::string>().rfind("spike screen off: 50% of the samples copy the one before (held)", 0),
      0u)
      << held.at("note");
  const json& own = doc.at("columns").at(1).at("screening");
  EXPECT_EQ(own.at("note").get<std::string>().rfind("spike screen: ", 0), 0u) << own.at("note");
  EXPECT_EQ(flowed(r.out).find("46750"), std::string::npos) << r.out;
}

}  // namespace
