// DR: deterministic drift omega t. nu^2(tau) = omega^2 tau^2 / 16 (docs/statistics.md section 3).
//
// omega is signed (a falling drift is negative) but the WV sees only omega^2: the
// optimiser works on |omega| (log transform of the magnitude, ParameterSpec::
// signed_magnitude), the sign is carried from a given or starting value, or taken from
// the series' own slope (orient_by_series, fit.h). validate() rejects omega = 0.
// Simulation: x_t = omega t for t = 0 .. n-1 (the path starts at 0; the WV does not depend
// on the offset); sum_moments and the Kalman rate state keep the sign.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

class Drift final : public Process {
 public:
  explicit Drift(const ProcessArgs&) {}
  std::string name() const override { return "DR"; }
  ProcessRole role() const override { return ProcessRole::kDrift; }
  int canonical_rank() const override { return 80; }
  bool deterministic() const override { return true; }
  // Haar coefficient of omega t: (sum of the recent tau/2 samples - sum of the older
  // tau/2) / tau = omega (tau/2)^2 / tau = omega tau / 4, so its square is the WV.
  double deterministic_coefficient(std::span<const double> theta, double tau) const override {
    return theta[0] * tau / 4.0;
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"omega", Transform::kLog, "drift slope per sample (signed; the WV sees only its magnitude)", true}};
    return specs;
  }
  std::string validate(std::span<const double> theta) const override { return Process::validate(theta); }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    const double w = theta[0];
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = w * w * tau[k] * tau[k] / 16.0;
  }
  void wv_jacobian(std::span<const double> theta, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k)
      jac(static_cast<Eigen::Index>(k), 0) = theta[0] * tau[k] * tau[k] / 8.0;
  }
  void wv_hessian(std::span<const double>, std::span<const double> tau,
                  Eigen::Ref<Eigen::MatrixXd> hess) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) hess(static_cast<Eigen::Index>(k), 0) = tau[k] * tau[k] / 8.0;
  }
  void generalized_autocovariance(std::span<const double>, std::span<double> out) const override {
    std::fill(out.begin(), out.end(), 0.0);
  }
  // x_t = omega t for t = 1..K sums to omega K (K + 1) / 2, without randomness.
  std::vector<SumMoments> sum_moments(std::span<const double> theta,
                                      std::span<const std::int64_t> counts) const override {
    std::vector<SumMoments> out;
    for (std::int64_t k : counts) {
      check_at_least("DR::sum_moments", "K", static_cast<double>(k), 1.0);
      const auto K = static_cast<double>(k);
      out.push_back({theta[0] * K * (K + 1.0) / 2.0, 0.0});
    }
    return out;
  }
  // IEEE 952 rate ramp: AVAR(T) = R^2 T^2 / 2. Here AVAR(m) = 2 WV(2m) = omega^2 m^2 / 2
  // with m = T f samples: R = omega f.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double) const override {
    KalmanTerm k;
    k.role = "deterministic drift: a rate state";
    k.q = 0.0;
    k.q_unit = "U^2/s^3";
    k.transition = 1.0;
    k.discrete = theta[0] * freq;
    k.discrete_unit = "U/s";
    k.note = "no process noise; the state's initial value is the drift rate omega f (the discrete value shown)";
    return {k};
  }
  // A rate ramp R = omega f whose sign the analysis does not assume: x = [value, slope],
  // d value / dt = slope, value(0) = 0, slope ~ N(0, R^2) (its error grows as |R| t^2 / 2).
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    ContinuousForm c;
    c.F = Eigen::MatrixXd::Zero(2, 2);
    c.F(0, 1) = 1.0;
    c.Qc = Eigen::MatrixXd::Zero(2, 2);
    c.P0 = Eigen::MatrixXd::Zero(2, 2);
    c.P0(1, 1) = theta[0] * freq * theta[0] * freq;
    c.H = Eigen::RowVectorXd::Zero(2);
    c.H(0) = 1.0;
    return c;
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    return {{"drift rate", theta[0] * freq, "U/s",
             "R = omega f, signed (IEEE 952 rate ramp: AVAR = R^2 T^2 / 2 sees |R|; the sign is the series' slope)",
             PhysicalKind::kDriftRate}};
  }
  void simulate(std::span<const double> theta, Rng&, std::span<double> out) const override {
    for (std::size_t t = 0; t < out.size(); ++t) out[t] += theta[0] * static_cast<double>(t);
  }
  std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const override {
    return internal::summed_size(a, b);
  }
  // The data times sqrt(c): the slope times sqrt(c), the WV (omega^2) times c.
  std::vector<double> scaled(std::span<const double> theta, double c) const override {
    return {theta[0] * std::sqrt(c)};
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // DR dominates the coarsest scale: |omega| = 4 sqrt(nu^2(tau_J)) / tau_J.
    const std::size_t n = std::min(ctx.tau.size(), ctx.wv.size());
    const double w = n ? 4.0 * std::sqrt(ctx.wv[n - 1]) / ctx.tau[n - 1] : 1.0;
    return {internal::positive_or(w, 1.0)};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(Drift, "DR", "deterministic drift: DR(omega), omega = slope per sample (signed)");

}  // namespace gmwm
