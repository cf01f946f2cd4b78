// The modified and Hadamard total variances (kinds_internal.h) in O(N) per averaging factor.
//
// Both average, over the windows of L = 3m points of a series z (the phase for MTOTVAR, the
// frequency for HTOTVAR), the 6m squared second differences D_j of m-point sums of the window
// detrended (its half-average slope s removed: u_i = z_{n+i} - s i) and reflected evenly at
// both ends to 9m points [rev u, u, rev u]: O(m) per window read directly. Here:
//
// 1. The 6m window starts j run over one period of u's even 6m-periodic extension E, so
//    sum_j D_j^2 is a circular sum. Each D_j is the third difference at lag m of E's running
//    sum W, which is u's running sum V(k) = sum_{i<k} u_i (k = 0..L) reflected oddly about
//    both ends; W less its line t V(L) / L is 2L-periodic, odd about 0 and L, and on 0..L it
//    is Vt(k) = V(k) - k V(L) / L (Vt(0) = Vt(L) = 0). With (20, -15, 6, -1) the
//    autocorrelation of the third difference's (-1, 3, -3, 1), that circular sum is
//      40 S(0) - 60 S(m) + 24 S(2m) + 30 (A(m) + A(5m)) - 12 (A(2m) + A(4m)) + 4 A(3m),
//    S(d) = sum_k Vt(k) Vt(k+d), A(e) = sum_k Vt(k) Vt(e-k), over the k with both in 0..L.
// 2. Vt(k) = P(n+k) - pi_n(k), P the running sum of z and pi_n a quadratic in k with
//    coefficients c = (P(n), (P(n+L) - P(n)) / L - s L / 2, s / 2), each O(1) from P. So a
//    window's sum is Vt' G Vt = P' G P - 2 c' Psi' P + c' H c (G the form of step 1, Psi = G
//    (1, k, k^2), H = (1, k, k^2)' Psi): P' G P's lagged products from prefix sums of
//    P(t) P(t + d) (d = 0, m, 2m), its anti-diagonals summed over every window at once (P(t)
//    times a prefix sum of P over every other index), Psi' P from prefix sums of t^r P(t)
//    (r = 0, 1, 2) over five ranges of k, H a 3 x 3 constant of m (power sums).
// 3. The windows are read in blocks of L, each with its own running sums over its 2L - 1
//    points of z less their least-squares line (no total variance sees a line of z: s takes
//    its slope), so the sums stay on the scale of a window and the terms of step 2, which
//    cancel to the window's sum, lose a few digits at most: within 1e-12 of the windows read
//    directly on 1e5-point white, random-walk and integrated random-walk phase (the tests
//    check 1e-10 against the literal definition, TotalDeviations.EqualTheir...).
#include "kinds_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace gmwm::stability::detail {
namespace {

// At or below this factor the windows are read directly: O(N m), measured at 27 and 40 ns per
// window for m = 1 and 2 against the prefix sums' 55 or so (77 ns direct at m = 3).
constexpr std::int64_t kLargestDirectFactor = 2;

// One band of the form G (step 1): weight w on the rows k in [a m, b m], reading the column
// shift m + sign k (S(d)'s weight split evenly over its two bands k + d and k - d; A(e) reads
// e - k).
struct Band {
  double w;
  int a, b, shift, sign;
};
constexpr std::array<Band, 10> kBands = {{{40, 0, 3, 0, 1},
                                          {-30, 0, 2, 1, 1},
                                          {-30, 1, 3, -1, 1},
                                          {12, 0, 1, 2, 1},
                                          {12, 2, 3, -2, 1},
                                          {30, 0, 1, 1, -1},
                                          {-12, 0, 2, 2, -1},
                                          {4, 0, 3, 3, -1},
                                          {-12, 1, 3, 4, -1},
                                          {30, 2, 3, 5, -1}}};
// S(d)'s (weight, d / m) and A(e)'s (weight, e / m) in P' G P.
constexpr std::array<std::pair<double, int>, 3> kLags = {{{40, 0}, {-60, 1}, {24, 2}}};
constexpr std::array<std::pair<double, int>, 5> kAntiDiagonals = {{{30, 1}, {-12, 2}, {4, 3}, {-12, 4}, {30, 5}}};
// The ranges [a m, b m] of k the bands read.
constexpr std::array<std::pair<int, int>, 5> kRanges = {{{0, 3}, {0, 2}, {1, 3}, {0, 1}, {2, 3}}};

struct Kernel {
  std::int64_t m = 0, span = 0;                                // m and L = 3m
  std::int64_t first_half = 0, second = 0;                     // floor(L / 2) points; the second half from ceil(L / 2)
  std::array<std::array<std::array<double, 3>, 5>, 3> coef{};  // Psi_q on range g: sum_r coef[q][g][r] k^r
  std::array<std::array<double, 3>, 3> h{};                    // H
};

// sum_{k=k1}^{k2} k^p, p = 0..4 (Faulhaber), in long double.
long double power_sum(int p, std::int64_t k1, std::int64_t k2) {
  const auto upto = [p](long double n) -> long double {
    switch (p) {
      case 0:
        return n + 1;
      case 1:
        return n * (n + 1) / 2;
      case 2:
        return n * (n + 1) * (2 * n + 1) / 6;
      case 3:
        return n * n * (n + 1) * (n + 1) / 4;
      default:
        return n * (n + 1) * (2 * n + 1) * (3 * n * n + 3 * n - 1) / 30;
    }
  };
  return upto(static_cast<long double>(k2)) - (k1 > 0 ? upto(static_cast<long double>(k1 - 1)) : 0.0L);
}

constexpr std::array<std::array<double, 3>, 3> kBinomial = {{{1, 0, 0}, {1, 1, 0}, {1, 2, 1}}};

Kernel kernel_of(std::int64_t m) {
  Kernel kern;
  kern.m = m;
  kern.span = 3 * m;
  kern.first_half = kern.span / 2;
  kern.second = (kern.span + 1) / 2;
  for (const Band& band : kBands) {
    const auto g = static_cast<std::size_t>(
        std::find(kRanges.begin(), kRanges.end(), std::pair<int, int>{band.a, band.b}) - kRanges.begin());
    const long double shift = static_cast<long double>(band.shift) * static_cast<long double>(m);
    // (shift + sign k)^q = sum_r binom(q, r) shift^(q-r) sign^r k^r
    std::array<std::array<long double, 3>, 3> poly{};
    for (int q = 0; q < 3; ++q)
      for (int r = 0; r <= q; ++r) poly[q][r] = kBinomial[q][r] * std::pow(shift, q - r) * (r % 2 == 1 ? band.sign : 1);
    for (std::size_t q = 0; q < 3; ++q) {
      for (std::size_t r = 0; r < 3; ++r) kern.coef[q][g][r] += static_cast<double>(band.w * poly[q][r]);
      for (std::size_t r = 0; r < 3; ++r) {
        long double hqr = 0.0L;  // sum_k (shift + sign k)^q k^r over the band
        for (std::size_t j = 0; j <= q; ++j)
          hqr += poly[q][j] * power_sum(static_cast<int>(j + r), band.a * m, band.b * m);
        kern.h[q][r] += static_cast<double>(band.w * hqr);
      }
    }
  }
  return kern;
}

// The running sums of one block: P over `points` points of z less their least-squares line,
// and the prefix sums the windows read (parity offset by 2: parity[t + 2] sums P over t, t - 2,
// ..., parity[0] = parity[1] = 0).
struct Block {
  std::vector<double> p, moment0, moment1, moment2, lag0, lag1, lag2, parity;
};

void running_sum(const double* z, std::int64_t points, std::vector<double>& p) {
  const double centre = 0.5 * static_cast<double>(points - 1);
  double mean = 0.0, slope = 0.0;
  for (std::int64_t t = 0; t < points; ++t) mean += z[t] - z[0];
  mean /= static_cast<double>(points);
  for (std::int64_t t = 0; t < points; ++t) slope += (static_cast<double>(t) - centre) * (z[t] - z[0] - mean);
  const double n = static_cast<double>(points);
  if (points > 1) slope /= n * (n * n - 1.0) / 12.0;  // sum (t - centre)^2
  p.assign(static_cast<std::size_t>(points) + 1, 0.0);
  double sum = 0.0, carry = 0.0;  // compensated (Kahan)
  for (std::int64_t t = 0; t < points; ++t) {
    const double term = (z[t] - z[0] - mean - slope * (static_cast<double>(t) - centre)) - carry;
    const double next = sum + term;
    carry = (next - sum) - term;
    sum = next;
    p[static_cast<std::size_t>(t) + 1] = sum;
  }
}

// prefix[t + 1] = prefix[t] + p[t] p[t + d] for t + d < size.
void lag_prefix(const std::vector<double>& p, std::int64_t d, std::vector<double>& prefix) {
  const auto size = static_cast<std::int64_t>(p.size());
  prefix.assign(static_cast<std::size_t>(size) + 1, 0.0);
  for (std::int64_t t = 0; t + d < size; ++t)
    prefix[static_cast<std::size_t>(t) + 1] =
        prefix[static_cast<std::size_t>(t)] + p[static_cast<std::size_t>(t)] * p[static_cast<std::size_t>(t + d)];
}

void fill_block(const double* z, std::int64_t points, std::int64_t m, Block& b) {
  running_sum(z, points, b.p);
  const auto size = static_cast<std::size_t>(b.p.size());
  const double* p = b.p.data();
  for (auto* v : {&b.moment0, &b.moment1, &b.moment2}) v->assign(size + 1, 0.0);
  b.parity.assign(size + 2, 0.0);
  for (std::size_t t = 0; t < size; ++t) {
    const double tt = static_cast<double>(t);
    b.moment0[t + 1] = b.moment0[t] + p[t];
    b.moment1[t + 1] = b.moment1[t] + tt * p[t];
    b.moment2[t + 1] = b.moment2[t] + tt * tt * p[t];
    b.parity[t + 2] = b.parity[t] + p[t];
  }
  lag_prefix(b.p, 0, b.lag0);
  lag_prefix(b.p, m, b.lag1);
  lag_prefix(b.p, 2 * m, b.lag2);
}

// The window at local index n: its sum without P' G P's anti-diagonals (step 2).
double window_sum(const Kernel& kern, const Block& b, std::int64_t n) {
  const double* p = b.p.data();
  const std::int64_t span = kern.span, m = kern.m;
  const double first = p[n], last = p[n + span];
  const double mean1 = (p[n + kern.first_half] - first) / static_cast<double>(kern.first_half);
  const double mean2 = (last - p[n + kern.second]) / static_cast<double>(span - kern.second);
  const double s = (mean2 - mean1) / static_cast<double>(kern.second);
  const double c0 = first, c1 = (last - first) / static_cast<double>(span) - s * static_cast<double>(span) / 2.0;
  const double c2 = s / 2.0;
  const auto lagged = [&](const std::vector<double>& prefix, std::int64_t d) {
    return prefix[static_cast<std::size_t>(n + span - d + 1)] - prefix[static_cast<std::size_t>(n)];
  };
  double sum =
      kLags[0].first * lagged(b.lag0, 0) + kLags[1].first * lagged(b.lag1, m) + kLags[2].first * lagged(b.lag2, 2 * m);
  // Each range's sum_k k^r P(n + k), r = 0, 1, 2, from the prefix sums of t^r P(t).
  const double nn = static_cast<double>(n);
  double cross0 = 0.0, cross1 = 0.0, cross2 = 0.0;
  for (std::size_t g = 0; g < kRanges.size(); ++g) {
    const auto lo = static_cast<std::size_t>(n + kRanges[g].first * m);
    const auto hi = static_cast<std::size_t>(n + kRanges[g].second * m + 1);
    const double d0 = b.moment0[hi] - b.moment0[lo], d1 = b.moment1[hi] - b.moment1[lo];
    const double d2 = b.moment2[hi] - b.moment2[lo];
    const double m0 = d0, m1 = d1 - nn * d0, m2 = d2 - 2.0 * nn * d1 + nn * nn * d0;
    const auto& k0 = kern.coef[0][g];
    const auto& k1 = kern.coef[1][g];
    const auto& k2 = kern.coef[2][g];
    cross0 += k0[0] * m0;
    cross1 += k1[0] * m0 + k1[1] * m1;
    cross2 += k2[0] * m0 + k2[1] * m1 + k2[2] * m2;
  }
  const auto& h = kern.h;
  sum -= 2.0 * (c0 * cross0 + c1 * cross1 + c2 * cross2);
  sum += c0 * (h[0][0] * c0 + h[0][1] * c1 + h[0][2] * c2) + c1 * (h[1][0] * c0 + h[1][1] * c1 + h[1][2] * c2) +
         c2 * (h[2][0] * c0 + h[2][1] * c1 + h[2][2] * c2);
  return sum;
}

// P' G P's anti-diagonals over the block's `windows` windows: for each e, sum over windows n
// and k of P(n + k) P(n + e - k), read as sum_a P(a) sum_n P(2n + e - a) (n the windows with
// k = a - n in e's range [klo, khi]).
double anti_diagonal_sums(const Kernel& kern, const Block& b, std::int64_t windows) {
  const double* p = b.p.data();
  const double* parity = b.parity.data();
  double total = 0.0;
  for (const auto& [w, em] : kAntiDiagonals) {
    const std::int64_t e = em * kern.m;
    const std::int64_t klo = std::max<std::int64_t>(0, e - kern.span), khi = std::min(kern.span, e);
    double sum = 0.0;
    for (std::int64_t a = klo; a <= windows - 1 + khi; ++a) {
      const std::int64_t n1 = std::max<std::int64_t>(0, a - khi), n2 = std::min(windows - 1, a - klo);
      sum += p[a] * (parity[2 * n2 + e - a + 2] - parity[2 * n1 + e - a]);
    }
    total += w * sum;
  }
  return total;
}

}  // namespace

