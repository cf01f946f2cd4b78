// gmwm stability (issue 48): the deviations of a file's columns on the command line, their
// JSON against Stable32's values for the NBS14 1000-point set, the terminal table, and the
// refusals (exit 2, one line naming what was expected, nothing written).
#include <gtest/gtest.h>

#include <cstdint>
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

class StabilityCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("stability_cli");
    // NBS14's 1000-point set as fractional frequency at 1 Hz, its stamps in seconds.
    std::string csv = "time [s],y\n";
    std::int64_t n = 1234567890;
    for (int i = 0; i < 1000; ++i) {
      char line[64];
      std::snprintf(line, sizeof line, "%d,%.17g\n", i, static_cast<double>(n) / 2147483647.0);
      csv += line;
      n = (16807 * n) % 2147483647;
    }
    gmwm::test::write_text(dir_ / "nbs.csv", csv);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The run's exit code 2, its one line holding `why`, nothing written.
  void expect_refused(const std::vector<std::string>& args, const std::string& why) {
    const auto r = run_gmwm(args, dir_);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  }

  fs::path dir_;
};

TEST_F(StabilityCommand, WritesEachKindsDeviationAtTheAskedTausAsStable32Gives) {
  const auto r = run_gmwm(
      {"stability", "nbs.csv", "--kind", "oadev,mdev,totdev", "--taus", "1,10,99", "--json", "out.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "out.json");
  EXPECT_EQ(doc["command"], "stability");
  EXPECT_EQ(doc["data"], "rate");
  EXPECT_EQ(doc["kinds"], json({"oadev", "mdev", "totdev"}));
  EXPECT_EQ(doc["phase_points"], 1001);
  const json& d = doc["columns"][0]["deviations"];
  // Stable32 1.60 on the set's phase (AF 1, 10, 99), as printed.
  const std::vector<std::pair<std::string, std::vector<double>>> stable32 = {
      {"oadev", {2.9223e-01, 9.1600e-02, 3.2616e-02}},
      {"mdev", {2.9223e-01, 6.1724e-02, 2.1850e-02}},
      {"totdev", {2.9223e-01, 9.1347e-02, 3.4106e-02}}};
  for (const auto& [kind, values] : stable32) {
    ASSERT_TRUE(d.contains(kind)) << kind;
    EXPECT_EQ(d[kind]["m"], json({1, 10, 99}));
    EXPECT_EQ(d[kind]["tau"], json({1.0, 10.0, 99.0}));
    for (std::size_t k = 0; k < values.size(); ++k)
      EXPECT_NEAR(d[kind]["value"][k].get<double>(), values[k], 0.5e-4 * values[k]) << kind << " " << k;
  }
  EXPECT_EQ(d["oadev"]["n"], json({999, 981, 803}));
  EXPECT_TRUE(d["oadev"]["unit"].is_null());
  // Each value's interval, Stable32's at tau = 1 s (its one-sigma "0.683", white FM).
  EXPECT_NEAR(doc["confidence"].get<double>(), 0.6827, 1e-4);
  EXPECT_EQ(doc["interval_method"], "stable32");
  EXPECT_TRUE(doc["noise_alpha"].is_null());
  EXPECT_NEAR(d["oadev"]["ci_low"][0].get<double>(), 2.8515e-01, 0.5e-5);
  EXPECT_NEAR(d["oadev"]["ci_high"][0].get<double>(), 2.9987e-01, 0.5e-5);
  EXPECT_NEAR(d["totdev"]["ci_low"][0].get<double>(), 2.8707e-01, 0.5e-5);
  EXPECT_EQ(d["oadev"]["alpha"][0], 0);
  EXPECT_EQ(d["oadev"]["noise"][0], "white FM");
  EXPECT_EQ(d["oadev"]["noise_id"][0], "acf");
  EXPECT_EQ(d["mdev"]["noise_id"][2], "b1+rn");  // 11 decimated points at 99 s
  for (const auto& [kind, curve] : d.items())
    for (std::size_t k = 0; k < curve["value"].size(); ++k) {
      EXPECT_LT(curve["ci_low"][k].get<double>(), curve["value"][k].get<double>()) << kind;
      EXPECT_GT(curve["ci_high"][k].get<double>(), curve["value"][k].get<double>()) << kind;
      EXPECT_GT(curve["edf"][k].get<double>(), 0.0) << kind;
    }
  // The terminal: per kind a table of tau, value, interval, degrees of freedom and noise;
  // what the interval is said below.
  EXPECT_NE(r.out.find("y: stability deviations, tau0 = 1 s, 1001 phase points"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tau [s]  oadev [U]       low      high    edf               noise"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("      1    0.29223   0.28515   0.29987    782      white FM (acf)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("flicker PM (b1+rn)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("U: the data's unit (--units declares it)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("low, high: the 68.27% chi-square interval (stable32 quantiles) from edf"), std::string::npos)
      << r.out;
}

TEST_F(StabilityCommand, AGivenNoiseAndExactQuantilesChangeTheIntervalsAsStable32sFixedAlphaRuns) {
  // At 128 s (7 averaged frequencies) B1 reads flicker PM; Stable32 1.60 printed white FM's
  // interval, 0.023045 .. 0.037027: --noise-alpha 0 gives it (within its 2.5e-4 of the
  // asymptotic edf, confidence_test.cc). --intervals exact moves the 1 s ends (782 degrees of
  // freedom) by under 0.3%.
  ASSERT_EQ(run_gmwm({"stability", "nbs.csv", "--taus", "1,128", "--json", "id.json"}, dir_).exit_code, 0);
  ASSERT_EQ(run_gmwm({"stability", "nbs.csv", "--taus", "1,128", "--noise-alpha", "0", "--json", "fixed.json"}, dir_)
                .exit_code,
            0);
  ASSERT_EQ(run_gmwm({"stability", "nbs.csv", "--taus", "1,128", "--intervals", "exact", "--json", "exact.json"}, dir_)
                .exit_code,
            0);
  const json id = read_json(dir_ / "id.json"), fixed = read_json(dir_ / "fixed.json"),
             exact = read_json(dir_ / "exact.json");
  const json& a = id["columns"][0]["deviations"]["oadev"];
  const json& f = fixed["columns"][0]["deviations"]["oadev"];
  EXPECT_EQ(a["alpha"], json({0, 1}));
  EXPECT_EQ(f["alpha"], json({0, 0}));
  EXPECT_EQ(f["noise_id"], json({"fixed", "fixed"}));
  EXPECT_EQ(fixed["noise_alpha"], 0);
  EXPECT_NEAR(f["ci_low"][1].get<double>(), 0.023045, 2.5e-4 * 0.023045);
  EXPECT_NEAR(f["ci_high"][1].get<double>(), 0.037027, 2.5e-4 * 0.037027);
  const json& e = exact["columns"][0]["deviations"]["oadev"];
  EXPECT_EQ(exact["interval_method"], "exact");
  EXPECT_NE(e["ci_low"][0].get<double>(), a["ci_low"][0].get<double>());
  EXPECT_NEAR(e["ci_low"][0].get<double>(), a["ci_low"][0].get<double>(), 0.003 * 0.29223);
}

TEST_F(StabilityCommand, Theo1sTimesAreThreeQuartersOfItsFactorsAndItsTableRowsReadThem) {
  const auto r =
      run_gmwm({"stability", "nbs.csv", "--kind", "theo1", "--taus", "7.5,15", "--json", "theo1.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json d = read_json(dir_ / "theo1.json")["columns"][0]["deviations"];
  EXPECT_EQ(d["theo1"]["m"], json({10, 20}));
  EXPECT_EQ(d["theo1"]["tau"], json({7.5, 15.0}));
  EXPECT_TRUE(d["theo1"]["ci_low"][0].is_null());  // no published interval rule
  // oadev reads 7.5 s as no whole number of periods
  expect_refused({"stability", "nbs.csv", "--kind", "oadev", "--taus", "7.5", "--json", "out.json"},
                 "--taus: 7.5 s is not a whole number of sampling periods of 1 s");
  expect_refused({"stability", "nbs.csv", "--kind", "theo1", "--taus", "1", "--json", "out.json"},
                 "--taus: 1 s is not a whole number of theo1's steps of 0.75 s");
}

TEST_F(StabilityCommand, TheOctavesStopAtEachKindsLargestFactorAndTdevCarriesThePhasesUnit) {
  const auto r =
      run_gmwm({"stability", "nbs.csv", "--kind", "oadev,tdev", "--units", "deg/s", "--json", "out.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json d = read_json(dir_ / "out.json")["columns"][0]["deviations"];
  EXPECT_EQ(d["oadev"]["m"], json({1, 2, 4, 8, 16, 32, 64, 128, 256}));  // up to (1001 - 1) / 2
  EXPECT_EQ(d["tdev"]["m"], json({1, 2, 4, 8, 16, 32, 64, 128, 256}));   // up to 1001 / 3
  EXPECT_EQ(d["oadev"]["unit"], "deg/s");
  EXPECT_EQ(d["tdev"]["unit"], "(deg/s)*s");
}

TEST_F(StabilityCommand, PhaseDataGiveTheDeviationsOfTheFrequencyTheyIntegrate) {
  // The set's phase (x_0 = 0, x_{i+1} = x_i + y_i) read with --data phase: its first
  // differences are the frequencies again, so every deviation is the rate file's.
  std::string csv = "time [s],x\n0,0\n";
  std::int64_t n = 1234567890;
  long double x = 0.0L;
  for (int i = 0; i < 1000; ++i) {
    x += static_cast<long double>(n) / 2147483647.0L;
    char line[64];
    std::snprintf(line, sizeof line, "%d,%.17g\n", i + 1, static_cast<double>(x));
    csv += line;
    n = (16807 * n) % 2147483647;
  }
  gmwm::test::write_text(dir_ / "phase.csv", csv);
  const std::vector<std::string> kinds = {"--kind", "adev,oadev,mdev,tdev,hdev,ohdev,totdev", "--taus", "decade"};
  std::vector<std::string> rate = {"stability", "nbs.csv", "--json", "rate.json"};
  std::vector<std::string> phase = {"stability", "phase.csv", "--data", "phase", "--json", "phase.json"};
  rate.insert(rate.end(), kinds.begin(), kinds.end());
  phase.insert(phase.end(), kinds.begin(), kinds.end());
  ASSERT_EQ(run_gmwm(rate, dir_).exit_code, 0);
  const auto r = run_gmwm(phase, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json a = read_json(dir_ / "rate.json")["columns"][0]["deviations"];
  const json b = read_json(dir_ / "phase.json");
  EXPECT_EQ(b["data"], "phase");
  for (const auto& [kind, curve] : a.items()) {
    const json& other = b["columns"][0]["deviations"][kind];
    ASSERT_EQ(other["m"], curve["m"]) << kind;
    for (std::size_t k = 0; k < curve["value"].size(); ++k)  // the phase's 17 digits, differenced
      EXPECT_NEAR(other["value"][k].get<double>() / curve["value"][k].get<double>(), 1.0, 1e-9) << kind << " " << k;
  }
}

TEST_F(StabilityCommand, ARateWithALargeOffsetGivesTheDeviationsOfItsFluctuations) {
  // The set plus 1e6 (a clock's frequency offset, a gyroscope's bias): its phase grows to
  // 1e9, where a double keeps 1e-7 of the steps it differences; the study removes the mean
  // rate first, so every deviation is the set's to the file's own digits.
  std::string csv = "time [s],y\n";
  std::int64_t n = 1234567890;
  for (int i = 0; i < 1000; ++i) {
    char line[64];
    std::snprintf(line, sizeof line, "%d,%.17g\n", i, 1e6 + static_cast<double>(n) / 2147483647.0);
    csv += line;
    n = (16807 * n) % 2147483647;
  }
  gmwm::test::write_text(dir_ / "offset.csv", csv);
  const std::vector<std::string> kinds = {"--kind", "adev,oadev,mdev,hdev,ohdev,totdev", "--json"};
  std::vector<std::string> plain = {"stability", "nbs.csv"}, offset = {"stability", "offset.csv"};
  plain.insert(plain.end(), kinds.begin(), kinds.end());
  offset.insert(offset.end(), kinds.begin(), kinds.end());
  plain.push_back("plain.json");
  offset.push_back("offset.json");
  ASSERT_EQ(run_gmwm(plain, dir_).exit_code, 0);
  ASSERT_EQ(run_gmwm(offset, dir_).exit_code, 0);
  const json a = read_json(dir_ / "plain.json")["columns"][0]["deviations"];
  const json b = read_json(dir_ / "offset.json")["columns"][0]["deviations"];
  for (const auto& [kind, curve] : a.items())
    for (std::size_t k = 0; k < curve["value"].size(); ++k)  // 1e6 + y keeps y to ~1e-10 in the file
      EXPECT_NEAR(b[kind]["value"][k].get<double>() / curve["value"][k].get<double>(), 1.0, 1e-8) << kind << " " << k;
}

// 2^19 samples need 8 MB at 16 bytes a value: --memory 4 sends the record to a temporary
// file, and its phase follows; every value, interval and noise is the same as in memory, and a
// kind that keeps arrays as long as the record is refused naming the kinds that do not.
TEST_F(StabilityCommand, ARecordBeyondTheMemoryBudgetGivesTheSameDeviationsAsInMemory) {
  std::string csv = "y\n";
  std::uint64_t state = 48;
  for (int i = 0; i < (1 << 19); ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // Knuth's MMIX LCG
    csv += std::to_string(static_cast<double>(state >> 11) / 9007199254740992.0 + 1e-6 * i) + "\n";
  }
  gmwm::test::write_text(dir_ / "long.csv", csv);
  const std::vector<std::string> args = {
      "stability", "long.csv", "--freq", "10", "--kind", "adev,oadev,mdev,tdev,hdev,ohdev,totdev,tierms", "--quiet"};
  auto in_memory = args, spilled = args;
  in_memory.insert(in_memory.end(), {"--json", "a.json"});
  spilled.insert(spilled.end(), {"--memory", "4", "--json", "b.json"});
  ASSERT_EQ(run_gmwm(in_memory, dir_).exit_code, 0);
  const auto r = run_gmwm(spilled, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json a = read_json(dir_ / "a.json"), b = read_json(dir_ / "b.json");
  a.erase("run");
  b.erase("run");
  EXPECT_EQ(a, b);
  EXPECT_EQ(b["columns"][0]["deviations"].size(), 8u);
  expect_refused(
      {"stability", "long.csv", "--freq", "10", "--kind", "adev,mtotdev", "--memory", "4", "--json", "out.json"},
      "long.csv: column 'y': its 524288 samples are beyond the memory budget (--memory), and mtotdev keeps "
      "working arrays as long as the record in memory; the kinds read in bounded memory are adev, oadev, "
      "mdev, tdev, hdev, ohdev, totdev and tierms (or raise --memory)");
}

TEST_F(StabilityCommand, EveryFactorOfALongRecordIsReadWhereItsWorkIsBounded) {
  // 2^17 samples: every ADEV and HDEV factor (65536 and 43690 of them, N / m points each)
  // reads 2.9e6 points; every OADEV factor 8.6e9, within the 2^39 (pipeline::kMaxAllTausWork).
  // The noise fixed: identified, the factors beyond N / 30 that B1 reads as phase noise each
  // take R(n) over the whole phase (about 10 s here; docs/stability.md).
  std::string csv = "y\n";
  for (int i = 0; i < (1 << 17); ++i) csv += std::to_string((i * 7919) % 13) + "\n";
  gmwm::test::write_text(dir_ / "long.csv", csv);
  const auto r = run_gmwm({"stability", "long.csv", "--freq", "1", "--kind", "adev,hdev", "--taus", "all",
                           "--noise-alpha", "0", "--json", "out.json", "--quiet"},
                          dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "out.json");
  const json& d = doc["columns"][0]["deviations"];
  EXPECT_EQ(d["adev"]["tau"].size(), 65536u);
  EXPECT_EQ(d["hdev"]["tau"].size(), 43690u);
  EXPECT_EQ(d["adev"]["tau"].back(), 65536.0);
}

TEST_F(StabilityCommand, RefusesWhatItCannotComputeInOneLineWritingNothing) {
  expect_refused({"stability", "nbs.csv", "--kind", "allan", "--json", "out.json"},
                 "--kind: found 'allan', expected adev, oadev, mdev, tdev, hdev, ohdev");
  expect_refused({"stability", "nbs.csv", "--confidence", "1", "--json", "out.json"},
                 "--confidence: found 1, expected a number between 0 and 1");
  expect_refused({"stability", "nbs.csv", "--noise-alpha", "-5", "--json", "out.json"},
                 "--noise-alpha: found -5, expected an integer from -4 (random-run FM) to 2 (white PM)");
  expect_refused({"stability", "nbs.csv", "--intervals", "fast", "--json", "out.json"},
                 "--intervals: found 'fast', expected stable32 or exact");
  expect_refused({"stability", "nbs.csv", "--taus", "1,2.5", "--json", "out.json"},
                 "--taus: 2.5 s is not a whole number of sampling periods of 1 s");
  expect_refused({"stability", "nbs.csv", "--kind", "hdev", "--taus", "400", "--json", "out.json"},
                 "--taus: 400 s is 400 periods, beyond hdev's largest 333 on 1001 phase points (333 s)");
  expect_refused({"stability", "nbs.csv", "--taus", "1e300", "--json", "out.json"},
                 "--taus: 1e+300 s is 1e+300 periods, beyond oadev's largest 500 on 1001 phase points (500 s)");
  expect_refused({"stability", "nbs.csv", "--taus", "fortnight", "--json", "out.json"},
                 "--taus: found 'fortnight', expected all, octave, decade or averaging times in seconds");
  expect_refused({"stability", "nbs.csv", "--kind", "mdev,mdev", "--json", "out.json"}, "--kind: mdev given twice");
  expect_refused({"stability", "nbs.csv", "--taus", "2,1", "--json", "out.json"},
                 "--taus: expected increasing averaging times, found 1 s after 2 s");
  expect_refused({"stability", "nbs.csv", "--taus", "1,1.0000000001", "--json", "out.json"},
                 "--taus: 1.0000000001 s is the averaging factor 1 again (1 s)");
  expect_refused({"stability", "nbs.csv", "--taus", "", "--json", "out.json"},
                 "--taus: found '', expected all, octave, decade or averaging times in seconds");
  // Every factor of a long record, beyond the points read for all (2^39): Theo1's 65536
  // factors of 2^17 samples, each N min(m / 2, log2(m)^2) points.
  std::string big = "y\n";
  for (int i = 0; i < (1 << 17); ++i) big += std::to_string(i % 5) + "\n";
  gmwm::test::write_text(dir_ / "big.csv", big);
  expect_refused({"stability", "big.csv", "--freq", "100", "--kind", "theo1", "--taus", "all", "--json", "out.json"},
                 "big.csv: --taus all: the 65532 averaging factors of 131073 phase points read 1.5e+13 points, beyond "
                 "the 5.5e+11 read for every factor (about 3.5 minutes); give octave, decade, a list of times or fewer "
                 "kinds");
  // A record with missing samples: the deviations read a regular record.
  std::string csv = "time [s],y\n";
  for (int i = 0; i < 200; ++i)
    if (i < 50 || i > 60) csv += std::to_string(i) + "," + std::to_string(i % 7) + "\n";
  gmwm::test::write_text(dir_ / "gappy.csv", csv);
  expect_refused({"stability", "gappy.csv", "--json", "out.json"},
                 "gappy.csv: 11 samples missing in 1 gaps of the timestamps 'time [s]'; gmwm stability reads a "
                 "regular record: give --gaps join");
}

}  // namespace
