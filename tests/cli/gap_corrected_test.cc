// `gmwm gap --corrected PATH` end to end (docs/gap.md, "The corrected configuration"): a
// sensor whose datasheet white noise is 1.7x too high gets a Kalibr yaml whose density is
// the sensor's, the fields it changed in the header and the JSON, the sensor without
// columns kept as it was; the corrected yaml, given back to gap, is not re-sized again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using gmwm::test::write_text;
using nlohmann::json;

namespace {

// The sensor: N = 1e-3 rad/s/sqrt(Hz) at 100 Hz (sigma2 = N^2 f = 1e-4), K = 1e-5
// rad/s^2/sqrt(Hz) (gamma2 = K^2 / f = 1e-12); 2^17 samples per axis.
constexpr double kN = 1e-3, kK = 1e-5;
constexpr const char* kSensor = "WN(sigma2=1e-4)+RW(gamma2=1e-12)";

// The figure of `key` in a Kalibr yaml ("key: value  # comment").
double yaml_figure(const std::string& text, const std::string& key) {
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1));
  ADD_FAILURE() << "no " << key;
  return NAN;
}

// Never silently worse (issue 43, item 6): on every column whose figures the file writes,
// the warning is there exactly when the file is worse than its input on the diagnosis'
// yardstick (objective beyond 1%, or more levels outside) or more optimistic than the full
// model (integrated error below 80% of its).
void expect_never_silently_worse(const json& corrected) {
  for (const json& col : corrected.at("columns")) {
    const json& in = col.at("gap_left").at("input");
    const json& file = col.at("gap_left").at("config");
    const json& full = col.at("gap_left").at("full");
    std::string warnings;
    for (const json& w : col.at("warnings")) warnings += w.get<std::string>() + "\n";
    if (col.at("verdict") != "written") {
      EXPECT_EQ(warnings, "") << col.at("name");
      continue;
    }
    const bool worse = file.at("objective").get<double>() > 1.01 * in.at("objective").get<double>() ||
                       file.at("levels_outside").get<int>() > in.at("levels_outside").get<int>();
    EXPECT_EQ(worse, warnings.find("than its input here") != std::string::npos) << col.dump(1);
    if (file.at("navigation_rms").is_number() && full.at("navigation_rms").is_number()) {
      const bool optimistic = file.at("navigation_rms").get<double>() < 0.8 * full.at("navigation_rms").get<double>();
      EXPECT_EQ(optimistic, warnings.find("more optimistic") != std::string::npos) << col.dump(1);
    }
  }
}

