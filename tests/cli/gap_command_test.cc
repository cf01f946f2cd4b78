// `gmwm gap` end to end: a sinusoid withheld from the baseline is located and named in
// the docs/cli.md JSON fields and in the terminal summary; a Kalibr imu.yaml and a Gazebo SDF as
// the baseline with their conversions; the same JSON for --threads 1 and 2; bad options
// (exit 2, one line).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::flowed;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr const char* kBase = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";

class GmwmGap : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_gap");
    // A 2 Hz sinusoid at 100 Hz (f = 0.02 cycles/sample) on top of the baseline.
    auto r = run_gmwm({"simulate", "--model", std::string(kBase) + "+SIN(A2=4e-4,f=2)", "--n", "65536", "--freq", "100",
                       "--names", "gyro_x", "--output", "sim.csv.gz", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(GmwmGap, LocatesAndNamesAWithheldSinusoidInTheContractFields) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "60", "--json", "g.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "g.json");
  EXPECT_EQ(doc.at("command"), "gap");
  ASSERT_EQ(doc.at("columns").size(), 1u);
  EXPECT_EQ(doc.at("cross_axis").at("tested"), 0);  // one column: no pair
  const json& c = doc["columns"][0];
  EXPECT_EQ(c.at("baseline_model"), "WN(sigma2=0.0001)+RW(gamma2=1e-10)");
  const json& gap = c.at("gap");
  EXPECT_TRUE(gap.at("detected").get<bool>());
  EXPECT_LT(gap.at("p_value").get<double>(), 0.05);
  ASSERT_FALSE(gap.at("bands").empty());
  for (const char* f : {"tau_from_seconds", "tau_to_seconds", "direction"})
    EXPECT_TRUE(gap["bands"][0].contains(f)) << f;
  EXPECT_EQ(gap["bands"][0]["direction"], "excess");
  ASSERT_EQ(gap.at("levels").size(), 16u);
  for (const char* f : {"tau_seconds", "ratio", "z"}) EXPECT_TRUE(gap["levels"][0].contains(f)) << f;
  // A stationary sinusoid: no window departs from the rest of the record.
  ASSERT_TRUE(gap.at("windows").is_array());
  EXPECT_TRUE(gap["windows"].empty()) << gap["windows"].dump();
  EXPECT_NEAR(gap.at("window_length_seconds").get<double>(), 81.92, 1e-9);
  const json& a = c.at("attribution");
  EXPECT_EQ(a.at("effect"), "SIN");
  EXPECT_NE(a.at("model").get<std::string>().find("SIN("), std::string::npos);
  bool frequency_found = false;
  for (const json& p : a.at("parameters"))
    if (p.at("name") == "f") {
      EXPECT_NEAR(p.at("value").get<double>(), 2.0, 0.1) << "Hz";
      // The bootstrap interval brackets the estimate.
      EXPECT_LT(p.at("ci_low").get<double>(), p.at("value").get<double>());
      EXPECT_GT(p.at("ci_high").get<double>(), p.at("value").get<double>());
      frequency_found = true;
    }
  EXPECT_TRUE(frequency_found);
  // Physical units: amplitude sqrt(A2) = 0.02 in the data's unit ("U" when undeclared).
  bool amplitude_found = false;
  for (const json& p : a.at("physical"))
    if (p.at("name") == "amplitude") {
      EXPECT_NEAR(p.at("value").get<double>(), 0.02, 0.002);
      EXPECT_EQ(p.at("unit"), "U");
      EXPECT_LT(p.at("ci_low").get<double>(), 0.02 * 1.1);
      amplitude_found = true;
    }
  EXPECT_TRUE(amplitude_found);
  // 60 s (K = 6000 samples) of the baseline's noise integrated, x 1/f = 0.01 s: WN
  // sqrt(6000 x 1e-4) / 100 = 7.746e-3, RW sqrt(1e-10 x 6000 x 6001 x 12001 / 6) / 100 =
  // 2.6836e-2; together sqrt(7.746e-3^2 + 2.6836e-2^2) = 2.7932e-2.
  const json& nav = c.at("navigation");
  EXPECT_EQ(nav.at("horizon_seconds").get<double>(), 60.0);
  EXPECT_NEAR(nav.at("rms_without").get<double>(), 2.7932e-2, 1e-6);
  ASSERT_FALSE(a.at("candidates").empty());
  for (const char* f : {"effect", "improvement", "threshold"}) EXPECT_TRUE(a["candidates"][0].contains(f)) << f;
  const json& s = c.at("shrinkage");
  for (const char* f : {"objective_before", "objective_after", "excess_removed", "levels_outside_before",
                        "levels_outside_after", "p_value_after"})
    EXPECT_TRUE(s.contains(f)) << f;
  EXPECT_GE(s["excess_removed"].get<double>(), 0.8);
  // The terminal summary reads in one line.
  auto t = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "60"}, dir_);
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(flowed(t.out).find("gyro_x: excess at"), std::string::npos) << t.out;
  EXPECT_NE(flowed(t.out).find("explained by SIN at 2"), std::string::npos) << t.out;
  EXPECT_NE(flowed(t.out).find("excess removed"), std::string::npos) << t.out;
  EXPECT_NE(flowed(t.out).find("levels outside "), std::string::npos) << t.out;
}

