// Side files end to end (issue 25): an export's JSON source and a Kalibr file read through
// pipes and FIFOs (the sniff keeps the bytes it looks at), or with a UTF-8 byte-order mark,
// give what the regular file gives.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using gmwm::test::RunOptions;
using gmwm::test::write_text;

namespace {

class GmwmSideFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("cli_side_files");
    ASSERT_NO_FATAL_FAILURE(gmwm::test::write_adis_gyro_fit(dir_, 16384));
    auto r =
        run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "file.yaml", "--partial", "--quiet"}, dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    from_file_ = read_text(dir_ / "file.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// The YAML without its comment lines (they name the source, which differs).
  static std::string values_of(const std::string& yaml) {
    std::string out;
    std::size_t at = 0;
    while (at < yaml.size()) {
      std::size_t end = yaml.find('\n', at);
      if (end == std::string::npos) end = yaml.size();
      const std::string line = yaml.substr(at, end - at);
      if (!line.empty() && line[0] != '#') out += line + "\n";
      at = end + 1;
    }
    return out;
  }

  static std::string cli() { return "'" + std::string(gmwm::test::gmwm_cli_path()) + "'"; }

  fs::path dir_;
  std::string from_file_;
};

}  // namespace

TEST_F(GmwmSideFiles, AnExportReadsAFitResultPipedIntoItWhole) {
  // The sniff used to consume the pipe's first byte: "invalid JSON at 2:11".
  RunOptions how;
  how.stdin_pipe = true;
  how.stdin_from = cli() + " fit sim.csv --model WN+RW --units gyro=rad/s --json - --quiet";
  const auto r = run_gmwm(
      {"export", "/dev/stdin", "--format", "kalibr", "--output", "pipe.yaml", "--partial", "--quiet"}, dir_, how);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(values_of(read_text(dir_ / "pipe.yaml")), values_of(from_file_));
}

TEST_F(GmwmSideFiles, AnExportReadsADataFilePipedIntoItWhole) {
  auto r = run_gmwm({"export", "sim.csv", "--model", "WN+RW", "--units", "gyro=rad/s", "--format", "kalibr", "--output",
                     "data.yaml", "--partial", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  RunOptions how;
  how.stdin_pipe = true;
  how.stdin_from = "cat sim.csv";
  r = run_gmwm({"export", "/dev/stdin", "--model", "WN+RW", "--units", "gyro=rad/s", "--format", "kalibr", "--output",
                "pipe.yaml", "--partial", "--quiet"},
               dir_, how);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(values_of(read_text(dir_ / "pipe.yaml")), values_of(read_text(dir_ / "data.yaml")));
}

TEST_F(GmwmSideFiles, AnExportReadsAResultFromAFifo) {
  // The sniff peeks at the FIFO (tee), the JSON reader then takes every byte.
  RunOptions how;
  how.before = "mkfifo r.fifo && (cat fit.json > r.fifo &);";
  const auto r =
      run_gmwm({"export", "r.fifo", "--format", "kalibr", "--output", "fifo.yaml", "--partial", "--quiet"}, dir_, how);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(values_of(read_text(dir_ / "fifo.yaml")), values_of(from_file_));
}

TEST_F(GmwmSideFiles, AnExportAcceptsAUtf8ByteOrderMark) {
  // RFC 8259 lets a reader ignore it; it was taken for a data file ("give --model").
  write_text(dir_ / "bom.json", "\xEF\xBB\xBF" + read_text(dir_ / "fit.json"));
  const auto r =
      run_gmwm({"export", "bom.json", "--format", "kalibr", "--output", "bom.yaml", "--partial", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(values_of(read_text(dir_ / "bom.yaml")), values_of(from_file_));
}

TEST_F(GmwmSideFiles, GapReadsAKalibrFilePipedIntoIt) {
  write_text(dir_ / "imu.yaml",
             "gyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
             "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\nupdate_rate: 200.0\n");
  auto r = run_gmwm({"gap", "sim.csv", "--columns", "gyro_x", "--kalibr", "imu.yaml", "--replicates", "40", "--json",
                     "file.json", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  RunOptions how;
  how.stdin_pipe = true;
  how.stdin_from = "cat imu.yaml";
  r = run_gmwm({"gap", "sim.csv", "--columns", "gyro_x", "--kalibr", "/dev/stdin", "--replicates", "40", "--json",
                "pipe.json", "--quiet"},
               dir_, how);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = gmwm::test::without_run(gmwm::test::read_json(dir_ / "file.json"));
  auto pipe = gmwm::test::without_run(gmwm::test::read_json(dir_ / "pipe.json"));
  EXPECT_EQ(file["columns"][0]["baseline_model"], pipe["columns"][0]["baseline_model"]);
}
