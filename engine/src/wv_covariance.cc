#include "gmwm/engine/wv_covariance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

// A lag k is in a component's "tail" once |Delta^2 g(k)| < kTailTolerance |Delta^2 g(0)|:
// the cross-covariance of two Haar coefficient processes is a fourth-order difference
// of the structure function V, i.e. a smoothed Delta^2 g. Continuing g linearly beyond
// that lag leaves a slope error of about that size, which moves V_ij by up to ~6e-7 of
// sqrt(V_ii V_jj) at the coarse levels (measured against the lag-by-lag sum, AR1 with
// phi 0.5-0.99; wv_covariance_test). A smaller tolerance lengthens the tables until the
// long-double rounding of V at the last lag kept dominates (1e-9 broke N = 1e6 with
// 1 - phi = 1e-4; see the comment in ComponentTable).
constexpr double kTailTolerance = 1e-6;
// Between breakpoints, n_ij(h) c_ij(h)^2 is a polynomial in h of degree at most 7 for WN,
// QN, RW and DR (their structure functions are at most cubic away from d = 0, 1; n_ij(h) is
// linear) and a smooth function for decaying stationary components; sums over long
// stretches use the corrected Simpson rule of sum_smooth, exact for degree 7 (error
// O(s^8 f^(8))), with at least kSimpsonPointsPerStretch panels and kPointsPerDecayScale
// per decay scale of the slowest stationary component, whose support spans about
// kDecayScalesInSupport e-folds (1e-6 = e^-13.8). Measured against the lag-by-lag sum at
// N = 1e6, 19 levels: polynomial models (RW; WN+RW; AR1(0.16)+RW) within 1e-12
// sqrt(V_ii V_jj) (the earlier rule, of O(s^6) error, with 32 panels and 4 per decay
// scale: 9.4e-9); models with slow AR1s (2 AR1 with phi 0.9999; 3 AR1 + WN + QN + RW;
// AR1(1 - 1e-6) + WN + RW) within 2.6e-8 (was 1.8e-7), in 0.78 of the time (issue 44).
// With 16 panels those reached 1.2e-7, with 8 panels 7.9e-6: beyond its support an AR1's
// geometric tail is close to, not exactly, a polynomial.
constexpr double kSimpsonPointsPerStretch = 24.0;
constexpr double kDecayScalesInSupport = 14.0;
constexpr double kPointsPerDecayScale = 3.0;
// Stretches shorter than this are summed lag by lag; the rule needs at least kMinPanels
// panels (eight points for each end's differences).
constexpr std::int64_t kExactStretch = 24;
constexpr std::int64_t kMinPanels = 8;
// A stochastic component whose WV is below this share of the model's at every level is
// left out: its coefficients' covariances are at most that share of the model's
// (|c_ij(h)| <= sqrt(nu_i nu_j) by Cauchy-Schwarz), so it moves V by less than about
// 2e-12 relative. Collapsed terms of a maximal model's fit (a WN at 1e-17 beside AR1s)
// would otherwise cost a full table and a term in every lag's sum.
constexpr double kNegligibleShare = 1e-12;
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
// exp(-60) = 9e-27: a geometric remainder rho^n below it is 0 at long-double precision
// (the reach of the remainder when V(T) gives no scale to compare it with).
constexpr double kNegligibleExponent = 60.0;
// The remainder's term is dropped once below this share of |V(T)|: long double's epsilon
// is 5.4e-20, and V beyond T only grows.
constexpr double kRemainderPrecision = 1e-21;

