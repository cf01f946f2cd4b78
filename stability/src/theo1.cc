// Theo1 (kinds_internal.h): NIST SP 1065 eq. 30, with h = m / 2 and k = h - delta,
//
//   Theo1(m) = sum_{i=0}^{N-m-1} sum_{k=1}^{h} f_i(k)^2 / k / (0.75 (N - m) (m tau0)^2),
//   f_i(k) = x_i - x_{i+k} - x_{i+m-k} + x_{i+m},
//
// (N - m) h terms: O(N m) read directly, which is what it costs here for h <= 128. Its weights
// 1/k have no prefix-sum form (no recurrence in k or i), so beyond that it is read through
// correlations: with A_i = x_i + x_{i+m} and E_k(i) = x_{i+k} + x_{i+m-k} (f = A - E),
//
//   sum_k f_i(k)^2 / k = H_h A_i^2 - 2 A_i sum_t w(t) x_{i+t} + sum_t w(t) x_{i+t}^2
//                        + 2 sum_k x_{i+k} x_{i+m-k} / k,
//
// H_h = sum_{k<=h} 1/k, w(t) = 1/t (t <= h) + 1/(m - t) (m - t <= h), t = 1 .. m-1. Summed over
// a block of window starts i, the second term is a correlation of A with x at lags 1 .. m-1
// (one FFT), the third prefix sums of x^2, and the last pairs x_a x_{a+m-2k} over a = i + k,
// whose window slides with k: a rectangle in (a, k) (one FFT correlation) and two triangles,
// each split into a rectangle and two half-size triangles down to small ones summed directly
// (O(h log^2 h)). O(N log^2 m) per factor in all. Each block of 4m window starts is read less
// the least-squares line of its 5m points (f sees no line), so the terms, which cancel to the
// sum, stay on the scale of the block: within 1e-13 of the direct sum on 1e5-point white,
// random-walk and integrated random-walk phase (Theo1.EqualsItsDefinitionOnRandomSeries
// checks 1e-10 against SP 1065's form).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <vector>

#include <unsupported/Eigen/FFT>

#include "kinds_internal.h"

