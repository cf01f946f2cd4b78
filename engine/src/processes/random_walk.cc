// RW: random walk with innovation variance gamma2. nu^2(tau) = gamma2 (tau^2 + 2)/(12 tau)
// (docs/statistics.md section 3). Not stationary: its generalised autocovariance is minus the
// semivariogram, g(h) = -gamma2 |h| / 2, valid for zero-sum filters (process.h).
#include <cmath>
#include <limits>

#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

class RandomWalk final : public Process {
 public:
  explicit RandomWalk(const ProcessArgs&) {}
  std::string name() const override { return "RW"; }
  ProcessRole role() const override { return ProcessRole::kWalk; }
  int canonical_rank() const override { return 70; }
  bool linear() const override { return true; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"gamma2", Transform::kLog, "random-walk innovation variance per sample"}};
    return specs;
  }
  static double unit(double tau) { return (tau * tau + 2.0) / (12.0 * tau); }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[0] * unit(tau[k]);
  }
  void wv_jacobian(std::span<const double>, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) jac(static_cast<Eigen::Index>(k), 0) = unit(tau[k]);
  }
  void wv_hessian(std::span<const double>, std::span<const double>, Eigen::Ref<Eigen::MatrixXd> hess) const override {
    hess.setZero();
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    for (std::size_t h = 0; h < out.size(); ++h) out[h] = -0.5 * theta[0] * static_cast<double>(h);
  }
  // Var(x_1 + ... + x_K) with x_t = e_1 + ... + e_t: e_s enters K - s + 1 of the terms,
  // so the variance is gamma2 sum_{n=1}^K n^2 = gamma2 K (K + 1) (2K + 1) / 6.
  std::vector<SumMoments> sum_moments(std::span<const double> theta,
                                      std::span<const std::int64_t> counts) const override {
    std::vector<SumMoments> out;
    for (std::int64_t k : counts) {
      check_at_least("RW::sum_moments", "K", static_cast<double>(k), 1.0);
      const auto K = static_cast<double>(k);
      out.push_back({0.0, theta[0] * K * (K + 1.0) * (2.0 * K + 1.0) / 6.0});
    }
    return out;
  }
  // IEEE 952: AVAR(T) = K^2 T / 3. Here AVAR(m) = 2 WV(2m) = gamma2 (4 m^2 + 2) / (12 m)
  // ~ gamma2 m / 3 for large m, with m = T f samples: K^2 = gamma2 f.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    KalmanTerm k;
    k.role = "bias random walk state";
    k.q = theta[0] * freq;
    k.q_unit = "U^2/s";
    k.transition = 1.0;
    k.discrete = k.q / filter_rate;
    k.discrete_unit = "U^2";
    k.note = "q = K^2 = gamma2 f; F = 1, Q_d = q dt";
    return {k};
  }
  // A bias random walk of density K^2 = gamma2 f, starting at 0.
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    ContinuousForm c;
    c.F = Eigen::MatrixXd::Zero(1, 1);
    c.Qc = Eigen::MatrixXd::Constant(1, 1, theta[0] * freq);
    c.P0 = Eigen::MatrixXd::Zero(1, 1);
    c.H = Eigen::RowVectorXd::Ones(1);
    return c;
  }
  // gamma2 f leaves the doubles for gamma2 near their ends (1e307 at 100 Hz: K inf, the
  // plan's K dropped as if the model had no walk): there the roots are taken apart.
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    const double k2 = theta[0] * freq;
    const double K = k2 >= std::numeric_limits<double>::min() && std::isfinite(k2)
                         ? std::sqrt(k2)
                         : std::sqrt(theta[0]) * std::sqrt(freq);
    return {{"random walk", K, "U/s/sqrt(Hz)", "K = sqrt(gamma2 f) (IEEE 952 rate random walk: AVAR = K^2 T / 3)",
             PhysicalKind::kRandomWalk}};
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    // x_t = e_0 + ... + e_t: the path starts with its first increment.
    const double s = std::sqrt(theta[0]);
    double state = 0.0;
    double* o = out.data();
    for_unit_normals(rng, out.size(), [&](const double* z, std::size_t t, std::size_t m) {
      double x = state;  // a local: a captured one might alias o[] and go through memory
      for (std::size_t k = 0; k < m; ++k) {
        x += scaled_normal(z[k], s);
        o[t + k] += x;
      }
      state = x;
    });
  }
  std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const override {
    return internal::summed_size(a, b);
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // RW dominates the coarsest scale: gamma2 = nu^2(tau_J) / ((tau_J^2 + 2)/(12 tau_J)).
    const std::size_t n = std::min(ctx.tau.size(), ctx.wv.size());
    const double g = n ? ctx.wv[n - 1] / unit(ctx.tau[n - 1]) : 1.0;
    return {internal::positive_or(g, 1.0)};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(RandomWalk, "RW", "random walk: RW(gamma2)");

}  // namespace gmwm
