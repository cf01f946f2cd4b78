// Special functions of ar1_math.h: value, first and second derivative, each computed
// without cancellation (power series near 0, closed expressions elsewhere).
#include "ar1_math.h"

#include <array>
#include <cmath>

#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/cos_pi.hpp>

namespace gmwm::internal {
namespace {

// Series lengths: for |x| <= 1 everything omitted (the whole tail, in absolute value) is
// below 2e-17 of each sum: the value, its first and its second derivative (at x = 1, the
// worst case; computed term by term). Double precision keeps 1.1e-16 of a sum, so the
// longer series once used (34, 31, 29, 26 terms, 1e-20 of the value alone) only added
// terms below its rounding, and these functions are a tenth of a selection's CPU.
constexpr int kSinhcTerms = 19;
constexpr int kS3Terms = 19;
constexpr int kHTerms = 25;
constexpr int kE1Terms = 21;

// exp(-y) for y beyond this is exactly 0 in doubles (below half the smallest subnormal,
// 2^-1075 = e^-745.13; IEEE 754 binary64): taken as 0 without the call, whose underflow
// path (errno, the exception flags) cost 2.3% of a selection's CPU at the coarse levels,
// where y = m L reaches 1e5 (issue 44). The same value either way.
constexpr double kExpUnderflowArg = 746.0;
double exp_of_minus(double y) { return y > kExpUnderflowArg ? 0.0 : std::exp(-y); }

// cos(pi m) with m reduced exactly (Boost.Math), in double (sinusoid.cc: no long double).
using CosPolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;

double factorial(int n) {
  double f = 1.0;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

// p(x) = sum_k c_k x^k with p' and p'' by Horner's scheme.
template <std::size_t K>
D2 power_series(const std::array<double, K>& c, double x) {
  double f = 0.0, f1 = 0.0, f2 = 0.0;
  for (std::size_t i = K; i-- > 0;) {
    f2 = f2 * x + f1;
    f1 = f1 * x + f;
    f = f * x + c[i];
  }
  return {f, f1, 2.0 * f2};
}

const std::array<double, kSinhcTerms>& sinhc_coefficients() {
  static const auto c = [] {
    std::array<double, kSinhcTerms> a{};
    for (int k = 0; k < kSinhcTerms; k += 2) a[static_cast<std::size_t>(k)] = 1.0 / factorial(k + 1);
    return a;
  }();
  return c;
}

const std::array<double, kS3Terms>& s3_coefficients() {
  static const auto c = [] {
    std::array<double, kS3Terms> a{};
    for (int k = 0; k < kS3Terms; k += 2) a[static_cast<std::size_t>(k)] = 1.0 / factorial(k + 3);
    return a;
  }();
  return c;
}

// h(y)/y^3 = sum_j (-1)^j (2^(j+4) - 8) y^j / (j+3)!  (from the exponential series of
// 4y - 6 + 8 e^-y - 2 e^-2y, whose terms of degree 0, 1, 2 vanish).
const std::array<double, kHTerms>& h_coefficients() {
  static const auto c = [] {
    std::array<double, kHTerms> a{};
    for (int j = 0; j < kHTerms; ++j)
      a[static_cast<std::size_t>(j)] = ((j % 2) ? -1.0 : 1.0) * (std::ldexp(1.0, j + 4) - 8.0) / factorial(j + 3);
    return a;
  }();
  return c;
}

// (1 - e^-y)/y = sum_k (-1)^k y^k / (k+1)!.
const std::array<double, kE1Terms>& e1_coefficients() {
  static const auto c = [] {
    std::array<double, kE1Terms> a{};
    for (int k = 0; k < kE1Terms; ++k) a[static_cast<std::size_t>(k)] = ((k % 2) ? -1.0 : 1.0) / factorial(k + 1);
    return a;
  }();
  return c;
}

}  // namespace

D2 sinhc_d2(double x) {
  if (std::fabs(x) <= kSeriesMaxArg) return power_series(sinhc_coefficients(), x);
  const double s = std::sinh(x), c = std::cosh(x);
  return {s / x, (x * c - s) / (x * x), (x * x * s - 2.0 * x * c + 2.0 * s) / (x * x * x)};
}

D2 sinh_minus_x_over_x3_d2(double x) {
  if (std::fabs(x) <= kSeriesMaxArg) return power_series(s3_coefficients(), x);
  const double s = std::sinh(x) - x, c = std::cosh(x) - 1.0, x2 = x * x, x3 = x2 * x;
  return {s / x3, c / x3 - 3.0 * s / (x3 * x), (s + x) / x3 - 6.0 * c / (x3 * x) + 12.0 * s / (x3 * x2)};
}

D2 haar_h_over_y3_d2(double y) {
  if (y <= kSeriesMaxArg) return power_series(h_coefficients(), y);
  // h = 4(y - u) - 2u^2, h' = 4u^2, h'' = 8 e^-y u, with u = 1 - e^-y (no cancellation
  // for y >= 1 beyond a factor 2 in h). u as 1 - e^-y: e^-y <= 1/e here, so the subtraction
  // keeps full precision and saves an expm1 (a tenth of a selection's CPU is this function).
  const double em = exp_of_minus(y), u = 1.0 - em;
  const double h = 4.0 * (y - u) - 2.0 * u * u, h1 = 4.0 * u * u, h2 = 8.0 * em * u;
  const double y3 = y * y * y;
  return {h / y3, h1 / y3 - 3.0 * h / (y3 * y), h2 / y3 - 6.0 * h1 / (y3 * y) + 12.0 * h / (y3 * y * y)};
}

D2 one_minus_exp_over_y_d2(double y) {
  if (y <= kSeriesMaxArg) return power_series(e1_coefficients(), y);
  const double em = exp_of_minus(y), u = 1.0 - em;  // e^-y <= 1/e: no cancellation
  return {u / y, em / y - u / (y * y), -em / y - 2.0 * em / (y * y) + 2.0 * u / (y * y * y)};
}

D2 neg_log_d2(double phi) {
  // phi - 1 is exact for phi >= 0.5 (Sterbenz), so log1p keeps full relative accuracy
  // of L = -log(phi) as phi -> 1.
  return {-std::log1p(phi - 1.0), -1.0 / phi, 1.0 / (phi * phi)};
}

D2 one_minus_pow_d2(double phi, double m) {
  // One logarithm and one exponential: p = phi^m (signed), and the derivatives -m phi^(m-1)
  // and -m (m - 1) phi^(m-2) as p / phi and p / phi^2 (two pow calls each cost about an
  // exponential and a logarithm; this function was 9% of a selection's CPU, issue 44).
  if (phi == 0.0) return {1.0, m == 1.0 ? -1.0 : 0.0, m == 2.0 ? -2.0 : 0.0};
  const double a = std::fabs(phi);
  const bool even = phi < 0.0 && std::fmod(m, 2.0) == 0.0;  // the parity matters only then
  const double lm = m * std::log(a);
  // |phi|^m and 1 - |phi|^m from one exponential: exp when |phi|^m <= 1/2 (then 1 - it
  // keeps full precision), expm1 when above (then 1 + it does).
  const bool small = lm <= -kLn2;
  const double e = small ? exp_of_minus(-lm) : std::expm1(lm);
  const double am = small ? e : 1.0 + e;  // |phi|^m
  if (phi < 0.0 && m != std::floor(m)) {
    // Between whole m a negative phi's power is continued as |phi|^m cos(pi m), the real part of
    // the principal |phi|^m e^{i pi m}, and the closed forms, written in a = phi^m, take it
    // (docs/statistics.md section 3): smooth, and +-|phi|^m at every whole m. d/dphi of
    // |phi|^m cos(pi m) is m p / phi, as for a whole m.
    const double p = am * boost::math::cos_pi(m, CosPolicy());
    return {1.0 - p, -m * (p / phi), -m * (m - 1.0) * (p / (phi * phi))};
  }
  const double p = (phi > 0.0 || even) ? am : -am;  // phi^m
  // 1 - |phi|^m without cancellation; an odd power of a negative phi adds.
  const double f = (phi > 0.0 || even) ? (small ? 1.0 - e : -e) : 1.0 + am;
  const double f1 = -m * (p / phi);
  const double f2 = (m == 1.0) ? 0.0 : -m * (m - 1.0) * (p / (phi * phi));
  return {f, f1, f2};
}

}  // namespace gmwm::internal
