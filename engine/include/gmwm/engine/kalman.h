#pragma once
// What to put in a Kalman filter for each component of a fitted noise model (issue 6,
// "a Kalman-filter-ready table"): its role in the filter, the continuous-time noise
// density q, and the discrete values at the filter's own rate f_k (dt = 1 / f_k):
//
//   WN  (sigma2 per sample at the data rate f): measurement noise, continuous density
//       q = N^2 = sigma2 / f [U^2/Hz]; R = q f_k per measurement at rate f_k.
//   RW  (gamma2): a bias state with F = 1, q = K^2 = gamma2 f [U^2/s^2/Hz = U^2/s^3 ... i.e.
//       (U/s)^2/Hz]; Q_d = q dt = gamma2 f / f_k.
//   AR1 / GM (correlation time T, stationary variance s2): a first-order Gauss-Markov bias
//       state, dx/dt = -x / T + w, q = 2 s2 / T [U^2/s]; F = exp(-dt / T),
//       Q_d = s2 (1 - F^2) (exact discretisation; Maybeck 1979, s.4.9).
//   DR  (omega per sample): a deterministic rate state (F = 1, Q_d = 0) of initial value
//       omega f [U/s].
//   QN  (Q2): rounding of the integrated output: white measurement noise of the rate
//       averaged over dt, R = 2 Q^2 f_k^2 with Q = sqrt(Q2) / f [U s] (its samples are
//       negatively correlated at lag 1: a white R is the usual approximation).
//   SIN, FLICKER, MA1, ARMA: no finite state with white driving noise of this form; the
//       term says what to do instead (a harmonic state pair; a few Gauss-Markov states).
// Unit patterns use "U" for the data unit (physical.h, render_unit).
#include <limits>
#include <string>

namespace gmwm {

struct KalmanTerm {
  std::string role;                                     ///< e.g. "measurement noise R", "bias random walk state"
  double q = std::numeric_limits<double>::quiet_NaN();  ///< continuous density
  std::string q_unit;                                   ///< pattern, e.g. "U^2/Hz"
  double transition = std::numeric_limits<double>::quiet_NaN();  ///< F at the filter rate (states)
  double discrete = std::numeric_limits<double>::quiet_NaN();    ///< R or Q_d at the filter rate
  std::string discrete_unit;                                     ///< pattern, e.g. "U^2"
  std::string note;  ///< the formula, or what to do when there is no such term
};

/// A first-order Gauss-Markov state with correlation time T (s) and stationary variance
/// s2 at filter rate filter_rate: q = 2 s2 / T, F = exp(-dt/T), Q_d = s2 (1 - F^2).
KalmanTerm gauss_markov_term(double T, double s2, double filter_rate);

}  // namespace gmwm
