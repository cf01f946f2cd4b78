#pragma once
// The deviations of deviation.h beyond the Allan, modified, Hadamard and total families, each
// at one averaging factor m of phase x (tau0 apart): the modified and Hadamard total variances
// (total_deviation.cc), Theo1 (theo1.cc), MTIE and TIE rms (time_error.cc). deviation.cc checks
// the factor and the phase before it calls them.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "gmwm/engine/parallel.h"

namespace gmwm::stability::detail {

// Sum of d(t)^2 over t in [first, last), in four interleaved double lanes: the loop
// vectorises (each lane's order fixed, so the value does not depend on the machine's vector
// width).
constexpr int kLanes = 4;
template <class D>
double lane_sum_of_squares(std::int64_t first, std::int64_t last, const D& d) {
  std::array<double, kLanes> lane{};
  std::int64_t t = first;
  for (; t + kLanes <= last; t += kLanes)
    for (int l = 0; l < kLanes; ++l) {
      const double v = d(t + l);
      lane[static_cast<std::size_t>(l)] += v * v;
    }
  for (; t < last; ++t) {
    const double v = d(t);
    lane[0] += v * v;
  }
  return (lane[0] + lane[1]) + (lane[2] + lane[3]);
}

// Terms summed in one piece; a longer sum is cut into pieces of this many, summed in parallel
// and added in their order, so that one factor's sum uses every thread (the first factors of
// an octave set are most of its work: m = 1 alone is half a non-overlapping ADEV's) and its
// value does not depend on the thread count. 2^16 terms (512 kB of phase a piece) amortise a
// task's cost (microseconds) over ~30 us of sums, and the pieces' partial sums keep 1e7
// squares' rounding near 1e-14 relative (checked against allantools and Stable32:
// tools/bench/RESULTS.md, "The frequency-stability deviations").
constexpr std::int64_t kPieceTerms = std::int64_t{1} << 16;

// Sum of d(t)^2 over t in [0, count): d must be a pure function of t (pieces run at once).
template <class D>
double sum_of_squares(std::int64_t count, const D& d) {
  if (count <= kPieceTerms) return lane_sum_of_squares(0, count, d);
  const std::int64_t pieces = (count + kPieceTerms - 1) / kPieceTerms;
  std::vector<double> piece(static_cast<std::size_t>(pieces));
  gmwm::parallel_for(std::int64_t{0}, pieces, [&](std::int64_t p) {
    piece[static_cast<std::size_t>(p)] =
        lane_sum_of_squares(p * kPieceTerms, std::min(count, (p + 1) * kPieceTerms), d);
  });
  double sum = 0.0;
  for (const double v : piece) sum += v;
  return sum;
}

/// MTOTVAR (NIST SP 1065 eq. 27): O(N) whatever m (total_deviation.cc explains how).
double modified_total_variance(std::span<const double> x, std::int64_t m, double tau0);

/// HTOTVAR (NIST SP 1065 eq. 29) for m >= 2, of the frequency y_i = (x_{i+1} - x_i) / tau0;
/// Stable32 reads OHVAR at m = 1, which deviation.cc does. O(N) whatever m.
double hadamard_total_variance(std::span<const double> x, std::int64_t m, double tau0);

/// The sum over the windows of 3m points of z (N - 3m + 1 of the phase, M - 3m + 1 of the
/// frequency) of the 6m squared second differences of m-point sums of the window, detrended
/// and reflected to 9m points (the numerator both total variances share), in O(N).
double total_window_sum(std::span<const double> z, std::int64_t m);
/// The same sum read window by window (O(N m)): what total_window_sum does for small m.
double total_window_sum_direct(std::span<const double> z, std::int64_t m);

/// Theo1 (NIST SP 1065 eq. 30) at the even factor m >= 10 (tau = 0.75 m tau0).
double theo1_variance(std::span<const double> x, std::int64_t m, double tau0);
/// Theo1's numerator sum_{i<N-m} sum_{k=1}^{m/2} (x_i - x_{i+k} - x_{i+m-k} + x_{i+m})^2 / k
/// term by term (O(N m)): what theo1_variance does for small m.
double theo1_sum_direct(std::span<const double> x, std::int64_t m);
/// The same numerator through correlations (O(N log^2 m)): what it does beyond.
double theo1_sum_by_correlation(std::span<const double> x, std::int64_t m);

/// MTIE: the largest spread max - min of x over the windows of m + 1 points (m tau0 long).
double max_time_interval_error(std::span<const double> x, std::int64_t m);
/// TIE rms: sqrt(sum_{i<N-m} (x_{i+m} - x_i)^2 / (N - m)).
double time_interval_error_rms(std::span<const double> x, std::int64_t m);

}  // namespace gmwm::stability::detail
