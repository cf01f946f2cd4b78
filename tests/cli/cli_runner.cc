#include "cli_runner.h"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

namespace gmwm::test {

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

}  // namespace

const char* gmwm_cli_path() {
  const char* given = std::getenv("GMWM_CLI");
  return given && *given ? given : GMWM_CLI_PATH;
}

CliRun run_gmwm(const std::vector<std::string>& args, const std::filesystem::path& dir) {
  return run_gmwm(args, dir, RunOptions{});
}

std::vector<std::string> staged_leftovers(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".gmwm-") != std::string::npos) out.push_back(name);
  }
  return out;
}

CliRun run_gmwm(const std::vector<std::string>& args, const std::filesystem::path& dir, const RunOptions& how) {
  static int counter = 0;
  const auto out_path = dir / (".stdout" + std::to_string(counter));
  const auto err_path = dir / (".stderr" + std::to_string(counter++));
  std::string cmd = "cd " + shell_quote(dir.string()) + " && " + how.before + " ";
  if (how.stdin_pipe) cmd += how.stdin_from + " | ";
  cmd += shell_quote(gmwm_cli_path());
  for (const auto& a : args) cmd += " " + shell_quote(a);
  if (!how.stdin_pipe) cmd += " < " + how.stdin_from;
  cmd += " > " + (how.stdout_to.empty() ? shell_quote(out_path.string()) : how.stdout_to) + " 2> " +
         shell_quote(err_path.string());
  cmd = "bash -c " + shell_quote(cmd);
  const int status = std::system(cmd.c_str());
  CliRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = read_text(out_path);
  run.err = read_text(err_path);
  std::filesystem::remove(out_path);
  std::filesystem::remove(err_path);
  return run;
}

std::string flowed(const std::string& text) {
  std::string out;
  bool space = false;
  for (char c : text) {
    if (c == ' ' || c == '\n' || c == '\t') {
      space = true;
      continue;
    }
    if (space && !out.empty()) out += ' ';
    space = false;
    out += c;
  }
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

nlohmann::json read_json(const std::filesystem::path& path) { return nlohmann::json::parse(read_text(path)); }

void write_noise_csv(const std::filesystem::path& path, int n, const std::string& name) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> z;
  std::ostringstream os;
  os.precision(17);
  os << name << "\n";
  for (int i = 0; i < n; ++i) os << z(rng) << "\n";
  write_text(path, os.str());
}

nlohmann::json without_run(nlohmann::json doc) {
  doc.erase("run");
  return doc;
}

void expect_bad_input(const CliRun& run, const std::vector<std::string>& mentions,
                      const std::filesystem::path& json_path) {
  EXPECT_EQ(run.exit_code, 2) << "stderr: " << run.err;
  const auto err_lines = lines_of(run.err);
  ASSERT_EQ(err_lines.size(), 1u) << "expected exactly one line on stderr, got:\n" << run.err;
  EXPECT_EQ(err_lines[0].rfind("gmwm: error: ", 0), 0u) << err_lines[0];
  for (const auto& m : mentions)
    EXPECT_NE(err_lines[0].find(m), std::string::npos) << "the message should mention '" << m << "': " << err_lines[0];
  EXPECT_TRUE(run.out.empty()) << "nothing should go to stdout, got:\n" << run.out;
  EXPECT_FALSE(std::filesystem::exists(json_path)) << json_path << " should not be written";
}

void write_adis_gyro_fit(const std::filesystem::path& dir, int n) {
  auto r =
      run_gmwm({"simulate", "--model", "WN(sigma2=5.75826048e-06)+RW(gamma2=1.880442245e-12)", "--n", std::to_string(n),
                "--freq", "200", "--signals", "3", "--names", "gyro_x,gyro_y,gyro_z", "--output", "sim.csv", "--quiet"},
               dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_gmwm({"fit", "sim.csv", "--model", "WN+RW", "--units", "gyro=rad/s", "--json", "fit.json", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace gmwm::test
