// libFuzzer entry point for one target, chosen at build time (GMWM_FUZZ_TARGET: its index
// in kTargets). Built by tools/fuzz.sh with clang -fsanitize=fuzzer,address,undefined.
#include <cstddef>
#include <cstdint>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gmwm::fuzz::kTargets[GMWM_FUZZ_TARGET].run(data, size);
  return 0;
}
