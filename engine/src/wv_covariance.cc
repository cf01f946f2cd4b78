#include "gmwm/engine/wv_covariance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/parallel_for.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

// A lag k is in a component's "tail" once |Delta^2 g(k)| < kTailTolerance |Delta^2 g(0)|:
// the cross-covariance of two Haar coefficient processes is a fourth-order difference
// of the structure function V, i.e. a smoothed Delta^2 g, so beyond that lag (plus the
// filters' length) its squares add less than ~1e-12 relative to the sum. Chosen so that
// the long-double rounding of V at the last lag kept stays below that level for AR1
// with 1 - phi >= 1e-6 (see the comment in ComponentTable).
constexpr double kTailTolerance = 1e-6;
// Between breakpoints, n_ij(h) c_ij(h)^2 is a polynomial in h for WN, QN and RW (their
// structure functions are polynomials away from d = 0, 1) and a smooth function for
// decaying stationary components; sums over long stretches use composite Simpson with
// at most kSimpsonPointsPerStretch points (error ~ (1/64)^4 relative for the degree-7
// polynomials), and at most 8 points per decay scale of the slowest stationary
// component, whose support spans about kDecayScalesInSupport e-folds (1e-6 = e^-13.8).
constexpr double kSimpsonPointsPerStretch = 64.0;
constexpr double kDecayScalesInSupport = 14.0;
// Components whose support is at most this many lags have (nearly) polynomial structure
// functions beyond it (WN: 1, QN and RW: 3, short-memory AR1/MA1 a few lags).
constexpr std::int64_t kPolynomialSupport = 16;
// Lags summed exactly on each side of a breakpoint (covers the short-support kinks).
constexpr std::int64_t kBreakpointMargin = 3;

// One stochastic component: V(d) = sum_{|k|<d} (d - |k|) (g(k) - g(0)), the structure
// function of its partial sums, in long double. Subtracting g(0) changes V by a
// multiple of d^2, which the Haar filters (second differences of the partial sums at
// equal spacing) annihilate, and removes the large constant of slowly decaying AR1s.
//
// Beyond its support the component's g is linear in the lag (|Delta^2 g| below
// kTailTolerance), so V is a cubic in d there: it is tabulated exactly up to the support
// (plus a margin) and continued in closed form beyond, which keeps the memory at the
// component's memory, not the record's length (a table of 3N long doubles per component
// cost 72 MB and half the selection's time at N = 1e6). Components that never decay
// (SIN) are tabulated to the full reach.
struct ComponentTable {
  std::vector<long double> V;     // V(0 .. T), T = V.size() - 1
  long double G_prev = 0.0L;      // G(T - 1) = sum_{|k| <= T-1} (g(k) - g0)
  long double delta = 0.0L;       // g(T - 1) - g0
  long double beta = 0.0L;        // g(k) = g(T - 1) + beta (k - T + 1) for k >= T
  std::int64_t support = 0;  // lags beyond which the component's c_ij(h) vanishes
  bool oscillating = false;  // no decay found (SIN): sum lag by lag

  long double at(std::int64_t d) const {
    const auto T = static_cast<std::int64_t>(V.size()) - 1;
    if (d <= T) return V[static_cast<std::size_t>(d)];
    // V(d) = V(T) + sum_{i=1}^{n} [G(T-1) + 2 i delta + beta i (i + 1)], n = d - T.
    const long double n = static_cast<long double>(d - T);
    return V.back() + n * G_prev + delta * n * (n + 1.0L) + beta * n * (n + 1.0L) * (n + 2.0L) / 3.0L;
  }
};

// First lag window over which the support is searched; doubled until the significant
// second differences end in its first half (or the reach is covered).
constexpr std::int64_t kFirstSupportWindow = std::int64_t{1} << 12;

