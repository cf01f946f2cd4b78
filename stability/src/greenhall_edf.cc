// Greenhall and Riley's equivalent degrees of freedom of the difference variances
// (confidence.h): C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances based
// on finite differences", Proc. 35th PTTI Meeting (2003), equations (7)-(13) and Tables 1-3.
// The variance's estimator averages M squared filter outputs z_n (the phase filtered by a
// d-th difference of span m, its averaging F, its stride m / S); 1 / edf is the variance of
// that mean over its square, a sum of the squared normalised autocovariances of z (the
// "basic sum"), in closed form for large M (the tables) and truncated at J_max terms.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/stability/confidence.h"

namespace gmwm::stability {
namespace {

// The basic sum is summed term by term up to this many lags; beyond, the tables' asymptotic
// forms (Greenhall and Riley 2003, section 4: "J_max = 100").
constexpr double kJmax = 100.0;

// Table 1: modified variances (F = 1), 1 / edf ~ (a0 - a1 / r) / r for r > d + 1; rows alpha
// = 2 .. -4, columns d = 1, 2, 3 (NaN: alpha + 2d <= 1, no such variance).
constexpr double kNo = std::numeric_limits<double>::quiet_NaN();
struct A01 {
  double a0, a1;
};
constexpr std::array<std::array<A01, 3>, 7> kTable1 = {{
    {{{2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}, {22.0 / 25.0, 2.0 / 3.0}}},
    {{{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}}},
    {{{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}}},
    {{{kNo, kNo}, {1.048, 0.534}, {1.180, 0.816}}},
    {{{kNo, kNo}, {1.302, 0.535}, {1.175, 0.777}}},
    {{{kNo, kNo}, {kNo, kNo}, {1.194, 0.703}}},
    {{{kNo, kNo}, {kNo, kNo}, {1.489, 0.702}}},
}};
// Table 2: unmodified variances (F = m), the same form; alpha = 2 .. -4.
constexpr std::array<std::array<A01, 3>, 7> kTable2 = {{
    {{{3.0 / 2.0, 1.0 / 2.0}, {35.0 / 18.0, 1.0}, {231.0 / 100.0, 3.0 / 2.0}}},
    {{{78.6, 25.2}, {790.0, 410.0}, {9950.0, 6520.0}}},
    {{{2.0 / 3.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}}},
    {{{kNo, kNo}, {0.852, 0.375}, {0.997, 0.617}}},
    {{{kNo, kNo}, {1.079, 0.368}, {1.033, 0.607}}},
    {{{kNo, kNo}, {kNo, kNo}, {1.053, 0.553}}},
    {{{kNo, kNo}, {kNo, kNo}, {1.302, 0.535}}},
}};
// Table 3: the flicker-PM (alpha = 1) unmodified variances' normaliser sz(0) ~ b0 + b1 ln m.
constexpr std::array<A01, 3> kTable3 = {{{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}}};

A01 table(const std::array<std::array<A01, 3>, 7>& t, int alpha, int d) {
  return t[static_cast<std::size_t>(2 - alpha)][static_cast<std::size_t>(d - 1)];
}

// Equation (7): the generalised autocovariance of the phase's power law, up to a constant.
double sw(double t, int alpha) {
  const double a = std::abs(t);
  const double log_term = a == 0.0 ? 0.0 : std::log(a);
  switch (alpha) {
    case 2:
      return -a;
    case 1:
      return t * t * log_term;
    case 0:
      return a * a * a;
    case -1:
      return std::pow(t, 4) * log_term;
    case -2:
      return std::pow(a, 5);
    case -3:
      return std::pow(t, 6) * log_term;
    default:  // -4
      return std::pow(a, 7);
  }
}

// Equation (8): after the averaging filter of factor F (F infinite: the limit, sw of alpha + 2).
double sx(double t, double f, int alpha) {
  if (std::isinf(f)) return sw(t, alpha + 2);
  return f * f * (2.0 * sw(t, alpha) - sw(t - 1.0 / f, alpha) - sw(t + 1.0 / f, alpha));
}

// Equation (9): after the d-th difference, binomial weights (-1)^k C(2d, d + k), |k| <= d.
double sz(double t, double f, int alpha, int d) {
  static constexpr std::array<std::array<double, 4>, 3> kWeights = {
      {{2.0, -1.0, 0.0, 0.0}, {6.0, -4.0, 1.0, 0.0}, {20.0, -15.0, 6.0, -1.0}}};
  const auto& w = kWeights[static_cast<std::size_t>(d - 1)];
  double s = w[0] * sx(t, f, alpha);
  for (int k = 1; k <= d; ++k) s += w[static_cast<std::size_t>(k)] * (sx(t - k, f, alpha) + sx(t + k, f, alpha));
  return s;
}

// Equation (10): the basic sum of J lags of M terms at stride S.
double basic_sum(double j_lags, double big_m, double s, double f, int alpha, int d) {
  const double z0 = sz(0.0, f, alpha, d);
  const double zj = sz(j_lags / s, f, alpha, d);
  double sum = z0 * z0 + (1.0 - j_lags / big_m) * zj * zj;
  for (int j = 1; j < static_cast<int>(j_lags); ++j) {
    const double z = sz(j / s, f, alpha, d);
    sum += 2.0 * (1.0 - j / big_m) * z * z;
  }
  return sum;
}

// 1 / edf from the basic sum (equation 11), with the normaliser sz(0) given.
double from_sum(double norm, double j_lags, double big_m, double s, double f, int alpha, int d) {
  return basic_sum(j_lags, big_m, s, f, alpha, d) / (norm * norm * big_m);
}

struct Design {
  int alpha, d;
  double m, f, s, big_m, j_lags, r;
};

// Case 1: modified variances (F = 1), any alpha.
double modified_case(const Design& g) {
  if (g.j_lags <= kJmax) return from_sum(sz(0.0, 1.0, g.alpha, g.d), g.j_lags, g.big_m, g.s, 1.0, g.alpha, g.d);
  if (g.r > g.d + 1) {
    const A01 a = table(kTable1, g.alpha, g.d);
    return (a.a0 - a.a1 / g.r) / g.r;
  }
  return from_sum(sz(0.0, 1.0, g.alpha, g.d), kJmax, kJmax, kJmax / g.r, 1.0, g.alpha, g.d);
}

// Case 2: unmodified variances, alpha <= 0 (F = m, or its limit once m (d + 1) > J_max).
double unmodified_fm_case(const Design& g) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (g.j_lags <= kJmax) {
    const double f = g.m * (g.d + 1) <= kJmax ? g.m : kInf;
    return from_sum(sz(0.0, f, g.alpha, g.d), g.j_lags, g.big_m, g.s, f, g.alpha, g.d);
  }
  if (g.r > g.d + 1) {
    const A01 a = table(kTable2, g.alpha, g.d);
    return (a.a0 - a.a1 / g.r) / g.r;
  }
  return from_sum(sz(0.0, kInf, g.alpha, g.d), kJmax, kJmax, kJmax / g.r, kInf, g.alpha, g.d);
}

// Case 3: unmodified variances, flicker PM (the normaliser grows with ln m: Table 3).
double unmodified_flicker_pm_case(const Design& g) {
  if (g.j_lags <= kJmax) return from_sum(sz(0.0, g.m, 1, g.d), g.j_lags, g.big_m, g.s, g.m, 1, g.d);
  const A01 b = kTable3[static_cast<std::size_t>(g.d - 1)];
  const double norm = b.a0 + b.a1 * std::log(g.m);
  if (g.r > g.d + 1) {
    const A01 a = table(kTable2, 1, g.d);
    return (a.a0 - a.a1 / g.r) / (norm * norm * g.r);
  }
  const double mp = kJmax / g.r;
  return basic_sum(kJmax, kJmax, mp, mp, 1, g.d) / (norm * norm * kJmax);
}

// Case 4: unmodified variances, white PM: z_n and z_{n + lS} share phase points only at the
// d lags l = 1 .. d, correlated by rho_l = C(2d, d + l) / C(2d, d); lags l >= r have no pair
// (r = M / S), so 1 / edf = (1 + 2 sum_{l < r, l <= d} (1 - l / r) rho_l^2) / M. For r > d it
// is Greenhall and Riley's (a0 - a1 / r) / M, a0 = C(4d, 2d) / C(2d, d)^2, a1 = d / 2.
double unmodified_white_pm_case(const Design& g) {
  static constexpr std::array<std::array<double, 3>, 3> kRho = {
      {{1.0 / 2.0, 0.0, 0.0}, {4.0 / 6.0, 1.0 / 6.0, 0.0}, {15.0 / 20.0, 6.0 / 20.0, 1.0 / 20.0}}};
  double sum = 1.0;
  for (int l = 1; l <= g.d && l < g.r; ++l) {
    const double rho = kRho[static_cast<std::size_t>(g.d - 1)][static_cast<std::size_t>(l - 1)];
    sum += 2.0 * (1.0 - l / g.r) * rho * rho;
  }
  return sum / g.big_m;
}

}  // namespace

