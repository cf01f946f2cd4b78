#pragma once
// Runs the built `gmwm` program (GMWM_CLI_PATH) for end-to-end tests and checks the error
// policy: bad input -> exit 2, one line on stderr, nothing written.

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace gmwm::test {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

/// How run_gmwm() starts the program (shell fragments, not quoted: the test writes them).
struct RunOptions {
  std::string before;                    ///< run first in the same shell, e.g. "ulimit -f 64;"
  std::string stdin_from = "/dev/null";  ///< stdin redirection target, or a pipe source with stdin_pipe
  bool stdin_pipe = false;               ///< `stdin_from | gmwm ...` instead of `< stdin_from`
  std::string stdout_to;                 ///< stdout to this path instead of the captured file (out stays empty)
};

/// The `gmwm` program the tests run: $GMWM_CLI when set (tools/sanitize.sh points it at
/// the AddressSanitizer build of the program, so that the hostile corpus runs against it
/// without rebuilding the tests), else the program built beside the tests (GMWM_CLI_PATH).
const char* gmwm_cli_path();

/// Runs `gmwm args...` in folder `dir` (relative paths resolve there), capturing stdout
/// and stderr.
CliRun run_gmwm(const std::vector<std::string>& args, const std::filesystem::path& dir);
CliRun run_gmwm(const std::vector<std::string>& args, const std::filesystem::path& dir, const RunOptions& how);

/// Files in `dir` left by an interrupted or failed write (gmwm's ".NAME.gmwm-XXXXXX").
std::vector<std::string> staged_leftovers(const std::filesystem::path& dir);

/// A terminal text as one line: every run of whitespace (a wrapped line's newline and hanging
/// indent included) one space, so that a sentence is found wherever the width wrapped it.
std::string flowed(const std::string& text);

/// Non-empty lines of a text.
std::vector<std::string> lines_of(const std::string& text);

void write_text(const std::filesystem::path& path, const std::string& text);
std::string read_text(const std::filesystem::path& path);
nlohmann::json read_json(const std::filesystem::path& path);

/// A CSV with header `name` and n Gaussian samples (fixed seed), no timestamp column.
void write_noise_csv(const std::filesystem::path& path, int n, const std::string& name = "x");

/// Writes `sim.csv` (three gyro axes gyro_x/y/z at 200 Hz with the EuRoC ADIS16448 figures,
/// N = 1.6968e-4 rad/s/sqrt(Hz), K = 1.9393e-5 rad/s^2/sqrt(Hz), n samples each) and
/// `fit.json` (WN+RW fitted with --units gyro=rad/s) in `dir`; gtest failures on error.
void write_adis_gyro_fit(const std::filesystem::path& dir, int n);

/// The document without its run-dependent "run" object.
nlohmann::json without_run(nlohmann::json doc);

/// Checks the bad-input contract for a run whose --json target is `json_path`: exit code
/// 2, exactly one line on stderr starting "gmwm: error: " and containing every string of
/// `mentions` (the input's name, the place, what was expected), nothing on stdout and no
/// file at `json_path`.
void expect_bad_input(const CliRun& run, const std::vector<std::string>& mentions,
                      const std::filesystem::path& json_path);

}  // namespace gmwm::test
