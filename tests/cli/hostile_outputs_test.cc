// The bad-input contract (hostile_harness.h) for what issue 25 found beyond reading a
// file: standard output closed under the writer (a pipe to `head -c1`); side files that
// are devices, sockets, FIFOs, endless pipes or too large; numbers in options and results
// at the edge of their types; the length of an error line.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hostile_harness.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gmwm::test::hostile;
using gmwm::test::RunOptions;

namespace {

// A CSV of `columns` signals of 1024 rows at 100 Hz: its wv JSON (about 2.5 kB a column)
// and its table are far beyond a pipe's 64 KiB, so a reader that stops after one byte
// makes the writer meet a closed pipe whatever the scheduling.
std::string wide_csv(int columns) {
  std::string s = "time";
  for (int c = 0; c < columns; ++c) s += ",g" + std::to_string(c);
  s += "\n";
  for (int i = 0; i < 1024; ++i) {
    s += std::to_string(i * 0.01);
    for (int c = 0; c < columns; ++c) s += "," + std::to_string(std::sin(i * 0.37 + c) * 1e-3 + c);
    s += "\n";
  }
  return s;
}

// Standard output into a reader that takes one byte and exits.
RunOptions to_head() {
  RunOptions how;
  how.stdout_to = ">(head -c1 >/dev/null)";
  return how;
}

// A fit result with one column whose "freq" is `freq` (JSON text).
std::string fit_result(const std::string& freq) {
  return R"j({"tool": "gmwm", "version": "0.1.0", "command": "fit", "input": "d.csv", "columns": [)j"
         R"j({"name": "gyro_x", "n": 4096, "freq": )j" +
         freq + R"j(, "model": "WN(sigma2=1e-06)+RW(gamma2=1e-12)", "unit": "rad/s", "status": "converged"}]})j";
}

const std::string kYaml =
    "accelerometer_noise_density: 4.9e-03\naccelerometer_random_walk: 3.0e-04\n"
    "gyroscope_noise_density: 8.73e-04\ngyroscope_random_walk: 2.0e-05\nupdate_rate: 100.0\n";

// A FIFO that no writer will open.
Setup fifo(const std::string& name) {
  return [name](const fs::path& d) { ::mkfifo((d / name).c_str(), 0600); };
}

// A Unix socket bound at `name` (the socket file stays once the descriptor is closed).
Setup socket_file(const std::string& name) {
  return [name](const fs::path& d) {
    const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    const std::string path = (d / name).string();
    std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
    ::bind(s, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    ::close(s);
  };
}

// A file of `bytes` bytes: `head`, then zeros (sparse: they are not written).
Setup sized(const std::string& name, const std::string& head, std::uintmax_t bytes) {
  return [name, head, bytes](const fs::path& d) {
    gmwm::test::write_text(d / name, head);
    fs::resize_file(d / name, bytes);
  };
}

std::vector<Case> corpus() {
  const auto wide = file("wide.csv", wide_csv(200));
  const auto base = file("base.csv", base_csv());
  std::vector<Case> c = {
      // --- standard output closed under the writer -------------------------------------------
      {"json on a closed pipe with a csv beside it",
       {"wv", "wide.csv", "--json", "-", "--csv", "out.csv"},
       {"--json -: cannot write to standard output: Broken pipe", "no output file was written"},
       wide,
       to_head()},
      {"fit json on a closed pipe",
       {"fit", "wide.csv", "--model", "WN", "--json", "-", "--quiet"},
       {"--json -", "Broken pipe"},
       wide,
       to_head()},
      {"simulated series on a closed pipe",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "200000", "--output", "-", "--json", "s.json"},
       {"--output -: cannot write to standard output: Broken pipe"},
       nullptr,
       to_head()},
      {"table on a closed pipe", {"wv", "wide.csv"}, {"cannot write to standard output: Broken pipe"}, wide, to_head()},
      // --- side files: --kalibr and --gazebo -------------------------------------------------
      {"Kalibr file that is /dev/zero",
       {"gap", "base.csv", "--kalibr", "/dev/zero"},
       {"--kalibr /dev/zero: is a character device, expected a Kalibr imu.yaml"},
       base},
      {"Gazebo file that is /dev/zero",
       {"gap", "base.csv", "--gazebo", "/dev/zero"},
       {"--gazebo /dev/zero: is a character device, expected a Gazebo SDF file"},
       base},
      {"Kalibr file that is a folder",
       {"gap", "base.csv", "--kalibr", "sub"},
       {"--kalibr sub: is a folder"},
       both(base, [](const fs::path& d) { fs::create_directory(d / "sub"); })},
      {"Gazebo file that is a socket",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"--gazebo s.sdf: is a socket"},
       both(base, socket_file("s.sdf"))},
      {"Kalibr FIFO with no writer",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"--kalibr k.yaml", "no writer"},
       both(base, fifo("k.yaml"))},
      {"Gazebo FIFO with no writer",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"--gazebo s.sdf", "no writer"},
       both(base, fifo("s.sdf"))},
      {"Kalibr file beyond 1 MiB",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"--kalibr k.yaml: holds more than 1048576 bytes, expected a Kalibr imu.yaml of at most 1 MiB"},
       both(base, file("k.yaml", kYaml + std::string(2 << 20, '#')))},
      {"Gazebo file beyond 64 MiB",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"--gazebo s.sdf: holds more than 67108864 bytes"},
       both(base, sized("s.sdf", "<sdf>", (64u << 20) + 1))},
      {"endless YAML through a pipe",
       {"gap", "base.csv", "--kalibr", "/dev/stdin"},
       {"--kalibr /dev/stdin: holds more than 1048576 bytes"},
       base,
       {.stdin_from = "yes '#'", .stdin_pipe = true}},
      // --- side files: an export's JSON source -----------------------------------------------
      {"export source that is /dev/zero",
       {"export", "/dev/zero", "--format", "kalibr", "--output", "o.yaml"},
       {"/dev/zero: is a character device"}},
      {"export source that is a socket",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: is a socket"},
       socket_file("r.json")},
      {"export source FIFO with no writer",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json", "no writer"},
       fifo("r.json")},
      {"export source beyond 64 MiB",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: holds more than 67108864 bytes"},
       sized("r.json", "{", (64u << 20) + 1)},
      {"endless JSON through a pipe",
       {"export", "/dev/stdin", "--format", "kalibr", "--output", "o.yaml"},
       {"/dev/stdin: holds more than 67108864 bytes, expected the --json result of gmwm fit or gmwm select"},
       nullptr,
       {.stdin_from = "yes '{'", .stdin_pipe = true}},
      {"export source in UTF-16",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: starts with a UTF-16 or UTF-32 byte-order mark, expected UTF-8 text"},
       file("r.json", bytes({0xFF, 0xFE, '{', 0, '}', 0}))},
      // --- whole numbers in options ----------------------------------------------------------
      {"negative seed",
       {"wv", "base.csv", "--seed=-1"},
       {"--seed: found '-1', expected an integer from 0 to 18446744073709551615"},
       base},
      {"seed beyond 64 bits",
       {"wv", "base.csv", "--seed", "18446744073709551616"},
       {"--seed: found '18446744073709551616', expected an integer from 0"},
       base},
      {"seed in hex", {"wv", "base.csv", "--seed", "0x10"}, {"--seed: found '0x10'"}, base},
      {"negative thread count",
       {"wv", "base.csv", "--threads=-1"},
       {"--threads: found '-1', expected an integer from 1 to 4096"},
       base},
      {"levels in octal notation", {"wv", "base.csv", "--levels", "+010"}, {"--levels: found '+010'"}, base},
      {"negative sample count",
       {"simulate", "--model", "WN(sigma2=1)", "--n=-5", "--output", "s.csv"},
       {"--n: found '-5', expected an integer from 1 to 1099511627776"}},
      {"signal count as a real",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--signals", "2.5", "--output", "s.csv"},
       {"--signals: found '2.5'"}},
      {"replicates in hex",
       {"select", "base.csv", "--model", "WN+RW", "--optimism", "bootstrap", "--replicates", "0x20"},
       {"--replicates: found '0x20'"},
       base},
      // --- real numbers in options -----------------------------------------------------------
      {"subnormal alpha",
       {"wv", "base.csv", "--alpha", "1e-320"},
       {"--alpha: found '1e-320', expected a number from 1e-10 to below 1"},
       base},
      {"alpha as a hex float", {"wv", "base.csv", "--alpha", "0x1p-4"}, {"--alpha: found '0x1p-4'"}, base},
      {"infinite alpha", {"fit", "base.csv", "--model", "WN", "--alpha", "inf"}, {"--alpha: found 'inf'"}, base},
      {"rate in hex",
       {"wv", "base.csv", "--freq", "0x1p3"},
       {"--freq: found '0x1p3', expected a sampling rate in Hz"},
       base},
      {"subnormal simulate rate",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--freq", "1e-310", "--output", "s.csv"},
       {"--freq: found '1e-310'"}},
      {"infinite inflation",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml", "--inflate", "inf"},
       {"--inflate: found 'inf'"},
       file("r.json", fit_result("100"))},
      {"infinite strength", {"gap-check", "--strengths", "1,inf"}, {"--strengths", "'inf'"}},
      {"efficiency in hex", {"wv", "base.csv", "--robust", "--eff", "0x1p-1"}, {"--eff: found '0x1p-1'"}, base},
      {"quantum as NaN",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--quantum", "nan", "--output", "s.csv"},
       {"--quantum: found 'nan'"}},
      {"Kalman rate in hex",
       {"fit", "base.csv", "--model", "WN+RW", "--kf-rate", "0x10"},
       {"--kf-rate: found '0x10'"},
       base},
      // --- sampling rates: --rate and a result's "freq" --------------------------------------
      {"subnormal export rate",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml", "--rate", "1e-310"},
       {"--rate: found '1e-310', expected a sampling rate in Hz from 1e-09 to 1e+09"},
       file("r.json", fit_result("100"))},
      {"subnormal rate in an export source",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json", "column 'gyro_x'", "\"freq\": found 4.94066e-324, expected a sampling rate in Hz from 1e-09"},
       file("r.json", fit_result("5e-324"))},
      // --- the length of an error line -------------------------------------------------------
      {"100 kB model in the message", {"fit", "base.csv", "--model", std::string(100000, 'Q')}, {"more bytes]"}, base},
      {"800 kB column name in the message",
       {"wv", "h.csv", "--freq", "100", "--columns", "nosuch"},
       {"h.csv", "nosuch", "more bytes]"},
       file("h.csv",
            [] {
              std::string s = std::string(800000, 'n') + ",b\n";
              for (int i = 0; i < 64; ++i) s += std::to_string(i % 5) + "," + std::to_string(i % 3) + "\n";
              return s;
            }())},
  };
  return c;
}

}  // namespace