double greenhall_edf(int alpha, int d, std::int64_t m, std::int64_t phase_points, std::int64_t filter,
                     std::int64_t stride) {
  if (d < 1 || d > 3) throw InputError("greenhall_edf: d = " + std::to_string(d) + ", expected 1, 2 or 3");
  if (m < 1) throw InputError("greenhall_edf: m = " + std::to_string(m) + ", expected at least 1");
  if ((filter != 1 && filter != m) || (stride != 1 && stride != m))
    throw InputError("greenhall_edf: F = " + std::to_string(filter) + ", S = " + std::to_string(stride) +
                     ", expected each 1 or m = " + std::to_string(m));
  const bool modified = filter == 1 && m > 1;
  const double mm = static_cast<double>(m), s = static_cast<double>(stride);
  const double span = (modified ? mm : 1.0) + mm * d;  // L = m / F + m d
  if (static_cast<double>(phase_points) < span)
    throw InputError("greenhall_edf: " + std::to_string(phase_points) + " phase points, expected at least " +
                     std::to_string(static_cast<std::int64_t>(span)));
  Design g{};
  g.alpha = std::clamp(alpha, 2 - 2 * d, 2);
  g.d = d;
  g.m = mm;
  g.f = static_cast<double>(filter);
  g.s = s;
  g.big_m = 1.0 + std::floor(s * (static_cast<double>(phase_points) - span) / mm);
  g.j_lags = std::min(g.big_m, (d + 1) * s);
  g.r = g.big_m / s;
  double inverse = 0.0;
  if (modified)
    inverse = modified_case(g);
  else if (g.alpha <= 0)
    inverse = unmodified_fm_case(g);
  else if (g.alpha == 1)
    inverse = unmodified_flicker_pm_case(g);
  else
    inverse = unmodified_white_pm_case(g);
  return 1.0 / inverse;
}

}  // namespace gmwm::stability