namespace gmwm::stability::detail {
namespace {

// Half factors h at or below which the terms are summed directly: O(N h), about 0.3 ns per
// term, the correlations' cost near h = 128 (measured on 1e6 points: 0.04 s direct, 0.06 s
// through correlations at m = 130; 0.17 s and 0.08 s at m = 514).
constexpr std::int64_t kLargestDirectHalf = 128;
// Window starts per block, in factors m: the block reads 5m points, its line removed.
constexpr std::int64_t kBlockFactors = 4;
// Products below which a correlation, and pairs below which a region of the last term, are
// summed directly rather than through FFTs (measured: 2^12 to 2^20 within 20% of each other
// at 1e6 points, 2^16 among the fastest).
constexpr std::int64_t kDirectCorrelationWork = 1 << 16;
constexpr std::int64_t kDirectRegionPairs = 1 << 16;

// sum_t u_t v_t over t < n in four lanes (the chain of additions split, so the loop runs at
// the multiplier's pace).
double dot(const double* u, const double* v, std::int64_t n) {
  std::array<double, 4> lane{};
  std::int64_t t = 0;
  for (; t + 4 <= n; t += 4)
    for (std::size_t l = 0; l < 4; ++l)
      lane[l] += u[t + static_cast<std::int64_t>(l)] * v[t + static_cast<std::int64_t>(l)];
  for (; t < n; ++t) lane[0] += u[t] * v[t];
  return (lane[0] + lane[1]) + (lane[2] + lane[3]);
}

// The FFT (its plans cached by size) and buffers one Theo1 factor reuses for its correlations.
struct Workspace {
  Eigen::FFT<double> fft;
  std::vector<double> a, b;
  std::vector<std::complex<double>> fa, fb;
  Workspace() { fft.SetFlag(Eigen::FFT<double>::HalfSpectrum); }
};

// The smallest even size at least n whose only prime factors are 2, 3 and 5 (kissfft's fast
// radices), at most 1.25 n or so: less padding than the next power of two.
std::int64_t fft_size(std::int64_t n) {
  std::int64_t best = 2;
  while (best < n) best *= 2;
  for (std::int64_t p5 = 1; p5 < best; p5 *= 5)
    for (std::int64_t p35 = p5; p35 < best; p35 *= 3) {
      std::int64_t size = p35 * 2;
      while (size < n) size *= 2;
      best = std::min(best, size);
    }
  return best;
}

// c(d) = sum_{i<nu} u_i v_{i+d} for d in [0, lags) (v has nu + lags - 1 points), directly or
// through a real FFT at least as long as v (no wrap: i + d < v's length).
std::vector<double> correlation(Workspace& w, const double* u, std::int64_t nu, const double* v, std::int64_t lags) {
  std::vector<double> c(static_cast<std::size_t>(lags), 0.0);
  const std::int64_t nv = nu + lags - 1;
  if (nu * lags <= kDirectCorrelationWork) {
    for (std::int64_t d = 0; d < lags; ++d) c[static_cast<std::size_t>(d)] = dot(u, v + d, nu);
    return c;
  }
  const std::int64_t n = fft_size(nv);
  const auto size = static_cast<std::size_t>(n);
  w.a.assign(size, 0.0);
  w.b.assign(size, 0.0);
  std::copy(u, u + nu, w.a.begin());
  std::copy(v, v + nv, w.b.begin());
  w.fa.resize(size);
  w.fb.resize(size);
  w.fft.fwd(w.fa.data(), w.a.data(), n);
  w.fft.fwd(w.fb.data(), w.b.data(), n);
  for (std::size_t k = 0; k <= size / 2; ++k) w.fa[k] = std::conj(w.fa[k]) * w.fb[k];
  w.fft.inv(w.a.data(), w.fa.data(), n);
  std::copy(w.a.begin(), w.a.begin() + lags, c.begin());
  return c;
}

// The last term's pairs: sum over k in [k0, k1) of (1/k) sum_{a in [lo(k), hi(k))} x_a
// x_{a+m-2k}, each edge at(k) = at + slope (k - k0), slope 0 or 1.
struct Pairs {
  const double* x;
  std::int64_t m;
  Workspace* work;
};
struct Edge {
  std::int64_t at, slope;
};

double pairs_direct(const Pairs& p, std::int64_t k0, std::int64_t k1, Edge lo, Edge hi) {
  double total = 0.0;
  for (std::int64_t k = k0; k < k1; ++k) {
    const std::int64_t a0 = lo.at + lo.slope * (k - k0), a1 = hi.at + hi.slope * (k - k0);
    if (a1 > a0) total += dot(p.x + a0, p.x + a0 + p.m - 2 * k, a1 - a0) / static_cast<double>(k);
  }
  return total;
}

// a in [a0, a1) for every k in [k0, k1): one correlation over the lags m - 2k.
double pairs_rectangle(const Pairs& p, std::int64_t k0, std::int64_t k1, std::int64_t a0, std::int64_t a1) {
  const std::int64_t lowest = p.m - 2 * (k1 - 1), lags = 2 * (k1 - k0) - 1;
  const std::vector<double> c = correlation(*p.work, p.x + a0, a1 - a0, p.x + a0 + lowest, lags);
  double total = 0.0;
  for (std::int64_t k = k0; k < k1; ++k)
    total += c[static_cast<std::size_t>(2 * (k1 - 1 - k))] / static_cast<double>(k);
  return total;
}

double pairs(const Pairs& p, std::int64_t k0, std::int64_t k1, Edge lo, Edge hi) {
  const std::int64_t n = k1 - k0;
  if (n <= 0) return 0.0;
  const std::int64_t widest = std::max(hi.at - lo.at, hi.at + hi.slope * (n - 1) - lo.at - lo.slope * (n - 1));
  if (widest <= 0) return 0.0;
  if (n <= 2 || n * widest <= kDirectRegionPairs) return pairs_direct(p, k0, k1, lo, hi);
  const std::int64_t common_lo = lo.at + lo.slope * (n - 1), common_hi = hi.at;  // a every k reads
  if (common_hi - common_lo >= n) {
    double total = pairs_rectangle(p, k0, k1, common_lo, common_hi);
    if (lo.slope != 0) total += pairs(p, k0, k1, lo, {common_lo, 0});
    if (hi.slope != 0) total += pairs(p, k0, k1, {common_hi, 0}, hi);
    return total;
  }
  const std::int64_t half = n / 2;
  return pairs(p, k0, k0 + half, lo, hi) +
         pairs(p, k0 + half, k1, {lo.at + lo.slope * half, lo.slope}, {hi.at + hi.slope * half, hi.slope});
}

// x[first, first + points) less its least-squares line.
std::vector<double> without_line(std::span<const double> x, std::int64_t first, std::int64_t points) {
  const double* z = x.data() + first;
  const double centre = 0.5 * static_cast<double>(points - 1), n = static_cast<double>(points);
  double mean = 0.0, slope = 0.0;
  for (std::int64_t t = 0; t < points; ++t) mean += z[t] - z[0];
  mean /= n;
  for (std::int64_t t = 0; t < points; ++t) slope += (static_cast<double>(t) - centre) * (z[t] - z[0] - mean);
  slope /= n * (n * n - 1.0) / 12.0;
  std::vector<double> out(static_cast<std::size_t>(points));
  for (std::int64_t t = 0; t < points; ++t)
    out[static_cast<std::size_t>(t)] = z[t] - z[0] - mean - slope * (static_cast<double>(t) - centre);
  return out;
}

// The numerator's terms of the window starts [first, first + count).
double block_sum(Workspace& work, std::span<const double> x, std::int64_t first, std::int64_t count, std::int64_t m) {
  const std::int64_t h = m / 2;
  const std::vector<double> z = without_line(x, first, count + m);
  std::vector<double> a(static_cast<std::size_t>(count)), squares(static_cast<std::size_t>(count + m) + 1, 0.0);
  double sum_a2 = 0.0;
  for (std::int64_t i = 0; i < count; ++i) {
    a[static_cast<std::size_t>(i)] = z[static_cast<std::size_t>(i)] + z[static_cast<std::size_t>(i + m)];
    sum_a2 += a[static_cast<std::size_t>(i)] * a[static_cast<std::size_t>(i)];
  }
  for (std::int64_t t = 0; t < count + m; ++t)
    squares[static_cast<std::size_t>(t) + 1] =
        squares[static_cast<std::size_t>(t)] + z[static_cast<std::size_t>(t)] * z[static_cast<std::size_t>(t)];
  const std::vector<double> c = correlation(work, a.data(), count, z.data(), m);  // lags 0 .. m-1
  long double harmonic = 0.0L;
  for (std::int64_t k = h; k >= 1; --k) harmonic += 1.0L / static_cast<long double>(k);
  double cross = 0.0, own = 0.0;
  for (std::int64_t t = 1; t < m; ++t) {
    const double w =
        (t <= h ? 1.0 / static_cast<double>(t) : 0.0) + (m - t <= h ? 1.0 / static_cast<double>(m - t) : 0.0);
    cross += w * c[static_cast<std::size_t>(t)];
    own += w * (squares[static_cast<std::size_t>(count + t)] - squares[static_cast<std::size_t>(t)]);
  }
  const double mid = pairs({z.data(), m, &work}, 1, h + 1, {1, 1}, {count + 1, 1});  // a = i + k, i < count
  return static_cast<double>(harmonic) * sum_a2 - 2.0 * cross + own + 2.0 * mid;
}

}  // namespace

double theo1_sum_direct(std::span<const double> x, std::int64_t m) {
  const std::int64_t n = static_cast<std::int64_t>(x.size()) - m;
  const double* p = x.data();
  long double total = 0.0L;
  for (std::int64_t k = 1; k <= m / 2; ++k) {
    const double s = sum_of_squares(n, [=](std::int64_t i) { return (p[i] - p[i + k]) + (p[i + m] - p[i + m - k]); });
    total += s / static_cast<double>(k);
  }
  return static_cast<double>(total);
}

double theo1_sum_by_correlation(std::span<const double> x, std::int64_t m) {
  const std::int64_t starts = static_cast<std::int64_t>(x.size()) - m, block = kBlockFactors * m;
  Workspace work;
  long double total = 0.0L;
  for (std::int64_t first = 0; first < starts; first += block)
    total += block_sum(work, x, first, std::min(block, starts - first), m);
  return static_cast<double>(total);
}

double theo1_variance(std::span<const double> x, std::int64_t m, double tau0) {
  const double tau = static_cast<double>(m) * tau0;
  const double starts = static_cast<double>(static_cast<std::int64_t>(x.size()) - m);
  const double sum = m / 2 <= kLargestDirectHalf ? theo1_sum_direct(x, m) : theo1_sum_by_correlation(x, m);
  return sum / (0.75 * starts * tau * tau);
}

}  // namespace gmwm::stability::detail
