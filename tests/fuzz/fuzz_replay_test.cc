// Replays the kept fuzzing corpora (tests/fuzz/corpus/<target>/: seeds and every input a
// fuzzer found interesting or crashing) through the same targets in the normal suite: each
// must end in a result or a refusal (InputError), never a crash or another exception.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz_targets.h"

namespace fs = std::filesystem;

namespace {

class FuzzCorpus : public ::testing::TestWithParam<gmwm::fuzz::Target> {};

TEST_P(FuzzCorpus, EveryKeptInputEndsInAResultOrARefusal) {
  const gmwm::fuzz::Target t = GetParam();
  const fs::path dir = fs::path(GMWM_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / t.name;
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  int replayed = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
    SCOPED_TRACE(e.path().string());
    EXPECT_NO_THROW(t.run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    ++replayed;
  }
  EXPECT_GT(replayed, 0) << "no seed in " << dir;
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzCorpus, ::testing::ValuesIn(gmwm::fuzz::kTargets),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
