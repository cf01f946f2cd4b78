#include "high_precision_reference.h"

#include <boost/math/differentiation/autodiff.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

namespace gmwm::test {
namespace {

using Real = boost::multiprecision::cpp_bin_float_100;
using boost::math::differentiation::make_fvar;
using Var = boost::math::differentiation::detail::fvar<Real, 2>;

// x^(2^k) by repeated squaring (exact for negative x too).
Var pow_two_to(Var x, int k) {
  for (int i = 0; i < k; ++i) x = x * x;
  return x;
}

// (phi^2 - 1) tau + 2 phi (phi^tau - 4 phi^(tau/2) + 3) over (phi - 1)^3 (phi + 1) tau^2.
Var ar1_closed_form(const Var& phi, int j) {
  const Real tau = boost::multiprecision::ldexp(Real(1), j);
  const Var a = pow_two_to(phi, j - 1), b = pow_two_to(phi, j);
  const Var num = (phi * phi - 1) * tau + 2 * phi * (b - 4 * a + 3);
  const Var d = phi - 1;
  return num / (d * d * d * (phi + 1) * tau * tau);
}

Var arma11_closed_form(const Var& phi, const Var& theta, int j) {
  const Real tau = boost::multiprecision::ldexp(Real(1), j);
  const Var a = pow_two_to(phi, j - 1), b = pow_two_to(phi, j);
  const Var num =
      (theta + phi) * (1 + theta * phi) * (3 - 4 * a + b) + (1 + theta) * (1 + theta) * (phi * phi - 1) * tau / 2;
  const Var d = phi - 1;
  return 2 * num / (d * d * d * (1 + phi) * tau * tau);
}

Reference to_reference(const Var& y) {
  return {static_cast<double>(y.derivative(0)), static_cast<double>(y.derivative(1)),
          static_cast<double>(y.derivative(2))};
}

}  // namespace

Reference ar1_reference(double phi, int j) { return to_reference(ar1_closed_form(make_fvar<Real, 2>(Real(phi)), j)); }

Reference gm_reference(double beta, double freq, double sigma2_gm, int j) {
  const Var b = make_fvar<Real, 2>(Real(beta));
  const Var L = b / Real(freq);
  const Var phi = exp(-L);
  const Var sigma2 = Real(sigma2_gm) * (1 - exp(-2 * L));
  return to_reference(sigma2 * ar1_closed_form(phi, j));
}

Reference arma11_reference(double phi, double theta, int j, int wrt) {
  if (wrt == 0) return to_reference(arma11_closed_form(make_fvar<Real, 2>(Real(phi)), Var(Real(theta)), j));
  return to_reference(arma11_closed_form(Var(Real(phi)), make_fvar<Real, 2>(Real(theta)), j));
}

}  // namespace gmwm::test
