#pragma once
// The deviations of deviation.h beyond the Allan, modified, Hadamard and total families, each
// at one averaging factor m of phase x (tau0 apart): the modified and Hadamard total variances
// (total_deviation.cc), Theo1 (theo1.cc), MTIE and TIE rms (time_error.cc). deviation.cc checks
// the factor and the phase before it calls them.
#include <array>
#include <cstdint>
#include <span>

namespace gmwm::stability::detail {

// Sum of d(t)^2 over t in [0, count), in four interleaved double lanes: the loop vectorises
// (each lane's order fixed, so the value does not depend on the machine's vector width), and
// 1e7 squares summed so keep their rounding near 1e-13 relative (checked against allantools
// and Stable32: tools/bench/RESULTS.md, "The frequency-stability deviations").
constexpr int kLanes = 4;
template <class D>
double sum_of_squares(std::int64_t count, D d) {
  std::array<double, kLanes> lane{};
  std::int64_t t = 0;
  for (; t + kLanes <= count; t += kLanes)
    for (int l = 0; l < kLanes; ++l) {
      const double v = d(t + l);
      lane[static_cast<std::size_t>(l)] += v * v;
    }
  for (; t < count; ++t) {
    const double v = d(t);
    lane[0] += v * v;
  }
  return (lane[0] + lane[1]) + (lane[2] + lane[3]);
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
