// The step scan of the gap diagnosis (gap_events.h, "STEP scan"; docs/gap.md, "The step
// scan"): its weights for a baseline, the scan of one series, and the law its null maximum
// is calibrated by.
#include "gap_events.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "gmwm/engine/vector_clones.h"

namespace gmwm::gap::detail {
namespace {

// The step scan's null maximum, max_t |z(t)| of a standardised scan, has the tail of the
// expected number of its upcrossings of b (Rice's formula; Leadbetter, Lindgren and
// Rootzen 1983, ch. 7): P(max <= b) ~ exp(-C b^a phi(b)), a between 1 (a smooth process) and
// 3 (a Brownian-like one). C and a are fitted by maximum likelihood to the replicates'
// maxima (C in closed form, a profiled on a grid), and the threshold is that law's
// (1 - level) quantile. A Gumbel law matched to their moments put the threshold at ~4.97 where
// the scan's null 0.625% quantile is 4.79 (exceeded 0.32% of the time; this law: 4.86, 0.50%;
// sd over sets of 200 replicates 0.044 against 0.082): the conservative threshold cost the
// scan 15 points of power at the oracle's level (tools/bench/bench_gap_step.cc "calibration";
// issue 43, item 5). On gmwm's own statistic, max |z| / max(1, RMS) (scan_step), the same
// study gives 4.816 +- 0.031, exceeded 0.605% for 0.625% (its empirical quantile 4.795);
// divided by the RMS always, its tail was a t's rather than a normal's and this law was
// anti-conservative there (0.95%), "gmwm-calibration" mode.
constexpr double kScanExponentMax = 6.0;  // a's grid: [0, 6] (beyond the Brownian 3)
constexpr double kScanExponentStep = 0.01;

// z[t] = -centre - self S[t] + sum_{j < k} a_j (S[t + m_j] + S[t - m_j]) for t in [b, e),
// in that order of operations (element by element: the AVX2 clone gives the same z).
GMWM_VECTOR_CLONES void scan_block(double* z, const double* S, const double* a, const std::int64_t* m, int k,
                                   double centre, double self, std::int64_t b, std::int64_t e) {
  for (std::int64_t t = b; t < e; ++t) z[t] = -centre - self * S[t];
  for (int j = 0; j < k; ++j) {
    const double aj = a[j];
    const std::int64_t mj = m[j];
    for (std::int64_t t = b; t < e; ++t) z[t] += aj * (S[t + mj] + S[t - mj]);
  }
}

}  // namespace

double scan_max_quantile(const Eigen::VectorXd& sample, double level) {
  const auto B = static_cast<double>(sample.size());
  const double min_b = sample.minCoeff();
  auto log_phi = [](double b) { return -0.5 * b * b - 0.5 * std::log(2.0 * M_PI); };
  double best = -std::numeric_limits<double>::infinity(), best_a = 0.0, best_log_c = 0.0;
  for (int k = 0; k * kScanExponentStep <= kScanExponentMax; ++k) {
    const double a = k * kScanExponentStep;
    if (!(min_b * min_b > a)) break;  // the density C phi(b) b^(a-1) (b^2 - a) must be positive
    // log-likelihood: sum_i [-C h_i + log C + (a - 1) log b_i + log phi(b_i) + log(b_i^2 - a)],
    // h_i = b_i^a phi(b_i); at its maximum over C, C = B / sum_i h_i.
    double sum_h = 0.0, rest = 0.0;
    for (const double b : sample) {
      const double lp = log_phi(b), lb = std::log(b);
      sum_h += std::exp(a * lb + lp);
      rest += (a - 1.0) * lb + lp + std::log(b * b - a);
    }
    const double log_c = std::log(B / sum_h), ll = -B + B * log_c + rest;
    if (ll > best) best = ll, best_a = a, best_log_c = log_c;
  }
  if (!std::isfinite(best)) return gumbel_quantile(sample, level);
  // C b^a phi(b) = -log(1 - level), decreasing in b beyond sqrt(a): bisection in log form.
  const double target = std::log(-std::log1p(-level));
  auto g = [&](double b) { return best_log_c + best_a * std::log(b) + log_phi(b); };
  double lo = std::sqrt(best_a) + 1e-12, hi = std::max(lo, 1.0);
  while (g(hi) > target) hi *= 2.0;
  if (g(lo) <= target) return lo;
  for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

StepScan make_step_scan(const Model& m, const Eigen::VectorXd& theta, std::int64_t n) {
  StepScan scan;
  const auto [first, last] = event_levels(n);
  if (last < first) return scan;
  const int L = last - first + 1;
  // g(h), h = 0..H, summed over the components: the arguments below reach m_j + m_k + 1
  // <= 2 m_last + 1.
  const std::int64_t H = (std::int64_t{1} << last) + 2;
  // g up to |x| = R = H + 1: the first differences below are taken over x in [-R, R].
  const std::vector<double> g = autocovariance(m, theta, static_cast<std::size_t>(H + 2));
  // Sums of g over rectangles by second differences: with D1(x + 1) - D1(x) = g(|x|) and
  // D2(x + 1) - D2(x) = D1(x) (both 0 at 0, long double: they grow as H^2 g and H^3 g),
  // sum_{s in [p, q)} sum_{t in [r, u)} g(|s - t|) = D2(q - r + 1) - D2(p - r + 1) -
  // D2(q - u + 1) + D2(p - u + 1). The sums are formal (a random walk's g is not a
  // covariance) but every Haar filter sums to zero, so their combinations are covariances.
  const std::int64_t R = H + 1;  // x in [-R, R]
  std::vector<long double> d1(static_cast<std::size_t>(2 * R + 1), 0.0L), d2(d1.size(), 0.0L);
  const auto at = [R](std::int64_t x) { return static_cast<std::size_t>(x + R); };
  const auto gx = [&g](std::int64_t x) { return static_cast<long double>(g[static_cast<std::size_t>(std::abs(x))]); };
  for (std::int64_t x = 0; x < R; ++x) d1[at(x + 1)] = d1[at(x)] + gx(x);
  for (std::int64_t x = 0; x > -R; --x) d1[at(x - 1)] = d1[at(x)] - gx(x - 1);
  for (std::int64_t x = 0; x < R; ++x) d2[at(x + 1)] = d2[at(x)] + d1[at(x)];
  for (std::int64_t x = 0; x > -R; --x) d2[at(x - 1)] = d2[at(x)] - d1[at(x - 1)];
  const auto rect = [&](std::int64_t p, std::int64_t q, std::int64_t r, std::int64_t u) {
    return d2[at(q - r + 1)] - d2[at(p - r + 1)] - d2[at(q - u + 1)] + d2[at(p - u + 1)];
  };
  // Cov(W_j(t0), W_k(t0)), W_j(t0) = (sum x[t0, t0 + m_j) - sum x[t0 - m_j, t0)) / (2 m_j).
  Eigen::MatrixXd sigma(L, L);
  for (int a = 0; a < L; ++a)
    for (int b = 0; b < L; ++b) {
      const std::int64_t mj = std::int64_t{1} << (first + a - 1), mk = std::int64_t{1} << (first + b - 1);
      const long double c = rect(0, mj, 0, mk) - rect(0, mj, -mk, 0) - rect(-mj, 0, 0, mk) + rect(-mj, 0, -mk, 0);
      sigma(a, b) = static_cast<double>(c / (4.0L * static_cast<long double>(mj) * static_cast<long double>(mk)));
    }
  if (!sigma.allFinite()) return scan;
  for (int k = 1; k <= L; ++k) {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(sigma.topLeftCorner(k, k));
    const Eigen::VectorXd s = Eigen::VectorXd::Constant(k, 0.5);
    const Eigen::VectorXd u = ldlt.solve(s);
    const double nc = s.dot(u);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(nc > 0.0) || !std::isfinite(nc) || !u.allFinite())
      return scan;
    scan.weight.emplace_back(u.data(), u.data() + k);
    for (double& w : scan.weight.back()) w /= std::sqrt(nc);
    scan.size_per_z.push_back(1.0 / std::sqrt(nc));
  }
  scan.first = first;
  scan.last = last;
  return scan;
}

StepScanResult scan_step(const std::vector<double>& x, const StepScan& scan) {
  if (x.size() < 2) return {};
  return scan_step(HaarModwt(x.data(), static_cast<std::int64_t>(x.size())), scan);
}

StepScanResult scan_step(const HaarModwt& modwt, const StepScan& scan) {
  StepScanResult r;
  const std::int64_t n = modwt.size();
  if (!scan.usable()) return r;
  const int L = scan.last - scan.first + 1;
  std::vector<std::int64_t> half(static_cast<std::size_t>(L));
  for (int j = 0; j < L; ++j) half[static_cast<std::size_t>(j)] = std::int64_t{1} << (scan.first + j - 1);
  const std::int64_t m0 = half.front(), mL = half.back();
  if (n < 4 * mL) return r;
  // The transform's prefix sums of the centred series: W_j(t0) = (S[t0 + m] - 2 S[t0] +
  // S[t0 - m]) / (2 m). (The scan built its own, with a pass for the mean and one for the
  // sums, on every reference replicate whose transform was already there; issue 44.)
  const double* S = modwt.prefix_sums().data();
  // z in a buffer kept per thread: every replicate scans a series of the record's length,
  // and a fresh vector of n doubles (zeroed, then page-faulted in) cost more than the scan
  // itself (perf: memset and page faults 55% of a gap run). Every entry read is written
  // first, so what the buffer held before does not matter.
  thread_local std::vector<double> z;
  if (z.size() < static_cast<std::size_t>(n + 1)) z.resize(static_cast<std::size_t>(n + 1));
  // Each level's mean coefficient over its M_j = n - 2m + 1 positions t0 = m .. n - m:
  // sum_t0 2m W_j(t0) = 2 H(m) - H(2m) + 2 T(m) - T(2m), H(a) the sum of S[0, a), T(c) of
  // S(n - c, n] (the interior sums cancel).
  std::vector<double> level_mean(static_cast<std::size_t>(L));
  {
    const auto head = [&](std::int64_t a) {
      double h = 0.0;
      for (std::int64_t u = 0; u < a; ++u) h += S[static_cast<std::size_t>(u)];
      return h;
    };
    const auto tail = [&](std::int64_t c) {
      double t = 0.0;
      for (std::int64_t u = n - c + 1; u <= n; ++u) t += S[static_cast<std::size_t>(u)];
      return t;
    };
    for (int j = 0; j < L; ++j) {
      const std::int64_t m = half[static_cast<std::size_t>(j)];
      const double sum = 2.0 * head(m) - head(2 * m) + 2.0 * tail(m) - tail(2 * m);
      level_mean[static_cast<std::size_t>(j)] =
          sum / (2.0 * static_cast<double>(m)) / static_cast<double>(n - 2 * m + 1);
    }
  }
  // z(t0) for t0 in [m0, n - m0], k(t0) the levels whose filter fits (m_j <= min(t0, n - t0)):
  // z = sum_j a_j (S[t0 + m_j] + S[t0 - m_j]) - 2 (sum_j a_j) S[t0] - sum_j w_j Wbar_j, with
  // a_j = w_j / (2 m_j). Runs of t0 with the same k, in blocks that stay in cache.
  constexpr std::int64_t kBlock = 512;
  const auto run = [&](std::int64_t lo, std::int64_t hi, int k) {  // t0 in [lo, hi)
    const std::vector<double>& w = scan.weight[static_cast<std::size_t>(k - 1)];
    std::vector<double> a(static_cast<std::size_t>(k));
    double centre = 0.0, self = 0.0;
    for (int j = 0; j < k; ++j) {
      a[static_cast<std::size_t>(j)] =
          w[static_cast<std::size_t>(j)] / (2.0 * static_cast<double>(half[static_cast<std::size_t>(j)]));
      self += 2.0 * a[static_cast<std::size_t>(j)];
      centre += w[static_cast<std::size_t>(j)] * level_mean[static_cast<std::size_t>(j)];
    }
    for (std::int64_t b = lo; b < hi; b += kBlock)
      scan_block(z.data(), S, a.data(), half.data(), k, centre, self, b, std::min(hi, b + kBlock));
  };
  for (int k = 1; k < L; ++k) {
    run(half[static_cast<std::size_t>(k - 1)], half[static_cast<std::size_t>(k)], k);
    run(n - half[static_cast<std::size_t>(k)] + 1, n - half[static_cast<std::size_t>(k - 1)] + 1, k);
  }
  run(mL, n - mL + 1, L);
  std::int64_t peak = m0;
  for (std::int64_t t = m0; t <= n - m0; ++t)
    if (std::abs(z[static_cast<std::size_t>(t)]) > std::abs(z[static_cast<std::size_t>(peak)])) peak = t;
  // The RMS away from the peak: a step's own signature in z spans the coarsest filter.
  double ss = 0.0;
  std::int64_t count = 0;
  for (std::int64_t t = m0; t <= n - m0; ++t) {
    if (std::abs(t - peak) < mL) continue;
    ss += z[static_cast<std::size_t>(t)] * z[static_cast<std::size_t>(t)];
    ++count;
  }
  const double rms = count > 0 ? std::sqrt(ss / static_cast<double>(count)) : 0.0;
  const double zp = z[static_cast<std::size_t>(peak)];
  r.statistic = std::abs(zp) / std::max(kStepScaleFloor, rms);
  r.rms = rms;
  r.sample = peak;
  int k = 0;
  while (k < L && half[static_cast<std::size_t>(k)] <= std::min(peak, n - peak)) ++k;
  r.size = zp * scan.size_per_z[static_cast<std::size_t>(k - 1)];
  // Each level's part of z at the peak, signed toward it.
  r.share.assign(static_cast<std::size_t>(L), 0.0);
  double largest = 0.0;
  for (int j = 0; j < k; ++j) {
    const std::int64_t m = half[static_cast<std::size_t>(j)];
    const double wj = (S[static_cast<std::size_t>(peak + m)] - 2.0 * S[static_cast<std::size_t>(peak)] +
                       S[static_cast<std::size_t>(peak - m)]) /
                          (2.0 * static_cast<double>(m)) -
                      level_mean[static_cast<std::size_t>(j)];
    const double part =
        scan.weight[static_cast<std::size_t>(k - 1)][static_cast<std::size_t>(j)] * wj * (zp < 0.0 ? -1.0 : 1.0);
    r.share[static_cast<std::size_t>(j)] = part;
    if (part > largest) {
      largest = part;
      r.level = scan.first + j;
    }
  }
  if (r.level == 0) r.level = scan.first + k - 1;
  for (double& v : r.share) v = largest > 0.0 ? v / largest : 0.0;
  return r;
}

}  // namespace gmwm::gap::detail