struct ComponentTable {
  std::vector<long double> V;  // V(0 .. T), T = V.size() - 1
  long double G_prev = 0.0L;   // G(T - 1) = sum_{|k| <= T-1} (g(k) - g0)
  // Beyond the table, g(T - 1 + i) - g0 = A + beta i + C rho^i (i >= 0): a line (WN, QN,
  // RW, MA1: C = 0) plus the geometric tail of a decaying component (AR1: its remaining
  // decay towards its asymptote A + beta i, found from the last second differences).
  long double A = 0.0L;
  long double beta = 0.0L;
  long double C = 0.0L;
  long double rho = 0.0L;
  double log_rho = 0.0;  // ln(rho): rho^n as exp(n ln rho) (powl in the lag loop cost 4x the whole sum)
  // 2 C rho / (1 - rho) and rho / (1 - rho), once per table (long-double divisions in the
  // lag loop cost a third of the sum).
  long double geometric_scale = 0.0L, geometric_shift = 0.0L;
  // Lags beyond the table past which geometric_scale geometric_shift rho^n is below
  // kRemainderPrecision |V(T)| (V only grows beyond T).
  long double geometric_reach = 0.0L;
  std::int64_t support = 0;  // lags beyond which the component's c_ij(h) vanishes
  bool oscillating = false;  // no decay found (SIN): sum lag by lag

  long double at(std::int64_t d) const {
    const auto T = static_cast<std::int64_t>(V.size()) - 1;
    if (d <= T) return V[static_cast<std::size_t>(d)];
    // V(T + n) = V(T) + sum_{i=1}^{n} G(T - 1 + i), G(T - 1 + i) = G(T - 1) + 2 sum_{l=1}^{i}
    // (A + beta l + C rho^l) = G(T - 1) + 2 A i + beta i (i + 1) + 2 C rho (1 - rho^i) / (1 - rho).
    const long double n = static_cast<long double>(d - T);
    long double v = V.back() + n * G_prev + A * n * (n + 1.0L) + beta * n * (n + 1.0L) * (n + 2.0L) / 3.0L;
    if (C != 0.0L) {
      // rho^n in double (single precision broke V's positive definiteness at phi 0.99999,
      // whose remainder is large), and only up to geometric_reach: beyond, its term is below
      // long-double precision of V.
      long double rn = 0.0L;
      if (n < geometric_reach) rn = static_cast<long double>(std::exp(static_cast<double>(n) * log_rho));
      v += geometric_scale * (n - geometric_shift * (1.0L - rn));
    }
    return v;
  }
};

// The tail of g beyond the last tabulated lags, g(T - 1 + i) = g0 + A + beta i + C rho^i:
// when the last three first differences decay geometrically (ratio rho in (0, 1), the
// AR1's phi), their limit is the slope and the rest is the geometric part still to come;
// otherwise (second differences zero: WN, QN, RW, MA1) the line through the last two.
// Continuing the last slope instead (the line alone) carried an AR1's residual slope
// |Delta g(T)| ~ 1e-6 of its curvature over every lag to the record's length: at the
// coarsest levels of a 2^18 record V_JJ came out 3e3 (phi 0.5) to 3e5 (phi 0.9) times the
// exact 2 nu_J^2 of a single coefficient.
void fit_tail(ComponentTable& t, const std::vector<double>& g, std::int64_t T) {
  const auto at = [&](std::int64_t k) { return static_cast<long double>(g[static_cast<std::size_t>(k)]); };
  const long double g0 = at(0);
  t.A = at(T - 1) - g0;
  t.beta = at(T - 1) - at(T - 2);
  if (T < 4) return;
  const long double d1 = at(T - 3) - at(T - 4), d2 = at(T - 2) - at(T - 3), d3 = at(T - 1) - at(T - 2);
  const long double s1 = d2 - d1, s2 = d3 - d2;
  if (s1 == 0.0L || s2 == 0.0L || (s1 > 0.0L) != (s2 > 0.0L)) return;
  const long double rho = s2 / s1;
  if (!(rho > 0.0L && rho < 1.0L)) return;
  // Delta g(T - 2 + i) = beta + E rho^i with s2 = E (rho - 1) / rho ... solved on d2, d3:
  // beta = d3 - s2 rho / (rho - 1); g(T - 1 + i) - g0 = A + beta i + C rho^i with
  // C = s2 rho^2 / (rho - 1)^2 and A = g(T - 1) - g0 - C.
  const long double q = rho - 1.0L;
  t.rho = rho;
  t.log_rho = std::log(static_cast<double>(rho));
  t.beta = d3 - s2 * rho / q;
  t.C = s2 * rho * rho / (q * q);
  t.A = at(T - 1) - g0 - t.C;
  t.geometric_scale = 2.0L * t.C * rho / (1.0L - rho);
  t.geometric_shift = rho / (1.0L - rho);
  const double amplitude = std::abs(static_cast<double>(t.geometric_scale * t.geometric_shift));
  const double floor = kRemainderPrecision * std::abs(static_cast<double>(t.V.empty() ? 0.0L : t.V.back()));
  t.geometric_reach = amplitude > 0.0 && floor > 0.0 && floor < amplitude
                          ? static_cast<long double>(std::log(floor / amplitude) / t.log_rho)
                          : static_cast<long double>(kNegligibleExponent / -t.log_rho);
}

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
  const std::int64_t T =
      t.oscillating ? max_lag : std::min<std::int64_t>(window, t.support + 2 * kBreakpointMargin + 2);
  const double g0 = g[0];
  t.V.assign(static_cast<std::size_t>(T) + 1, 0.0L);
  long double G = 0.0L;  // sum_{|k|<=d} (g(k) - g0)
  for (std::size_t d = 0; d + 1 < t.V.size(); ++d) {
    G += (d == 0) ? 0.0L : 2.0L * (static_cast<long double>(g[d]) - g0);
    t.V[d + 1] = t.V[d] + G;
  }
  // G now holds G(T - 1).
  t.G_prev = G;
  fit_tail(t, g, T);
  return t;
}

