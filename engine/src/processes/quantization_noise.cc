// QN: quantization noise with parameter Q2. nu^2(tau) = 6 Q2 / tau^2 (docs/statistics.md section 3).
// x_t = sqrt(12 Q2) (U_t - U_{t-1}), U i.i.d. uniform(0, 1): the increments of an i.i.d.
// sequence of variance Q2, so g(0) = 2 Q2, g(1) = -Q2, g(h) = 0 beyond.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

class QuantizationNoise final : public Process {
 public:
  explicit QuantizationNoise(const ProcessArgs&) {}
  std::string name() const override { return "QN"; }
  ProcessRole role() const override { return ProcessRole::kQuantization; }
  int canonical_rank() const override { return 60; }
  bool linear() const override { return true; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"Q2", Transform::kLog, "quantization noise coefficient Q^2 per sample"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = 6.0 * theta[0] / (tau[k] * tau[k]);
  }
  void wv_jacobian(std::span<const double>, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) jac(static_cast<Eigen::Index>(k), 0) = 6.0 / (tau[k] * tau[k]);
  }
  void wv_hessian(std::span<const double>, std::span<const double>, Eigen::Ref<Eigen::MatrixXd> hess) const override {
    hess.setZero();
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    std::fill(out.begin(), out.end(), 0.0);
    if (out.size() > 0) out[0] = 2.0 * theta[0];
    if (out.size() > 1) out[1] = -theta[0];
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    boost::random::uniform_real_distribution<double> u(0.0, 1.0);
    const double scale = std::sqrt(12.0) * std::sqrt(theta[0]);  // 12 Q2 overflows for Q2 > 1.5e307
    double prev = u(rng);
    for (double& v : out) {
      const double cur = u(rng);
      v += scale * (cur - prev);
      prev = cur;
    }
  }
  // IEEE 952: AVAR(T) = 3 Q^2 / T^2 with T in seconds. Here AVAR(m) = 2 WV(2m)
  // = 2 * 6 Q2 / (2m)^2 = 3 Q2 / m^2 with m = T f samples, = 3 (sqrt(Q2) / f)^2 / T^2,
  // so Q = sqrt(Q2) / f in U*s (for a rate in U: the angle/velocity quantization step
  // is sqrt(12) Q).
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    KalmanTerm k;
    const double Q = std::sqrt(theta[0]) / freq;
    k.role = "measurement noise R (quantization, approximate)";
    k.discrete = 2.0 * Q * Q * filter_rate * filter_rate;
    k.discrete_unit = "U^2";
    k.note = "R = 2 Q^2 f_k^2, Q = sqrt(Q2) / f; lag-1 correlated, a white R is the usual approximation";
    return {k};
  }
  // The rounding of the integrated output: its increments telescope, so the integral of the
  // component is the difference of two roundings (sd sqrt(2) Q at most), never growing:
  // nothing that accumulates, no state.
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    ContinuousForm c = stateless_form(0.0);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "QN (Q = %.3g U*s) left out: the rounding of the integrated output telescopes, an error of at "
                  "most sqrt(2) Q that never accumulates",
                  std::sqrt(theta[0]) / freq);
    c.notes.push_back(buf);
    return c;
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    return {{"quantization", std::sqrt(theta[0]) / freq, "U*s",
             "Q = sqrt(Q2) / f (IEEE 952: AVAR = 3 Q^2 / T^2; step = sqrt(12) Q)", PhysicalKind::kQuantization}};
  }
  std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const override {
    return internal::summed_size(a, b);
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // QN dominates the finest scale: Q2 = tau_1^2 nu^2(tau_1) / 6.
    const double q = ctx.tau.empty() || ctx.wv.empty() ? 1.0 : ctx.tau[0] * ctx.tau[0] * ctx.wv[0] / 6.0;
    return {internal::positive_or(q, 1.0)};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(QuantizationNoise, "QN", "quantization noise: QN(Q2)");

}  // namespace gmwm
