// SIN: x_t = A sin(2 pi f t + U), U ~ uniform(0, 2 pi) (a random phase makes it
// stationary), with parameters A2 = A^2 and f in cycles/sample (0 < f < 1/2).
// nu^2(tau) = (A2/2) sin^4(pi f tau/2) / ((tau/2)^2 sin^2(pi f)) (docs/statistics.md section 3);
// g(h) = (A2/2) cos(2 pi f h). Angles go through sin_pi/cos_pi (Boost.Math), which
// reduce f tau/2 exactly, so coarse scales keep full accuracy. Users see f in Hz when
// the sampling rate is known (to_display/from_display).
#include <algorithm>
#include <cmath>
#include <type_traits>

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/cos_pi.hpp>
#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/sin_pi.hpp>
#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/process_registry.h"
#include "jet.h"
#include "process_util.h"

namespace gmwm {
namespace {

using internal::Jet;

/// sin_pi / cos_pi in double: Boost.Math's default policy promotes a double argument to
/// long double, whose sinl/cosl (x87) were 30% of a `gap` run's CPU (the SIN candidate's WV
/// at every fit evaluation); the exact argument reduction that keeps coarse scales accurate
/// is done either way (x - 2 floor(x / 2) is exact in double), so the double result is
/// within 1e-14 of the promoted one up to tau = 2^40 (sinusoid_test).
using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
double sin_pi(double x) { return boost::math::sin_pi(x, DoublePolicy()); }
double cos_pi(double x) { return boost::math::cos_pi(x, DoublePolicy()); }

/// Guessed f = 1/tau_peak is clamped into [kSinGuessFMin, kSinGuessFMax]: 0.45 keeps
/// logit(2f) = 2.2 away from the Nyquist boundary; 1e-9 cycles/sample is far coarser
/// than any record.
constexpr double kSinGuessFMin = 1e-9;
constexpr double kSinGuessFMax = 0.45;

template <class T>
T sin_pi_t(const T& x) {
  constexpr double pi = boost::math::constants::pi<double>();
  const double v = internal::value(x);
  if constexpr (std::is_same_v<T, double>) {
    return sin_pi(v);  // a value alone: no cosine (lift would drop it)
  } else {
    const double s = sin_pi(v), c = cos_pi(v);
    return internal::lift(x, internal::D2{s, pi * c, -pi * pi * s});
  }
}

// The unit WV at half-scale m, given b = sin_pi_t(f) (the same at every level: formed once
// per evaluation by the callers, each level's value as it was when formed per level).
template <class T>
T sin_unit_wv(const T& f, const T& b, double m) {
  const T a = sin_pi_t(T(f * m));
  const T a2 = a * a;
  return 0.5 * a2 * a2 / ((m * m) * b * b);
}

class Sinusoid final : public internal::JetDifferentiated<Sinusoid, 2> {
 public:
  explicit Sinusoid(const ProcessArgs&) {}
  std::string name() const override { return "SIN"; }
  ProcessRole role() const override { return ProcessRole::kPeriodic; }
  int canonical_rank() const override { return 90; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"A2", Transform::kLog, "squared amplitude"},
        {"f", Transform::kLogitHalf, "frequency (cycles/sample; Hz when the rate is known)"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    const double b = sin_pi_t(theta[1]);
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[0] * sin_unit_wv(theta[1], b, 0.5 * tau[k]);
  }
  template <class J>
  void derivatives(std::span<const double> theta, std::span<const double> tau, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) const {
    const J a2 = J::variable(theta[0], 0);
    const J f = J::variable(theta[1], 1);
    const J b = sin_pi_t(f);
    for (std::size_t k = 0; k < tau.size(); ++k)
      internal::store_jet_row(a2 * sin_unit_wv(f, b, 0.5 * tau[k]), static_cast<Eigen::Index>(k), jac, hess, value);
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    for (std::size_t h = 0; h < out.size(); ++h)
      out[h] = 0.5 * theta[0] * cos_pi(2.0 * theta[1] * static_cast<double>(h));
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    // A sin(2 pi f t + U) = A [sin(2 pi f t) cos U + cos(2 pi f t) sin U].
    boost::random::uniform_real_distribution<double> phase(0.0, 2.0 * boost::math::constants::pi<double>());
    const double u = phase(rng);
    const double amp = std::sqrt(theta[0]);
    const double cu = amp * std::cos(u), su = amp * std::sin(u);
    for (std::size_t t = 0; t < out.size(); ++t) {
      const double x = 2.0 * theta[1] * static_cast<double>(t);
      out[t] += cu * sin_pi(x) + su * cos_pi(x);
    }
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // The SIN WV peaks near tau = 1/f (without any information: f = 1/4).
    const double f = std::clamp(1.0 / internal::guess_tau(ctx, 4.0), kSinGuessFMin, kSinGuessFMax);
    double a2 = 1.0;
    if (std::min(ctx.tau.size(), ctx.wv.size()) > 0) {
      const std::size_t k = internal::guess_level(ctx);
      // Fallback when the WV of this f vanishes at that level (f tau/2 an integer):
      // the SIN WV at its peak (f tau/2 = 1/2) is about (A2/2)(4/pi^2) ~ A2/5.
      a2 = internal::positive_or(ctx.wv[k] / sin_unit_wv(f, sin_pi_t(f), 0.5 * ctx.tau[k]),
                                 internal::positive_or(5.0 * ctx.wv[k], 1.0));
    }
    return {a2, f};
  }
  // x_t = A sin(2 pi f t + U): amplitude sqrt(A2) in U, frequency f (cycles/sample) times
  // the rate in Hz.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    KalmanTerm k;
    k.role = "deterministic harmonic: two states";
    k.q = 0.0;
    k.q_unit = "U^2/s";
    k.transition = std::cos(2.0 * M_PI * theta[1] * freq / filter_rate);
    k.discrete = 0.0;
    k.discrete_unit = "U^2";
    k.note =
        "a rotation by 2 pi F dt of (a, b) with no process noise (the value shown is its cosine), "
        "or a notch filter on the measurement";
    return {k};
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    return {{"amplitude", std::sqrt(theta[0]), "U", "A = sqrt(A2) (x = A sin(2 pi F t + U))", PhysicalKind::kAmplitude},
            {"frequency", theta[1] * freq, "Hz", "F = f_cycles_per_sample * f_rate", PhysicalKind::kFrequency}};
  }
  double to_display(int k, double natural) const override {
    return (k == 1 && context().freq_known) ? natural * context().freq : natural;
  }
  double from_display(int k, double shown) const override {
    return (k == 1 && context().freq_known) ? shown / context().freq : shown;
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(Sinusoid, "SIN", "sinusoid with random phase: SIN(A2, f)");

}  // namespace gmwm
