#include "gmwm/engine/haar_modwt.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "gmwm/engine/check.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/samples.h"
#include "gmwm/engine/vector_clones.h"

namespace gmwm {

namespace {

// Values passed between releases of the pages behind a pass over a series in a file
// (and its prefix sums): 1 << 20 doubles = 8 MiB, a multiple of the four accumulators of
// sum_of_squares_half_width, so that blocking changes no sum.
constexpr std::int64_t kPassBlock = std::int64_t{1} << 20;

// A compensated (Neumaier 1974) running sum carried from one block of a pass to the next.
struct CompensatedSum {
  double sum = 0.0, compensation = 0.0;
};

// The sum of x[b, e) added to `acc`. Plain functions over a range, with their state
// passed by value: the running sums stay in registers (as lambdas capturing them by
// reference they went through the stack, 2.7 times slower).
[[gnu::noinline]] CompensatedSum add_range(const double* x, std::int64_t b, std::int64_t e, CompensatedSum acc) {
  double m = acc.sum, mc = acc.compensation;
  for (std::int64_t i = b; i < e; ++i) {
    const double v = x[i], t = m + v;
    mc += std::abs(m) >= std::abs(v) ? (m - t) + v : (v - t) + m;
    m = t;
  }
  return {m, mc};
}

// The prefix sums p[i + 1] = sum_{k <= i} (x[k] - mu) for i in [b, e), continuing `acc`;
// `peak` is raised to the largest |p[i + 1]|.
[[gnu::noinline]] CompensatedSum prefix_range(const double* x, double mu, double* p, std::int64_t b, std::int64_t e,
                                              CompensatedSum acc, double& peak) {
  double s = acc.sum, c = acc.compensation, pk = peak;
  for (std::int64_t i = b; i < e; ++i) {
    const double v = x[i] - mu, t = s + v;
    c += std::abs(s) >= std::abs(v) ? (s - t) + v : (v - t) + s;
    s = t;
    const double q = s + c;
    p[i + 1] = q;
    pk = std::max(pk, std::abs(q));
  }
  peak = pk;
  return {s, c};
}

// One level's coefficients (a_k - 2 b_k + c_k) / tau, k in [0, M).
GMWM_VECTOR_CLONES void haar_coefficients(const double* a, const double* b, const double* c, double inv, std::int64_t M,
                                          double* out) {
  for (std::int64_t k = 0; k < M; ++k) out[k] = (a[k] - 2.0 * b[k] + c[k]) * inv;
}

// Coefficients k in [from, to) whose square exceeds cut, each formed as haar_coefficients
// forms it.
GMWM_VECTOR_CLONES std::int64_t count_squares_above(const double* a, const double* b, const double* c, double inv,
                                                    double cut, std::int64_t from, std::int64_t to) {
  std::int64_t count = 0;
  for (std::int64_t k = from; k < to; ++k) {
    const double w = (a[k] - 2.0 * b[k] + c[k]) * inv;
    count += w * w > cut ? 1 : 0;
  }
  return count;
}

}  // namespace

HaarModwt::HaarModwt(const double* x, std::int64_t n) : n_(n) {
  check_at_least("HaarModwt", "series length", static_cast<double>(n), 2.0);
  // A series held in a file (Samples::in_file) gets its prefix sums in a temporary file
  // too, and both files' pages are released behind each pass: the transform then costs
  // no memory that grows with n.
  const bool in_file = detail::in_sample_file(x, static_cast<std::size_t>(n));
  double* p = nullptr;
  if (in_file) {
    file_ = std::make_unique<detail::TemporaryArray>(static_cast<std::size_t>(n) + 1);
    p = file_->data();
  } else {
    prefix_.resize(static_cast<std::size_t>(n) + 1);
    p = prefix_.data();
  }
  p_ = p;
  // Centre by the mean (the Haar filter has zero sum, so W is unchanged) to keep the
  // prefix sums small. Both sums are compensated (Neumaier 1974): the rounding error
  // stays O(eps) whatever n, as with the long-double loop this replaces, at a fraction of
  // its cost (x87 arithmetic was a quarter of a gap run's time: 200 reference replicates
  // of 1e6 samples per column). In memory each pass is one call over the whole series;
  // for a file, block by block, releasing the pages behind between blocks.
  const std::int64_t block = in_file ? kPassBlock : n;
  CompensatedSum mean;
  for (std::int64_t b = 0; b < n; b += block) {
    const std::int64_t e = std::min(n, b + block);
    mean = add_range(x, b, e, mean);
    if (in_file) detail::release_file_pages(x, x + e);
  }
  const double mu = (mean.sum + mean.compensation) / static_cast<double>(n);
  CompensatedSum prefix;
  double peak = 0.0;
  p[0] = 0.0;
  for (std::int64_t b = 0; b < n; b += block) {
    const std::int64_t e = std::min(n, b + block);
    prefix = prefix_range(x, mu, p, b, e, prefix, peak);
    if (in_file) {
      detail::release_file_pages(x, x + e);
      detail::release_file_pages(p, p + e);
    }
  }
  max_abs_prefix_ = peak;
}

HaarModwt::~HaarModwt() = default;
// A moved vector keeps its buffer and a moved unique_ptr its array: p_ stays valid.
HaarModwt::HaarModwt(HaarModwt&&) noexcept = default;
HaarModwt& HaarModwt::operator=(HaarModwt&&) noexcept = default;

double HaarModwt::noise_floor(int level) const {
  // Each stored prefix sum carries a relative rounding error of eps/2; the filter
  // combines four of them (weights 1, -2, 1) and divides by tau.
  constexpr double kCombinedWeights = 4.0;
  constexpr double kSafety = 4.0;
  return kSafety * kCombinedWeights * std::numeric_limits<double>::epsilon() * max_abs_prefix_ / std::ldexp(1.0, level);
}

int HaarModwt::max_levels() const {
  int j = 0;
  while ((std::int64_t{2} << j) <= n_) ++j;
  return j;
}

std::int64_t HaarModwt::count(int level) const { return n_ - (std::int64_t{1} << level) + 1; }

void HaarModwt::coefficients(int level, std::vector<double>& out) const {
  const std::int64_t tau = std::int64_t{1} << level, m = tau / 2;
  const std::int64_t M = count(level);
  out.resize(static_cast<std::size_t>(M > 0 ? M : 0));
  const double inv = 1.0 / static_cast<double>(tau);
  const double* a = p_ + tau;  // S_{t+1} for t = tau-1
  const double* b = p_ + m;    // S_{t+1-m}
  const double* c = p_;        // S_{t+1-tau}
  haar_coefficients(a, b, c, inv, M, out.data());
}

std::int64_t HaarModwt::count_above(int level, double cut) const {
  if (level < 1 || level > max_levels()) return 0;
  const std::int64_t tau = std::int64_t{1} << level, m = tau / 2;
  const std::int64_t M = count(level);
  const double inv = 1.0 / static_cast<double>(tau);
  const double* a = p_ + tau;
  const double* b = p_ + m;
  const double* c = p_;
  if (!file_) return count_squares_above(a, b, c, inv, cut, 0, M);
  // A file's pages are released behind each block, as in squares().
  std::int64_t total = 0;
  for (std::int64_t from = 0; from < M; from += kPassBlock) {
    const std::int64_t to = std::min(M, from + kPassBlock);
    total += count_squares_above(a, b, c, inv, cut, from, to);
    detail::release_file_pages(p_, c + to);
    detail::release_file_pages(b + from, b + to);
    detail::release_file_pages(a + from, a + to);
  }
  return total;
}

double HaarModwt::sum_of_squares(int level) const {
  if (const Squares* k = kept(level)) return k->sum;
  const std::int64_t tau = std::int64_t{1} << level;
  return sum_of_squares_half_width(tau / 2);
}

const HaarModwt::Squares* HaarModwt::kept(int level) const {
  const auto i = static_cast<std::size_t>(level - 1);
  return level >= 1 && i < kept_valid_.size() && kept_valid_[i] ? &kept_[i] : nullptr;
}

namespace {

// Values of t per block of the several-half-widths pass: 2^17 doubles (1 MiB) of S_t stay
// in cache while every half-width's S_{t+m} and S_{t+2m} stream past, each in runs long
// enough for the prefetcher. Measured on this machine kind (72 half-widths, 1e8 samples,
// one thread): 4.8 s as one pass each; shared passes with blocks of 2^11 4.5 s, 2^13 3.9 s,
// 2^15 3.1 s, 2^17 2.8 s, 2^19 2.8 s. A multiple of four, so that each half-width's four
// accumulators see the values in the order of its own pass.
constexpr std::int64_t kSharedPassBlock = 131072;

// sum over k in [from, to) (multiples of 4) of (a_k - 2 b_k + c_k)^2 into four lanes, and
// with kPeaks each lane's largest square (squares() with its peak); without, the loop is
// the plain sum's vectorised kernel.
template <bool kPeaks>
inline void add_lanes(const double* a, const double* b, const double* c, std::int64_t from, std::int64_t to,
                      double* lane, double* peak) {
  double t0 = lane[0], t1 = lane[1], t2 = lane[2], t3 = lane[3];
  double q0 = 0.0, q1 = 0.0, q2 = 0.0, q3 = 0.0;
  if constexpr (kPeaks) q0 = peak[0], q1 = peak[1], q2 = peak[2], q3 = peak[3];
  for (std::int64_t k = from; k < to; k += 4) {
    const double d0 = a[k] - 2.0 * b[k] + c[k];
    const double d1 = a[k + 1] - 2.0 * b[k + 1] + c[k + 1];
    const double d2 = a[k + 2] - 2.0 * b[k + 2] + c[k + 2];
    const double d3 = a[k + 3] - 2.0 * b[k + 3] + c[k + 3];
    const double e0 = d0 * d0, e1 = d1 * d1, e2 = d2 * d2, e3 = d3 * d3;
    t0 += e0;
    t1 += e1;
    t2 += e2;
    t3 += e3;
    if constexpr (kPeaks) {
      q0 = std::max(q0, e0);
      q1 = std::max(q1, e1);
      q2 = std::max(q2, e2);
      q3 = std::max(q3, e3);
    }
  }
  lane[0] = t0, lane[1] = t1, lane[2] = t2, lane[3] = t3;
  if constexpr (kPeaks) peak[0] = q0, peak[1] = q1, peak[2] = q2, peak[3] = q3;
}
// The two kernels, each in an AVX2 and a baseline clone (vector_clones.h: the same sums
// bit for bit): they are most of every WV, Allan deviation and gap replicate's level passes.
GMWM_VECTOR_CLONES void add_squares(const double* a, const double* b, const double* c, std::int64_t from,
                                    std::int64_t to, double* lane) {
  add_lanes<false>(a, b, c, from, to, lane, nullptr);
}
GMWM_VECTOR_CLONES void add_squares_and_peaks(const double* a, const double* b, const double* c, std::int64_t from,
                                              std::int64_t to, double* lane, double* peak) {
  add_lanes<true>(a, b, c, from, to, lane, peak);
}

}  // namespace

void HaarModwt::keep_squares(int first, int last) {
  first = std::max(first, 1);
  last = std::min(last, max_levels());
  if (last < first) return;
  kept_.resize(static_cast<std::size_t>(std::max<std::size_t>(kept_.size(), static_cast<std::size_t>(last))));
  kept_valid_.resize(kept_.size(), 0);
  if (file_) {  // a file's pages are released pass by pass (squares): one pass per level there
    for (int j = first; j <= last; ++j) {
      kept_[static_cast<std::size_t>(j - 1)] = squares(std::int64_t{1} << (j - 1), true);
      kept_valid_[static_cast<std::size_t>(j - 1)] = 1;
    }
    return;
  }
  // In memory, the levels share blocked passes (kSharedPassBlock, as
  // sums_of_squares_half_width): each level's four lanes see its values in the order of
  // its own pass, so the sums are squares()'s to the bit and the peaks (maxima) the same.
  // A gap run keeps 10-14 event levels of every reference replicate: one pass each was 17%
  // of its CPU (issue 44).
  const auto L = static_cast<std::size_t>(last - first + 1);
  std::vector<std::array<double, 4>> lanes(L, {0.0, 0.0, 0.0, 0.0}), peaks(L, {0.0, 0.0, 0.0, 0.0});
  std::vector<std::int64_t> half(L), whole(L, 0);
  std::int64_t longest = 0;
  for (std::size_t i = 0; i < L; ++i) {
    half[i] = std::int64_t{1} << (first - 1 + static_cast<int>(i));
    const std::int64_t M = n_ - 2 * half[i] + 1;
    if (M < 1) continue;
    whole[i] = M - M % 4;
    longest = std::max(longest, whole[i]);
  }
  for (std::int64_t from = 0; from < longest; from += kSharedPassBlock) {
    const std::int64_t to = std::min(longest, from + kSharedPassBlock);
    for (std::size_t i = 0; i < L; ++i) {
      const std::int64_t end = std::min(to, whole[i]);
      if (end > from)
        add_squares_and_peaks(p_ + 2 * half[i], p_ + half[i], p_, from, end, lanes[i].data(), peaks[i].data());
    }
  }
  for (std::size_t i = 0; i < L; ++i) {
    const std::int64_t m = half[i], tau = 2 * m, M = n_ - tau + 1;
    Squares sq;
    if (M >= 1) {
      double s0 = lanes[i][0];
      double peak = std::max(std::max(peaks[i][0], peaks[i][1]), std::max(peaks[i][2], peaks[i][3]));
      for (std::int64_t k = whole[i]; k < M; ++k) {
        const double d = p_[k + tau] - 2.0 * p_[k + m] + p_[k];
        s0 += d * d;
        peak = std::max(peak, d * d);
      }
      const double inv = 1.0 / static_cast<double>(tau);
      sq = {(s0 + lanes[i][1] + lanes[i][2] + lanes[i][3]) * inv * inv, peak * inv * inv};
    }
    kept_[static_cast<std::size_t>(first - 1) + i] = sq;
    kept_valid_[static_cast<std::size_t>(first - 1) + i] = 1;
  }
}

double HaarModwt::sum_of_squares_half_width(std::int64_t m) const { return squares(m, false).sum; }

HaarModwt::Squares HaarModwt::squares_of_level(int level) const {
  if (level < 1 || level > max_levels()) return {};  // no coefficient
  if (const Squares* k = kept(level)) return *k;
  return squares(std::int64_t{1} << (level - 1), true);
}

std::vector<double> HaarModwt::sums_of_squares_half_width(std::span<const std::int64_t> m) const {
  std::vector<double> out(m.size(), 0.0);
  // A half-width whose level's squares are kept (keep_squares) is read, not passed over.
  std::vector<char> read(m.size(), 0);
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m[i] >= 1 && std::has_single_bit(static_cast<std::uint64_t>(m[i])))
      if (const Squares* k = kept(std::countr_zero(static_cast<std::uint64_t>(m[i])) + 1)) {
        out[i] = k->sum;
        read[i] = 1;
      }
  // A file's pages are released pass by pass (squares): one pass per half-width there.
  if (file_) {
    for (std::size_t i = 0; i < m.size(); ++i)
      if (!read[i]) out[i] = sum_of_squares_half_width(m[i]);
    return out;
  }
  std::vector<std::array<double, 4>> lanes(m.size(), {0.0, 0.0, 0.0, 0.0});
  std::vector<std::int64_t> whole(m.size(), 0);
  std::int64_t longest = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const std::int64_t M = n_ - 2 * m[i] + 1;
    if (read[i] || m[i] < 1 || M < 1) continue;
    whole[i] = M - M % 4;
    longest = std::max(longest, whole[i]);
  }
  for (std::int64_t from = 0; from < longest; from += kSharedPassBlock) {
    const std::int64_t to = std::min(longest, from + kSharedPassBlock);
    for (std::size_t i = 0; i < m.size(); ++i) {
      const std::int64_t end = std::min(to, whole[i]);
      if (end > from) add_squares(p_ + 2 * m[i], p_ + m[i], p_, from, end, lanes[i].data());
    }
  }
  for (std::size_t i = 0; i < m.size(); ++i) {
    const std::int64_t tau = 2 * m[i], M = n_ - tau + 1;
    if (read[i] || m[i] < 1 || M < 1) continue;  // kept, or no term: 0, as squares()
    const double* a = p_ + tau;
    const double* b = p_ + m[i];
    double s0 = lanes[i][0];
    for (std::int64_t k = whole[i]; k < M; ++k) {
      const double d = a[k] - 2.0 * b[k] + p_[k];
      s0 += d * d;
    }
    const double inv = 1.0 / static_cast<double>(tau);
    out[i] = (s0 + lanes[i][1] + lanes[i][2] + lanes[i][3]) * inv * inv;
  }
  return out;
}