double total_window_sum_direct(std::span<const double> z, std::int64_t m) {
  const std::int64_t span = 3 * m, windows = static_cast<std::int64_t>(z.size()) - span + 1;
  const std::int64_t first_half = span / 2, second = (span + 1) / 2;
  std::vector<double> v(static_cast<std::size_t>(span) + 1), w(static_cast<std::size_t>(3 * span) + 1);
  long double total = 0.0L;
  for (std::int64_t n = 0; n < windows; ++n) {
    const double* x = z.data() + n;
    double mean1 = 0.0, mean2 = 0.0;
    for (std::int64_t i = 0; i < first_half; ++i) mean1 += x[i] - x[0];
    for (std::int64_t i = second; i < span; ++i) mean2 += x[i] - x[0];
    const double s = (mean2 / static_cast<double>(span - second) - mean1 / static_cast<double>(first_half)) /
                     static_cast<double>(second);
    for (std::int64_t k = 0; k < span; ++k)  // V(k + 1) of the detrended points
      v[static_cast<std::size_t>(k) + 1] = v[static_cast<std::size_t>(k)] + (x[k] - x[0] - s * static_cast<double>(k));
    // W(t), t = -L .. 2L, at w[t + L]: V reflected oddly about both ends.
    for (std::int64_t t = -span; t <= 2 * span; ++t)
      w[static_cast<std::size_t>(t + span)] =
          t < 0       ? -v[static_cast<std::size_t>(-t)]
          : t <= span ? v[static_cast<std::size_t>(t)]
                      : 2.0 * v[static_cast<std::size_t>(span)] - v[static_cast<std::size_t>(2 * span - t)];
    double sum = 0.0;
    for (std::int64_t a = 0; a < 2 * span; ++a) {  // the window starts -L .. L - 1
      const double* q = w.data() + a;
      const double d = q[3 * m] - 3.0 * q[2 * m] + 3.0 * q[m] - q[0];
      sum += d * d;
    }
    total += sum;
  }
  return static_cast<double>(total);
}

