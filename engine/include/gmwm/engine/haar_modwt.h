#pragma once
// Haar MODWT coefficients by prefix sums (docs/statistics.md section 1):
//   W_{j,t} = (S_{t+1} - 2 S_{t+1-m_j} + S_{t+1-tau_j}) / tau_j,  t = tau_j - 1 .. N - 1,
// with S_k = sum_{i<k} (x_i - xbar) (the Haar filter ignores a constant level; centring
// keeps the prefix sums small). Only the M_j = N - tau_j + 1 coefficients that do not
// wrap around the boundary are used. All levels cost O(N J) and share one prefix sum.
// The prefix sums of a series held in a file (gmwm::Samples, samples.h) go to a temporary
// file, and the pages behind each pass are released: memory then does not grow with N.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace gmwm {

namespace detail {
class TemporaryArray;
}

class HaarModwt {
 public:
  /// Builds the prefix sums of x (n >= 2).
  HaarModwt(const double* x, std::int64_t n);
  ~HaarModwt();
  HaarModwt(HaarModwt&&) noexcept;
  HaarModwt& operator=(HaarModwt&&) noexcept;

  std::int64_t size() const { return n_; }
  /// J = floor(log2 N): the deepest level with at least one coefficient.
  int max_levels() const;
  /// M_j = N - 2^j + 1.
  std::int64_t count(int level) const;
  /// The M_j coefficients of a level, in time order.
  void coefficients(int level, std::vector<double>& out) const;
  /// sum_t W_{j,t}^2 without materialising the coefficients.
  double sum_of_squares(int level) const;
  /// How many coefficients of a level have W_{j,t}^2 > cut, without materialising them
  /// (the same values as `coefficients`, bit for bit); 0 outside 1..max_levels().
  std::int64_t count_above(int level, double cut) const;
  /// The same for a Haar filter of any half-width m (width 2m, not only 2^(j-1)): the
  /// sum over t of ((S_{t+2m} - 2 S_{t+m} + S_t) / 2m)^2, N - 2m + 1 terms; 0 when there
  /// are none. The overlapping Allan variance at averaging factor m is twice its mean.
  double sum_of_squares_half_width(std::int64_t m) const;
  /// sum_of_squares_half_width of each of several half-widths in one pass over the prefix
  /// sums, block by block (the block's S_t serve every half-width from cache, where a pass
  /// per half-width reads them from memory each time): the same values, bit for bit, as
  /// one call per half-width (each sum is accumulated in the same order).
  std::vector<double> sums_of_squares_half_width(std::span<const std::int64_t> m) const;
  /// sum_t W_{j,t}^2 and max_t W_{j,t}^2 of a level in one pass (the gap's burst
  /// statistic log(max / mean) on every reference replicate); the sum equals sum_of_squares.
  struct Squares {
    double sum = 0.0, peak = 0.0;
  };
  Squares squares_of_level(int level) const;
  /// Computes squares_of_level for levels [first, last] once and keeps them: later calls
  /// of squares_of_level and sum_of_squares on those levels return the kept values (the
  /// same numbers, one pass instead of two when a caller wants the peaks and the WV).
  void keep_squares(int first, int last);
  /// The prefix sums S_0 .. S_n of the mean-centred series (S_0 = 0), which every level's
  /// coefficients combine: for other filters over the same series (the gap's step scan).
  /// Valid while the transform lives; in a temporary file for a series held in one.
  std::span<const double> prefix_sums() const { return {p_, static_cast<std::size_t>(n_) + 1}; }
  /// Bound on the round-off of a coefficient of this level: a coefficient of a
  /// quantized series that is exactly 0 comes out below it (the mean-centred prefix
  /// sums are not on the data's lattice). Robust estimators count such values as zeros.
  double noise_floor(int level) const;

 private:
  Squares squares(std::int64_t half_width, bool with_peak) const;
  const Squares* kept(int level) const;

  std::int64_t n_;
  std::vector<Squares> kept_;  // by level - 1; kept_valid_ marks the levels computed
  std::vector<char> kept_valid_;
  std::vector<double> prefix_;                    // S_0 .. S_n in memory, or
  std::unique_ptr<detail::TemporaryArray> file_;  // in a temporary file
  const double* p_ = nullptr;                     // whichever holds them
  double max_abs_prefix_ = 0.0;
};

/// The transforms of several series, built in parallel (one task per series): what the
/// classical WV and the Allan deviation of those series share (classical_wv.h, allan.h).
std::vector<std::unique_ptr<HaarModwt>> haar_transforms(const std::vector<std::span<const double>>& series);

/// HaarModwt::sums_of_squares_half_width of several transforms, half_widths[c] on
/// transforms[c], in parallel: each series' half-widths in kSharedPassGroups interleaved
/// groups (small and large half-widths mixed, so the groups cost alike), one shared pass
/// each, every group of every series one task. The same values whatever the thread count.
std::vector<std::vector<double>> sums_of_squares_half_width(const std::vector<std::unique_ptr<HaarModwt>>& transforms,
                                                            const std::vector<std::vector<std::int64_t>>& half_widths);
/// Groups per series of that parallel pass: four keep two cores busy on a single series;
/// each group re-reads the block of S_t the others read, a small part of the traffic.
inline constexpr std::size_t kSharedPassGroups = 4;

}  // namespace gmwm