HaarModwt::Squares HaarModwt::squares(std::int64_t m, bool with_peak) const {
  const std::int64_t tau = 2 * m;
  const std::int64_t M = n_ - tau + 1;
  if (m < 1 || M < 1) return {};
  const double* a = p_ + tau;
  const double* b = p_ + m;
  const double* c = p_;
  // Four independent accumulators let the compiler vectorise and pipeline the loop. In
  // memory, one loop; for prefix sums in a file, blocks of kPassBlock (a multiple of four:
  // the sums are those of one loop), releasing the pages behind each of the three
  // pointers between blocks (they are tau apart: up to half the series at the coarsest
  // level; the pages between them are read again from the file's page cache). The peak
  // has its own loop shape so the plain sum keeps its vectorised kernel.
  double lane[4] = {0.0, 0.0, 0.0, 0.0}, peaks[4] = {0.0, 0.0, 0.0, 0.0};
  auto kernel = [&](std::int64_t from, std::int64_t to) {  // k in [from, to), multiples of 4
    if (with_peak)
      add_squares_and_peaks(a, b, c, from, to, lane, peaks);
    else
      add_squares(a, b, c, from, to, lane);
  };
  const std::int64_t whole = M - M % 4;  // the four-wide part; the rest goes to s0
  if (!file_) {
    kernel(0, whole);
  } else {
    for (std::int64_t from = 0; from < whole; from += kPassBlock) {
      const std::int64_t to = std::min(whole, from + kPassBlock);
      kernel(from, to);
      detail::release_file_pages(p_, c + to);
      detail::release_file_pages(b + from, b + to);
      detail::release_file_pages(a + from, a + to);
    }
  }
  double s0 = lane[0], peak = std::max(std::max(peaks[0], peaks[1]), std::max(peaks[2], peaks[3]));
  for (std::int64_t k = whole; k < M; ++k) {
    const double d = a[k] - 2.0 * b[k] + c[k];
    s0 += d * d;
    peak = std::max(peak, d * d);
  }
  const double inv = 1.0 / static_cast<double>(tau);
  return {(s0 + lane[1] + lane[2] + lane[3]) * inv * inv, peak * inv * inv};
}

