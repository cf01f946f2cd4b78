// End to end: no run overwrites what it reads, writes through a device, FIFO or symlink,
// leaves half of its outputs behind, or loses data past 4 GB of gzip text.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <thread>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using gmwm::test::staged_leftovers;
using gmwm::test::write_text;

namespace {

class GmwmCliOutputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_outputs");
    gmwm::test::write_noise_csv(dir_ / "base.csv", 512);
    base_ = read_text(dir_ / "base.csv");
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// The contract for a refused output: exit 2, one line naming `mentions`, nothing on
  /// stdout, the input unchanged, no file among `absent`, no temporary file.
  void expect_refused(const gmwm::test::CliRun& r, const std::vector<std::string>& mentions,
                      const std::vector<std::string>& absent = {}) {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const auto lines = gmwm::test::lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << r.err;
    EXPECT_EQ(lines[0].rfind("gmwm: error: ", 0), 0u) << lines[0];
    for (const auto& m : mentions) EXPECT_NE(lines[0].find(m), std::string::npos) << "want '" << m << "': " << lines[0];
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(read_text(dir_ / "base.csv"), base_) << "the input must not change";
    for (const auto& a : absent) EXPECT_FALSE(fs::exists(dir_ / a)) << a << " must not be written";
    EXPECT_TRUE(staged_leftovers(dir_).empty()) << "temporary file left: " << staged_leftovers(dir_).front();
  }

  fs::path dir_;
  std::string base_;
};

}  // namespace

TEST_F(GmwmCliOutputSafety, RefusesAWvCsvThatIsTheInput) {
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--csv", "base.csv"}, dir_),
                 {"--csv 'base.csv': is the input 'base.csv'"});
}

TEST_F(GmwmCliOutputSafety, RefusesAFitJsonThatIsTheInputThroughAnotherSpelling) {
  expect_refused(run_gmwm({"fit", "base.csv", "--freq", "100", "--model", "WN", "--json", "./base.csv"}, dir_),
                 {"--json './base.csv': is the input"});
}

TEST_F(GmwmCliOutputSafety, RefusesAnExportOutputThatIsItsSourceResult) {
  ASSERT_EQ(run_gmwm({"fit", "base.csv", "--freq", "100", "--model", "WN+RW", "--json", "fit.json", "--quiet"}, dir_)
                .exit_code,
            0);
  const std::string fit = read_text(dir_ / "fit.json");
  expect_refused(run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "fit.json"}, dir_),
                 {"--output 'fit.json': is the input 'fit.json'"});
  EXPECT_EQ(read_text(dir_ / "fit.json"), fit);
}

TEST_F(GmwmCliOutputSafety, RefusesTwoOutputsNamingTheSameFile) {
  expect_refused(
      run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--output", "x.csv", "--json", "x.csv"}, dir_),
      {"--json 'x.csv': names the same file as --output 'x.csv'"}, {"x.csv"});
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--csv", "-", "--json", "-"}, dir_),
                 {"already writes to standard output"});
}

TEST_F(GmwmCliOutputSafety, RefusesASymlinkOrFifoTargetAndLeavesThemAsTheyWere) {
  write_text(dir_ / "real.json", "keep");
  fs::create_symlink("real.json", dir_ / "link.json");
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--json", "link.json"}, dir_),
                 {"--json 'link.json': is a symbolic link"});
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(read_text(dir_ / "real.json"), "keep");

  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--csv", "fifo"}, dir_), {"--csv 'fifo': is a FIFO"});
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo"));
}

TEST_F(GmwmCliOutputSafety, RefusesADeviceTarget) {
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--json", "/dev/full"}, dir_),
                 {"--json '/dev/full': is a character device"});
  struct stat st {};
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/full must still be a device";
}

TEST_F(GmwmCliOutputSafety, WritesNoOutputWhenALaterOneFails) {
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--csv", "ok.csv", "--json", "/proc/x.json"}, dir_),
                 {"cannot write '/proc/x.json'"}, {"ok.csv"});
  expect_refused(
      run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--output", "ok.csv", "--json", "/proc/x.json"},
               dir_),
      {"cannot write '/proc/x.json'"}, {"ok.csv"});
}