TEST_F(GmwmGap, PrintsEachColumnsHeadlineFirstAndItsDetailsOnlyWithVerbose) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The headline comes first (after the timing note), what to change after it, the hint last.
  const auto headline = r.out.find("\ngyro_x: ");
  ASSERT_NE(headline, std::string::npos) << r.out;
  EXPECT_LT(headline, r.out.find("what to change")) << r.out;
  EXPECT_NE(r.out.find("(--verbose: per column the levels against the reference band"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("  baseline: "), std::string::npos) << r.out;
  auto v = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40", "--verbose"}, dir_);
  ASSERT_EQ(v.exit_code, 0) << v.err;
  EXPECT_NE(v.out.find("  baseline: "), std::string::npos) << v.out;
  EXPECT_EQ(v.out.find("(--verbose:"), std::string::npos) << v.out;
  // The same summary in both, first.
  EXPECT_EQ(v.out.rfind(r.out.substr(0, r.out.find("(--verbose:")), 0), 0u) << v.out;
}

TEST_F(GmwmGap, AddsOnlyTheEffectsGivenAndRefusesAnUnknownOneNamingTheKnownOnes) {
  // The sinusoid withheld, SIN not allowed: the attribution is not SIN.
  auto r = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40", "--effects", "DR,AR1", "--max-steps",
                     "1", "--json", "g.json"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "g.json");
  const json& a = doc["columns"][0]["attribution"];
  ASSERT_FALSE(a.at("candidates").empty());
  for (const json& c : a["candidates"]) EXPECT_TRUE(c.at("effect") == "DR" || c.at("effect") == "AR1") << c.dump();
  EXPECT_NE(a.at("effect"), "SIN");
  auto bad = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--effects", "DR,OUTLIERS", "--json", "x.json"}, dir_);
  expect_bad_input(bad, {"--effects 'DR,OUTLIERS': unknown effect 'OUTLIERS'", "REPARAMETERISE"}, dir_ / "x.json");
}

