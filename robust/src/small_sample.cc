#include "small_sample.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gmwm::robust::internal {
namespace {

// p = chi(u), q = chi'(u) u at u = W^2 / s.
struct PQ {
  double p, q;
};

PQ pq(RobustKind kind, double c2, double u) {
  if (kind == RobustKind::kHuber) return u < c2 ? PQ{u, u} : PQ{c2, 0.0};
  if (u >= c2) return {0.0, 0.0};
  const double v = u / c2, r = 1.0 - v, r3 = r * r * r;
  return {u * r3 * r, u * r3 * (1.0 - 5.0 * v)};
}

}  // namespace

double small_sample_bias(std::span<const double> coefficients, const Tuning& t, double scale, double tau) {
  const auto stride = static_cast<std::size_t>(std::max(1.0, tau / kSamplesPerScale));
  thread_local std::vector<double> sub;
  sub.clear();
  for (std::size_t k = 0; k < coefficients.size(); k += stride) sub.push_back(coefficients[k]);
  const std::span<const double> w(sub);
  const std::size_t M = w.size();
  tau /= static_cast<double>(stride);  // in subsample steps
  if (M < 8 || !(scale > 0.0)) return 0.0;
  const double c2 = t.c * t.c, inv_s = 1.0 / scale;
  const auto b = static_cast<std::size_t>(std::clamp(std::min(kBatchScales * tau, static_cast<double>(M) / kMinBatches),
                                                     1.0, static_cast<double>(M) / 2.0));
  // Overlapping batch means (Meketon & Schmeiser 1984) of p and q, by a sliding window:
  // K = M - b + 1 windows. Sums are of values centred at their Gaussian means (a and
  // slope), so the final centring at the sample means does not cancel digits.
  auto at = [&](std::size_t k) {
    PQ v = pq(t.kind, c2, w[k] * w[k] * inv_s);
    return PQ{v.p - t.a, v.q - t.slope};
  };
  double wp = 0.0, wq = 0.0;  // window sums
  double tp = 0.0, tq = 0.0;  // totals
  for (std::size_t k = 0; k < b; ++k) {
    const PQ v = at(k);
    wp += v.p;
    wq += v.q;
  }
  tp = wp;
  tq = wq;
  const std::size_t K = M - b + 1;
  double sp = 0.0, sq = 0.0, spp = 0.0, spq = 0.0;  // over windows, of the window means
  const double inv_b = 1.0 / static_cast<double>(b);
  for (std::size_t i = 0;; ++i) {
    const double mp = wp * inv_b, mq = wq * inv_b;
    sp += mp;
    sq += mq;
    spp += mp * mp;
    spq += mp * mq;
    if (i + 1 == K) break;
    const PQ in = at(i + b), out = at(i);
    wp += in.p - out.p;
    wq += in.q - out.q;
    tp += in.p;
    tq += in.q;
  }
  const double Md = static_cast<double>(M), Kd = static_cast<double>(K), bd = static_cast<double>(b);
  const double mu_p = tp / Md, mu_q = tq / Md;
  // sum_i (mp_i - mu_p)^2 and sum_i (mp_i - mu_p)(mq_i - mu_q)
  const double cpp = spp - 2.0 * mu_p * sp + Kd * mu_p * mu_p;
  const double cpq = spq - mu_p * sq - mu_q * sp + Kd * mu_p * mu_q;
  // Long-run (co)variance sigma^2 = M b / ((M - b + 1)(M - b)) sum(...); Var(pbar) = sigma^2 / M.
  const double norm = bd / (Kd * (Md - bd));
  const double var_p = norm * cpp, cov_pq = norm * cpq;
  const double slope = t.slope;
  return -cov_pq / (slope * slope) + t.curvature * var_p / (2.0 * slope * slope * slope);
}

}  // namespace gmwm::robust::internal