ComponentTable make_table(const Process& p, std::span<const double> theta, std::int64_t max_lag) {
  std::vector<double> g;
  std::int64_t last = 0, window = std::min(kFirstSupportWindow, max_lag);
  for (;;) {
    g.assign(static_cast<std::size_t>(window) + 2, 0.0);
    p.generalized_autocovariance(theta, g);
    // Second differences (g symmetric: g(-1) = g(1)).
    auto d2 = [&](std::size_t k) { return k == 0 ? 2.0 * (g[1] - g[0]) : g[k + 1] - 2.0 * g[k] + g[k - 1]; };
    const double ref = std::abs(d2(0)) > 0 ? std::abs(d2(0)) : std::abs(g[0]);
    last = 0;
    for (std::size_t k = 1; k + 1 < g.size(); ++k)
      if (std::abs(d2(k)) > kTailTolerance * ref) last = static_cast<std::int64_t>(k);
    if (2 * last < window || window >= max_lag) break;
    window = std::min(2 * window, max_lag);
  }
  ComponentTable t;
  t.support = last + 1;
  t.oscillating = t.support >= max_lag - 1;
  // The exact part: up to the support plus the margin cross_cov reads around it.
  const std::int64_t T = t.oscillating ? max_lag : std::min<std::int64_t>(window, t.support + 2 * kBreakpointMargin + 2);
  const double g0 = g[0];
  t.V.assign(static_cast<std::size_t>(T) + 1, 0.0L);
  long double G = 0.0L;  // sum_{|k|<=d} (g(k) - g0)
  for (std::size_t d = 0; d + 1 < t.V.size(); ++d) {
    G += (d == 0) ? 0.0L : 2.0L * (static_cast<long double>(g[d]) - g0);
    t.V[d + 1] = t.V[d] + G;
  }
  // G now holds G(T - 1).
  t.G_prev = G;
  t.delta = static_cast<long double>(g[static_cast<std::size_t>(T) - 1]) - g0;
  t.beta = static_cast<long double>(g[static_cast<std::size_t>(T) - 1]) - static_cast<long double>(g[static_cast<std::size_t>(T) - 2]);
  return t;
}

// Running sums of n(h) c(h)^2 and n(h) c(h) over lags.
struct Sums {
  long double squares = 0.0L, linear = 0.0L;
  Sums& operator+=(const Sums& o) { squares += o.squares; linear += o.linear; return *this; }
  friend Sums operator+(Sums x, const Sums& y) { return x += y; }
  friend Sums operator*(long double w, Sums x) { x.squares *= w; x.linear *= w; return x; }
};

struct Level {
  std::int64_t tau, m, M;
};

// c_ij(h) = Cov(W_{i,t}, W_{j,t+h}) for one component:
//   -1/2 sum_k sum_l c_k e_l V(|P_k - Q_l|) / (tau_i tau_j),
// c = e = (1, -2, 1) at offsets (0, -m, -tau) from t+1 and t+h+1.
long double cross_cov(const ComponentTable& t, const Level& a, const Level& b, std::int64_t h) {
  const std::int64_t po[3] = {0, -a.m, -a.tau}, qo[3] = {0, -b.m, -b.tau};
  const long double w[3] = {1.0L, -2.0L, 1.0L};
  long double s = 0.0L;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      const std::int64_t d = std::llabs(po[k] - qo[l] - h);
      s += w[k] * w[l] * t.at(d);
    }
  return -0.5L * s / (static_cast<long double>(a.tau) * static_cast<long double>(b.tau));
}

}  // namespace

