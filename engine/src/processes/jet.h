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
template <int N>
struct Jet {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  double v = 0.0;
  Vec g = Vec::Zero();
  Mat h = Mat::Zero();

  Jet() = default;
  Jet(double value) : v(value) {}  // NOLINT: constants convert implicitly
  /// The i-th independent variable at `value`.
  static Jet variable(double value, int i) {
    Jet j(value);
    j.g(i) = 1.0;
    return j;
  }
};

inline double value(double x) { return x; }
template <int N>
double value(const Jet<N>& x) {
  return x.v;
}

/// f(x) given f, f', f'' at x.v.
template <int N>
[[gnu::always_inline]] inline Jet<N> chain(const Jet<N>& x, double f, double f1, double f2) {
  Jet<N> r;
  r.v = f;
  r.g = f1 * x.g;
  r.h = f1 * x.h + f2 * x.g * x.g.transpose();
  return r;
}
inline double lift(double, const D2& d) { return d.f; }
template <int N>
[[gnu::always_inline]] inline Jet<N> lift(const Jet<N>& x, const D2& d) {
  return chain(x, d.f, d.f1, d.f2);
}

template <int N>
[[gnu::always_inline]] inline Jet<N> operator-(const Jet<N>& a) {
  Jet<N> r;
  r.v = -a.v;
  r.g = -a.g;
  r.h = -a.h;
  return r;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator+(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator-(const Jet<N>& a, const Jet<N>& b) {
  return a + (-b);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator*(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  r.h = a.v * b.h + b.v * a.h + a.g * b.g.transpose() + b.g * a.g.transpose();
  return r;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator/(const Jet<N>& a, const Jet<N>& b) {
  // q = a / b  =>  a = q b, differentiated twice and solved for q', q''.
  Jet<N> q;
  q.v = a.v / b.v;
  q.g = (a.g - q.v * b.g) / b.v;
  q.h = (a.h - q.v * b.h - q.g * b.g.transpose() - b.g * q.g.transpose()) / b.v;
  return q;
}

// Mixed Jet/double arithmetic.
template <int N>
[[gnu::always_inline]] inline Jet<N> operator+(const Jet<N>& a, double b) {
  Jet<N> r = a;
  r.v += b;
  return r;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator+(double a, const Jet<N>& b) {
  return b + a;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator-(const Jet<N>& a, double b) {
  return a + (-b);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator-(double a, const Jet<N>& b) {
  return (-b) + a;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator*(const Jet<N>& a, double b) {
  Jet<N> r;
  r.v = a.v * b;
  r.g = a.g * b;
  r.h = a.h * b;
  return r;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator*(double a, const Jet<N>& b) {
  return b * a;
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator/(const Jet<N>& a, double b) {
  return a * (1.0 / b);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> operator/(double a, const Jet<N>& b) {
  return Jet<N>(a) / b;
}

// Elementary functions (found by argument-dependent lookup next to std:: ones).
template <int N>
[[gnu::always_inline]] inline Jet<N> exp(const Jet<N>& x) {
  const double e = std::exp(x.v);
  return chain(x, e, e, e);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> expm1(const Jet<N>& x) {
  const double e = std::exp(x.v);
  return chain(x, std::expm1(x.v), e, e);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> log(const Jet<N>& x) {
  return chain(x, std::log(x.v), 1.0 / x.v, -1.0 / (x.v * x.v));
}
template <int N>
[[gnu::always_inline]] inline Jet<N> log1p(const Jet<N>& x) {
  const double d = 1.0 / (1.0 + x.v);
  return chain(x, std::log1p(x.v), d, -d * d);
}
template <int N>
[[gnu::always_inline]] inline Jet<N> sqrt(const Jet<N>& x) {
  const double s = std::sqrt(x.v);
  return chain(x, s, 0.5 / s, -0.25 / (s * x.v));
}

}  // namespace gmwm::internal