// The components' tables summed into one (V is linear in the components): the cross
// covariance of the Haar coefficients is the same second difference of the summed V, so
// each lag reads 9 values of one table instead of 9 per component (the lag loop's x87
// arithmetic was 86% of the covariance's time). Up to T, the longest table's reach, the
// sum is tabulated; beyond, every component's V is its cubic plus a geometric remainder
// (ComponentTable::at), so the sum is one cubic in n = d - T (each table's re-expanded about
// T: x = n + s with s = T - T_t) plus the remainders of the components still decaying.
struct CombinedTable {
  std::vector<long double> V;                              // sum of the tables' V(0 .. T)
  long double c0 = 0.0L, c1 = 0.0L, c2 = 0.0L, c3 = 0.0L;  // the cubic in n beyond T
  struct Remainder {
    long double scale = 0.0L;  // geometric_scale * geometric_shift
    double log_rho = 0.0;
    long double shift = 0.0L;  // s = T - T_t
    long double reach = 0.0L;  // geometric_reach, in the table's own n
  };
  std::vector<Remainder> remainders;

  explicit CombinedTable(const std::vector<ComponentTable>& tables) {
    std::int64_t T = 0;
    for (const auto& t : tables) T = std::max<std::int64_t>(T, static_cast<std::int64_t>(t.V.size()) - 1);
    V.assign(static_cast<std::size_t>(T) + 1, 0.0L);
    for (const auto& t : tables)
      for (std::int64_t d = 0; d <= T; ++d) V[static_cast<std::size_t>(d)] += t.at(d);
    // Each table beyond its own T_t, in x = d - T_t (at()): V(T_t) + x G + A x (x + 1) +
    // beta x (x + 1) (x + 2) / 3 + g (x - shift) + g shift rho^x (g = geometric_scale), i.e.
    // the cubic k3 x^3 + k2 x^2 + k1 x + k0 and the remainder; about T, x = n + s.
    for (const auto& t : tables) {
      const long double s = static_cast<long double>(T - (static_cast<std::int64_t>(t.V.size()) - 1));
      const long double g = t.C != 0.0L ? t.geometric_scale : 0.0L;
      const long double k3 = t.beta / 3.0L, k2 = t.A + t.beta, k1 = t.G_prev + t.A + 2.0L * t.beta / 3.0L + g;
      c3 += k3;
      c2 += k2 + 3.0L * k3 * s;
      c1 += k1 + 2.0L * k2 * s + 3.0L * k3 * s * s;
      if (t.C != 0.0L) remainders.push_back({g * t.geometric_shift, t.log_rho, s, t.geometric_reach});
    }
    // The constant: the sum at T itself, less the remainders there (added back in at()).
    c0 = V.back();
    for (const auto& r : remainders) c0 -= remainder(r, 0.0L);
  }
  static long double remainder(const Remainder& r, long double n) {
    const long double x = n + r.shift;
    return x < r.reach ? r.scale * static_cast<long double>(std::exp(static_cast<double>(x) * r.log_rho)) : 0.0L;
  }
  long double at(std::int64_t d) const {
    const auto T = static_cast<std::int64_t>(V.size()) - 1;
    if (d <= T) return V[static_cast<std::size_t>(d)];
    const long double n = static_cast<long double>(d - T);
    long double v = ((c3 * n + c2) * n + c1) * n + c0;
    for (const auto& r : remainders) v += remainder(r, n);
    return v;
  }
};

