// gmwm fleet (issue 30): every recording of a manifest analysed as `gmwm select` would, one
// row per unit x axis; the manifest's bad rows refused up front, one line each; a recording
// that fails is a row with its reason, never a stopped run.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr const char* kTruth = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";

class GmwmFleet : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_fleet");
    for (int k = 1; k <= 3; ++k) {
      auto r = run_gmwm(
          {"simulate", "--model", kTruth, "--n", "16384", "--freq", "100", "--signals", "2", "--names", "gyro_x,gyro_y",
           "--seed", std::to_string(k), "--output", "unit" + std::to_string(k) + ".csv", "--quiet"},
          dir_);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  fs::path dir_;
};

TEST_F(GmwmFleet, GivesEachUnitAndAxisTheNumbersSelectGivesItsRecording) {
  write("fleet.csv",
        "path,unit,model,units\n"
        "unit1.csv,SN1,IMU-X,\"gyro=rad/s\"\n"
        "unit2.csv,SN2,IMU-X,\"gyro=rad/s\"\n"
        "unit3.csv,SN3,IMU-X,\"gyro=rad/s\"\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "AR1+WN+RW", "--csv", "table.csv", "--json", "fleet.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fleet.json");
  EXPECT_EQ(doc.at("command"), "fleet");
  EXPECT_EQ(doc.at("failed"), 0);
  ASSERT_EQ(doc.at("rows").size(), 6u);  // 3 units x 2 axes
  for (int k = 1; k <= 3; ++k) {
    const std::string unit = "unit" + std::to_string(k) + ".csv";
    auto s = run_gmwm({"select", unit, "--model", "AR1+WN+RW", "--units", "gyro=rad/s", "--json", "s.json", "--quiet"},
                      dir_);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const json sel = read_json(dir_ / "s.json");
    for (int a = 0; a < 2; ++a) {
      const json& row = doc["rows"][static_cast<std::size_t>(2 * (k - 1) + a)];
      const json& col = sel["columns"][static_cast<std::size_t>(a)];
      EXPECT_EQ(row.at("unit"), "SN" + std::to_string(k));
      EXPECT_EQ(row.at("axis"), col.at("name"));
      EXPECT_EQ(row.at("unit_of_data"), "rad/s");
      EXPECT_EQ(row.at("status"), "ok");
      EXPECT_EQ(row.at("chosen"), col.at("best_model"));
      for (const auto& [figure, key] : {std::pair{"N", "white"}, {"K", "walk"}, {"B", "instability"}})
        EXPECT_EQ(row.at(figure).at("value"), col.at("noise_figures").at(key).at("value")) << figure;
      EXPECT_EQ(row.at("gof_p_value"), col.at("best_fit").at("gof").at("p_value"));
    }
  }
  // The table: a header and one line per row, each saying the level its figures are read from.
  const std::string table = gmwm::test::read_text(dir_ / "table.csv");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 7);
  EXPECT_NE(table.find(",n,first_level,N,"), std::string::npos) << table.substr(0, 200);
  EXPECT_EQ(table.rfind("unit,model,group,path,axis,unit_of_data,status,chosen,", 0), 0u);
}