TEST_F(GmwmCliOutputSafety, AFitWithAnUnwritableReportWritesNoJson) {
  if (!fs::exists("/usr/share/javascript/vega/vega-view.min.js") && !std::getenv("GMWM_VEGA_DIR"))
    GTEST_SKIP() << "libjs-vega not installed: --report is unavailable";
  expect_refused(
      run_gmwm({"fit", "base.csv", "--freq", "100", "--model", "WN", "--json", "ok.json", "--report", "/proc/r.html"},
               dir_),
      {"cannot write '/proc/r.html"}, {"ok.json"});
}

TEST_F(GmwmCliOutputSafety, WritesNothingPastAFileSizeLimit) {
  // ulimit -f 64: at most 64 KiB per file. The simulated CSV is ~4 MB.
  gmwm::test::RunOptions how;
  how.before = "ulimit -f 64;";
  expect_refused(
      run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "200000", "--output", "big.csv", "--json", "s.json"},
               dir_, how),
      {"cannot write 'big.csv'", "File too large"}, {"big.csv", "s.json"});
}

TEST_F(GmwmCliOutputSafety, ReportsAWriteErrorOnStandardOutput) {
  gmwm::test::RunOptions how;
  how.stdout_to = "/dev/full";
  expect_refused(run_gmwm({"wv", "base.csv", "--freq", "100", "--json", "-"}, dir_, how),
                 {"cannot write to standard output: No space left on device"});
}

TEST_F(GmwmCliOutputSafety, ReplacesAnExistingOutputWhole) {
  write_text(dir_ / "wv.csv", std::string(100000, '~'));
  const auto r = run_gmwm({"wv", "base.csv", "--freq", "100", "--csv", "wv.csv", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(dir_ / "wv.csv");
  EXPECT_EQ(csv.find('~'), std::string::npos) << "no byte of the old file may remain";
  EXPECT_TRUE(staged_leftovers(dir_).empty());
}

namespace {

// Starts `gmwm args...` in `dir` (no core dump, stdout and stderr to /dev/null).
pid_t start_gmwm(const std::vector<std::string>& args, const fs::path& dir) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit none{0, 0};
    ::setrlimit(RLIMIT_CORE, &none);
    // A runner that ignores these (nohup, a CI job in the background) passes that on through
    // exec; gmwm rightly leaves an ignored signal alone, so the test resets them.
    for (const int sig : {SIGHUP, SIGINT, SIGQUIT, SIGTERM}) std::signal(sig, SIG_DFL);
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 0), ::dup2(null, 1), ::dup2(null, 2);
    std::vector<char*> argv{const_cast<char*>(gmwm::test::gmwm_cli_path())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(gmwm::test::gmwm_cli_path(), argv.data());
    ::_exit(127);
  }
  return pid;
}

// Bytes written so far to an unnamed file of `dir` that process `pid` holds open (its
// /proc link reads "DIR/#INODE (deleted)"), or -1 when it has none.
long long staged_bytes(pid_t pid, const fs::path& dir) {
  std::error_code ec;
  const fs::path fds = "/proc/" + std::to_string(pid) + "/fd";
  for (const auto& e : fs::directory_iterator(fds, ec)) {
    const fs::path to = fs::read_symlink(e.path(), ec);
    if (ec) continue;
    const std::string t = to.string();
    if (t.rfind(fs::canonical(dir).string() + "/#", 0) != 0) continue;
    struct stat st {};
    if (::stat(e.path().c_str(), &st) == 0) return st.st_size;
  }
  return -1;
}

}  // namespace

TEST_F(GmwmCliOutputSafety, NoKillWhileAnOutputIsWrittenLeavesAnythingInItsFolder) {
  // 3e6 samples: about 60 MB of CSV, written over a second or more; each signal is sent
  // once the staged file holds 1 MB (no sleep to guess).
  for (int sig : {SIGKILL, SIGQUIT, SIGALRM, SIGTERM, SIGINT}) {
    const fs::path out = dir_ / ("run" + std::to_string(sig));
    fs::create_directory(out);
    const pid_t pid = start_gmwm(
        {"simulate", "--model", "WN(sigma2=1)", "--n", "3000000", "--output", "big.csv", "--json", "s.json"}, out);
    const auto t0 = std::chrono::steady_clock::now();
    long long bytes = -1;
    while ((bytes = staged_bytes(pid, out)) < (1 << 20) &&
           std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_GE(bytes, 1 << 20) << "signal " << sig << ": no unnamed staged file seen growing in " << out;
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ": status " << status;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_TRUE(fs::is_empty(out)) << "signal " << sig << ": a file was left in " << out << ": "
                                   << fs::directory_iterator(out)->path();
  }
}
