// The fleet's unit of work (fleet/fleet_record.h) and its cache (fleet/fleet_cache.h): a
// record read back gives the computed values to the last bit, a task run from its text gives
// the record of the study here, the cache key follows what decides the result and nothing
// else, and a text that is not a record is refused naming what it lacks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/fleet/fleet_cache.h"
#include "gmwm/fleet/fleet_record.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gmwm;
using namespace gmwm::fleet;

namespace {

// Bitwise equality of doubles (NaN equal to NaN of the same bits).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same(const std::vector<double>& a, const std::vector<double>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(same_bits(a[i], b[i])) << what << "[" << i << "]";
}

void expect_same(const Readoff& a, const Readoff& b) {
  for (auto [x, y] : {std::pair{a.value, b.value},
                      {a.low, b.low},
                      {a.high, b.high},
                      {a.tau, b.tau},
                      {a.region_from, b.region_from},
                      {a.region_to, b.region_to}})
    EXPECT_TRUE(same_bits(x, y));
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.how, b.how);
  ASSERT_EQ(a.sources.size(), b.sources.size());
  for (std::size_t i = 0; i < a.sources.size(); ++i) {
    EXPECT_EQ(a.sources[i].first, b.sources[i].first);
    EXPECT_TRUE(same_bits(a.sources[i].second, b.sources[i].second));
  }
}

class FleetRecordTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("fleet_record");
    write_recording("unit.csv", 1);
    recording_.path = (dir_ / "unit.csv").string();
    recording_.unit = "SN1";
    recording_.model = "IMU-X";
    recording_.units = "gyro=rad/s";
    options_.model = "AR1+WN+RW";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Two gyro axes of WN + RW + a slow AR1 at 100 Hz, 2^14 samples, with a time column.
  void write_recording(const std::string& name, std::uint64_t seed) {
    const Model m = parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-10)+AR1(phi=0.999,sigma2=1e-8)");
    const std::int64_t n = 1 << 14;
    const auto x = simulate(m, m.given_values(), n, seed, 0);
    const auto y = simulate(m, m.given_values(), n, seed, 1);
    std::ofstream out(dir_ / name);
    out.precision(17);
    out << "time,gyro_x,gyro_y\n";
    for (std::int64_t i = 0; i < n; ++i)
      out << static_cast<double>(i) / 100.0 << ',' << x[static_cast<std::size_t>(i)] << ','
          << y[static_cast<std::size_t>(i)] << '\n';
  }

  fs::path dir_;
  io::FleetRecording recording_;
  FleetStudyOptions options_;
};

TEST_F(FleetRecordTest, ARecordReadBackGivesEveryComputedValueToTheLastBit) {
  const FleetRecord r = study_fleet_recording(recording_, options_);
  ASSERT_EQ(r.status, "ok");
  ASSERT_EQ(r.axes.size(), 2u);
  const std::string text = fleet_record_text(r);
  const FleetRecord back = parse_fleet_record(text, "test");
  EXPECT_EQ(fleet_record_text(back), text);
  ASSERT_EQ(back.axes.size(), r.axes.size());
  for (std::size_t k = 0; k < r.axes.size(); ++k) {
    const FleetRow &a = r.axes[k], &b = back.axes[k];
    EXPECT_EQ(a.axis, b.axis);
    EXPECT_EQ(a.data_unit, "rad/s");
    EXPECT_EQ(a.chosen, b.chosen);
    EXPECT_EQ(a.chosen_structure, b.chosen_structure);
    EXPECT_TRUE(same_bits(a.gof_p, b.gof_p));
    EXPECT_EQ(a.n, b.n);
    EXPECT_EQ(a.first_level, 1);  // nothing repeats: auto is level 1
    EXPECT_EQ(a.first_level, b.first_level);
    ASSERT_TRUE(a.figures_known && b.figures_known);
    for (auto [fa, fb] : {std::pair{&a.figures.white, &b.figures.white},
                          {&a.figures.walk, &b.figures.walk},
                          {&a.figures.instability, &b.figures.instability}}) {
      expect_same(fa->figure, fb->figure);
      expect_same(fa->model, fb->model);
      expect_same(fa->data, fb->data);
      EXPECT_EQ(fa->source, fb->source);
      EXPECT_EQ(fa->note, fb->note);
    }
    const FleetCurves &ca = r.curves[k], &cb = back.curves[k];
    expect_same(ca.wv.wv, cb.wv.wv, "wv");
    expect_same(ca.wv.variance, cb.wv.variance, "variance");
    expect_same(ca.wv.ci_low, cb.wv.ci_low, "ci_low");
    EXPECT_EQ(ca.wv.coefficients, cb.wv.coefficients);
    EXPECT_EQ(ca.wv.n, cb.wv.n);
    expect_same(ca.adev.adev, cb.adev.adev, "adev");
    expect_same(ca.adev.edf, cb.adev.edf, "edf");
    EXPECT_EQ(ca.adev.m, cb.adev.m);
    expect_same(ca.model, cb.model, "model adev");
    EXPECT_FALSE(ca.adev.adev.empty());
  }
}