TEST_F(GmwmFleet, RefusesTheManifestsBadRowsUpFrontOneLineEachNamingTheRow) {
  write("fleet.csv",
        "path,unit,model,columns,units\n"
        "unit1.csv,SN1,IMU-X,,\n"
        "missing.csv,SN2,IMU-X,,\n"
        "unit2.csv,SN3,IMU-X,gyro_q,\n"
        "unit3.csv,SN4,IMU-X,,gyro=dge/s\n"
        "unit3.csv,SN1,IMU-X,,\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "fleet.json"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "fleet.json"));
  for (const char* line :
       {"fleet.csv:3: ", "fleet.csv:4: ", "fleet.csv:5: units: ", "fleet.csv:6: unit 'SN1' given twice"})
    EXPECT_NE(r.err.find(std::string("gmwm: error: ") + line), std::string::npos) << line << "\n" << r.err;
  EXPECT_NE(r.err.find("gyro_q"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("fleet.csv:2: "), std::string::npos) << r.err;  // the good row is not named
  EXPECT_NE(r.err.find("4 row(s) of the manifest refused; nothing analysed"), std::string::npos) << r.err;
}

TEST_F(GmwmFleet, RefusesAManifestWithOneBadRowInOneLine) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN1,IMU-X\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(r, {"fleet.csv:3: unit 'SN1' given twice (first at row 2); nothing analysed"},
                               dir_ / "f.json");
}

TEST_F(GmwmFleet, SaysAtMostAHundredBadRowsAndHowManyMore) {
  std::string manifest = "path,unit,model\n";
  for (int k = 0; k < 151; ++k) manifest += "unit1.csv,SN1,IMU-X\n";  // 150 copies of the first unit
  write("fleet.csv", manifest);
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 102) << r.err;
  EXPECT_NE(r.err.find("gmwm: error: ... and 50 more bad row(s)\n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("150 row(s) of the manifest refused"), std::string::npos) << r.err;
}

TEST_F(GmwmFleet, RefusesAUnitNameWithAControlByteBeforeItReachesAnOutput) {
  write("fleet.csv", "path,unit,model\nunit1.csv,\"SN\x1b[31m1\",IMU-X\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--csv", "t.csv"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("fleet.csv:2: unit: found a control character in 'SN\\x1B[31m1', expected printable text"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "t.csv"));
}

// Issue 42 item 14: a field of 2 MB made the terminal table take 28.6 s. A field is at most
// io::kMaxManifestFieldBytes (4096, a path's longest), a longer one refused up front in one
// line naming its row and field, in CSV and in YAML.
TEST_F(GmwmFleet, RefusesAManifestFieldLongerThanAPathInOneLineNamingTheRowAndField) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN" + std::string(2 << 20, '2') + ",IMU-X\n");
  const auto t0 = std::chrono::steady_clock::now();
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json"}, dir_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  gmwm::test::expect_bad_input(r, {"fleet.csv:3: unit: found 2097154 bytes, expected at most 4096"}, dir_ / "f.json");
  EXPECT_LT(seconds, 2.0);  // read and refused: no analysis, no table
  write("fleet.yaml",
        "recordings:\n  - {path: unit1.csv, unit: SN1, model: IMU-X, group: " + std::string(4097, 'g') + "}\n");
  auto y = run_gmwm({"fleet", "fleet.yaml", "--model", "WN+RW", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(y, {"fleet.yaml:2: group: found 4097 bytes, expected at most 4096"}, dir_ / "f.json");
  // At the cap: analysed, the name whole in the JSON.
  write("fleet.csv", "path,unit,model,group\nunit1.csv,SN1,IMU-X," + std::string(4096, 'g') + "\n");
  auto ok = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json", "--no-cache"}, dir_);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(read_json(dir_ / "f.json")["rows"][0].at("group"), std::string(4096, 'g'));
}

// Names reach the JSON as UTF-8: bytes that are not UTF-8 were replaced there (U+FFFD) and
// kept raw in the CSV, so two units "SN\xFF1" and "SN\xFE1" were one unit in the JSON.
TEST_F(GmwmFleet, RefusesANameThatIsNotUtf8BeforeItReachesAnOutput) {
  write("fleet.csv",
        "path,unit,model\nunit1.csv,SN\xFF"
        "1,IMU-X\nunit2.csv,SN\xFE"
        "1,IMU-X\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json", "--csv", "f.csv"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("gmwm: error: fleet.csv:2: unit: found bytes that are not UTF-8 in 'SN\\xFF1', expected UTF-8 "
                       "text"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("gmwm: error: fleet.csv:3: unit: found bytes that are not UTF-8 in 'SN\\xFE1'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "f.json"));
  EXPECT_FALSE(fs::exists(dir_ / "f.csv"));
  // A model or group cut inside a character (a lead byte without its continuation).
  write("fleet.csv", "path,unit,model,group\nunit1.csv,SN1,IMU-X,line-\xC3\n");
  auto g = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(g, {"fleet.csv:2: group: found bytes that are not UTF-8"}, dir_ / "f.json");
  // UTF-8 names are names: kept whole in every output.
  write("fleet.csv", "path,unit,model\nunit1.csv,SN-\xC3\xA9\xE2\x82\xAC,IMU-X\n");
  auto ok = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json", "--no-cache"}, dir_);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(read_json(dir_ / "f.json")["rows"][0].at("unit"), "SN-\xC3\xA9\xE2\x82\xAC");
}

// A manifest saved by a spreadsheet as "CSV UTF-8" begins with a byte-order mark: read as
// the text after it (it was refused with the mark unseen in the header's first name). One
// saved as UTF-16 is refused naming its encoding.
TEST_F(GmwmFleet, ReadsAManifestWithAByteOrderMarkAndRefusesUtf16NamingTheEncoding) {
  write("fleet.csv", "\xEF\xBB\xBFpath,unit,model\nunit1.csv,SN1,IMU-X\n");
  auto csv = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json", "--quiet"}, dir_);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(read_json(dir_ / "f.json").at("rows").size(), 2u);
  write("fleet.yaml", "\xEF\xBB\xBFrecordings:\n  - {path: unit1.csv, unit: SN1, model: IMU-X}\n");
  auto yaml = run_gmwm({"fleet", "fleet.yaml", "--model", "WN+RW", "--json", "y.json", "--quiet"}, dir_);
  ASSERT_EQ(yaml.exit_code, 0) << yaml.err;
  std::string utf16 = "\xFF\xFE";
  for (char c : std::string("path,unit,model\nunit1.csv,SN1,IMU-X\n")) utf16 += std::string(1, c) + '\0';
  write("wide.csv", utf16);
  auto wide = run_gmwm({"fleet", "wide.csv", "--model", "WN+RW", "--json", "w.json"}, dir_);
  gmwm::test::expect_bad_input(wide, {"wide.csv:1: found UTF-16 text", "expected UTF-8"}, dir_ / "w.json");
  write("nul.csv", std::string("path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN") + '\0' + "2,IMU-X\n");
  auto nul = run_gmwm({"fleet", "nul.csv", "--model", "WN+RW", "--json", "w.json"}, dir_);
  gmwm::test::expect_bad_input(nul, {"nul.csv:3: found a NUL byte, expected text"}, dir_ / "w.json");
}

TEST_F(GmwmFleet, RefusesAManifestWithCrOnlyLineEndsNamingThem) {
  write("mac.csv", "path,unit,model\runit1.csv,SN1,IMU-X\r");
  auto r = run_gmwm({"fleet", "mac.csv", "--model", "WN+RW", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(r, {"mac.csv:1: found carriage returns (CR) as line ends", "expected LF or CRLF"},
                               dir_ / "f.json");
  write("dos.csv", "path,unit,model\r\nunit1.csv,SN1,IMU-X\r\n");  // CRLF: read
  auto dos = run_gmwm({"fleet", "dos.csv", "--model", "WN+RW", "--json", "f.json", "--quiet"}, dir_);
  EXPECT_EQ(dos.exit_code, 0) << dos.err;
}

TEST_F(GmwmFleet, ARecordingThatCannotBeReadIsARowWithItsReasonAndTheOthersGoOn) {
  // A data row far into the file is not a number: the header is fine, the read fails.
  std::string text = gmwm::test::read_text(dir_ / "unit2.csv");
  const auto at = text.find('\n', text.size() / 2);
  text.insert(at + 1, "0.5,abc,0.1\n");
  write("unit2.csv", text);
  write("fleet.yaml",
        "recordings:\n"
        "  - {path: unit1.csv, unit: SN1, model: IMU-X}\n"
        "  - {path: unit2.csv, unit: SN2, model: IMU-X}\n"
        "  - {path: unit3.csv, unit: SN3, model: IMU-X}\n");
  auto r = run_gmwm({"fleet", "fleet.yaml", "--model", "WN+RW", "--json", "fleet.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fleet.json");
  EXPECT_EQ(doc.at("failed"), 1);
  ASSERT_EQ(doc.at("rows").size(), 5u);  // 2 + the failed recording's one + 2
  const json& failed = doc["rows"][2];
  EXPECT_EQ(failed.at("unit"), "SN2");
  EXPECT_EQ(failed.at("axis"), "");
  EXPECT_NE(failed.at("status").get<std::string>().find("abc"), std::string::npos) << failed.dump();
  EXPECT_EQ(doc["rows"][3].at("status"), "ok");
  EXPECT_NE(r.err.find("gmwm: warning: unit 'SN2': "), std::string::npos) << r.err;
}

TEST_F(GmwmFleet, FlagsTheUnitWhoseWhiteNoiseIsTwiceTheFleetsAndNoOtherUnit) {
  // Seven units of one model, one of them with 4x the white-noise variance (N twice the others').
  std::string manifest = "path,unit,model\n";
  for (int k = 1; k <= 7; ++k) {
    const std::string spec = k == 5 ? "WN(sigma2=4e-4)+RW(gamma2=1e-10)" : kTruth;
    auto r = run_gmwm({"simulate", "--model", spec, "--n", "16384", "--freq", "100", "--names", "gyro_x", "--seed",
                       std::to_string(10 + k), "--output", "u" + std::to_string(k) + ".csv", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    manifest += "u" + std::to_string(k) + ".csv,SN" + std::to_string(k) + ",IMU-X\n";
  }
  write("fleet.csv", manifest);
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "fleet.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fleet.json");
  for (const json& row : doc.at("rows")) {
    if (row.at("unit") == "SN5") {
      // N twice the fleet's; B too (a WN+RW model's Allan minimum rises with its N), not K.
      ASSERT_FALSE(row.at("flags").empty()) << row.dump();
      EXPECT_EQ(row["flags"][0].get<std::string>().rfind("N: 2", 0), 0u) << row.dump();  // 2.0x the median
      for (const json& f : row["flags"]) EXPECT_NE(f.get<std::string>().rfind("K: ", 0), 0u) << row.dump();
    } else {
      EXPECT_TRUE(row.at("flags").empty()) << row.dump();
    }
  }
  bool n_summary = false;
  for (const json& s : doc.at("summary"))
    if (s.at("figure") == "N") {
      n_summary = true;
      EXPECT_EQ(s.at("units"), 7);
      EXPECT_EQ(s.at("flagged"), json::array({"SN5"}));
      EXPECT_NEAR(s.at("median").get<double>(), std::sqrt(1e-4 / 100.0), 0.02 * std::sqrt(1e-4 / 100.0));
    }
  EXPECT_TRUE(n_summary);
  EXPECT_NE(r.out.find("SN5, gyro_x: N: 2"), std::string::npos) << r.out;
}

// --- The cache: a re-run computes only what is missing or changed -------------------------

// The table without its wall times and cache flags (the only columns a cached row may change),
// found by the header's names.
std::string table_without_timings(const std::string& csv) {
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted)
        out.emplace_back();
      else
        out.back() += c;
    }
    return out;
  };
  std::istringstream in(csv);
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = fields(line);
    if (keep.empty())
      for (const std::string& name : f) keep.push_back(name != "seconds" && name != "cached");
    if (f.size() != keep.size()) return "malformed line: " + line;
    for (std::size_t i = 0; i < f.size(); ++i)
      if (keep[i]) out += f[i] + ",";
    out += "\n";
  }
  return out;
}

std::vector<fs::path> cache_entries(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") out.push_back(e.path());
  return out;
}

TEST_F(GmwmFleet, AReRunTakesEveryRecordingFromTheCacheAndGivesTheSameTable) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN2,IMU-X\nunit3.csv,SN3,IMU-X\n");
  auto first = run_gmwm({"fleet", "fleet.csv", "--model", "AR1+WN+RW", "--csv", "a.csv", "--json", "a.json"}, dir_);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(read_json(dir_ / "a.json").at("cached"), 0);
  EXPECT_EQ(cache_entries(dir_ / ".gmwm-cache").size(), 3u);
  auto again = run_gmwm({"fleet", "fleet.csv", "--model", "AR1+WN+RW", "--csv", "b.csv", "--json", "b.json"}, dir_);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json b = read_json(dir_ / "b.json");
  EXPECT_EQ(b.at("cached"), 3);
  for (const json& row : b.at("rows")) EXPECT_TRUE(row.at("cached").get<bool>()) << row.dump();
  EXPECT_NE(again.out.find("3 from the cache"), std::string::npos) << again.out;
  // Every figure, model and p-value as computed, to the last digit (the wall times are the first run's).
  json a = gmwm::test::without_run(read_json(dir_ / "a.json")), bb = gmwm::test::without_run(b);
  for (json* d : {&a, &bb}) {
    (*d)["cached"] = 0;
    for (json& row : (*d)["rows"]) row["cached"] = false;
  }
  EXPECT_EQ(a, bb);
  EXPECT_EQ(table_without_timings(gmwm::test::read_text(dir_ / "a.csv")),
            table_without_timings(gmwm::test::read_text(dir_ / "b.csv")));
  // Another seed is another key: nothing taken from the cache.
  auto seeded = run_gmwm({"fleet", "fleet.csv", "--model", "AR1+WN+RW", "--seed", "9", "--json", "c.json"}, dir_);
  ASSERT_EQ(seeded.exit_code, 0) << seeded.err;
  EXPECT_EQ(read_json(dir_ / "c.json").at("cached"), 0);
}

TEST_F(GmwmFleet, AChangedOrDamagedEntryIsComputedAgainAndNoCacheLeavesNoFolder) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN2,IMU-X\n");
  auto nocache = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--no-cache", "--quiet"}, dir_);
  ASSERT_EQ(nocache.exit_code, 0) << nocache.err;
  EXPECT_FALSE(fs::exists(dir_ / ".gmwm-cache"));
  auto first = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--cache", "c", "--quiet"}, dir_);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(cache_entries(dir_ / "c").size(), 2u);
  // One entry damaged (cut in half), one recording changed (another unit's bytes).
  const fs::path victim = cache_entries(dir_ / "c").front();
  const std::string text = gmwm::test::read_text(victim);
  write("c/" + victim.filename().string(), text.substr(0, text.size() / 2));
  fs::copy_file(dir_ / "unit3.csv", dir_ / "unit2.csv", fs::copy_options::overwrite_existing);
  auto again = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--cache", "c", "--json", "d.json"}, dir_);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json d = read_json(dir_ / "d.json");
  // The damaged entry's recording and the changed one computed again: at most one from the cache.
  int from_cache = d.at("cached").get<int>();
  EXPECT_LE(from_cache, 1);
  EXPECT_EQ(d.at("failed"), 0);
  for (const json& row : d.at("rows")) EXPECT_EQ(row.at("status"), "ok");
}

// The rows of a fleet document without what a recomputed row may change (its wall time and
// cache flag).
json rows_without_timings(json doc) {
  json rows = doc.at("rows");
  for (json& row : rows) row.erase("seconds"), row.erase("cached");
  return rows;
}

// A cache entry's record edited by hand as issue 42 found it done: every axis's B x1000. The
// record's JSON is found in the entry whatever precedes it (its sorted keys start with "axes").
void multiply_b_by_1000(const fs::path& entry) {
  const std::string text = gmwm::test::read_text(entry);
  const auto at = text.find("{\"axes\"");
  ASSERT_NE(at, std::string::npos) << text.substr(0, 200);
  json record = json::parse(text.substr(at));
  for (json& axis : record.at("axes"))
    if (!axis.at("figures").is_null()) {
      json& b = axis["figures"]["B"]["figure"]["value"];
      b = b.get<double>() * 1000.0;
    }
  gmwm::test::write_text(entry, text.substr(0, at) + record.dump());
}

TEST_F(GmwmFleet, AnEditedSwappedOrCutCacheEntryIsComputedAgainAndSaidSoNamingItsFile) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN2,IMU-X\nunit3.csv,SN3,IMU-X\n");
  auto first = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "a.json", "--quiet"}, dir_);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const json fresh = rows_without_timings(read_json(dir_ / "a.json"));
  std::vector<fs::path> entries = cache_entries(dir_ / ".gmwm-cache");
  ASSERT_EQ(entries.size(), 3u);
  std::sort(entries.begin(), entries.end());
  // One entry's B x1000; the other two swapped.
  multiply_b_by_1000(entries[0]);
  const std::string one = gmwm::test::read_text(entries[1]), two = gmwm::test::read_text(entries[2]);
  gmwm::test::write_text(entries[1], two);
  gmwm::test::write_text(entries[2], one);
  auto again = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "b.json", "--quiet"}, dir_);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json b = read_json(dir_ / "b.json");
  EXPECT_EQ(b.at("cached"), 0);
  for (const json& row : b.at("rows")) EXPECT_FALSE(row.at("cached").get<bool>()) << row.dump();
  EXPECT_EQ(rows_without_timings(b), fresh);  // every figure as computed: no B x1000, no unit's numbers swapped
  // One warning at the default log level per entry not used, naming its file and what is wrong.
  const std::vector<std::string> lines = gmwm::test::lines_of(again.err);
  ASSERT_EQ(lines.size(), 3u) << again.err;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string name = (fs::path(".gmwm-cache") / entries[k].filename()).string();
    const auto line = std::find_if(lines.begin(), lines.end(),
                                   [&](const std::string& l) { return l.find(name) != std::string::npos; });
    ASSERT_NE(line, lines.end()) << name << "\n" << again.err;
    EXPECT_EQ(line->rfind("gmwm: warning: fleet cache: ", 0), 0u) << *line;
    EXPECT_NE(line->find(k == 0 ? "edited)" : "found the record of another key"), std::string::npos) << *line;
    EXPECT_NE(line->find("computed again"), std::string::npos) << *line;
  }
  EXPECT_EQ(b.at("cache_problems").size(), 3u);
  // The entries were written again: one cut short is the only one computed.
  ASSERT_EQ(cache_entries(dir_ / ".gmwm-cache").size(), 3u);
  const std::string whole = gmwm::test::read_text(entries[1]);
  gmwm::test::write_text(entries[1], whole.substr(0, whole.size() / 2));
  auto cut = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "c.json", "--quiet"}, dir_);
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  const json c = read_json(dir_ / "c.json");
  EXPECT_EQ(c.at("cached"), 2);
  EXPECT_EQ(rows_without_timings(c), fresh);
  ASSERT_EQ(gmwm::test::lines_of(cut.err).size(), 1u) << cut.err;
  EXPECT_NE(cut.err.find(entries[1].filename().string()), std::string::npos) << cut.err;
  EXPECT_NE(cut.err.find("cut short"), std::string::npos) << cut.err;
}