TEST_F(GmwmGap, NamesATemperatureCouplingGivenATemperatureColumn) {
  // gyro_x = the baseline's noise + 2e-3 x a slowly wandering temperature.
  auto r = run_gmwm({"simulate", "--model", std::string(kBase), "--n", "65536", "--freq", "100", "--names", "noise",
                     "--output", "noise.csv", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir_ / "noise.csv");
  std::ofstream out(dir_ / "coupled.csv");
  std::string line;
  std::getline(in, line);
  out << "gyro_x,temp\n";
  out.precision(17);
  double temp = 25.0;
  for (int i = 0; std::getline(in, line); ++i) {
    temp += 0.01 * std::sin(1e-3 * i) + 0.002 * std::cos(0.37 * i);   // deterministic, slow
    const double noise = std::stod(line.substr(line.find(',') + 1));  // "time,noise"
    out << noise + 2e-3 * temp << "," << temp << "\n";
  }
  out.close();
  auto g = run_gmwm({"gap", "coupled.csv", "--freq", "100", "--model", kBase, "--temperature", "temp", "--replicates",
                     "60", "--json", "t.json"},
                    dir_);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const json doc = read_json(dir_ / "t.json");
  EXPECT_EQ(doc.at("temperature_column"), "temp");
  ASSERT_EQ(doc.at("columns").size(), 1u);  // the temperature is not diagnosed itself
  const json& t = doc["columns"][0].at("attribution").at("temperature");
  EXPECT_TRUE(t.at("significant").get<bool>());
  EXPECT_LT(t.at("ci_low").get<double>(), 2e-3);
  EXPECT_GT(t.at("ci_high").get<double>(), 2e-3);
  EXPECT_EQ(doc["columns"][0]["attribution"]["effect"], "TEMPERATURE");
  expect_bad_input(run_gmwm({"gap", "coupled.csv", "--freq", "100", "--model", kBase, "--temperature", "celsius",
                             "--json", "x.json"},
                            dir_),
                   {"--temperature 'celsius'", "gyro_x, temp"}, dir_ / "x.json");
}

TEST_F(GmwmGap, TakesTheNamedImuOfAKalibrChainAndRefusesAnAmbiguousOne) {
  std::ofstream(dir_ / "chain.yaml")
      << "imu0:\n  accelerometer_noise_density: 2.0e-3\n  accelerometer_random_walk: 3.0e-3\n"
         "  gyroscope_noise_density: 1.0e-3\n  gyroscope_random_walk: 1.0e-4\n"
         "imu1:\n  accelerometer_noise_density: 2.0e-2\n  accelerometer_random_walk: 3.0e-2\n"
         "  gyroscope_noise_density: 1.0e-2\n  gyroscope_random_walk: 1.0e-3\n";
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--kalibr", "chain.yaml", "--json", "g.json"}, dir_),
                   {"chain.yaml: an IMU chain with imu0, imu1", "chain.yaml:imu0"}, dir_ / "g.json");
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--kalibr", "chain.yaml:cam0", "--json", "g.json"}, dir_),
                   {"--kalibr chain.yaml:cam0", "FILE:imuN"}, dir_ / "g.json");
  auto r = run_gmwm(
      {"gap", "sim.csv.gz", "--kalibr", "chain.yaml:imu1", "--replicates", "40", "--quiet", "--json", "g.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // imu1's gyro density 1e-2 rad/s/sqrt(Hz): sigma2 = 1e-4 x 100 = 1e-2 (imu0's would give 1e-4).
  const std::string base = read_json(dir_ / "g.json")["columns"][0]["baseline_model"];
  EXPECT_EQ(base.rfind("WN(sigma2=0.01", 0), 0u) << base;
}

TEST_F(GmwmGap, TakesAKalibrImuYamlAndPrintsItsConversions) {
  std::ofstream(dir_ / "imu.yaml") << "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
                                      "gyroscope_noise_density: 1.0e-3\ngyroscope_random_walk: 1.0e-4\n"
                                      "update_rate: 100.0\n";
  auto r = run_gmwm({"gap", "sim.csv.gz", "--kalibr", "imu.yaml", "--replicates", "40", "--json", "g.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      flowed(r.out).find("conversion: gyroscope_noise_density = 0.001 rad/s/sqrt(Hz) -> WN sigma2 = (N)^2 x f = 0.0001 "
                         "(rad/s)^2 per sample at f = 100 Hz"),
      std::string::npos)
      << r.out;
  const json doc = read_json(dir_ / "g.json");
  // sigma2 = (1e-3)^2 x 100, gamma2 = (1e-4)^2 / 100 (the rate estimated from the timestamps).
  const std::string base = doc["columns"][0]["baseline_model"];
  EXPECT_EQ(base.rfind("WN(sigma2=0.0001", 0), 0u) << base;
  EXPECT_NE(base.find("+RW(gamma2=9.99999999999"), std::string::npos) << base;
  EXPECT_EQ(doc["columns"][0]["conversions"].size(), 2u);
}

TEST_F(GmwmGap, TakesTheShippedGazeboSdfAndPrintsItsConversions) {
  const std::string sdf = std::string(GMWM_SOURCE_DIR) + "/data/adis16405_gz.sdf";
  auto r = run_gmwm({"gap", "sim.csv.gz", "--gazebo", sdf, "--replicates", "40", "--json", "g.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(flowed(r.out).find(
                "conversion: angular_velocity stddev = 0.00873 rad/s per sample (not a density) -> WN sigma2 = "
                "(s)^2 = 7.62129e-05 (rad/s)^2 per sample"),
            std::string::npos)
      << r.out;
  EXPECT_NE(flowed(r.out).find("valid once the noise spans a few LSBs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\ngyro_x: "), std::string::npos) << r.out;
  const json doc = read_json(dir_ / "g.json");
  EXPECT_EQ(doc.at("baseline_source"), "gz-sensors SDF <noise> blocks (" + sdf + ")");
  // AR1: phi = exp(-1/(f x 1000 s)) ~ 0.99999 (T = 1000 s, under 10 records of 655 s: kept
  // as a Gauss-Markov bias); WN: 0.00873^2 + 0.000873^2 / 12 = 7.627641075e-5 (rate-free).
  const std::string base = doc["columns"][0]["baseline_model"];
  EXPECT_EQ(base.rfind("AR1(phi=0.99999", 0), 0u) << base;
  EXPECT_NE(base.find("+WN(sigma2=7.62764107"), std::string::npos) << base;
  // alike axes, mean, bias_mean, bias_stddev, stddev, precision, their sum, dynamic bias.
  EXPECT_EQ(doc["columns"][0]["conversions"].size(), 8u) << doc["columns"][0]["conversions"].dump();
}

TEST_F(GmwmGap, TakesTheColumnsAxisFromAGazeboSdfWhoseAxesDiffer) {
  auto axis = [](const char* a, const char* s) {
    return std::string("<") + a + "><noise type=\"gaussian\"><stddev>" + s + "</stddev></noise></" + a + ">";
  };
  std::ofstream(dir_ / "axes.sdf") << "<sdf version=\"1.9\"><model name=\"m\"><link name=\"l\">"
                                      "<sensor name=\"imu\" type=\"imu\"><imu><angular_velocity>"
                                   << axis("x", "0.01") << axis("y", "0.02") << axis("z", "0.03")
                                   << "</angular_velocity></imu></sensor></link></model></sdf>\n";
  auto r = run_gmwm({"gap", "sim.csv.gz", "--gazebo", "axes.sdf", "--replicates", "40", "--json", "g.json", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "g.json");
  // gyro_x takes the <x> block: 0.01^2.
  EXPECT_EQ(doc["columns"][0]["baseline_model"].get<std::string>().rfind("WN(sigma2=0.0001", 0), 0u)
      << doc["columns"][0]["baseline_model"];
  EXPECT_NE(doc["columns"][0]["conversions"].dump().find("angular_velocity <x> stddev = 0.01 rad/s"), std::string::npos)
      << doc["columns"][0]["conversions"].dump();
}

TEST_F(GmwmGap, RejectsAGazeboFileWithoutImuNoiseWithOneLine) {
  // A camera's noise only: nothing to build an IMU baseline from.
  std::ofstream(dir_ / "camera.sdf") << "<sdf version=\"1.9\"><model name=\"c\"><link name=\"l\">"
                                        "<sensor name=\"cam\" type=\"camera\"><camera><noise type=\"gaussian\">"
                                        "<mean>0</mean><stddev>0.007</stddev></noise></camera></sensor>"
                                        "</link></model></sdf>\n";
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--gazebo", "camera.sdf", "--json", "x.json"}, dir_),
                   {"camera.sdf: no IMU <noise> block or RotorS/PX4 IMU plugin parameters found"}, dir_ / "x.json");
  std::ofstream(dir_ / "bad.sdf") << "<sdf>\n<model>\n</sdf>\n";
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--gazebo", "bad.sdf", "--json", "x.json"}, dir_),
                   {"bad.sdf:2: XML parse error"}, dir_ / "x.json");
}