TEST_F(FleetRecordTest, ARecordWithMissingSamplesKeepsTheWindowsEachScaleReadThatMissSomeAndItsGaps) {
  // The recording less 300 samples at 50 s: its WV's deep levels and its Allan deviation's
  // long factors read windows missing samples, and the record read back says how many and
  // where the samples are missing (the joint model reads its simulated unit through them).
  std::ifstream in(dir_ / "unit.csv");
  std::ofstream out(dir_ / "gappy.csv");
  std::string line;
  for (int row = -1; std::getline(in, line); ++row)
    if (row < 5000 || row >= 5300) out << line << '\n';
  out.close();
  recording_.path = (dir_ / "gappy.csv").string();
  const FleetRecord r = study_fleet_recording(recording_, options_);
  ASSERT_EQ(r.status, "ok");
  const FleetRecord back = parse_fleet_record(fleet_record_text(r), "test");
  ASSERT_EQ(back.curves.size(), r.curves.size());
  for (std::size_t k = 0; k < r.curves.size(); ++k) {
    const FleetCurves &a = r.curves[k], &b = back.curves[k];
    ASSERT_EQ(a.wv.partial.size(), a.wv.wv.size());
    EXPECT_GT(a.wv.partial.back(), 0) << "the deepest level crosses the gap";
    EXPECT_EQ(a.wv.partial, b.wv.partial);
    ASSERT_EQ(a.adev.complete.size(), a.adev.size());
    EXPECT_EQ(a.adev.complete, b.adev.complete);
    EXPECT_EQ(a.adev.partial, b.adev.partial);
    ASSERT_EQ(a.missing.size(), 1u);
    EXPECT_EQ(a.missing.front().start, 5000);
    EXPECT_EQ(a.missing.front().length, 300);
    ASSERT_EQ(b.missing.size(), 1u);
    EXPECT_EQ(b.missing.front().start, 5000);
    EXPECT_EQ(b.missing.front().length, 300);
  }
  // Runs that do not lie on the grid of the axes' samples are refused naming the field.
  for (const char* runs : {"[[5000,300],[5100,2]]", "[[5000,0]]", "[[5000]]", "{}"}) {
    std::string text = fleet_record_text(r);
    const std::string was = "\"missing\":[[5000,300]]";
    const std::size_t at = text.find(was);
    ASSERT_NE(at, std::string::npos) << text.substr(0, 200);
    text.replace(at, was.size(), std::string("\"missing\":") + runs);
    try {
      parse_fleet_record(text, "entry.json");
      FAIL() << "took missing runs " << runs;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("entry.json: field 'missing': expected "), std::string::npos) << e.what();
    }
  }
  // A record whose counts do not match its levels (a worker's or a cache file's fault) is
  // refused naming the field, not read into a WV of mismatched arrays.
  std::string text = fleet_record_text(r);
  const std::size_t at = text.find("\"partial\":[");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 11, "7,");
  try {
    parse_fleet_record(text, "entry.json");
    FAIL() << "took a partial count too many";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("entry.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("partial"), std::string::npos) << e.what();
  }
}

TEST_F(FleetRecordTest, ATaskRunFromItsTextGivesTheRecordOfTheStudyHere) {
  FleetRecord here = study_fleet_recording(recording_, options_);
  FleetRecord there = parse_fleet_record(run_fleet_task(fleet_task_text(recording_, options_)), "task");
  here.seconds = there.seconds = 0.0;  // wall times differ; nothing else may
  for (auto* r : {&here, &there})
    for (FleetRow& row : r->axes) row.seconds = 0.0;
  EXPECT_EQ(fleet_record_text(there), fleet_record_text(here));
}

