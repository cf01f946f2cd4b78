// MA1: x_t = e_t + theta e_{t-1}, e_t ~ N(0, sigma2), |theta| < 1 (invertible).
// nu^2(tau) = sigma2 ((1 + theta)^2 tau - 6 theta) / tau^2 (docs/statistics.md section 3);
// g(0) = sigma2 (1 + theta^2), g(1) = sigma2 theta, g(h) = 0 beyond. Simulation draws
// e_{-1} as well, so the path is stationary from its first sample (no burn-in needed).
#include <algorithm>
#include <cmath>

#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

/// theta proposed by initial_guess: 0, where the WV is that of a white noise and the
/// optimiser's gradient in theta, sigma2 (2 tau - 6)/tau^2, is non-zero.
constexpr double kMa1GuessTheta = 0.0;

class Ma1Process final : public Process {
 public:
  explicit Ma1Process(const ProcessArgs&) {}
  std::string name() const override { return "MA1"; }
  int canonical_rank() const override { return 30; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{{"theta", Transform::kAtanh, "MA1 coefficient"},
                                                  {"sigma2", Transform::kLog, "MA1 innovation variance per sample"}};
    return specs;
  }
  static double unit(double theta, double tau) {
    return ((1.0 + theta) * (1.0 + theta) * tau - 6.0 * theta) / (tau * tau);
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[1] * unit(theta[0], tau[k]);
  }
  void wv_jacobian(std::span<const double> theta, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const auto r = static_cast<Eigen::Index>(k);
      const double t = tau[k];
      jac(r, 0) = theta[1] * (2.0 * (1.0 + theta[0]) * t - 6.0) / (t * t);
      jac(r, 1) = unit(theta[0], t);
    }
  }
  void wv_hessian(std::span<const double> theta, std::span<const double> tau,
                  Eigen::Ref<Eigen::MatrixXd> hess) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const auto r = static_cast<Eigen::Index>(k);
      const double t = tau[k];
      const double cross = (2.0 * (1.0 + theta[0]) * t - 6.0) / (t * t);
      hess(r, 0) = 2.0 * theta[1] / t;  // (theta, theta)
      hess(r, 1) = cross;               // (theta, sigma2)
      hess(r, 2) = cross;               // (sigma2, theta)
      hess(r, 3) = 0.0;                 // (sigma2, sigma2)
    }
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    std::fill(out.begin(), out.end(), 0.0);
    if (out.size() > 0) out[0] = theta[1] * (1.0 + theta[0] * theta[0]);
    if (out.size() > 1) out[1] = theta[1] * theta[0];
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    const double s = std::sqrt(theta[1]);
    double prev = 0.0;
    rng.unit_normals(&prev, 1);
    prev = scaled_normal(prev, s);  // e_{-1}
    double* o = out.data();
    for_unit_normals(rng, out.size(), [&](const double* z, std::size_t t, std::size_t m) {
      double p = prev;  // a local: a captured one might alias o[]
      const double th = theta[0];
      for (std::size_t k = 0; k < m; ++k) {
        const double e = scaled_normal(z[k], s);
        o[t + k] += e + th * p;
        p = e;
      }
      prev = p;
    });
  }
  // MA1(theta = 0) is WN(sigma2); MA1(theta -> -1) is QN(Q2 = sigma2): its WV is
  // sigma2 (1 + theta)^2 / tau + 6 (-theta sigma2) / tau^2, i.e. WN + QN for theta <= 0.
  std::optional<std::vector<double>> represent(const Process& other,
                                               std::span<const double> other_theta) const override {
    if (other.name() == "WN") return std::vector<double>{0.0, other_theta[0]};
    if (other.name() == "QN") return std::vector<double>{-internal::phi_at_bound(), other_theta[0]};
    return Process::represent(other, other_theta);
  }
  std::vector<SimplerForm> simpler_forms(std::span<const double> theta) const override {
    const double th = theta[0], s2 = theta[1];
    std::vector<SimplerForm> out{{make_process("WN", context()), {s2 * (1.0 + th) * (1.0 + th)}, "WN-like"}};
    if (th < 0.0) out.push_back({make_process("QN", context()), {-th * s2}, "QN-like"});
    return out;
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    double s = 1.0;
    if (std::min(ctx.tau.size(), ctx.wv.size()) > 0) {
      const std::size_t k = internal::guess_level(ctx);
      s = internal::positive_or(ctx.wv[k] / unit(kMa1GuessTheta, ctx.tau[k]), 1.0);
    }
    return {kMa1GuessTheta, s};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(Ma1Process, "MA1", "first-order moving average: MA1(theta, sigma2)");

}  // namespace gmwm