double total_window_sum(std::span<const double> z, std::int64_t m) {
  if (m <= kLargestDirectFactor) return total_window_sum_direct(z, m);
  const Kernel kern = kernel_of(m);
  const std::int64_t windows = static_cast<std::int64_t>(z.size()) - kern.span + 1;
  Block b;
  long double total = 0.0L;
  for (std::int64_t first = 0; first < windows; first += kern.span) {
    const std::int64_t count = std::min(kern.span, windows - first);
    fill_block(z.data() + first, count + kern.span - 1, m, b);
    double sum = anti_diagonal_sums(kern, b, count);
    for (std::int64_t n = 0; n < count; ++n) sum += window_sum(kern, b, n);
    total += sum;
  }
  return static_cast<double>(total);
}

double modified_total_variance(std::span<const double> x, std::int64_t m, double tau0) {
  const double md = static_cast<double>(m), tau = md * tau0;
  const double windows = static_cast<double>(static_cast<std::int64_t>(x.size()) - 3 * m + 1);
  // sum_n (1 / 6m) sum_j (D_j / m)^2 / (2 tau^2 (N - 3m + 1))
  return total_window_sum(x, m) / (6.0 * md * md * md * 2.0 * tau * tau * windows);
}

double hadamard_total_variance(std::span<const double> x, std::int64_t m, double tau0) {
  std::vector<double> y(x.size() - 1);
  for (std::size_t i = 0; i + 1 < x.size(); ++i) y[i] = x[i + 1] - x[i];
  const double md = static_cast<double>(m);
  const double windows = static_cast<double>(static_cast<std::int64_t>(y.size()) - 3 * m + 1);
  // sum_n (1 / 6m) sum_j (D_j / m)^2 / (6 (M - 3m + 1)), y in units of tau0
  return total_window_sum(y, m) / (6.0 * md * md * md * 6.0 * windows * tau0 * tau0);
}

}  // namespace gmwm::stability::detail