TEST_F(GmwmGap, WritesTheSameJsonWithOneAndTwoThreads) {
  auto one = run_gmwm(
      {"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40", "--threads", "1", "--json", "1.json"}, dir_);
  auto two = run_gmwm(
      {"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40", "--threads", "2", "--json", "2.json"}, dir_);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  json a = read_json(dir_ / "1.json"), b = read_json(dir_ / "2.json");
  a.erase("run");
  b.erase("run");
  EXPECT_EQ(a, b);
}

TEST_F(GmwmGap, StopsOnAUnitMixUpNamingTheUnitsThatFit) {
  // Data in deg/s (a rad/s white noise of 1e-4 scaled by (180/pi)^2) against a Kalibr file
  // in rad/s: exit 2, one line suggesting --units gyro=deg/s, no output.
  std::ofstream(dir_ / "imu.yaml") << "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
                                      "gyroscope_noise_density: 1.0e-3\ngyroscope_random_walk: 1.0e-6\n"
                                      "update_rate: 100.0\n";
  auto s = run_gmwm({"simulate", "--model", "WN(sigma2=0.32828)+RW(gamma2=1e-9)", "--n", "16384", "--freq", "100",
                     "--names", "gyro_x", "--output", "deg.csv", "--quiet"},
                    dir_);
  ASSERT_EQ(s.exit_code, 0) << s.err;
  expect_bad_input(run_gmwm({"gap", "deg.csv", "--kalibr", "imu.yaml", "--replicates", "40", "--json", "x.json"}, dir_),
                   {"deg.csv", "gyro_x", "--units gyro=deg/s", "(deg/s per rad/s)^2 = 3283"}, dir_ / "x.json");
  // Declared, it runs; and --no-unit-check lets the user diagnose anyway.
  auto r = run_gmwm({"gap", "deg.csv", "--kalibr", "imu.yaml", "--units", "gyro=deg/s", "--replicates", "40", "--quiet",
                     "--json", "ok.json"},
                    dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_gmwm({"gap", "deg.csv", "--kalibr", "imu.yaml", "--no-unit-check", "--replicates", "40", "--quiet"}, dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(GmwmGap, AYamlAndARotorsFileWithTheSameFiguresGiveTheSameDiagnosis) {
  // The same densities in a Kalibr imu.yaml and a RotorS plugin whose bias correlation
  // time is far beyond the record (a random walk over it): one baseline, one diagnosis.
  std::ofstream(dir_ / "imu.yaml") << "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-4\n"
                                      "gyroscope_noise_density: 1.0e-3\ngyroscope_random_walk: 1.0e-5\n"
                                      "update_rate: 100.0\n";
  std::ofstream(dir_ / "imu.sdf")
      << "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\"><model name=\"m\">\n"
         "<plugin filename=\"librotors_gazebo_imu_plugin.so\" name=\"rotors_gazebo_imu_plugin\">\n"
         "  <gyroscopeNoiseDensity>1.0e-3</gyroscopeNoiseDensity>\n"
         "  <gyroscopeRandomWalk>1.0e-5</gyroscopeRandomWalk>\n"
         "  <gyroscopeBiasCorrelationTime>1.0e9</gyroscopeBiasCorrelationTime>\n"
         "  <gyroscopeTurnOnBiasSigma>0.0</gyroscopeTurnOnBiasSigma>\n"
         "  <accelerometerNoiseDensity>2.0e-3</accelerometerNoiseDensity>\n"
         "  <accelerometerRandomWalk>3.0e-4</accelerometerRandomWalk>\n"
         "  <accelerometerBiasCorrelationTime>1.0e9</accelerometerBiasCorrelationTime>\n"
         "  <accelerometerTurnOnBiasSigma>0.0</accelerometerTurnOnBiasSigma>\n"
         "</plugin>\n</model></sdf>\n";
  auto a = run_gmwm({"gap", "sim.csv.gz", "--kalibr", "imu.yaml", "--replicates", "40", "--quiet", "--json", "a.json"},
                    dir_);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  auto b =
      run_gmwm({"gap", "sim.csv.gz", "--gazebo", "imu.sdf", "--replicates", "40", "--quiet", "--json", "b.json"}, dir_);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json ja = read_json(dir_ / "a.json")["columns"][0], jb = read_json(dir_ / "b.json")["columns"][0];
  // The RotorS bias reads as a random walk over this record, said in its conversions.
  const std::string conv = jb["conversions"].dump();
  EXPECT_NE(conv.find("RW-like"), std::string::npos) << conv;
  EXPECT_EQ(ja["attribution"]["steps"], jb["attribution"]["steps"]) << ja["headline"] << "\n" << jb["headline"];
  EXPECT_EQ(ja["gap"]["detected"], jb["gap"]["detected"]);
  EXPECT_EQ(ja["shrinkage"]["levels_outside_before"], jb["shrinkage"]["levels_outside_before"]);
  EXPECT_EQ(ja["shrinkage"]["levels_outside_after"], jb["shrinkage"]["levels_outside_after"]);
  EXPECT_NEAR(ja["gap"]["p_value"].get<double>(), jb["gap"]["p_value"].get<double>(), 0.03);
}

TEST_F(GmwmGap, DrawsNoProgressBarWhenStandardErrorIsNotATerminal) {
  // The test runner's standard error is a pipe: the table is shown, the bar is not.
  auto r = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("left"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\ngyro_x: "), std::string::npos) << r.out;
}

TEST_F(GmwmGap, HeadlineIsTheSameInTheTerminalAndTheJson) {
  auto r = run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "40", "--json", "g.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = read_json(dir_ / "g.json")["columns"][0];
  const std::string h = c["headline"];
  EXPECT_NE(flowed(r.out).find("gyro_x: " + flowed(h)), std::string::npos) << r.out << "\n" << h;
  EXPECT_NE(h.find("levels outside "), std::string::npos) << h;
  const double s = c["shrinkage"]["excess_removed"];
  EXPECT_GE(s, 0.0);
  EXPECT_LE(s, 1.0);
  EXPECT_TRUE(c.contains("remaining"));
}

TEST_F(GmwmGap, RejectsBadOptionsWithOneLine) {
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--json", "x.json"}, dir_),
                   {"--model", "--kalibr", "--gazebo", "--fit"}, dir_ / "x.json");
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--model", "WN+RW", "--json", "x.json"}, dir_), {"SPEC_WITH_VALUES"},
                   dir_ / "x.json");
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--units", "gyro=g", "--json", "x.json"}, dir_),
                   {"unit 'g' for gyro"}, dir_ / "x.json");
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--model", kBase, "--replicates", "5", "--json", "x.json"}, dir_),
                   {"--replicates"}, dir_ / "x.json");
  expect_bad_input(run_gmwm({"gap", "sim.csv.gz", "--kalibr", "absent.yaml", "--json", "x.json"}, dir_),
                   {"absent.yaml"}, dir_ / "x.json");
}

}  // namespace

