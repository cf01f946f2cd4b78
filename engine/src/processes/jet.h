#pragma once
// Second-order forward-mode differentiation for the processes' closed forms.
//
// A Jet<N> carries a value together with its gradient and Hessian with respect to N
// variables; arithmetic propagates them exactly (chain and product rules), so derivatives
// computed through a Jet are the analytic derivatives of the very expression used for
// the value: no step size, no truncation error, and the same numerical stability as the
// value when the expression is written in a stable form (see ar1_math.h).
//
// Formulas are written once as templates over the scalar type T (double or Jet<N>).
// Special functions with their own stable series are "lifted" from a D2 triple
// (f, f', f'') evaluated at the value.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

namespace gmwm::internal {

/// A function value with its first and second derivatives at one point.
struct D2 {
  double f;
  double f1;
  double f2;
};

// The arithmetic below is always inlined: as calls, Jet<2>'s products and quotients (seven
// doubles each) were 13% of a fit's CPU, in call overhead and copies (issue 44). The same
// operations in the same order either way.
/// No Hessian: a Jet of order 1 carries none (zero bytes in the Jet).
struct NoHessian {};

/// Order 2: value, gradient and Hessian; order 1: value and gradient only, for callers that
/// want no Hessian (an optimiser's gradient: Process::derivatives with hess == nullptr).
/// The gradient is formed by the same operations in the same order either way, so it is
/// the same to the bit (JetTest.GivesTheSameGradientWithOrWithoutTheHessian).
template <int N, int Order = 2>
struct Jet {
  static_assert(Order == 1 || Order == 2, "a Jet carries first or first and second derivatives");
  static constexpr bool kHessian = Order == 2;
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = std::conditional_t<kHessian, Eigen::Matrix<double, N, N>, NoHessian>;
  double v = 0.0;
  Vec g = Vec::Zero();
  [[no_unique_address]] Mat h = zero_hessian();

  Jet() = default;
  Jet(double value) : v(value) {}  // NOLINT: constants convert implicitly
  /// The i-th independent variable at `value`.
  static Jet variable(double value, int i) {
    Jet j(value);
    j.g(i) = 1.0;
    return j;
  }

 private:
  static Mat zero_hessian() {
    if constexpr (kHessian)
      return Mat::Zero();
    else
      return {};
  }
};

inline double value(double x) { return x; }
template <int N, int O>
double value(const Jet<N, O>& x) {
  return x.v;
}

/// f(x) given f, f', f'' at x.v.
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> chain(const Jet<N, O>& x, double f, double f1, double f2) {
  Jet<N, O> r;
  r.v = f;
  r.g = f1 * x.g;
  if constexpr (O == 2) r.h = f1 * x.h + f2 * x.g * x.g.transpose();
  return r;
}
inline double lift(double, const D2& d) { return d.f; }
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> lift(const Jet<N, O>& x, const D2& d) {
  return chain(x, d.f, d.f1, d.f2);
}

template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator-(const Jet<N, O>& a) {
  Jet<N, O> r;
  r.v = -a.v;
  r.g = -a.g;
  if constexpr (O == 2) r.h = -a.h;
  return r;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator+(const Jet<N, O>& a, const Jet<N, O>& b) {
  Jet<N, O> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  if constexpr (O == 2) r.h = a.h + b.h;
  return r;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator-(const Jet<N, O>& a, const Jet<N, O>& b) {
  return a + (-b);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator*(const Jet<N, O>& a, const Jet<N, O>& b) {
  Jet<N, O> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  if constexpr (O == 2) r.h = a.v * b.h + b.v * a.h + a.g * b.g.transpose() + b.g * a.g.transpose();
  return r;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator/(const Jet<N, O>& a, const Jet<N, O>& b) {
  // q = a / b  =>  a = q b, differentiated twice and solved for q', q''.
  Jet<N, O> q;
  q.v = a.v / b.v;
  q.g = (a.g - q.v * b.g) / b.v;
  if constexpr (O == 2) q.h = (a.h - q.v * b.h - q.g * b.g.transpose() - b.g * q.g.transpose()) / b.v;
  return q;
}

// Mixed Jet/double arithmetic.
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator+(const Jet<N, O>& a, double b) {
  Jet<N, O> r = a;
  r.v += b;
  return r;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator+(double a, const Jet<N, O>& b) {
  return b + a;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator-(const Jet<N, O>& a, double b) {
  return a + (-b);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator-(double a, const Jet<N, O>& b) {
  return (-b) + a;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator*(const Jet<N, O>& a, double b) {
  Jet<N, O> r;
  r.v = a.v * b;
  r.g = a.g * b;
  if constexpr (O == 2) r.h = a.h * b;
  return r;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator*(double a, const Jet<N, O>& b) {
  return b * a;
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator/(const Jet<N, O>& a, double b) {
  return a * (1.0 / b);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> operator/(double a, const Jet<N, O>& b) {
  return Jet<N, O>(a) / b;
}

// Elementary functions (found by argument-dependent lookup next to std:: ones).
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> exp(const Jet<N, O>& x) {
  const double e = std::exp(x.v);
  return chain(x, e, e, e);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> expm1(const Jet<N, O>& x) {
  const double e = std::exp(x.v);
  return chain(x, std::expm1(x.v), e, e);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> log(const Jet<N, O>& x) {
  return chain(x, std::log(x.v), 1.0 / x.v, -1.0 / (x.v * x.v));
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> log1p(const Jet<N, O>& x) {
  const double d = 1.0 / (1.0 + x.v);
  return chain(x, std::log1p(x.v), d, -d * d);
}
template <int N, int O>
[[gnu::always_inline]] inline Jet<N, O> sqrt(const Jet<N, O>& x) {
  const double s = std::sqrt(x.v);
  return chain(x, s, 0.5 / s, -0.25 / (s * x.v));
}

}  // namespace gmwm::internal
