// End to end: no run overwrites what it reads, writes through a device, FIFO or symlink,
// leaves half of its outputs behind, or loses data past 4 GB of gzip text.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
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
  expect_refused(run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--output", "x.csv", "--json",
                           "x.csv"},
                          dir_),
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
  expect_refused(run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--output", "ok.csv", "--json",
                           "/proc/x.json"},
                          dir_),
                 {"cannot write '/proc/x.json'"}, {"ok.csv"});
}

TEST_F(GmwmCliOutputSafety, AFitWithAnUnwritableReportWritesNoJson) {
  if (!fs::exists("/usr/share/javascript/vega/vega-view.min.js") && !std::getenv("GMWM_VEGA_DIR"))
    GTEST_SKIP() << "libjs-vega not installed: --report is unavailable";
  expect_refused(run_gmwm({"fit", "base.csv", "--freq", "100", "--model", "WN", "--json", "ok.json", "--report",
                           "/proc/r.html"},
                          dir_),
                 {"cannot write '/proc/r.html"}, {"ok.json"});
}

TEST_F(GmwmCliOutputSafety, WritesNothingPastAFileSizeLimit) {
  // ulimit -f 64: at most 64 KiB per file. The simulated CSV is ~4 MB.
  gmwm::test::RunOptions how;
  how.before = "ulimit -f 64;";
  expect_refused(run_gmwm({"simulate", "--model", "WN(sigma2=1)", "--n", "200000", "--output", "big.csv", "--json",
                           "s.json"},
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