// Issue 42 item 15: a cache that cannot be one was dropped in silence (the warning was below
// the default log level) and the run lost its resumability; it is refused before any work.
TEST_F(GmwmFleet, RefusesACacheThatIsAFileOrBelowOneOrALinkToNothingBeforeAnyWork) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\n");
  write(".gmwm-cache", "my notes\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(
      r,
      {"the default cache .gmwm-cache: found a file, expected the folder of the fleet's cached records", "--no-cache"},
      dir_ / "f.json");
  EXPECT_EQ(gmwm::test::read_text(dir_ / ".gmwm-cache"), "my notes\n");
  write("notes.txt", "mine\n");
  auto given = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--cache", "notes.txt", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(given, {"--cache notes.txt: found a file, expected the folder"}, dir_ / "f.json");
  auto below = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--cache", "notes.txt/c", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(below, {"--cache notes.txt/c's parent notes.txt: found a file"}, dir_ / "f.json");
  fs::create_symlink(dir_ / "gone", dir_ / "link");
  auto dangling = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--cache", "link", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(dangling, {"--cache link: found a link to nothing"}, dir_ / "f.json");
  EXPECT_EQ(gmwm::test::read_text(dir_ / "notes.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(dir_ / "gone"));
}

// A cache whose entries cannot be written (here each entry's name taken by a folder that is
// not empty) is said at the default log level: the run goes on, its records not cached.
TEST_F(GmwmFleet, ACacheThatCannotBeWrittenIsSaidAndTheRunGoesOn) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\nunit2.csv,SN2,IMU-X\n");
  auto first = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--quiet"}, dir_);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  for (const fs::path& e : cache_entries(dir_ / ".gmwm-cache")) {
    fs::remove(e);
    fs::create_directory(e);
    write((e / "kept").lexically_relative(dir_).string(), "a file: the folder is not removed\n");
  }
  auto again = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "f.json", "--quiet"}, dir_);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_json(dir_ / "f.json").at("failed"), 0);
  EXPECT_NE(again.err.find("gmwm: warning: fleet cache: "), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("the records of this run from then on were not cached"), std::string::npos) << again.err;
}