// Running sums of n(h) c(h)^2 and n(h) c(h) over lags.
struct Sums {
  long double squares = 0.0L, linear = 0.0L;
  Sums& operator+=(const Sums& o) {
    squares += o.squares;
    linear += o.linear;
    return *this;
  }
  friend Sums operator+(Sums x, const Sums& y) { return x += y; }
  friend Sums operator*(long double w, Sums x) {
    x.squares *= w;
    x.linear *= w;
    return x;
  }
};

struct Level {
  std::int64_t tau, m, M;
};

// c_ij(h) = Cov(W_{i,t}, W_{j,t+h}) for one component:
//   -1/2 sum_k sum_l c_k e_l V(|P_k - Q_l|) / (tau_i tau_j),
// c = e = (1, -2, 1) at offsets (0, -m, -tau) from t+1 and t+h+1; `scale` is
// -1/2 / (tau_i tau_j). The double sum as second differences: D_k = V_k0 - 2 V_k1 + V_k2
// per row, then D_0 - 2 D_1 + D_2. Nine terms in one running sum were a chain of
// dependent x87 additions through the stack (its accumulator spilled): 23% of a selection's
// CPU; the rows are independent, and their differences are taken before the large values
// meet, so the rounding is no worse (against the nine terms summed in binary128: QN alone
// 3.8e-10 against 1.8e-10, WN + RW, RW, AR1 + RW, AR1 + WN + DR, two AR1 within 1e-13
// either way, of sqrt(V_ii V_jj) at N = 2^18; issue 44).
template <class Table>
long double cross_cov(const Table& t, const Level& a, const Level& b, std::int64_t h, long double scale) {
  const std::int64_t po[3] = {0, -a.m, -a.tau}, qo[3] = {0, -b.m, -b.tau};
  long double D[3];
  for (int k = 0; k < 3; ++k) {
    const long double v0 = t.at(std::llabs(po[k] - qo[0] - h)), v1 = t.at(std::llabs(po[k] - qo[1] - h)),
                      v2 = t.at(std::llabs(po[k] - qo[2] - h));
    D[k] = (v0 + v2) - 2.0L * v1;
  }
  return scale * ((D[0] + D[2]) - 2.0L * D[1]);
}

