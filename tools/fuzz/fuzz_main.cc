// libFuzzer entry point for one target, chosen at build time (GMWM_FUZZ_TARGET: its index
// in kTargets). Built by tools/fuzz.sh with clang -fsanitize=fuzzer,address,undefined.
#include <cstddef>
#include <cstdint>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gmwm::fuzz::kTargets[GMWM_FUZZ_TARGET].run(data, size);
  return 0;
}

// The structure-aware half of the mutations (issue 25): for the binary readers, one mutation
// in three sets one of the input's size fields (size_fields.h) to an extreme value; the rest
// are libFuzzer's own.
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  const gmwm::fuzz::Target& t = gmwm::fuzz::kTargets[GMWM_FUZZ_TARGET];
  if (t.size_fields && seed % 3 == 0 && gmwm::fuzz::drive_to_extreme(data, size, t.size_fields(data, size), seed / 3))
    return size;
  return LLVMFuzzerMutate(data, size, max_size);
}