HOSTILE_CORPUS(HostileOutputs, corpus());

// A whole number is read in decimal whatever its leading zeros (CLI11 alone read "010" as
// octal 8).
TEST(HostileOutputs, LeadingZerosDoNotMakeAnOctalNumber) {
  const fs::path dir = gmwm::test::temp_dir("octal");
  gmwm::test::write_text(dir / "base.csv", base_csv());
  const gmwm::test::CliRun r = gmwm::test::run_gmwm({"wv", "base.csv", "--levels", "010", "--json", "-"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["columns"][0]["levels"].size(), 10u);
  fs::remove_all(dir);
}

// Every error line is at most gmwm::kMaxErrorLineBytes (500) and its note, whatever it
// quotes, and keeps its end: what was expected.
TEST(HostileOutputs, AnErrorLineIsCappedAndKeepsWhatWasExpected) {
  const fs::path dir = gmwm::test::temp_dir("cap");
  const gmwm::test::CliRun r = gmwm::test::run_gmwm({"wv", "x.csv", "--freq", std::string(100000, '7') + "x"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  const auto lines = gmwm::test::lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LE(lines[0].size(), std::string("gmwm: error: ").size() + 500 + 32) << lines[0];
  EXPECT_NE(lines[0].find("more bytes]"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("expected a sampling rate in Hz from 1e-09 to 1e+09"), std::string::npos) << lines[0];
  fs::remove_all(dir);
}
