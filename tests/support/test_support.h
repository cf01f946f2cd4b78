#pragma once
// Shared helpers for the test suites.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::test {

/// The folder with the real IMU recordings: the folder named by $GMWM_SHARED_DATA,
/// else a default folder beside the source tree. std::nullopt when absent (the caller skips, unless
/// GMWM_REQUIRE_SHARED_DATA=1, in which case absence is a test failure).
std::optional<std::filesystem::path> shared_data_dir();

/// Path of a file in the shared data folder, or skips the current test (GTEST_SKIP is
/// issued by the macro below) / fails when the data is required.
std::string shared_data_file(const std::string& name);

/// One gzip member holding `text` (zlib at the best compression): concatenated members are
/// one gzip stream.
std::string gzip_member(const std::string& text);

/// A fresh temporary directory for one test.
std::filesystem::path temp_dir(const std::string& tag);

/// A fresh temporary directory removed with everything in it when the folder goes out of
/// scope, however the test ends (an ASSERT's early return left temp_dir's folders behind).
struct TempFolder {
  std::filesystem::path path;
  explicit TempFolder(const std::string& tag) : path(temp_dir(tag)) {}
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  ~TempFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

/// Classical WVs of replicates of `spec` (a model with every value): replicate k has
/// 2^log2n[k] samples, stream (seed, k).
std::vector<WaveletVariance> simulated_replicates(const std::string& spec, const std::vector<int>& log2n,
                                                  std::uint64_t seed);

/// A PX4 ULog file written byte by byte from the published format (independent of the
/// reader in io/): header, a flag-bits message, an info message, the formats of
/// sensor_combined (PX4's field layout) and sensor_gyro, subscriptions, a logged string
/// and a sync message among the data. sensor_combined sample i has timestamp
/// t0 + i * step_us, gyro_rad = (i, -i, 2i) / 1024 and accelerometer_m_s2 = (9.81 + i / 4096,
/// 0.5 + (i mod 7) / 8, -i / 2048) (floats, exact); sensor_gyro instance k sample i has x = k + i / 512,
/// y = z = 0. `stamps`, when given, replaces sensor_combined's timestamps. `resubscribe_at`
/// >= 0: before sample i = resubscribe_at, sensor_combined is subscribed again under msg_id
/// 8 (its format defined again too, as after a logger restart), and its later data use it.
struct UlogFixture {
  int samples = 64;
  std::uint64_t t0 = 1000000, step_us = 5000;  // 200 Hz
  int gyro_instances = 2;
  std::vector<std::uint64_t> stamps;
  int resubscribe_at = -1;
};
std::vector<unsigned char> ulog_bytes(const UlogFixture& f = {});
/// The fixture's sensor_combined values as doubles: (gyro_x..z, accel_x..z) per sample.
std::vector<std::vector<double>> ulog_expected(const UlogFixture& f = {});

}  // namespace gmwm::test

/// Skips the current test with a clear message when the shared data folder is absent,
/// or fails when GMWM_REQUIRE_SHARED_DATA=1.
#define GMWM_REQUIRE_SHARED_DATA()                                                        \
  do {                                                                                    \
    if (!::gmwm::test::shared_data_dir()) {                                               \
      const char* req = std::getenv("GMWM_REQUIRE_SHARED_DATA");                          \
      if (req && std::string(req) == "1")                                                 \
        FAIL() << "shared data folder not found (set GMWM_SHARED_DATA); required in CI";  \
      GTEST_SKIP() << "shared data folder not found: set GMWM_SHARED_DATA to the folder " \
                      "with adis_16405_imu1.csv.gz to run this test";                     \
    }                                                                                     \
  } while (0)