std::vector<std::unique_ptr<HaarModwt>> haar_transforms(const std::vector<std::span<const double>>& series) {
  std::vector<std::unique_ptr<HaarModwt>> out(series.size());
  gmwm::parallel_for(std::size_t{0}, series.size(), [&](std::size_t c) {
    out[c] = std::make_unique<HaarModwt>(series[c].data(), static_cast<std::int64_t>(series[c].size()));
  });
  return out;
}

std::vector<std::vector<double>> sums_of_squares_half_width(const std::vector<std::unique_ptr<HaarModwt>>& transforms,
                                                            const std::vector<std::vector<std::int64_t>>& half_widths) {
  check_size_match("sums_of_squares_half_width", "half-width lists", half_widths.size(), "transforms",
                   transforms.size());
  struct Group {
    std::size_t series;
    std::vector<std::size_t> items;
  };
  std::vector<Group> groups;
  std::vector<std::vector<double>> out(transforms.size());
  for (std::size_t c = 0; c < transforms.size(); ++c) {
    out[c].assign(half_widths[c].size(), 0.0);
    std::vector<Group> own(kSharedPassGroups, Group{c, {}});
    for (std::size_t i = 0; i < half_widths[c].size(); ++i) own[i % kSharedPassGroups].items.push_back(i);
    for (auto& g : own)
      if (!g.items.empty()) groups.push_back(std::move(g));
  }
  gmwm::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t t) {
    const Group& g = groups[t];
    std::vector<std::int64_t> m;
    for (std::size_t i : g.items) m.push_back(half_widths[g.series][i]);
    const std::vector<double> sums = transforms[g.series]->sums_of_squares_half_width(m);
    for (std::size_t i = 0; i < g.items.size(); ++i) out[g.series][g.items[i]] = sums[i];
  });
  return out;
}

}  // namespace gmwm