// sum_{h=u}^{v} f(h) for f smooth on [u, v] (no breakpoint inside), sampled every
// `max_step` lags at most: composite Simpson on the grid u + q s plus the Euler-Maclaurin
// terms that turn an integral into a sum over the integers,
//   sum = integral + (f(u) + f(B))/2 + [f']/12 - [f''']/720 + [f^(5)]/30240
// ([g] = g(B) - g(u)), with Simpson's own error removed up to s^6 (Simpson = integral +
// s^4/180 [f'''] - s^6/1512 [f^(5)] + O(s^8)); f', f''' and f^(5) at the ends come from
// eight-point one-sided differences on the same grid (step s), exact for degree 7, so the
// rule costs no extra evaluation and is exact for the polynomials of degree 7 that
// n(h) c(h)^2 is between breakpoints of WN, QN, RW and DR (checked in exact rationals);
// its error is O(s^8 f^(8)). The part of the stretch the grid leaves over (shorter than its
// number of panels) is summed the same way, or lag by lag when short.
template <class F>
Sums sum_smooth(const F& f, std::int64_t u, std::int64_t v, double max_step) {
  Sums total;
  for (;;) {
    const std::int64_t len = v - u;
    std::int64_t panels = 0, s = 0;
    if (len >= kExactStretch && max_step >= 2.0) {
      panels = static_cast<std::int64_t>(std::ceil(static_cast<double>(len) / max_step));
      panels = std::max<std::int64_t>(kMinPanels, panels + (panels % 2));
      s = len / panels;
    }
    if (s < 2) {
      for (std::int64_t h = u; h <= v; ++h) total += f(h);
      return total;
    }
    const std::int64_t B = u + panels * s;
    std::vector<Sums> y(static_cast<std::size_t>(panels) + 1);
    for (std::int64_t q = 0; q <= panels; ++q) y[static_cast<std::size_t>(q)] = f(u + q * s);
    const long double h = static_cast<long double>(s);
    Sums simpson = y.front() + y.back();
    for (std::int64_t q = 1; q < panels; ++q) simpson += ((q % 2) ? 4.0L : 2.0L) * y[static_cast<std::size_t>(q)];
    // Eight-point one-sided differences at the left end (forward, y[0..7]; the weights solve
    // the Vandermonde system of the points 0..7 for the k-th derivative at 0); at the right
    // end the same stencil on y[P], y[P-1], ... gives the odd derivatives with flipped sign.
    const std::size_t P = static_cast<std::size_t>(panels);
    auto stencil = [&](const long double c[8], bool right) {
      Sums r;
      for (std::size_t k = 0; k < 8; ++k) r += c[k] * (right ? y[P - k] : y[k]);
      return right ? (-1.0L) * r : r;
    };
    static constexpr long double kD1[8] = {-363.0L / 140.0L, 7.0L,         -21.0L / 2.0L, 35.0L / 3.0L,
                                           -35.0L / 4.0L,    21.0L / 5.0L, -7.0L / 6.0L,  1.0L / 7.0L};
    static constexpr long double kD3[8] = {-967.0L / 120.0L, 638.0L / 15.0L, -3929.0L / 40.0L,  389.0L / 3.0L,
                                           -2545.0L / 24.0L, 268.0L / 5.0L,  -1849.0L / 120.0L, 29.0L / 15.0L};
    static constexpr long double kD5[8] = {-23.0L / 3.0L,  295.0L / 6.0L, -135.0L,       1235.0L / 6.0L,
                                           -565.0L / 3.0L, 207.0L / 2.0L, -95.0L / 3.0L, 25.0L / 6.0L};
    const long double h2 = h * h, h4 = h2 * h2;
    const Sums d1_diff = (1.0L / h) * (stencil(kD1, true) + (-1.0L) * stencil(kD1, false));
    const Sums d3_diff = (1.0L / (h2 * h)) * (stencil(kD3, true) + (-1.0L) * stencil(kD3, false));
    const Sums d5_diff = (1.0L / (h4 * h)) * (stencil(kD5, true) + (-1.0L) * stencil(kD5, false));
    const long double c3 = -h4 / 180.0L - 1.0L / 720.0L;
    const long double c5 = h4 * h2 / 1512.0L + 1.0L / 30240.0L;
    total +=
        (h / 3.0L) * simpson + 0.5L * (y.front() + y.back()) + (1.0L / 12.0L) * d1_diff + c3 * d3_diff + c5 * d5_diff;
    if (B == v) return total;
    u = B + 1;
    max_step = std::min(max_step, static_cast<double>(v - u) / static_cast<double>(kMinPanels));
  }
}

}  // namespace

