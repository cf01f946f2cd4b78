// MTIE and TIE rms (kinds_internal.h), O(N) per averaging factor.
//
// MTIE reads every window of w = m + 1 points (Stable32's AF m: the window spans m tau0, and
// its "#" is N - m windows) by van Herk and Gil-Werman's running extremes: the points cut
// into blocks of w, a window starting at i inside block b is the suffix of b from i and the
// prefix of block b + 1 up to i + m, so its maximum and minimum are two lookups; each block
// costs O(w) and only two blocks are held at once.
#include <algorithm>
#include <cmath>
#include <vector>

#include "kinds_internal.h"

namespace gmwm::stability::detail {

double max_time_interval_error(std::span<const double> x, std::int64_t m) {
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t width = m + 1, starts = n - m;
  std::vector<double> suffix_max(static_cast<std::size_t>(width)), suffix_min(static_cast<std::size_t>(width));
  double largest = 0.0;
  for (std::int64_t block = 0; block < starts; block += width) {
    // The suffix extremes of this block (points block .. block + width - 1).
    const std::int64_t last = std::min(block + width, n) - 1;
    double hi = x[static_cast<std::size_t>(last)], lo = hi;
    for (std::int64_t i = last; i >= block; --i) {
      hi = std::max(hi, x[static_cast<std::size_t>(i)]);
      lo = std::min(lo, x[static_cast<std::size_t>(i)]);
      suffix_max[static_cast<std::size_t>(i - block)] = hi;
      suffix_min[static_cast<std::size_t>(i - block)] = lo;
    }
    // The window starting at `block` is the whole block; the later ones end in the next.
    largest = std::max(largest, suffix_max[0] - suffix_min[0]);
    double next_hi = -INFINITY, next_lo = INFINITY;
    for (std::int64_t i = block + 1; i < std::min(block + width, starts); ++i) {
      const double v = x[static_cast<std::size_t>(i + m)];
      next_hi = std::max(next_hi, v);
      next_lo = std::min(next_lo, v);
      const auto at = static_cast<std::size_t>(i - block);
      largest = std::max(largest, std::max(suffix_max[at], next_hi) - std::min(suffix_min[at], next_lo));
    }
  }
  return largest;
}

double time_interval_error_rms(std::span<const double> x, std::int64_t m) {
  const std::int64_t count = static_cast<std::int64_t>(x.size()) - m;
  const double* p = x.data();
  const double sum = sum_of_squares(
      count, [=](std::int64_t i) { return p[i + m] - p[i]; }, reads_at(x, 0, m, 2, 1));
  return std::sqrt(sum / static_cast<double>(count));
}

}  // namespace gmwm::stability::detail
