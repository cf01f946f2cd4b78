#pragma once
// gmwm::parallel_for: tbb::parallel_for over an index range [first, last), with its fork
// and join told to ThreadSanitizer.
//
// oneTBB's scheduler (task spawning, stealing, the wait at the join) lives in libtbb,
// which Debian builds without ThreadSanitizer: TSan then sees no happens-before edge
// between the caller's writes and the bodies' reads, nor between the bodies' writes and
// the caller's reads after the join, and reports each of them as a race. Under TSan the
// wrapper adds exactly those edges (caller -> every body at the fork, every body -> caller
// at the join) and nothing between two bodies, so a real race between bodies is still
// reported. Without TSan it is tbb::parallel_for itself.

#include <tbb/parallel_for.h>

#if defined(__SANITIZE_THREAD__)
#define GMWM_TSAN_ANNOTATIONS 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define GMWM_TSAN_ANNOTATIONS 1
#endif
#endif

#ifdef GMWM_TSAN_ANNOTATIONS
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace gmwm {

namespace tsan {
/// Happens-before edges for ThreadSanitizer: everything before release(p) on one thread
/// happens before everything after a later acquire(p) on another. No-ops without TSan.
inline void release([[maybe_unused]] const void* p) {
#ifdef GMWM_TSAN_ANNOTATIONS
  __tsan_release(const_cast<void*>(p));
#endif
}
inline void acquire([[maybe_unused]] const void* p) {
#ifdef GMWM_TSAN_ANNOTATIONS
  __tsan_acquire(const_cast<void*>(p));
#endif
}
}  // namespace tsan

template <class Index, class Body>
void parallel_for(Index first, Index last, const Body& body) {
#ifdef GMWM_TSAN_ANNOTATIONS
  const char fork = 0, join = 0;
  tsan::release(&fork);
  tbb::parallel_for(first, last, [&](Index i) {
    tsan::acquire(&fork);
    body(i);
    tsan::release(&join);
  });
  tsan::acquire(&join);
#else
  tbb::parallel_for(first, last, body);
#endif
}

}  // namespace gmwm