TEST_F(FleetRecordTest, ARecordingThatCannotBeReadIsARecordWithItsReason) {
  std::ofstream(dir_ / "bad.csv") << "time,gyro_x\n0,1\n0.01,oops\n";
  io::FleetRecording bad = recording_;
  bad.path = (dir_ / "bad.csv").string();
  const FleetRecord r = parse_fleet_record(run_fleet_task(fleet_task_text(bad, options_)), "task");
  EXPECT_TRUE(r.axes.empty());
  EXPECT_NE(r.status.find("bad.csv"), std::string::npos) << r.status;
  EXPECT_NE(r.status, "ok");
}

TEST_F(FleetRecordTest, OptionsThatATaskCannotCarryAreRefusedBeforeAnyWork) {
  FleetStudyOptions o = options_;
  o.select.fit.omega_matrix = Eigen::MatrixXd::Identity(3, 3);
  try {
    fleet_task_text(recording_, o);
    FAIL() << "a caller-given Omega was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("omega_matrix"), std::string::npos) << e.what();
  }
}

TEST_F(FleetRecordTest, ATextThatIsNotARecordIsRefusedNamingTheFieldItLacks) {
  const std::string text = fleet_record_text(study_fleet_recording(recording_, options_));
  for (const auto& [broken, mention] : std::vector<std::pair<std::string, std::string>>{
           {"{not json", "not JSON"},
           {R"({"version": )" + std::to_string(kFleetRecordVersion) + R"(, "status": "ok"})", "'freq'"},
           {R"({"version": 99})", "'version'"},
           {text.substr(0, text.size() / 2), "not JSON"}}) {
    try {
      parse_fleet_record(broken, "entry.json");
      FAIL() << "took " << broken.substr(0, 40);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("entry.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  }
}

TEST_F(FleetRecordTest, TheCacheKeyFollowsTheContentTheReadingAndTheOptionsButNotThePathOrTheUnitId) {
  const FleetCache cache((dir_ / "cache").string());
  const std::string key = cache.key(recording_, options_);
  EXPECT_EQ(key.size(), 64u);
  // The same bytes elsewhere, under another unit id: the same key.
  fs::copy_file(dir_ / "unit.csv", dir_ / "copy.csv");
  io::FleetRecording moved = recording_;
  moved.path = (dir_ / "copy.csv").string();
  moved.unit = "SN-other";
  EXPECT_EQ(cache.key(moved, options_), key);
  // Another content, another reading, other options: other keys.
  write_recording("other.csv", 2);
  io::FleetRecording other = recording_;
  other.path = (dir_ / "other.csv").string();
  EXPECT_NE(cache.key(other, options_), key);
  io::FleetRecording deg = recording_;
  deg.units = "gyro=deg/s";
  EXPECT_NE(cache.key(deg, options_), key);
  FleetStudyOptions seeded = options_;
  seeded.select.seed = 7;
  EXPECT_NE(cache.key(recording_, seeded), key);
  FleetStudyOptions more_memory = options_;
  more_memory.memory_budget = 1e6;  // how, not what, is computed
  EXPECT_EQ(cache.key(recording_, more_memory), key);
}

TEST_F(FleetRecordTest, TheCacheHoldsAnEntryWholeAndForgetsIt) {
  const FleetCache cache((dir_ / "a" / "b").string());
  EXPECT_FALSE(cache.load("0123").has_value());
  cache.store("0123", "{\"x\": 1}");
  ASSERT_TRUE(cache.load("0123").has_value());
  EXPECT_EQ(*cache.load("0123"), "{\"x\": 1}");
  cache.forget("0123");
  EXPECT_FALSE(cache.load("0123").has_value());
  EXPECT_FALSE(FleetCache("").load("0123").has_value());
}

TEST(FleetCacheHash, IsTheSha256OfTheBytes) {
  // FIPS 180-2 test vectors.
  EXPECT_EQ(text_sha256("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(text_sha256(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  const fs::path dir = gmwm::test::temp_dir("fleet_hash");
  std::ofstream(dir / "abc") << "abc";
  EXPECT_EQ(file_sha256((dir / "abc").string()), text_sha256("abc"));
  EXPECT_THROW(file_sha256((dir / "missing").string()), InputError);
  fs::remove_all(dir);
}

TEST_F(FleetRecordTest, AGapBaselineTravelsInTheTaskAndItsVerdictInTheRecord) {
  FleetStudyOptions o = options_;
  FleetGapBaseline g;
  g.format = io::SimFormat::kDatasheet;
  g.name = "sheet.yaml";  // never read: the text travels
  g.text = "gyroscope:\n  noise_density: 0.001 rad/s/sqrt(Hz)\n  rate_random_walk: 0.0001 rad/s^2/sqrt(Hz)\n";
  g.replicates = 40;
  o.gap = g;
  const std::string task = fleet_task_text(recording_, o);
  const FleetRecord r = parse_fleet_record(run_fleet_task(task), "task");
  ASSERT_EQ(r.axes.size(), 2u);
  for (const FleetRow& row : r.axes) {
    EXPECT_FALSE(row.gap_verdict.empty());
    EXPECT_FALSE(row.gap_headline.empty());
    EXPECT_TRUE(std::isfinite(row.gap_p));
  }
  EXPECT_EQ(fleet_record_text(parse_fleet_record(fleet_record_text(r), "back")), fleet_record_text(r));
  // The baseline's text is part of the cache key; its file name is not read.
  const FleetCache cache((dir_ / "c").string());
  FleetStudyOptions other = o;
  other.gap->text += "  bias_instability: 0.001 rad/s\n";
  EXPECT_NE(cache.key(recording_, other), cache.key(recording_, o));
  EXPECT_NE(cache.key(recording_, o), cache.key(recording_, options_));
  // A unit mix-up or a missing sensor is each axis's "not diagnosed", the selection kept.
  FleetStudyOptions accel_only = o;
  accel_only.gap->text = "accelerometer:\n  noise_density: 0.001 m/s^2/sqrt(Hz)\n";
  const FleetRecord n = parse_fleet_record(run_fleet_task(fleet_task_text(recording_, accel_only)), "task");
  ASSERT_EQ(n.status, "ok");
  for (const FleetRow& row : n.axes) {
    EXPECT_EQ(row.gap_verdict, "not diagnosed");
    EXPECT_FALSE(row.chosen.empty());
  }
}

// A unit whose driver holds its samples (each 50 Hz measurement copied once at 100 Hz) is
// selected, and diagnosed, above the scales the copies smooth (the first level auto, the
// default), as gmwm select --first-level auto and gmwm gap would: the row says where, the
// task carries the level, and the cache key follows it.
TEST_F(FleetRecordTest, AUnitWhoseSamplesAreHeldIsSelectedAndDiagnosedAboveTheScalesTheySmooth) {
  const Model m = parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-10)");
  const std::int64_t n = 1 << 14;
  const auto x = simulate(m, m.given_values(), n / 2, 21, 0);
  const auto y = simulate(m, m.given_values(), n, 21, 1);
  {
    std::ofstream out(dir_ / "held.csv");
    out.precision(17);
    out << "time,gyro_x,gyro_y\n";
    for (std::int64_t i = 0; i < n; ++i)
      out << static_cast<double>(i) / 100.0 << ',' << x[static_cast<std::size_t>(i / 2)] << ','
          << y[static_cast<std::size_t>(i)] << '\n';
  }
  io::FleetRecording held = recording_;
  held.path = (dir_ / "held.csv").string();
  FleetStudyOptions o = options_;
  o.model = "WN+RW";
  FleetGapBaseline g;
  g.format = io::SimFormat::kDatasheet;
  g.name = "sheet.yaml";
  g.text = "gyroscope:\n  noise_density: 0.001 rad/s/sqrt(Hz)\n  rate_random_walk: 0.0001 rad/s^2/sqrt(Hz)\n";
  g.replicates = 40;
  o.gap = g;
  const FleetRecord r = parse_fleet_record(run_fleet_task(fleet_task_text(held, o)), "task");
  ASSERT_EQ(r.status, "ok");
  ASSERT_EQ(r.axes.size(), 2u);
  EXPECT_GE(r.axes[0].first_level, 5) << r.axes[0].axis;  // above the copies' smoothed levels 1-4
  EXPECT_NE(r.axes[0].gap_headline.find("compared from level " + std::to_string(r.axes[0].first_level)),
            std::string::npos)
      << r.axes[0].gap_headline;
  EXPECT_EQ(r.axes[1].first_level, 1);  // its own samples
  EXPECT_EQ(r.axes[1].gap_headline.find("compared from level"), std::string::npos);
  FleetStudyOptions every = o;
  every.first_level = 1;
  const FleetRecord e = study_fleet_recording(held, every);
  EXPECT_EQ(e.axes[0].first_level, 1);
  const FleetCache cache((dir_ / "c").string());
  EXPECT_NE(cache.key(held, every), cache.key(held, o));
  every.first_level = 63;
  EXPECT_NE(every.Validate().find("first level: found 63, expected auto or a whole number from 1 to 62"),
            std::string::npos)
      << every.Validate();
}

}  // namespace
