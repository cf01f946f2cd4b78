// WN: white noise with variance sigma2. nu^2(tau) = sigma2 / tau (docs/statistics.md section 3).
#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/random/normal_distribution.hpp>

#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

class WhiteNoise final : public Process {
 public:
  explicit WhiteNoise(const ProcessArgs&) {}
  std::string name() const override { return "WN"; }
  ProcessRole role() const override { return ProcessRole::kWhite; }
  int canonical_rank() const override { return 50; }
  bool linear() const override { return true; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{{"sigma2", Transform::kLog, "white-noise variance per sample"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[0] / tau[k];
  }
  void wv_jacobian(std::span<const double>, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) jac(static_cast<Eigen::Index>(k), 0) = 1.0 / tau[k];
  }
  void wv_hessian(std::span<const double>, std::span<const double>, Eigen::Ref<Eigen::MatrixXd> hess) const override {
    hess.setZero();
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    std::fill(out.begin(), out.end(), 0.0);
    if (!out.empty()) out[0] = theta[0];
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    // normal_distribution<double>(0, sqrt(sigma2)) per sample, a run of draws at a time.
    const double s = std::sqrt(theta[0]);
    double* o = out.data();
    for_unit_normals(rng, out.size(), [&](const double* z, std::size_t t, std::size_t m) {
      for (std::size_t k = 0; k < m; ++k) o[t + k] += scaled_normal(z[k], s);
    });
  }
  // IEEE 952: AVAR(T) = N^2 / T. Here AVAR(m) = 2 WV(2m) = sigma2 / m with m = T f samples,
  // so N^2 = sigma2 / f.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    KalmanTerm k;
    k.role = "measurement noise R";
    k.q = theta[0] / freq;
    k.q_unit = "U^2/Hz";
    k.discrete = k.q * filter_rate;
    k.discrete_unit = "U^2";
    k.note = "q = N^2 = sigma2 / f; R = q f_k (= sigma2 when the filter runs at the data rate)";
    return {k};
  }
  // White noise of density N^2 = sigma2 / f: no state.
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    return stateless_form(theta[0] / freq);
  }
  // sigma2 / f leaves the normal doubles for sigma2 near their ends (1e-307 at 100 Hz):
  // there the roots are taken apart.
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    const double n2 = theta[0] / freq;
    const double N = n2 >= std::numeric_limits<double>::min() && std::isfinite(n2)
                         ? std::sqrt(n2)
                         : std::sqrt(theta[0]) / std::sqrt(freq);
    return {{"noise density", N, "U/sqrt(Hz)",
             "N = sqrt(sigma2 / f) (IEEE 952: AVAR = N^2 / T; angle/velocity random walk)",
             PhysicalKind::kNoiseDensity}};
  }
  std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const override {
    return internal::summed_size(a, b);
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // The finest scale is where white noise dominates: sigma2 = tau_1 nu^2(tau_1).
    double s = ctx.tau.empty() ? 1.0 : ctx.tau[0] * ctx.wv[0];
    if (!(s > 0.0) || !std::isfinite(s)) s = 1.0;
    return {s};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(WhiteNoise, "WN", "white noise: WN(sigma2)");

}  // namespace gmwm
