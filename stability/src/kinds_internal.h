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
#include "gmwm/engine/samples.h"

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
// A piece's terms span at most this many phase points (a strided sum's pieces hold fewer
// terms), so that the pages a piece reads, released once it is done when the phase lives in a
// temporary file (samples.h), stay a few MB whatever the factor.
constexpr std::int64_t kPiecePoints = std::int64_t{1} << 16;

// A fault in a file mapping maps the whole page-cache folio around it, up to 2 MiB (a PMD on
// x86-64 Linux; 6.x kernels keep file pages in such large folios), so what a piece releases
// is widened to the 2 MiB boundaries of the file around its reads: the pages a strided read
// brought in on either side of it are dropped too (a sum read again after is faulted back in
// from the page cache). A strided ADEV of 3e7 points in a file peaked at 249 MB at m = 1e5
// when only the whole pages between a piece's reads were released, 23 MB with this
// (tools/bench/RESULTS.md, "Stability beyond the memory budget").
constexpr std::int64_t kFolioPoints = (std::int64_t{2} << 20) / 8;

// Releases x[lo, hi) of a phase of `points` points in a file, widened to the folio
// boundaries around it (nothing for a phase in memory).
inline void release_around(const double* x, std::int64_t points, std::int64_t lo, std::int64_t hi) {
  if (hi <= lo) return;
  const std::int64_t from = lo / kFolioPoints * kFolioPoints;
  const std::int64_t to = std::min(points, (hi + kFolioPoints - 1) / kFolioPoints * kFolioPoints);
  gmwm::detail::release_file_pages(x + from, x + to);
}

// Pieces between two releases: each release is a TLB shootdown on every thread (madvise),
// which at one a piece (512 kB) took 40% of a pass's time in the kernel; one every 16 pieces
// (8 MB of each read stream) holds a few tens of MB at most.
constexpr std::int64_t kReleasePieces = 16;

// Where term t of a sum reads the phase x: x[offset + t * stride] for each of `count` reads.
// When x lives in a temporary file, each piece's pages are released once it is summed, so a
// pass over a record of any length holds memory that does not grow with it (samples.h).
struct Reads {
  struct Read {
    std::int64_t offset = 0, stride = 1;
  };
  const double* x = nullptr;
  std::int64_t points = 0;  // x's length
  std::array<Read, 4> read{};
  int count = 0;
  // The pages terms [first, last) read, released (nothing when x is in memory).
  void release(std::int64_t first, std::int64_t last) const {
    if (x == nullptr || last <= first) return;
    for (int k = 0; k < count; ++k) {
      const Read& r = read[static_cast<std::size_t>(k)];
      const std::int64_t a = r.offset + first * r.stride, b = r.offset + (last - 1) * r.stride;
      const std::int64_t lo = std::clamp<std::int64_t>(std::min(a, b), 0, points);
      const std::int64_t hi = std::clamp<std::int64_t>(std::max(a, b) + 1, 0, points);
      release_around(x, points, lo, hi);
    }
  }
};

// Reads at offsets k * step (k < count), stride `stride`: the differences of the Allan and
// Hadamard families (step m), TIE's.
inline Reads reads_at(std::span<const double> x, std::int64_t start, std::int64_t step, int count,
                      std::int64_t stride) {
  Reads r;
  if (!gmwm::detail::in_sample_file(x.data(), x.size())) return r;
  r.x = x.data();
  r.points = static_cast<std::int64_t>(x.size());
  r.count = count;
  for (int k = 0; k < count; ++k) r.read[static_cast<std::size_t>(k)] = {start + k * step, stride};
  return r;
}

// Terms a piece holds when consecutive terms are `stride` phase points apart (the same in
// memory and in a file: the value does not depend on where the phase lives).
inline std::int64_t piece_terms(std::int64_t stride) {
  return std::clamp<std::int64_t>(kPiecePoints / std::max<std::int64_t>(stride, 1), 1, kPieceTerms);
}

// Sum over t in [0, count) of piece(first, last) for the pieces of `per` terms, in parallel
// and added in their order; each piece's pages released behind it.
template <class P>
double sum_in_pieces(std::int64_t count, std::int64_t per, const Reads& reads, const P& piece) {
  const std::int64_t pieces = (count + per - 1) / per;
  if (pieces <= 1) {
    const double v = piece(0, count);
    reads.release(0, count);
    return v;
  }
  std::vector<double> part(static_cast<std::size_t>(pieces));
  gmwm::parallel_for(std::int64_t{0}, pieces, [&](std::int64_t p) {
    const std::int64_t first = p * per, last = std::min(count, first + per);
    part[static_cast<std::size_t>(p)] = piece(first, last);
    if ((p + 1) % kReleasePieces == 0 || last == count)
      reads.release(std::max<std::int64_t>(0, last - kReleasePieces * per), last);
  });
  double sum = 0.0;
  for (const double v : part) sum += v;
  return sum;
}

// Sum of d(t)^2 over t in [0, count): d must be a pure function of t (pieces run at once),
// reading the phase where `reads` says, consecutive terms `stride` points apart.
template <class D>
double sum_of_squares(std::int64_t count, const D& d, const Reads& reads = {}, std::int64_t stride = 1) {
  return sum_in_pieces(count, piece_terms(stride), reads,
                       [&](std::int64_t first, std::int64_t last) { return lane_sum_of_squares(first, last, d); });
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
