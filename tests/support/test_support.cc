#include "test_support.h"

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

#include <cstdlib>
#include <random>

namespace gmwm::test {

std::optional<std::filesystem::path> shared_data_dir() {
  std::filesystem::path p;
  if (const char* env = std::getenv("GMWM_SHARED_DATA"); env && *env) {
    p = env;
  } else {
    p = std::filesystem::path(GMWM_SOURCE_DIR) / ".." / "shared" / "data";
  }
  if (std::filesystem::exists(p / "adis_16405_imu1.csv.gz")) return std::filesystem::canonical(p);
  return std::nullopt;
}

std::string shared_data_file(const std::string& name) {
  auto d = shared_data_dir();
  return d ? (*d / name).string() : std::string();
}

std::filesystem::path temp_dir(const std::string& tag) {
  std::random_device rd;
  auto p = std::filesystem::temp_directory_path() /
           ("gmwm_test_" + tag + "_" + std::to_string(rd()));
  std::filesystem::create_directories(p);
  return p;
}

std::vector<WaveletVariance> simulated_replicates(const std::string& spec, const std::vector<int>& log2n,
                                                  std::uint64_t seed) {
  const Model m = parse_model(spec);
  std::vector<WaveletVariance> out;
  for (std::size_t k = 0; k < log2n.size(); ++k) {
    const std::int64_t n = std::int64_t{1} << log2n[k];
    const auto x = simulate(m, m.given_values(), n, seed, k);
    out.push_back(classical_wv(x.data(), n));
  }
  return out;
}

}  // namespace gmwm::test