namespace {

TEST(GmwmGapCheck, ScoresEveryFamilyAndTheNullSideInTheContractFields) {
  const fs::path dir = gmwm::test::temp_dir("cli_gap_check");
  auto r = run_gmwm(
      {"gap-check", "--cases", "1", "--n", "16384", "--replicates", "40", "--strengths", "8", "--json", "c.json"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir / "c.json");
  EXPECT_EQ(doc.at("command"), "gap-check");
  // 8 families x 1 case, 5 base-only and 2 off-by-20% cases.
  EXPECT_EQ(doc.at("cases"), 15);
  EXPECT_LE(doc.at("correct").get<int>(), 15);
  EXPECT_GE(doc.at("false_alarms").get<int>(), 0);
  const json& confusion = doc.at("confusion");
  for (const char* t : {"QN", "DR", "AR1", "FLICKER", "SIN", "OUTLIERS", "STEP", "TRANSIENT", "none", "REPARAMETERISE"})
    EXPECT_TRUE(confusion.contains(t)) << t;
  int total = 0;
  for (const auto& [truth, row] : confusion.items())
    for (const auto& [reported, n] : row.items()) total += n.get<int>();
  EXPECT_EQ(total, 15);
  EXPECT_TRUE(doc.at("power").contains("SIN"));
  EXPECT_TRUE(doc["power"]["SIN"].contains("8"));
  EXPECT_EQ(doc.at("case_list").size(), 15u);
  EXPECT_NE(flowed(r.out).find("confusion matrix"), std::string::npos) << r.out;
  expect_bad_input(run_gmwm({"gap-check", "--strengths", "2,x", "--json", "x.json"}, dir), {"--strengths"},
                   dir / "x.json");
  expect_bad_input(run_gmwm({"gap-check", "--replicates", "3", "--json", "x.json"}, dir), {"--replicates"},
                   dir / "x.json");
  expect_bad_input(run_gmwm({"gap-check", "--families", "STEP,WOBBLE", "--json", "x.json"}, dir),
                   {"--families", "WOBBLE"}, dir / "x.json");
  expect_bad_input(run_gmwm({"gap-check", "--families", "RW", "--json", "x.json"}, dir), {"RW", "withheld"},
                   dir / "x.json");
  fs::remove_all(dir);
}

}  // namespace
