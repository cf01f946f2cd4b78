#pragma once
// gmwm::parallel_for: body(i) for every i in [first, last), in parallel: what every
// parallel loop of gmwm goes through. Each body writes only its own results, so the
// outcome does not depend on the schedule or the thread count.
//
// Normally this is tbb::parallel_for. Under ThreadSanitizer (a GMWM_SANITIZE=thread
// build) the bodies run on std::threads instead: oneTBB's scheduler lives in libtbb,
// which Debian builds without TSan, so TSan cannot see its hand-offs (task spawning,
// stealing, the join, recycled task memory) and reports them as races by the dozen,
// hiding any real one. std::thread creation and join are visible to TSan, so there the
// only reports left are races between gmwm's own bodies, which is what the TSan run is
// for (tools/sanitize.sh thread).

#include <tbb/parallel_for.h>

#if defined(__SANITIZE_THREAD__)
#define GMWM_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define GMWM_THREAD_SANITIZER 1
#endif
#endif

#ifdef GMWM_THREAD_SANITIZER
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#endif

namespace gmwm {

#ifdef GMWM_THREAD_SANITIZER
/// Threads of a parallel_for under ThreadSanitizer: at least two, so that bodies overlap.
inline unsigned sanitizer_threads() { return std::max(2u, std::thread::hardware_concurrency()); }
#endif

template <class Index, class Body>
void parallel_for(Index first, Index last, const Body& body) {
#ifdef GMWM_THREAD_SANITIZER
  std::atomic<Index> next{first};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (Index i = next++; i < last; i = next++) {
      try {
        body(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < sanitizer_threads(); ++t) threads.emplace_back(work);
  work();
  for (auto& t : threads) t.join();
  if (error) std::rethrow_exception(error);
#else
  tbb::parallel_for(first, last, body);
#endif
}

}  // namespace gmwm