// A killed run resumes: the recordings finished before the kill are cached (each entry
// whole), and the re-run computes only the others, giving the table of an uninterrupted run.
TEST_F(GmwmFleet, AKilledRunResumesAndComputesOnlyTheMissingRecordings) {
  std::string manifest = "path,unit,model\n";
  for (int k = 1; k <= 8; ++k) {
    auto r = run_gmwm({"simulate", "--model", "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-4)+RW(gamma2=1e-10)", "--n",
                       "65536", "--freq", "100", "--signals", "3", "--names", "gyro_x,gyro_y,gyro_z", "--seed",
                       std::to_string(20 + k), "--output", "k" + std::to_string(k) + ".csv", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    manifest += "k" + std::to_string(k) + ".csv,SN" + std::to_string(k) + ",IMU-X\n";
  }
  write("fleet.csv", manifest);
  const std::vector<std::string> args = {"fleet", "fleet.csv", "--model", "2*AR1+WN+RW", "--threads", "1", "--quiet"};
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir_.c_str()) != 0) ::_exit(126);
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 0), ::dup2(null, 1), ::dup2(null, 2);
    std::vector<char*> argv = {const_cast<char*>(gmwm::test::gmwm_cli_path())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  // Killed (SIGKILL: nothing of its own runs) once two recordings are cached.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  while (cache_entries(dir_ / ".gmwm-cache").size() < 2 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";
  const std::size_t done_before = cache_entries(dir_ / ".gmwm-cache").size();
  ASSERT_GE(done_before, 2u);
  ASSERT_LT(done_before, 8u);
  // Every entry left is whole: it reads back (the re-run takes each of them).
  std::vector<std::string> resumed_args = args;
  resumed_args.insert(resumed_args.end(), {"--json", "resumed.json", "--csv", "resumed.csv"});
  auto resumed = run_gmwm(resumed_args, dir_);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const json doc = read_json(dir_ / "resumed.json");
  EXPECT_EQ(doc.at("cached").get<std::size_t>(), done_before);
  EXPECT_EQ(doc.at("rows").size(), 24u);
  EXPECT_EQ(cache_entries(dir_ / ".gmwm-cache").size(), 8u);
  // The same table as a run that was never interrupted.
  std::vector<std::string> whole_args = args;
  whole_args.insert(whole_args.end(), {"--no-cache", "--csv", "whole.csv"});
  auto whole = run_gmwm(whole_args, dir_);
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(table_without_timings(gmwm::test::read_text(dir_ / "resumed.csv")),
            table_without_timings(gmwm::test::read_text(dir_ / "whole.csv")));
}