Eigen::MatrixXd model_wv_covariance(const Model& model, const Eigen::VectorXd& theta,
                                    std::int64_t n, int levels) {
  check_at_least("model_wv_covariance", "n", static_cast<double>(n), 2.0);
  check_at_least("model_wv_covariance", "levels", levels, 1.0);
  std::vector<Level> lv;
  for (int j = 1; j <= levels; ++j) {
    const std::int64_t tau = std::int64_t{1} << j;
    check_at_least("model_wv_covariance", "coefficients at the last level", static_cast<double>(n - tau + 1), 1.0);
    lv.push_back({tau, tau / 2, n - tau + 1});
  }
  const std::int64_t max_lag = 3 * n + 4;
  std::vector<int> stochastic;
  for (int c = 0; c < model.num_components(); ++c)
    if (!model.components()[static_cast<std::size_t>(c)].process->deterministic()) stochastic.push_back(c);
  // The deterministic components' Haar coefficient at each level (constant in time).
  std::vector<long double> det(static_cast<std::size_t>(levels), 0.0L);
  for (int c = 0; c < model.num_components(); ++c) {
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    if (!p.deterministic()) continue;
    const std::span<const double> th{theta.data() + model.offset(c), static_cast<std::size_t>(p.size())};
    for (int j = 0; j < levels; ++j)
      det[static_cast<std::size_t>(j)] += p.deterministic_coefficient(th, static_cast<double>(lv[static_cast<std::size_t>(j)].tau));
  }
  std::vector<ComponentTable> tables(stochastic.size());
  tbb::parallel_for(std::size_t{0}, stochastic.size(), [&](std::size_t k) {
    const int c = stochastic[k];
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    tables[k] = make_table(p, {theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, max_lag);
  });
  const int J = levels;
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(J, J);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < J; ++i)
    for (int j = i; j < J; ++j) pairs.emplace_back(i, j);
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t idx) {
    const auto [i, j] = pairs[idx];
    const Level& a = lv[static_cast<std::size_t>(i)];
    const Level& b = lv[static_cast<std::size_t>(j)];
    // Lags h with coefficient pairs: t in [tau_a - 1, n - 1], t + h in [tau_b - 1, n - 1].
    auto count = [&](std::int64_t h) -> long double {
      const std::int64_t lo = std::max(a.tau - 1, b.tau - 1 - h), hi = std::min(n - 1, n - 1 - h);
      return hi >= lo ? static_cast<long double>(hi - lo + 1) : 0.0L;
    };
    // Both sums at once: n(h) c(h)^2 (the Gaussian term) and n(h) c(h) (the covariance
    // of the two levels' coefficient means, needed with a deterministic component).
    auto f = [&](std::int64_t h) -> Sums {
      long double c = 0.0L;
      for (const auto& t : tables)
        if (h >= -(a.tau + t.support) && h <= b.tau + t.support) c += cross_cov(t, a, b, h);
      const long double pairs_at_h = count(h);
      return {pairs_at_h * c * c, pairs_at_h * c};
    };
    std::int64_t reach = 0, margin = kBreakpointMargin;
    bool oscillating = false;
    for (const auto& t : tables) {
      reach = std::max(reach, t.support);
      oscillating = oscillating || t.oscillating;
      if (t.support <= kPolynomialSupport) margin = std::max(margin, t.support + kBreakpointMargin);
    }
    // t + h in [tau_b - 1, n - 1] with t in [tau_a - 1, n - 1]: h in [-(M_b - 1), M_a - 1];
    // the filters (plus the components' reach) overlap for h in [-(tau_a + K), tau_b + K].
    const std::int64_t h_lo = std::max(-(b.M - 1), -(a.tau + reach) - 1);
    const std::int64_t h_hi = std::min(a.M - 1, b.tau + reach + 1);
    // c(h) is smooth between breakpoints: where two filter edges meet (po_k - qo_l) and
    // where the pair count n(h) changes slope (0, tau_b - tau_a). A decaying component
    // varies on its own scale only within its support K of a breakpoint; further away
    // every component is polynomial in h. Sum each stretch by Simpson, the few lags
    // around each breakpoint exactly.
    std::vector<std::int64_t> base = {0, b.tau - a.tau};
    const std::int64_t po[3] = {0, -a.m, -a.tau}, qo[3] = {0, -b.m, -b.tau};
    for (auto x : po)
      for (auto y : qo) base.push_back(x - y);
    std::vector<std::int64_t> cuts = {h_lo, h_hi + 1};
    std::vector<std::int64_t> pts;
    for (auto c : base) {
      for (std::int64_t d = -margin; d <= margin; ++d) pts.push_back(c + d);
      for (const auto& t : tables)
        if (t.support > kPolynomialSupport) { cuts.push_back(c - t.support); cuts.push_back(c + t.support + 1); }
    }
    for (const auto& t : tables) { cuts.push_back(-(a.tau + t.support)); cuts.push_back(b.tau + t.support + 1); }
    pts.insert(pts.end(), cuts.begin(), cuts.end());
    pts.erase(std::remove_if(pts.begin(), pts.end(), [&](std::int64_t x) { return x < h_lo || x > h_hi + 1; }), pts.end());
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    // Variation scale of c(h) on a stretch: the decay scale of the components whose
    // support reaches it from the nearest breakpoint.
    auto smoothness = [&](std::int64_t u, std::int64_t v) {
      std::int64_t dist = std::numeric_limits<std::int64_t>::max();
      for (auto c : base) {
        if (c >= u && c <= v) return 1.0;
        dist = std::min<std::int64_t>(dist, std::min<std::int64_t>(std::llabs(c - u), std::llabs(c - v)));
      }
      double sm = std::numeric_limits<double>::infinity();
      for (const auto& t : tables)
        if (t.support > kPolynomialSupport && t.support >= dist)
          sm = std::min(sm, static_cast<double>(t.support) / kDecayScalesInSupport);
      return sm;
    };
    Sums sum;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const std::int64_t u = pts[k], v = pts[k + 1] - 1;  // stretch [u, v]
      const std::int64_t len = v - u;
      std::int64_t s = 1;
      if (!oscillating && len > 16) {
        const double by_len = static_cast<double>(len) / kSimpsonPointsPerStretch;
        s = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::min(by_len, smoothness(u, v) / 8.0)));
      }
      if (s == 1) {
        for (std::int64_t h = u; h <= v; ++h) sum += f(h);
        continue;
      }
      const std::int64_t steps = (len / (2 * s)) * 2;
      const std::int64_t B = u + steps * s;
      const Sums ends = f(u) + f(B);
      Sums simpson = ends;
      for (std::int64_t q = 1; q < steps; ++q) simpson += ((q % 2) ? 4.0L : 2.0L) * f(u + q * s);
      // Sum over the integers of [u, B] ~ integral (s/3 x Simpson) + (f(u) + f(B)) / 2.
      sum += (static_cast<long double>(s) / 3.0L) * simpson + 0.5L * ends;
      for (std::int64_t h = B + 1; h <= v; ++h) sum += f(h);
    }
    // nuhat = mean (d + S)^2 with d the deterministic coefficient: for Gaussian S the
    // third moments vanish, leaving Cov = 2 sum n c^2 / (M_i M_j) + 4 d_i d_j sum n c / (M_i M_j).
    const long double mm = static_cast<long double>(a.M) * static_cast<long double>(b.M);
    const long double di = det[static_cast<std::size_t>(i)], dj = det[static_cast<std::size_t>(j)];
    const double v = static_cast<double>((2.0L * sum.squares + 4.0L * di * dj * sum.linear) / mm);
    V(i, j) = v;
    V(j, i) = v;
  });
  return V;
}

Eigen::MatrixXd bootstrap_wv_covariance(const Model& model, const Eigen::VectorXd& theta,
                                        std::int64_t n, int levels, int replicates,
                                        std::uint64_t seed, const WvEstimator& estimator,
                                        double alpha) {
  check_at_least("bootstrap_wv_covariance", "replicates", replicates, 2.0);
  Eigen::MatrixXd W(replicates, levels);
  tbb::parallel_for(0, replicates, [&](int r) {
    const auto x = simulate(model, theta, n, seed, static_cast<std::uint64_t>(r));
    const WaveletVariance w = estimator.compute(x.data(), n, levels, alpha);
    for (int j = 0; j < levels; ++j) W(r, j) = w.wv[static_cast<std::size_t>(j)];
  });
  const Eigen::RowVectorXd mean = W.colwise().mean();
  const Eigen::MatrixXd centred = W.rowwise() - mean;
  return centred.transpose() * centred / static_cast<double>(replicates - 1);
}

}  // namespace gmwm
