#pragma once
// Numerically stable Haar WV of an AR1 (and the pieces ARMA11 and GM reuse), written
// once as templates over double and Jet<N> (jet.h), so the derivatives are the analytic
// derivatives of the same stable expressions.
//
// The closed form of docs/statistics.md section 3, with m = tau/2 and a = phi^m,
//
//   nu^2 / sigma2 = [ (1 - phi^2) tau - 2 phi (1 - a)(3 - a) ] / ((1 - phi)^3 (1 + phi) tau^2),
//
// cancels catastrophically as phi -> 1 (numerator and denominator are O((1-phi)^3) built
// from O(1 - phi) terms). With phi = exp(-L) and y = m L the numerator is
// phi [ 4m (sinh L - L) + h(y) ], h(y) = 4y - 6 + 8 e^-y - 2 e^-2y, and the denominator is
// 32 m^2 e^-2L sinh^2(L/2) sinh L, so
//
//   nu^2 / sigma2 = e^L [ 4 s3(L) + m^2 H(y) ] / (8 m sinhc(L/2)^2 sinhc(L)),
//
// with sinhc(x) = sinh(x)/x, s3(x) = (sinh x - x)/x^3 and H(y) = h(y)/y^3: every factor is
// a positive, O(1), smooth function computed by its power series near 0 (so nothing
// cancels), and the two terms in the bracket are both positive. As L -> 0 this tends to
// the random-walk WV (m/6 + 1/(12 m)), as it should.
//
// Near phi = -1 (m even, so a = |phi|^m) the numerator carries a factor (1 + phi) that
// is cancelled analytically: 1 - a = (1 + phi) G(-phi) with G(x) = (1 - x^m)/(1 - x)
// (geometric_ratio, stable as x -> 1). Between -1/2 and 1/2 the direct form is used;
// m = 1 is the exact 1/(2 (1 + phi)).
//
// ARMA11: with (theta + phi)(1 + theta phi) = phi (1 + theta)^2 + theta (1 - phi)^2 the
// closed form splits into (1 + theta)^2 times the AR1 WV minus 2 theta sigma2 K, with
//   K = (1 - a)(3 - a) / ((1 - phi)(1 + phi) tau^2),
// where (1 - a)/(1 - phi) = G(phi) = m E1(m L) / E1(L), E1(y) = (1 - e^-y)/y, is again
// stable (and likewise G(-phi) near phi = -1).
//
// Accuracy (tests/engine/processes/ar1_test.cc, arma11_test.cc, against 100-digit
// references): value, first and second derivatives to 1e-10 relative or better for
// phi in [-1 + 1e-6, 1 - 1e-9] and tau = 2 .. 2^30.

#include <algorithm>
#include <cmath>

#include <optional>

#include "gmwm/engine/process.h"
#include "jet.h"
#include "process_util.h"

namespace gmwm::internal {

/// |phi| above which the log forms are used (phi = e^-L with L < ln 2, where the series
/// of sinhc and s3 converge fast); for |phi| <= 1/2 the direct closed form loses at
/// most a factor ~3 to cancellation (worst at phi = 1/2, tau = 4: 3 - 2.0625).
inline constexpr double kAr1LogFormMinPhi = 0.5;
inline constexpr double kLn2 = 0.69314718055994530942;

/// Power-series / closed-expression switch for H and E1: at y = 1 the closed expressions
/// lose at most ~30 ulps in the second derivative (12 h/y^5 - 6 h'/y^4 + h''/y^3 at y = 1
/// is 0.34 from terms of size 9.6), and the series need ~30 terms.
inline constexpr double kSeriesMaxArg = 1.0;

D2 sinhc_d2(double x);                 ///< sinh(x)/x
D2 sinh_minus_x_over_x3_d2(double x);  ///< (sinh x - x)/x^3
D2 haar_h_over_y3_d2(double y);        ///< (4y - 6 + 8e^-y - 2e^-2y)/y^3, y >= 0
D2 one_minus_exp_over_y_d2(double y);  ///< (1 - e^-y)/y, y >= 0
D2 neg_log_d2(double phi);             ///< -log(phi), phi in (0, 1]
/// 1 - phi^m, m >= 1; for phi < 0 and m not whole, phi^m is the continuation |phi|^m cos(pi m).
D2 one_minus_pow_d2(double phi, double m);

template <class T>
T one_minus_pow(const T& phi, double m) {
  return lift(phi, one_minus_pow_d2(value(phi), m));
}

/// nu^2/sigma2 of an AR1 with phi = exp(-L), L > 0, at tau = 2m, stable for all L:
///   e^L (4 s3(L) + m^2 H(mL)) / (8 m sinhc(L/2)^2 sinhc(L)).
/// The factors that depend on L only are computed once at construction, so a WV over J
/// levels costs one H per level (they were 60% of the AR1 kernels' time when evaluated
/// per level).
template <class T>
class Ar1LogForm {
 public:
  explicit Ar1LogForm(const T& L) : L_(L), l_(value(L)) {
    using std::exp;
    if (l_ >= kLn2) {
      phi_ = exp(-L);
      return;
    }
    const T sc = lift(L, sinhc_d2(l_));
    const T half = 0.5 * L;
    const T sch = lift(half, sinhc_d2(0.5 * l_));  // sinhc(L/2)
    s3x4_ = 4.0 * lift(L, sinh_minus_x_over_x3_d2(l_));
    scale_ = exp(L) / (8.0 * sch * sch * sc);
  }
  T at(double m) const;

