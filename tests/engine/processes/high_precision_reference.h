#pragma once
// Reference values for the near-unit-root tests: the naive closed forms of docs/statistics.md
// section 3 evaluated in 100-digit arithmetic (Boost.Multiprecision), differentiated exactly by
// Boost.Math's autodiff. The closed form loses ~2 log10(1/(1-phi)) + 3 digits to
// cancellation, which leaves > 70 correct digits for every case tested here.

namespace gmwm::test {

/// A value with its first and second derivative in one parameter, rounded to double.
struct Reference {
  double value;
  double d1;
  double d2;
};

// Arguments are doubles, converted exactly: the references are for the very double
// values the engine sees (phi = 1 - 1e-9 is not exactly representable, and the WV at
// tau = 2^30 is sensitive to its last bits).

/// AR1 WV per unit sigma2 at tau = 2^j, and its derivatives in phi.
Reference ar1_reference(double phi, int j);
/// GM WV at tau = 2^j and its derivatives in beta (phi = exp(-beta/f),
/// sigma2 = sigma2_gm (1 - exp(-2 beta/f))).
Reference gm_reference(double beta, double freq, double sigma2_gm, int j);
/// ARMA11 WV per unit sigma2 at tau = 2^j with derivatives in phi (wrt = 0) or theta (1).
Reference arma11_reference(double phi, double theta, int j, int wrt);

}  // namespace gmwm::test
