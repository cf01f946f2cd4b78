// The program's allocation functions: malloc and free, as the standard library's own,
// plus a request for transparent huge pages on every large block (a signal, its prefix
// sums, a level's coefficients, a replicate's buffers: megabytes each).
//
// Why: each fresh 4 KiB page costs a page fault on first touch, and under a hypervisor a
// fault is several microseconds. `gmwm wv --robust` on 1e6 samples took 11,300 faults
// (45 MB first touched); with 2 MiB pages its CPU time fell to 0.77 of that (farm-bench,
// n = 9, issue 44; the same effect as glibc's GLIBC_TUNABLES=glibc.malloc.hugetlb=1, which
// a user would have to set before starting the program). Results are unchanged: only the
// page size of the memory differs. Where the kernel's THP mode is "never" the advice is
// ignored; in "madvise" mode (Debian's default) it is what turns them on for these blocks.
//
// Replacing the global allocation functions is the standard's own hook (replaceable
// allocation functions, [new.delete]); the libraries of this program allocate through them,
// a Python process is not affected. Under AddressSanitizer or ThreadSanitizer the
// sanitizer's own replacements stay in place (its new/delete checks).
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

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