 private:
  T L_;
  double l_;
  T phi_{}, s3x4_{}, scale_{};
};

/// nu^2/sigma2 by the direct closed form; accurate for phi <= kAr1LogFormMinPhi.
template <class T>
T ar1_unit_wv_direct(const T& phi, double m) {
  const T om = one_minus_pow(phi, m);
  const T omp = 1.0 - phi;
  const T opp = 1.0 + phi;
  return (omp * opp * (2.0 * m) - 2.0 * phi * om * (2.0 + om)) / (omp * omp * omp * opp * (4.0 * m * m));
}

template <class T>
T Ar1LogForm<T>::at(double m) const {
  if (l_ >= kLn2) return ar1_unit_wv_direct(phi_, m);
  const T y = m * L_;
  const T hh = lift(y, haar_h_over_y3_d2(m * l_));
  return scale_ * (s3x4_ + (m * m) * hh) / m;
}

/// One level of Ar1LogForm (a WV over several levels should keep the form).
template <class T>
T ar1_unit_wv_log(const T& L, double m) {
  return Ar1LogForm<T>(L).at(m);
}

/// -log(phi) for phi in (0, 1).
template <class T>
T neg_log(const T& phi) {
  return lift(phi, neg_log_d2(value(phi)));
}

/// (1 - x^m)/(1 - x) for x in (0, 1), without cancellation as x -> 1:
/// m E1(m L)/E1(L) with L = -log x (E1(y) = (1 - e^-y)/y) above kAr1LogFormMinPhi.
template <class T>
T geometric_ratio(const T& x, double m) {
  if (value(x) > kAr1LogFormMinPhi) {
    const T L = neg_log(x);
    const T y = m * L;
    return m * lift(y, one_minus_exp_over_y_d2(value(y))) / lift(L, one_minus_exp_over_y_d2(value(L)));
  }
  return one_minus_pow(x, m) / (1.0 - x);
}

/// True when phi is close enough to -1 that the factor (1 + phi) must be cancelled
/// analytically: 1 - phi^m = (1 + phi) G(-phi) for even m, G = geometric_ratio.
inline bool near_minus_one_even(double phi, double m) { return phi < -kAr1LogFormMinPhi && std::fmod(m, 2.0) == 0.0; }

/// nu^2/sigma2 of an AR1 at tau = 2m, phi in (-1, 1), for any number of levels: the
/// log form's L-only factors are computed once. m = 1 is the exact 1/(2 (1 + phi))
/// (docs/statistics.md section 3, "Handy checks").
template <class T>
class Ar1UnitWv {
 public:
  explicit Ar1UnitWv(const T& phi) : phi_(phi) {
    if (value(phi) > kAr1LogFormMinPhi) log_form_.emplace(neg_log(phi));
  }
  T at(double m) const {
    const T& phi = phi_;
    if (m == 1.0) return 0.5 / (1.0 + phi);
    if (log_form_) return log_form_->at(m);
    if (near_minus_one_even(value(phi), m)) {
      // N = (1 + phi) [ (1 - phi) 2m - 2 phi G (2 + om) ], om = (1 + phi) G.
      const T g = geometric_ratio(T(-phi), m);
      const T om = (1.0 + phi) * g;
      const T omp = 1.0 - phi;
      return (omp * (2.0 * m) - 2.0 * phi * g * (2.0 + om)) / (omp * omp * omp * (4.0 * m * m));
    }
    return ar1_unit_wv_direct(phi, m);
  }

