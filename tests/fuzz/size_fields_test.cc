// The size fields of the binary readers' seeds (size_fields.h), each driven to every extreme
// the fuzzers' mutator uses, one at a time: a deterministic sweep in the normal suite of what
// the fuzzers explore at random (issue 25). Every variant must end in a result or a refusal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_targets.h"
#include "size_fields.h"

namespace fs = std::filesystem;

namespace {

// The number of extremes drive_to_extreme() picks from (its list of 16; 7 for ASCII lengths).
constexpr std::uint64_t kExtremes = 16;
// Fields swept per seed: the first ones (headers, the first records and chunks) and then
// every k-th, so that a seed of hundreds of messages stays a few seconds.
constexpr std::size_t kFieldsPerSeed = 96;

class SizeFieldSweep : public ::testing::TestWithParam<gmwm::fuzz::Target> {};

TEST_P(SizeFieldSweep, EverySizeFieldOfTheSeedsAtEveryExtremeEndsInAResultOrARefusal) {
  const gmwm::fuzz::Target t = GetParam();
  const fs::path dir = fs::path(GMWM_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / t.name;
  int seeds = 0;
  std::size_t variants = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().rfind("seed_", 0) != 0) continue;
    std::ifstream in(e.path(), std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    const auto fields = t.size_fields(bytes.data(), bytes.size());
    EXPECT_FALSE(fields.empty()) << e.path();
    const std::size_t step = std::max<std::size_t>(1, fields.size() / kFieldsPerSeed);
    for (std::size_t f = 0; f < fields.size(); f += step) {
      for (std::uint64_t x = 0; x < kExtremes; ++x) {
        std::vector<std::uint8_t> v = bytes;
        ASSERT_TRUE(gmwm::fuzz::drive_to_extreme(v.data(), v.size(), {fields[f]}, x));
        SCOPED_TRACE(e.path().string() + " field at byte " + std::to_string(fields[f].offset) + ", extreme " +
                     std::to_string(x));
        EXPECT_NO_THROW(t.run(v.data(), v.size()));
        ++variants;
      }
    }
    ++seeds;
  }
  EXPECT_GT(seeds, 0) << "no seed_* in " << dir;
  RecordProperty("variants", static_cast<int>(variants));
}

std::vector<gmwm::fuzz::Target> binary_targets() {
  std::vector<gmwm::fuzz::Target> out;
  for (const auto& t : gmwm::fuzz::kTargets)
    if (t.size_fields) out.push_back(t);
  return out;
}

INSTANTIATE_TEST_SUITE_P(BinaryReaders, SizeFieldSweep, ::testing::ValuesIn(binary_targets()),
                         [](const auto& param) { return std::string(param.param.name); });

}  // namespace