class GmwmGapCorrected : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_gap_corrected");
    auto r = run_gmwm({"simulate", "--model", kSensor, "--n", "131072", "--freq", "100", "--signals", "3", "--names",
                       "gyro_x,gyro_y,gyro_z", "--output", "sim.csv.gz", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The datasheet: white noise 1.7x the sensor's, the random walk right, accelerometer figures of its own.
    write_text(dir_ / "datasheet.yaml",
               "accelerometer_noise_density: 4.9e-03\naccelerometer_random_walk: 3.0e-04\n"
               "gyroscope_noise_density: 1.7e-03\ngyroscope_random_walk: 1.0e-05\n"
               "update_rate: 100.0\n");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(GmwmGapCorrected, WritesAKalibrYamlWhoseWhiteNoiseIsTheSensorsAndSaysWhatChanged) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--kalibr", "datasheet.yaml", "--replicates", "60", "--corrected",
                     "corrected.yaml", "--json", "g.json", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "corrected.yaml");
  // 2^17 samples put N's read-off within ~1% (its Allan deviation at 1 s averages 1e4
  // independent pairs); 5% is the issue's bar.
  EXPECT_NEAR(yaml_figure(yaml, "gyroscope_noise_density"), kN, 0.05 * kN) << yaml;
  // No accelerometer column: its figures are the input's, not zeros.
  EXPECT_DOUBLE_EQ(yaml_figure(yaml, "accelerometer_noise_density"), 4.9e-3);
  EXPECT_DOUBLE_EQ(yaml_figure(yaml, "accelerometer_random_walk"), 3.0e-4);
  EXPECT_NE(yaml.find("# changed: gyroscope_noise_density 0.0017 -> "), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("changed: accelerometer"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("written as 0"), std::string::npos) << yaml;

  const json doc = read_json(dir_ / "g.json");
  const json& c = doc.at("corrected");
  EXPECT_EQ(c.at("format"), "kalibr");
  expect_never_silently_worse(c);
  EXPECT_EQ(c.at("content").get<std::string>(), yaml);
  bool density_changed = false;
  for (const json& ch : c.at("changes")) {
    if (ch.at("field") == "gyroscope_noise_density") {
      density_changed = ch.at("changed").get<bool>();
      EXPECT_DOUBLE_EQ(ch.at("input").get<double>(), 1.7e-3);
      EXPECT_EQ(ch.at("unit"), "rad/s/sqrt(Hz)");
    }
    if (ch.at("field").get<std::string>().rfind("accelerometer", 0) == 0) {
      EXPECT_FALSE(ch.at("changed").get<bool>());
    }
  }
  EXPECT_TRUE(density_changed);
  ASSERT_EQ(c.at("columns").size(), 3u);
  for (const json& col : c.at("columns")) {
    const json& left = col.at("gap_left");
    // The datasheet misses every fine level; the corrected file (WN + RW, all this sensor has) fits.
    EXPECT_GT(left.at("input").at("levels_outside").get<int>(), 3) << col.at("name");
    EXPECT_LT(left.at("config").at("objective").get<double>(), 0.05 * left.at("input").at("objective").get<double>())
        << col.at("name");
    EXPECT_LE(left.at("config").at("levels_outside").get<int>(), 2) << col.at("name");
  }

  // The same data against the corrected file: nothing left to re-size.
  r = run_gmwm(
      {"gap", "sim.csv.gz", "--kalibr", "corrected.yaml", "--replicates", "60", "--json", "again.json", "--quiet"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const json& col : read_json(dir_ / "again.json").at("columns"))
    for (const json& step : col.at("attribution").at("steps"))
      EXPECT_NE(step.get<std::string>(), "REPARAMETERISE") << col.at("name");
}

TEST_F(GmwmGapCorrected, WritesOneModelStringPerColumnForAModelBaseline) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--columns", "gyro_x", "--model", "WN(sigma2=2.89e-4)+RW(gamma2=1e-12)",
                     "--replicates", "60", "--corrected", "corrected.txt", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_text(dir_ / "corrected.txt");
  std::istringstream is(text);
  std::string model_line;
  for (std::string line; std::getline(is, line);)
    if (line.rfind("gyro_x: ", 0) == 0) model_line = line;
  ASSERT_FALSE(model_line.empty()) << text;
  EXPECT_NE(model_line.find("WN(sigma2="), std::string::npos) << model_line;
  EXPECT_NE(text.find("# gap left, gyro_x: input "), std::string::npos) << text;
}

TEST_F(GmwmGapCorrected, RecoversNAndNamesQnAndTheAr1OfASensorWhoseDatasheetIsOffInN) {
  // The issue-26 round trip: a WN + QN + AR1 + RW sensor (N = 1e-3 rad/s/sqrt(Hz), a
  // quantization with Q2 = 3e-5, a bias instability with T = 10 s) against a datasheet
  // whose N is 1.7x too high. The datasheet misses every fine level, so no effect helps
  // on the datasheet's own sizes: the baseline is re-sized and QN and the AR1 are found
  // with it (a veto on the count of levels outside stopped this search before).
  auto r =
      run_gmwm({"simulate", "--model", "WN(sigma2=1e-4)+QN(Q2=3e-5)+AR1(phi=0.999,sigma2=2e-9)+RW(gamma2=1e-12)", "--n",
                "262144", "--freq", "100", "--signals", "1", "--names", "gyro_x", "--output", "rt.csv.gz", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_gmwm({"gap", "rt.csv.gz", "--kalibr", "datasheet.yaml", "--replicates", "100", "--corrected", "rt.yaml",
                "--json", "rt.json", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // N's read-off on 2^18 samples is within ~1% (its Allan deviation at 1 s averages 2.6e3
  // pairs; QN adds 0.5% at 1 s); 5% is the issue's bar.
  EXPECT_NEAR(yaml_figure(read_text(dir_ / "rt.yaml"), "gyroscope_noise_density"), kN, 0.05 * kN);
  const json col = read_json(dir_ / "rt.json").at("columns").at(0);
  std::vector<std::string> steps;
  for (const json& s : col.at("attribution").at("steps")) steps.push_back(s.get<std::string>());
  const std::string headline = col.at("headline");
  EXPECT_NE(std::find(steps.begin(), steps.end(), "QN"), steps.end()) << headline;
  EXPECT_NE(std::find(steps.begin(), steps.end(), "AR1"), steps.end()) << headline;
  EXPECT_NE(headline.find("explained by QN"), std::string::npos) << headline;
  // The share removed is a share: in [0, 1] without clamping.
  const double S = col.at("shrinkage").at("excess_removed");
  EXPECT_GE(S, 0.0);
  EXPECT_LE(S, 1.0);
}

TEST_F(GmwmGapCorrected, RefusesACorrectedPathThatIsTheBaselineItself) {
  const std::string before = read_text(dir_ / "datasheet.yaml");
  auto r =
      run_gmwm({"gap", "sim.csv.gz", "--kalibr", "datasheet.yaml", "--corrected", "datasheet.yaml", "--quiet"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--corrected"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(dir_ / "datasheet.yaml"), before);
}

// --datasheet (docs/gap.md, "A datasheet as the baseline"): the figures in the datasheet's
// own units; the corrected datasheet keeps the input's keys and units.
TEST_F(GmwmGapCorrected, ADatasheetInItsOwnUnitsGetsACorrectedDatasheetWithTheSensorsDensity) {
  // N 1.7x the sensor's, as an angle random walk: 1.7e-3 rad/s/sqrt(Hz) = 1.7e-3 x 60 x 180/pi deg/sqrt(h).
  const double arw = 1.7e-3 * 60.0 * 180.0 / M_PI;
  write_text(dir_ / "sheet.yaml", "name: test part\ngyroscope:\n  angle_random_walk: " + std::to_string(arw) +
                                      " deg/sqrt(h)\n  rate_random_walk: 2.0626 deg/h/sqrt(h)\n");
  auto r = run_gmwm({"gap", "sim.csv.gz", "--datasheet", "sheet.yaml", "--replicates", "60", "--corrected",
                     "corrected.yaml", "--json", "g.json"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Every conversion is printed, from the datasheet's unit to SI to the per-sample term.
  EXPECT_NE(r.out.find("conversion: angle_random_walk = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("deg/sqrt(h) = 0.0017 rad/s/sqrt(Hz) -> WN sigma2 = N^2 f"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("what to change (datasheet, --corrected writes it)"), std::string::npos) << r.out;
  const std::string yaml = read_text(dir_ / "corrected.yaml");
  const std::size_t at = yaml.find("  angle_random_walk: ");
  ASSERT_NE(at, std::string::npos) << yaml;
  const double corrected = std::stod(yaml.substr(at + 21));
  EXPECT_NE(yaml.find(" deg/sqrt(h)\n", at), std::string::npos) << yaml;
  // The sensor's N in deg/sqrt(h), within the issue's 5%.
  EXPECT_NEAR(corrected, kN * 60.0 * 180.0 / M_PI, 0.05 * kN * 60.0 * 180.0 / M_PI) << yaml;
  EXPECT_NE(yaml.find("# changed: gyroscope/angle_random_walk 5.844 -> "), std::string::npos) << yaml;
  EXPECT_EQ(read_json(dir_ / "g.json").at("corrected").at("format"), "datasheet");
  expect_never_silently_worse(read_json(dir_ / "g.json").at("corrected"));
  // Given back, the corrected datasheet is not re-sized in N again.
  r = run_gmwm(
      {"gap", "sim.csv.gz", "--datasheet", "corrected.yaml", "--replicates", "60", "--quiet", "--json", "h.json"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const json& col : read_json(dir_ / "h.json").at("columns")) {
    const json& steps = col.at("attribution").at("steps");
    EXPECT_EQ(std::find(steps.begin(), steps.end(), "REPARAMETERISE"), steps.end()) << col.at("name") << steps;
  }
}

TEST_F(GmwmGapCorrected, ADatasheetWithoutUnitsOrBesideAnotherBaselineIsRefusedWithOneLineAndNothingWritten) {
  write_text(dir_ / "bad.yaml", "gyroscope:\n  noise_density: 0.05\n");
  auto r =
      run_gmwm({"gap", "sim.csv.gz", "--datasheet", "bad.yaml", "--corrected", "c.yaml", "--json", "g.json"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--datasheet bad.yaml:2: gyroscope.noise_density: found 0.05 without a unit"), std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "c.yaml"));
  EXPECT_FALSE(fs::exists(dir_ / "g.json"));
  r = run_gmwm({"gap", "sim.csv.gz", "--datasheet", "bad.yaml", "--kalibr", "datasheet.yaml"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--datasheet"), std::string::npos) << r.err;
}

// A simulator's file keeps what the diagnosis cannot see: the constant offsets (turn-on
// bias) and the sensor without columns.
TEST_F(GmwmGapCorrected, ACorrectedSdfKeepsTheTurnOnBiasAndTheUndiagnosedAccelerometer) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--gazebo", std::string(GMWM_SOURCE_DIR) + "/data/adis16405_gz.sdf",
                     "--replicates", "40", "--corrected", "corrected.sdf", "--quiet", "--no-unit-check"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string sdf = read_text(dir_ / "corrected.sdf");
  const std::size_t gyro = sdf.find("<angular_velocity>", sdf.find("-->")),
                    accel = sdf.find("<linear_acceleration>", gyro);
  ASSERT_NE(gyro, std::string::npos) << sdf;
  ASSERT_NE(accel, std::string::npos) << "the accelerometer was dropped:\n" << sdf;
  // The gyroscope's turn-on bias sigma (5.24e-2 rad/s in the input), kept on each axis as written.
  const std::string gyro_block = sdf.substr(gyro, accel - gyro);
  std::size_t kept = 0;
  for (std::size_t at = gyro_block.find("<bias_stddev>5.24e-2</bias_stddev>"); at != std::string::npos;
       at = gyro_block.find("<bias_stddev>5.24e-2</bias_stddev>", at + 1))
    ++kept;
  EXPECT_EQ(kept, 3u) << gyro_block;
  // Every gyroscope axis was diagnosed: each axis gets its own white noise (real units' axes
  // differ by more than one figure can hold), the same N within sampling error here.
  std::vector<double> stddev;
  for (std::size_t at = gyro_block.find("<stddev>"); at != std::string::npos; at = gyro_block.find("<stddev>", at + 1))
    stddev.push_back(std::stod(gyro_block.substr(at + 8)));
  ASSERT_EQ(stddev.size(), 3u) << gyro_block;
  EXPECT_FALSE(stddev[0] == stddev[1] && stddev[1] == stddev[2]) << gyro_block;
  for (double s : stddev) EXPECT_NEAR(s, kN * 10.0, 0.05 * kN * 10.0);  // N sqrt(100 Hz)
  // The accelerometer's Gauss-Markov bias as the input has it (3.0e-4 m/s^3/sqrt(Hz), 300 s).
  const std::string accel_block = sdf.substr(accel);
  // (read back through the input's AR1: equal to the last digits)
  const auto element = [&](const std::string& tag) {
    const std::size_t at = accel_block.find("<" + tag + ">");
    return at == std::string::npos ? NAN : std::stod(accel_block.substr(at + tag.size() + 2));
  };
  EXPECT_NEAR(element("dynamic_bias_stddev"), 3.0e-4, 1e-12) << accel_block;
  EXPECT_NEAR(element("dynamic_bias_correlation_time"), 300.0, 1e-9) << accel_block;
  EXPECT_EQ(sdf.find("changed: linear_acceleration/x/noise/dynamic_bias_stddev"), std::string::npos) << sdf;
  EXPECT_NE(sdf.find("precision 0.000873 rad/s not written"), std::string::npos) << sdf;
}

// A run on some columns (--columns) changes only what those columns hold (issue 43, item
// 6): a gz-sensors axis not diagnosed, the sensor without columns, the comments and the
// model around the sensor stay exactly as the input wrote them (values and text); in a
// format with one figure per sensor, a figure that also holds a left-out axis is kept,
// said in the header, the terminal and the JSON.
TEST_F(GmwmGapCorrected, ASubsetRunLeavesEveryAxisItDidNotDiagnoseExactlyAsTheInputWroteIt) {
  const std::string input_sdf = read_text(fs::path(GMWM_SOURCE_DIR) / "data" / "adis16405_gz.sdf");
  auto r = run_gmwm(
      {"gap", "sim.csv.gz", "--columns", "gyro_x", "--gazebo", std::string(GMWM_SOURCE_DIR) + "/data/adis16405_gz.sdf",
       "--replicates", "40", "--corrected", "x.sdf", "--json", "x.json", "--quiet", "--no-unit-check"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string sdf = read_text(dir_ / "x.sdf");
  // The header comment follows the XML declaration; without it, the file is the input but
  // for gyro_x's <noise> block (the <x> of <angular_velocity>).
  const std::size_t header = sdf.find("<!--"), header_end = sdf.find("-->\n", header);
  ASSERT_NE(header_end, std::string::npos) << sdf;
  EXPECT_NE(sdf.substr(header, header_end - header).find("gmwm gap: the corrected"), std::string::npos) << sdf;
  sdf.erase(header, header_end + 4 - header);
  const auto x_block = [](const std::string& text) {
    const std::size_t gyro = text.find("<angular_velocity>"), x = text.find("<x>", gyro);
    return std::make_pair(x, text.find("</x>", x));
  };
  const auto [in_x, in_x_end] = x_block(input_sdf);
  const auto [out_x, out_x_end] = x_block(sdf);
  ASSERT_NE(out_x_end, std::string::npos) << sdf;
  EXPECT_EQ(sdf.substr(0, out_x), input_sdf.substr(0, in_x));
  EXPECT_EQ(sdf.substr(out_x_end), input_sdf.substr(in_x_end)) << "gyro_y, gyro_z and the accelerometer changed";
  EXPECT_NE(sdf.substr(out_x, out_x_end - out_x), input_sdf.substr(in_x, in_x_end - in_x)) << "gyro_x not written";

  // Kalibr holds one gyroscope figure for three axes: gyro_x alone does not change it.
  const std::string input_yaml = read_text(dir_ / "datasheet.yaml");
  r = run_gmwm({"gap", "sim.csv.gz", "--columns", "gyro_x", "--kalibr", "datasheet.yaml", "--replicates", "40",
                "--corrected", "x.yaml", "--json", "k.json"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "x.yaml");
  std::string body;
  std::istringstream is(yaml);
  for (std::string line; std::getline(is, line);)
    if (line.rfind("#", 0) != 0) body += line + "\n";
  EXPECT_EQ(body, input_yaml);
  const std::string kept =
      "kept, gyro_x: the gyroscope's figures hold its three axes and --columns diagnosed gyro_x only: the input's "
      "are kept";
  EXPECT_NE(yaml.find("# " + kept), std::string::npos) << yaml;
  // The terminal wraps its lines (continuations indented): compared with the runs of
  // white space made one.
  const auto one_line = [](const std::string& t) {
    std::string o;
    for (char ch : t)
      if (!std::isspace(static_cast<unsigned char>(ch)) || (!o.empty() && o.back() != ' '))
        o += std::isspace(static_cast<unsigned char>(ch)) ? ' ' : ch;
    return o;
  };
  EXPECT_NE(one_line(r.out).find(" " + kept), std::string::npos) << r.out;
  expect_never_silently_worse(read_json(dir_ / "k.json").at("corrected"));
  expect_never_silently_worse(read_json(dir_ / "x.json").at("corrected"));
  const json col = read_json(dir_ / "k.json").at("corrected").at("columns").at(0);
  EXPECT_EQ(col.at("verdict"), "kept: holds axes not diagnosed");
  EXPECT_EQ(col.at("gap_left").at("config").at("objective"), col.at("gap_left").at("input").at("objective"));
}

// A figure the input's text shares with another one (a YAML anchor and alias) is never
// written through: the accelerometer nobody diagnosed would take the gyroscope's correction
// (found by trying a hostile input: issue 43, item 6).
TEST_F(GmwmGapCorrected, AFigureAliasedByAnUndiagnosedOneKeepsTheInputsAndSaysWhy) {
  write_text(dir_ / "alias.yaml",
             "gyroscope_noise_density: 1.7e-03\ngyroscope_random_walk: &walk 1.0e-05\n"
             "accelerometer_noise_density: 4.9e-03\naccelerometer_random_walk: *walk\nupdate_rate: 100.0\n");
  const std::string input = read_text(dir_ / "alias.yaml");
  auto r = run_gmwm({"gap", "sim.csv.gz", "--kalibr", "alias.yaml", "--replicates", "40", "--corrected", "a.yaml",
                     "--json", "a.json", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = read_text(dir_ / "a.yaml");
  std::string body;  // the file but for its header: the input as it was
  std::istringstream is(yaml);
  for (std::string line; std::getline(is, line);)
    if (line.rfind("#", 0) != 0) body += line + "\n";
  EXPECT_EQ(body, input);
  EXPECT_NE(yaml.find("would change accelerometer_random_walk too"), std::string::npos) << yaml;
  for (const json& col : read_json(dir_ / "a.json").at("corrected").at("columns"))
    EXPECT_EQ(col.at("verdict"), "kept: not found in the input's text") << col.dump(1);
}

}  // namespace
