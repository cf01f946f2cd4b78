// The program's memory policy, in its allocation functions (malloc and free, as the
// standard library's own) and two malloc settings: large blocks on transparent huge pages,
// and freed memory kept for the next block. Results are unchanged (json_identity: every
// command identical); only where the memory comes from differs.
//
// Why: each fresh 4 KiB page costs a page fault on first touch, and under a hypervisor a
// fault costs microseconds. `gmwm wv --robust` on 1e6 samples took 11,300 faults (45 MB
// first touched), a bootstrap selection 138,000 for ten draws per model. Measured on imu1
// gyro_x (farm-bench, issue 44): wv --robust bisquare CPU A/B 0.76 with huge pages alone,
// select --optimism bootstrap --replicates 10 A/B 0.81 with both (tools/bench/RESULTS.md).
// Where the kernel's THP mode is "never" the advice is ignored; in "madvise" mode (Debian's
// default) it is what turns huge pages on for these blocks.
//
// Replacing the global allocation functions is the standard's own hook (replaceable
// allocation functions, [new.delete]); the libraries of this program allocate through them,
// a Python process is not affected. Under AddressSanitizer or ThreadSanitizer the
// sanitizer's own allocator stays in place.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

#include <malloc.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

// x86-64's and arm64's (4 KiB granule) transparent huge page: 2 MiB.
constexpr std::uintptr_t kHugePage = std::uintptr_t{1} << 21;
// Blocks from this size on are advised: at least one whole huge page lies inside them
// whatever their alignment, and the rounding of the last page wastes at most a third.
constexpr std::size_t kAdviseFrom = std::size_t{3} << 20;

void advise_huge_pages(void* p, std::size_t size) {
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + size) & ~(kHugePage - 1);
  // Advice only: a refusal (an old kernel, THP compiled out) leaves 4 KiB pages.
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

// Freed memory is kept for the next block instead of going back to the kernel: a
// bootstrap or gap replicate frees its series, prefix sums and coefficients (8 MB each at
// 1e6 samples) and allocates them again for the next draw; glibc returned them (blocks
// from its dynamic mmap threshold on were unmapped, the top of a thread's heap trimmed),
// so every draw faulted its pages in again. Blocks up to kHeapBlocksUpTo come from the
// heap (its largest allowed threshold: half glibc's 64 MiB thread heap), and the heap is
// never trimmed (138,000 -> 4,800 page faults for the bootstrap above). The cost: the
// process keeps its peak heap until it exits (a `serve` session too; its studies are
// bounded by the request limits).
constexpr int kHeapBlocksUpTo = 32 << 20;
constexpr int kNeverTrim = -1;  // M_TRIM_THRESHOLD -1: no trimming (mallopt(3))

struct KeepFreedMemory {
  KeepFreedMemory() {
    (void)mallopt(M_MMAP_THRESHOLD, kHeapBlocksUpTo);
    (void)mallopt(M_TRIM_THRESHOLD, kNeverTrim);
  }
};
const KeepFreedMemory keep_freed_memory;

void* allocate(std::size_t size) {
  if (size == 0) size = 1;
  for (;;) {
    if (void* p = std::malloc(size)) {
      if (size >= kAdviseFrom) advise_huge_pages(p, size);
      return p;
    }
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

}  // namespace

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

#endif
