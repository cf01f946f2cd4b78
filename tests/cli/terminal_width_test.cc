// The terminal is for people (issue 29): every line the README's example commands print fits
// a 100-column terminal (report::kTerminalWidth), and the README's first command (tools/demo.sh:
// wv and fit of one axis) fits one 100 x 50 screen.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/report/terminal.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::run_gmwm;

namespace {

// The height of the screen the README's first command must fit, per axis.
constexpr std::size_t kScreenLines = 50;

// The words of a shell command line, double quotes removed ("a b" is one word).
std::vector<std::string> words_of(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false, any = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
      any = true;
    } else if (c == ' ' && !quoted) {
      if (any || !cur.empty()) out.push_back(cur);
      cur.clear();
      any = false;
    } else {
      cur += c;
    }
  }
  if (any || !cur.empty()) out.push_back(cur);
  return out;
}

// The README's example commands ("build/gmwm ..." lines of its code blocks, continuation
// lines joined), in order.
std::vector<std::string> readme_commands() {
  std::ifstream in(fs::path(GMWM_SOURCE_DIR) / "README.md");
  std::vector<std::string> out;
  bool code = false;
  std::string pending;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      code = !code;
      continue;
    }
    if (!code) continue;
    if (!pending.empty()) {
      pending += line;
    } else if (line.rfind("build/gmwm ", 0) == 0) {
      pending = line;
    }
    if (!pending.empty() && !pending.empty() && pending.back() == '\\') {
      pending.pop_back();
      continue;
    }
    if (!pending.empty()) out.push_back(pending);
    pending.clear();
  }
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string l; std::getline(is, l);) out.push_back(l);
  return out;
}

std::size_t columns(const std::string& line) {
  std::size_t n = 0;
  for (char c : line) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}

class TerminalWidth : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_terminal_width"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(TerminalWidth, EveryLineOfTheReadmesExampleCommandsFitsOneHundredColumns) {
  const fs::path data = fs::path(GMWM_SOURCE_DIR) / "data";
  int ran = 0;
  for (const std::string& command : readme_commands()) {
    std::vector<std::string> args = words_of(command);
    args.erase(args.begin());  // build/gmwm
    bool runnable = true;
    for (std::string& a : args) {
      if (a.rfind("data/", 0) == 0) a = (data / a.substr(5)).string();
      // Recordings the README names but does not ship (a user's day1.csv.gz, flight.ulg ...).
      for (const char* ext : {".csv.gz", ".ulg", ".bag", ".db3", ".mcap"})
        if (a.size() > std::string(ext).size() &&
            a.compare(a.size() - std::string(ext).size(), std::string::npos, ext) == 0 &&
            !fs::exists(fs::path(a).is_absolute() ? fs::path(a) : dir_ / a))
          runnable = false;
    }
    // `serve` runs until it is stopped: its own test starts and stops it (serve_command_test.cc).
    if (!runnable || args.front() == "serve") continue;
    const auto r = run_gmwm(args, dir_);
    ++ran;
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    for (const std::string& l : lines(r.out))
      EXPECT_LE(columns(l), gmwm::report::kTerminalWidth) << command << ":\n" << l;
    // stderr keeps one message a line (warnings and errors, for grep and logs): not wrapped.
  }
  EXPECT_GE(ran, 20) << "the README's examples on shipped data";
}

TEST_F(TerminalWidth, TheReadmesFirstCommandFitsOneScreenForItsAxis) {
  // tools/demo.sh: the wavelet variance and the fit of one axis of the shipped example.
  const std::string example = (fs::path(GMWM_SOURCE_DIR) / "data" / "example_imu6.csv.gz").string();
  const auto wv = run_gmwm({"wv", example, "--columns", "gyro_x", "--freq", "100"}, dir_);
  const auto fit = run_gmwm({"fit", example, "--columns", "gyro_x", "--freq", "100", "--model", "AR1+WN+RW"}, dir_);
  ASSERT_EQ(wv.exit_code, 0) << wv.err;
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_LE(lines(wv.out).size() + lines(fit.out).size(), kScreenLines) << wv.out << fit.out;
  // The summary comes first: the axis, its model and verdict, then N, K, B.
  EXPECT_NE(fit.out.find("gyro_x: AR1+WN+RW; GoF p = "), std::string::npos) << fit.out;
  EXPECT_NE(fit.out.find("N white noise"), std::string::npos);
  // --verbose adds the details (the fit table, the Kalman terms), still within the width.
  const auto verbose =
      run_gmwm({"fit", example, "--columns", "gyro_x", "--freq", "100", "--model", "AR1+WN+RW", "--verbose"}, dir_);
  ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
  EXPECT_NE(verbose.out.find("Kalman filter at 100 Hz"), std::string::npos) << verbose.out;
  EXPECT_GT(lines(verbose.out).size(), lines(fit.out).size());
  for (const std::string& l : lines(verbose.out)) EXPECT_LE(columns(l), gmwm::report::kTerminalWidth) << l;
}

}  // namespace