// --spec: each unit's figures against the datasheet limits of its model, in the limit's unit.
TEST_F(GmwmFleet, ChecksEachUnitAgainstTheSpecAndNamesTheOneAboveIt) {
  // N of the truth: sqrt(1e-4 / 100) = 1e-3 rad/s/sqrt(Hz) = 3.44 deg/sqrt(h); the unit with
  // 4x the white-noise variance has twice that. The limit 5 deg/sqrt(h) lies between.
  auto r = run_gmwm({"simulate", "--model", "WN(sigma2=4e-4)+RW(gamma2=1e-10)", "--n", "16384", "--freq", "100",
                     "--signals", "2", "--names", "gyro_x,gyro_y", "--seed", "4", "--output", "unit4.csv", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  write("fleet.csv",
        "path,unit,model,units\nunit1.csv,SN1,IMU-X,gyro=rad/s\nunit2.csv,SN2,IMU-X,gyro=rad/s\n"
        "unit3.csv,SN3,IMU-X,gyro=rad/s\nunit4.csv,SN4,IMU-X,gyro=rad/s\n");
  write("spec.yaml", "IMU-X:\n  gyroscope:\n    angle_random_walk: 5 deg/sqrt(h)\n");
  auto f = run_gmwm(
      {"fleet", "fleet.csv", "--model", "WN+RW", "--spec", "spec.yaml", "--json", "f.json", "--csv", "f.csv"}, dir_);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const json doc = read_json(dir_ / "f.json");
  EXPECT_EQ(doc.at("spec"), "spec.yaml");
  for (const json& row : doc.at("rows")) {
    ASSERT_EQ(row.at("spec").size(), 1u) << row.dump();
    const json& c = row["spec"][0];
    EXPECT_EQ(c.at("figure"), "N");
    EXPECT_EQ(c.at("limit"), 5.0);
    EXPECT_EQ(c.at("limit_unit"), "deg/sqrt(h)");
    const double expected = (row.at("unit") == "SN4" ? 2.0 : 1.0) * 1e-3 * 180.0 / M_PI * 60.0;
    EXPECT_NEAR(c.at("value").get<double>(), expected, 0.05 * expected) << row.dump();
    EXPECT_EQ(c.at("verdict"), row.at("unit") == "SN4" ? "fail" : "pass") << row.dump();
    EXPECT_EQ(row.at("spec_verdict"), row.at("unit") == "SN4" ? "fail (N)" : "pass");
  }
  for (const json& s : doc.at("summary"))
    EXPECT_EQ(s.at("out_of_spec"), s.at("figure") == "N" ? json::array({"SN4"}) : json::array()) << s.dump();
  EXPECT_NE(f.out.find("against the spec spec.yaml"), std::string::npos) << f.out;
  EXPECT_NE(gmwm::test::read_text(dir_ / "f.csv").find(",fail (N),"), std::string::npos);
}

TEST_F(GmwmFleet, RefusesASpecThatIsNotOneNamingTheFileAndLineBeforeAnyWork) {
  write("fleet.csv", "path,unit,model\nunit1.csv,SN1,IMU-X\n");
  write("spec.yaml", "IMU-X:\n  gyroscope:\n    angle_random_walk: 5 deg/h\n");
  auto r = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--spec", "spec.yaml", "--json", "f.json"}, dir_);
  gmwm::test::expect_bad_input(r, {"spec.yaml:3", "angle_random_walk", "deg/h"}, dir_ / "f.json");
  EXPECT_FALSE(fs::exists(dir_ / ".gmwm-cache"));
}

// --gap-datasheet: each recording diagnosed against the baseline as `gmwm gap` would; a unit
// whose noise is the baseline's has no gap, one with an unmodelled Gauss-Markov bias has one.
TEST_F(GmwmFleet, DiagnosesEachUnitsGapAgainstTheBaselineAsGapDoes) {
  for (const auto& [name, spec] : {std::pair{"plain.csv", "WN(sigma2=1e-4)+RW(gamma2=1e-10)"},
                                   {"biased.csv", "WN(sigma2=1e-4)+RW(gamma2=1e-10)+AR1(phi=0.999,sigma2=4e-7)"}}) {
    auto r = run_gmwm({"simulate", "--model", spec, "--n", "65536", "--freq", "100", "--names", "gyro_x", "--seed", "5",
                       "--output", name, "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  // The baseline: N = sqrt(1e-4 / 100) = 1e-3 rad/s/sqrt(Hz), K = sqrt(1e-10 * 100) = 1e-4 rad/s^2/sqrt(Hz).
  write("sheet.yaml",
        "gyroscope:\n  noise_density: 0.001 rad/s/sqrt(Hz)\n  rate_random_walk: 0.0001 rad/s^2/sqrt(Hz)\n");
  write("fleet.csv", "path,unit,model\nplain.csv,P,IMU-X\nbiased.csv,B,IMU-X\n");
  auto f = run_gmwm({"fleet", "fleet.csv", "--model", "AR1+WN+RW", "--gap-datasheet", "sheet.yaml", "--gap-replicates",
                     "50", "--json", "f.json", "--csv", "f.csv"},
                    dir_);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const json doc = read_json(dir_ / "f.json");
  EXPECT_EQ(doc.at("gap_baseline"), "sheet.yaml");
  ASSERT_EQ(doc.at("rows").size(), 2u);
  const json& plain = doc["rows"][0];
  const json& biased = doc["rows"][1];
  EXPECT_EQ(plain.at("gap").at("verdict"), "none") << plain.dump();
  EXPECT_NE(biased.at("gap").at("verdict"), "none") << biased.dump();
  EXPECT_NE(biased.at("gap").at("headline").get<std::string>().find("AR1"), std::string::npos) << biased.dump();
  EXPECT_LT(biased.at("gap").at("p_value").get<double>(), 0.05);
  EXPECT_NE(f.out.find("the gap against sheet.yaml"), std::string::npos) << f.out;
  // The same as gmwm gap gives the recording.
  auto g = run_gmwm(
      {"gap", "biased.csv", "--datasheet", "sheet.yaml", "--replicates", "50", "--json", "g.json", "--quiet"}, dir_);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_EQ(read_json(dir_ / "g.json")["columns"][0].at("headline"), biased.at("gap").at("headline"));
  // A baseline that is not one: refused before any work, naming its option, file and line.
  write("bad.yaml", "gyroscope:\n  noise_density: 0.001\n");
  auto bad =
      run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--gap-datasheet", "bad.yaml", "--json", "b.json"}, dir_);
  gmwm::test::expect_bad_input(bad, {"--gap-datasheet", "bad.yaml:2", "without a unit"}, dir_ / "b.json");
}

// --joint: each group's axis's joint model (its units as replicates) with the shared-theta test.
TEST_F(GmwmFleet, GivesEachGroupsAxisItsJointModelWithTheSharedThetaTest) {
  write("fleet.csv",
        "path,unit,model,units\nunit1.csv,SN1,IMU-X,gyro=rad/s\nunit2.csv,SN2,IMU-X,gyro=rad/s\n"
        "unit3.csv,SN3,IMU-X,gyro=rad/s\n");
  auto r =
      run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--joint", "--joint-draws", "39", "--json", "f.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "f.json");
  ASSERT_EQ(doc.at("joint").size(), 2u);  // gyro_x, gyro_y
  for (const json& j : doc.at("joint")) {
    EXPECT_EQ(j.at("status"), "ok") << j.dump();
    EXPECT_EQ(j.at("units"), 3);
    EXPECT_EQ(j.at("unit"), "rad/s");
    // The three units share the truth WN(sigma2=1e-4)+RW(gamma2=1e-10): N = 1e-3 rad/s/sqrt(Hz),
    // and the test (bootstrap, 3 units) does not reject. (164 s of each do not always show the
    // random walk: the smallest equivalent model may be WN alone.)
    EXPECT_TRUE(j.at("recommended") == "WN+RW" || j.at("recommended") == "WN") << j.dump();
    EXPECT_NEAR(j.at("N").at("value").get<double>(), 1e-3, 0.02e-3) << j.dump();
    EXPECT_EQ(j.at("replicate_test").at("calibration"), "bootstrap");
    EXPECT_EQ(j.at("replicate_test").at("draws"), 39);
    EXPECT_TRUE(j.at("replicate_test").at("shared").get<bool>()) << j.dump();
  }
  EXPECT_NE(r.out.find("the joint model of each group's axis"), std::string::npos) << r.out;
  // Without --joint: none.
  auto plain = run_gmwm({"fleet", "fleet.csv", "--model", "WN+RW", "--json", "p.json", "--quiet"}, dir_);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_TRUE(read_json(dir_ / "p.json").at("joint").empty());
}

// Issue 30's acceptance on real units: the three ADIS16405 recordings as a fleet of three give
// the table `gmwm select` gives each of them.
TEST_F(GmwmFleet, TheThreeAdisUnitsAsAFleetGiveWhatSelectGivesEachUnit) {
  GMWM_REQUIRE_SHARED_DATA();
  std::string manifest = "path,unit,model,units,rate\n";
  std::vector<std::string> files;
  for (int k = 1; k <= 3; ++k) {
    files.push_back(gmwm::test::shared_data_file("adis_16405_imu" + std::to_string(k) + ".csv.gz"));
    manifest += files.back() + ",imu" + std::to_string(k) + ",ADIS16405,\"gyro=deg/s,accel=g\",100\n";
  }
  write("adis.csv", manifest);
  auto r = run_gmwm({"fleet", "adis.csv", "--model", "AR1+WN+RW", "--json", "fleet.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fleet.json");
  ASSERT_EQ(doc.at("rows").size(), 18u);  // 3 units x 6 axes
  for (int k = 0; k < 3; ++k) {
    auto s = run_gmwm({"select", files[static_cast<std::size_t>(k)], "--freq", "100", "--model", "AR1+WN+RW", "--units",
                       "gyro=deg/s,accel=g", "--json", "s.json", "--quiet"},
                      dir_);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const json sel = read_json(dir_ / "s.json");
    for (std::size_t a = 0; a < 6; ++a) {
      const json& row = doc["rows"][static_cast<std::size_t>(6 * k) + a];
      const json& col = sel["columns"][a];
      EXPECT_EQ(row.at("axis"), col.at("name"));
      EXPECT_EQ(row.at("chosen"), col.at("best_model"));
      for (const auto& [figure, key] : {std::pair{"N", "white"}, {"K", "walk"}, {"B", "instability"}})
        for (const char* part : {"value", "low", "high"})
          EXPECT_EQ(row.at(figure).at(part), col.at("noise_figures").at(key).at(part)) << figure << " " << part;
    }
  }
}

}  // namespace
