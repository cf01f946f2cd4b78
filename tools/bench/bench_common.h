#pragma once
// Shared helpers of the benchmark programs: where the shared IMU recordings are, and
// a wall clock. Benchmarks print their figures; tools/bench/run_all.sh collects them
// into tools/bench/RESULTS.md.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace gmwm::bench {

/// The folder named by $GMWM_SHARED_DATA, else a default folder beside the source tree. Exits with a clear
/// message when the folder is absent (benchmarks need the real data).
inline std::string shared_data_file(const std::string& name) {
  std::filesystem::path dir;
  if (const char* env = std::getenv("GMWM_SHARED_DATA"); env && *env)
    dir = env;
  else
    dir = std::filesystem::path(GMWM_SOURCE_DIR) / ".." / "shared" / "data";
  const auto p = dir / name;
  if (!std::filesystem::exists(p)) {
    std::fprintf(stderr, "benchmark: %s not found (set GMWM_SHARED_DATA)\n", p.c_str());
    std::exit(2);
  }
  return p.string();
}

class Stopwatch {
 public:
  Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  void reset() { t0_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace gmwm::bench