// Cov(nuhat) of levels first..first + levels - 1 (tau = 2^first samples first).
static Eigen::MatrixXd covariance_of_levels(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int first,
                                            int levels) {
  check_at_least("model_wv_covariance", "n", static_cast<double>(n), 2.0);
  check_at_least("model_wv_covariance", "levels", levels, 1.0);
  check_at_least("model_wv_covariance", "first level", first, 1.0);
  std::vector<Level> lv;
  for (int j = first; j < first + levels; ++j) {
    const std::int64_t tau = std::int64_t{1} << j;
    check_at_least("model_wv_covariance", "coefficients at the last level", static_cast<double>(n - tau + 1), 1.0);
    lv.push_back({tau, tau / 2, n - tau + 1});
  }
  const std::int64_t max_lag = 3 * n + 4;
  std::vector<double> taus(static_cast<std::size_t>(levels));
  for (int j = 0; j < levels; ++j)
    taus[static_cast<std::size_t>(j)] = static_cast<double>(lv[static_cast<std::size_t>(j)].tau);
  std::vector<std::vector<double>> parts;
  std::vector<double> total(static_cast<std::size_t>(levels), 0.0);
  std::vector<int> candidates;
  for (int c = 0; c < model.num_components(); ++c) {
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    if (p.deterministic()) continue;
    std::vector<double> part(static_cast<std::size_t>(levels));
    p.wv({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, taus, part);
    for (int j = 0; j < levels; ++j) total[static_cast<std::size_t>(j)] += std::abs(part[static_cast<std::size_t>(j)]);
    candidates.push_back(c);
    parts.push_back(std::move(part));
  }
  std::vector<int> stochastic;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    bool visible = false;
    for (int j = 0; j < levels && !visible; ++j)
      visible =
          !(std::abs(parts[k][static_cast<std::size_t>(j)]) < kNegligibleShare * total[static_cast<std::size_t>(j)]);
    if (visible) stochastic.push_back(candidates[k]);
  }
  // The deterministic components' Haar coefficient at each level (constant in time).
  std::vector<long double> det(static_cast<std::size_t>(levels), 0.0L);
  for (int c = 0; c < model.num_components(); ++c) {
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    if (!p.deterministic()) continue;
    const std::span<const double> th{theta.data() + model.offset(c), static_cast<std::size_t>(p.size())};
    for (int j = 0; j < levels; ++j)
      det[static_cast<std::size_t>(j)] +=
          p.deterministic_coefficient(th, static_cast<double>(lv[static_cast<std::size_t>(j)].tau));
  }
  bool deterministic = false;
  for (const long double d : det) deterministic = deterministic || d != 0.0L;
  std::vector<ComponentTable> tables(stochastic.size());
  gmwm::parallel_for(std::size_t{0}, stochastic.size(), [&](std::size_t k) {
    const int c = stochastic[k];
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    tables[k] = make_table(p, {theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, max_lag);
  });
  const CombinedTable combined(tables);
  const int J = levels;
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(J, J);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < J; ++i)
    for (int j = i; j < J; ++j) pairs.emplace_back(i, j);
  gmwm::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t idx) {
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
    // -1/2 / (tau_a tau_b), a power of two: multiplying by it is dividing, exactly.
    const long double scale = -0.5L / (static_cast<long double>(a.tau) * static_cast<long double>(b.tau));
    auto f = [&](std::int64_t h) -> Sums {
      const long double c = cross_cov(combined, a, b, h, scale);
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
        if (t.support > kPolynomialSupport) {
          cuts.push_back(c - t.support);
          cuts.push_back(c + t.support + 1);
        }
    }
    for (const auto& t : tables) {
      cuts.push_back(-(a.tau + t.support));
      cuts.push_back(b.tau + t.support + 1);
    }
    pts.insert(pts.end(), cuts.begin(), cuts.end());
    pts.erase(std::remove_if(pts.begin(), pts.end(), [&](std::int64_t x) { return x < h_lo || x > h_hi + 1; }),
              pts.end());
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
    // Every stretch polynomial of degree <= 7: no component of long support and no slow
    // geometric tail (an AR1 decaying by e or more a lag is within the margin of exact
    // lags), so the rule is exact on kMinPanels panels (the polynomial models' rows: 0.72
    // of their time; against the lag-by-lag sum at N = 1e6, 19 levels: WN + RW, RW, QN,
    // QN + RW, MA1 + WN, AR1(0.16) + RW within 2.0e-12, AR1(0.36) + WN + QN + RW 1.3e-11
    // (the 24-panel rule: 2.7e-12); issue 44). With a deterministic
    // component the linear sum is used too, which cancels (QN + DR); those keep the
    // finer rule.
    bool polynomial = !oscillating && !deterministic;
    for (const auto& t : tables)
      polynomial = polynomial && t.support <= kPolynomialSupport && (t.C == 0.0L || t.log_rho < -1.0);
    Sums sum;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const std::int64_t u = pts[k], v = pts[k + 1] - 1;  // stretch [u, v]
      if (oscillating) {
        for (std::int64_t h = u; h <= v; ++h) sum += f(h);
        continue;
      }
      const double len = static_cast<double>(v - u);
      const double per_stretch = polynomial ? static_cast<double>(kMinPanels) : kSimpsonPointsPerStretch;
      const double max_step = std::min(len / per_stretch, smoothness(u, v) / kPointsPerDecayScale);
      sum += sum_smooth(f, u, v, max_step);
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

Eigen::MatrixXd model_wv_covariance(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int levels) {
  return covariance_of_levels(model, theta, n, 1, levels);
}

Eigen::MatrixXd bootstrap_wv_covariance(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int levels,
                                        int replicates, std::uint64_t seed, const WvEstimator& estimator, double alpha,
                                        const std::function<void(int, int)>& progress) {
  check_at_least("bootstrap_wv_covariance", "replicates", replicates, 2.0);
  Eigen::MatrixXd W(replicates, levels);
  std::atomic<int> done{0};
  gmwm::parallel_for(0, replicates, [&](int r) {
    const auto x = simulate(model, theta, n, seed, static_cast<std::uint64_t>(r));
    const WaveletVariance w = estimator.compute(x.data(), n, levels, alpha);
    for (int j = 0; j < levels; ++j) W(r, j) = w.wv[static_cast<std::size_t>(j)];
    const int d = ++done;
    if (progress) progress(d, replicates);
  });
  const Eigen::RowVectorXd mean = W.colwise().mean();
  const Eigen::MatrixXd centred = W.rowwise() - mean;
  return centred.transpose() * centred / static_cast<double>(replicates - 1);
}

Eigen::MatrixXd model_wv_covariance(const Model& model, const Eigen::VectorXd& theta, const WaveletVariance& wv) {
  // A WV that drop_fine_levels cut starts above level 1: its block of the covariance.
  Eigen::MatrixXd v = covariance_of_levels(model, theta, wv.n, first_level(wv), wv.levels());
  const auto J = static_cast<Eigen::Index>(wv.levels());
  if (static_cast<Eigen::Index>(wv.coefficients.size()) != J) return v;
  // The share of each level's windows read (1 without gaps): complete ones, or at long
  // levels the near-complete ones the gappy WV read there (counted alike).
  Eigen::VectorXd kept(J);
  bool gaps = false;
  for (Eigen::Index j = 0; j < J; ++j) {
    const double all = static_cast<double>(wv.n) - wv.tau[static_cast<std::size_t>(j)] + 1.0;
    const double complete = static_cast<double>(wv.coefficients[static_cast<std::size_t>(j)]);
    kept(j) = all > 0.0 && complete > 0.0 ? std::min(complete / all, 1.0) : 1.0;
    gaps = gaps || kept(j) < 1.0;
  }
  if (!gaps) return v;
  for (Eigen::Index i = 0; i < J; ++i)
    for (Eigen::Index j = 0; j < J; ++j) v(i, j) *= std::min(kept(i), kept(j)) / (kept(i) * kept(j));
  return v;
}

Eigen::MatrixXd wv_covariance_at(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta) {
  if (wv.covariance) return *wv.covariance;
  return model_wv_covariance(model, theta, wv) / wv.efficiency.value_or(1.0);
}

}  // namespace gmwm
