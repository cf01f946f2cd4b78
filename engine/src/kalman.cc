#include "gmwm/engine/kalman.h"

#include <cmath>

#include "gmwm/engine/check.h"
#include "gmwm/engine/process.h"

namespace gmwm {

KalmanTerm gauss_markov_term(double T, double s2, double filter_rate) {
  KalmanTerm k;
  k.role = "first-order Gauss-Markov bias state";
  k.q = 2.0 * s2 / T;
  k.q_unit = "U^2/s";
  k.transition = std::exp(-1.0 / (filter_rate * T));
  k.discrete = -s2 * std::expm1(-2.0 / (filter_rate * T));  // s2 (1 - F^2)
  k.discrete_unit = "U^2";
  k.note = "dx/dt = -x/T + w, q = 2 s2 / T; F = exp(-dt/T), Q_d = s2 (1 - F^2)";
  return k;
}

std::vector<KalmanTerm> Process::kalman(std::span<const double> theta, double freq, double filter_rate) const {
  check_size_match("Process::kalman", "theta", theta.size(), "parameters of " + name(), parameters().size());
  check_positive("Process::kalman", "freq", freq);
  check_positive("Process::kalman", "filter_rate", filter_rate);
  return kalman_impl(theta, freq, filter_rate);
}

std::vector<KalmanTerm> Process::kalman_impl(std::span<const double>, double, double) const {
  KalmanTerm k;
  k.role = "no finite Gauss-Markov state";
  k.note = name() +
           " has no state with white driving noise of the usual form; model it from its fitted "
           "autocovariance or approximate it with Gauss-Markov states";
  return {k};
}

std::optional<ContinuousForm> Process::continuous_form(std::span<const double> theta, double freq) const {
  check_size_match("Process::continuous_form", "theta", theta.size(), "parameters of " + name(), parameters().size());
  check_positive("Process::continuous_form", "freq", freq);
  return continuous_form_impl(theta, freq);
}

std::optional<ContinuousForm> Process::continuous_form_impl(std::span<const double>, double) const {
  return std::nullopt;
}

ContinuousForm stateless_form(double white) {
  ContinuousForm c;
  c.F.resize(0, 0);
  c.Qc.resize(0, 0);
  c.P0.resize(0, 0);
  c.H.resize(0);
  c.white = white;
  return c;
}

ContinuousForm gauss_markov_form(double T, double s2, double dt) {
  // A state that forgets within a sample (e^-L < 1e-13) is white to that precision; as a
  // state its exact step would need exp(+L) of the Van Loan block, which overflows past
  // L ~ 700 (an AR1 with phi < 1e-304): its samples' density s2 dt coth(L/2) alone.
  constexpr double kWhiteBeyondL = 30.0;
  if (dt / T > kWhiteBeyondL) return stateless_form(s2 * dt / std::tanh(0.5 * dt / T));
  ContinuousForm c;
  // coth(L/2) - 2/L = L/6 - L^3/360 + ...: the series below L = 1e-3, where the difference
  // of the two would lose all its digits (its third term is then below 1e-13 relative).
  const double L = dt / T;
  constexpr double kSeriesBelow = 1e-3;
  const double excess = L < kSeriesBelow ? L / 6.0 - L * L * L / 360.0 : 1.0 / std::tanh(0.5 * L) - 2.0 / L;
  c.white = s2 * dt * excess;
  c.F = Eigen::MatrixXd::Constant(1, 1, -1.0 / T);
  c.Qc = Eigen::MatrixXd::Constant(1, 1, 2.0 * s2 / T);
  c.P0 = Eigen::MatrixXd::Constant(1, 1, s2);
  c.H = Eigen::RowVectorXd::Ones(1);
  return c;
}

}  // namespace gmwm