 private:
  T phi_;
  std::optional<Ar1LogForm<T>> log_form_;
};

/// One level of Ar1UnitWv.
template <class T>
T ar1_unit_wv(const T& phi, double m) {
  return Ar1UnitWv<T>(phi).at(m);
}

/// K = (1 - phi^m)(3 - phi^m) / ((1 - phi^2) tau^2), the ARMA11 cross term.
template <class T>
T arma11_cross_term(const T& phi, double m) {
  if (m == 1.0) return (3.0 - phi) / (4.0 * (1.0 + phi));
  if (value(phi) > kAr1LogFormMinPhi) {
    const T g = geometric_ratio(phi, m);  // (1 - a)/(1 - phi)
    return g * (2.0 + (1.0 - phi) * g) / ((1.0 + phi) * (4.0 * m * m));
  }
  if (near_minus_one_even(value(phi), m)) {
    const T g = geometric_ratio(T(-phi), m);  // (1 - a)/(1 + phi)
    return g * (2.0 + (1.0 + phi) * g) / ((1.0 - phi) * (4.0 * m * m));
  }
  const T om = one_minus_pow(phi, m);
  return om * (2.0 + om) / ((1.0 - phi) * (1.0 + phi) * (4.0 * m * m));
}

/// nu^2/sigma2 of an ARMA11 at tau = 2m.
template <class T>
T arma11_unit_wv(const Ar1UnitWv<T>& ar1, const T& phi, const T& theta, double m) {
  const T opt = 1.0 + theta;
  return opt * opt * ar1.at(m) - 2.0 * theta * arma11_cross_term(phi, m);
}

/// An AR1 WV peaks near tau = 3.79 / (1 - phi) (docs/statistics.md section 4, starting values).
inline constexpr double kAr1PeakTauTimesOneMinusPhi = 3.79;
/// Guessed phi is clamped into [lo, kAr1GuessPhiMax]: 1 - 1e-8 keeps atanh(phi) ~ 9.5
/// well inside double range while covering correlation times up to ~4e8 samples.
inline constexpr double kAr1GuessPhiMax = 1.0 - 1e-8;

struct Ar1Guess {
  double phi;
  double sigma2;
};

/// Starting AR1 values: phi from where the bump peaks (ctx.tau_hint, else the peak of
/// ctx.wv), clamped into [phi_min, kAr1GuessPhiMax]; sigma2 so that the AR1 WV equals
/// ctx.wv at the level nearest that scale.
inline Ar1Guess ar1_initial_guess(const GuessContext& ctx, double phi_min) {
  const double tau_peak = guess_tau(ctx, 2.0 * kAr1PeakTauTimesOneMinusPhi);
  const double phi = std::clamp(1.0 - kAr1PeakTauTimesOneMinusPhi / tau_peak, phi_min, kAr1GuessPhiMax);
  double sigma2 = 1.0;
  const std::size_t n = std::min(ctx.tau.size(), ctx.wv.size());
  if (n > 0) {
    const std::size_t k = guess_level(ctx);
    const double tau = std::max(2.0, 2.0 * std::round(0.5 * ctx.tau[k]));
    sigma2 = positive_or(ctx.wv[k] / ar1_unit_wv(phi, 0.5 * tau), 1.0);
  }
  return {phi, sigma2};
}

/// The shapes an AR1's WV takes over scales tau (Process::shape_family), as phis: positive
/// phi = exp(-1 / T) at correlation times T (samples) from kAr1ShapeMinT to
/// kAr1ShapeMaxTFactor x the largest scale, kAr1ShapePointsPerOctave per octave of T, and
/// the negative phis of kAr1ShapeNegativePhis (WVs concentrated at the finest scales, the
/// form a noise-fitting AR1 takes there). Neighbouring shapes correlate above 0.99 in
/// the WV metric at 4 per octave (an AR1 bump spans about 3 octaves of tau), so the
/// largest excess over the grid is that over the continuum within Monte-Carlo error.
inline constexpr double kAr1ShapeMinT = 0.25;
inline constexpr double kAr1ShapeMaxTFactor = 4.0;
inline constexpr int kAr1ShapePointsPerOctave = 4;
inline constexpr double kAr1ShapeNegativePhis[] = {-0.3, -0.6, -0.9, -0.99};

inline std::vector<double> ar1_shape_phis(std::span<const double> tau) {
  double top = 2.0;
  for (double t : tau) top = std::max(top, t);
  std::vector<double> out(std::begin(kAr1ShapeNegativePhis), std::end(kAr1ShapeNegativePhis));
  const double octaves = std::log2(kAr1ShapeMaxTFactor * top / kAr1ShapeMinT);
  const int points = static_cast<int>(std::ceil(octaves * kAr1ShapePointsPerOctave));
  for (int k = 0; k <= points; ++k) {
    const double T = kAr1ShapeMinT * std::exp2(static_cast<double>(k) / kAr1ShapePointsPerOctave);
    out.push_back(std::exp(-1.0 / T));
  }
  return out;
}

}  // namespace gmwm::internal
