// ARMA11: x_t = phi x_{t-1} + e_t + theta e_{t-1}, e_t ~ N(0, sigma2).
// WV: the closed form of docs/statistics.md section 3 rewritten as (1 + theta)^2 AR1(phi, sigma2)
// - 2 theta sigma2 K(phi) (ar1_math.h), which stays accurate as phi -> 1; derivatives are
// exact (Jet). Autocovariance: g(0) = sigma2 (1 + 2 theta phi + theta^2)/(1 - phi^2),
// g(h) = phi^(h-1) sigma2 (1 + theta phi)(phi + theta)/(1 - phi^2) for h >= 1.
//
// Simulation starts exactly from the stationary distribution of the state
// (x_{-1}, e_{-1}): Var x = g(0), Var e = sigma2, Cov(x, e) = sigma2, i.e.
// x_{-1} = e_{-1} + sqrt(g(0) - sigma2) z with g(0) - sigma2 = sigma2 (phi + theta)^2 /
// (1 - phi^2). That is the limit of an infinitely long burn-in, so none is needed.
#include <cmath>

#include "ar1_math.h"
#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

using internal::Jet;

/// Lowest phi an initial guess proposes (as for AR1).
constexpr double kArma11GuessPhiMin = -0.9;

class Arma11Process final : public internal::JetDifferentiated<Arma11Process, 3> {
 public:
  explicit Arma11Process(const ProcessArgs&) {}
  std::string name() const override { return "ARMA11"; }
  int canonical_rank() const override { return 40; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{{"phi", Transform::kAtanh, "AR coefficient"},
                                                  {"theta", Transform::kAtanh, "MA coefficient"},
                                                  {"sigma2", Transform::kLog, "innovation variance per sample"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    const internal::Ar1UnitWv<double> ar1(theta[0]);
    for (std::size_t k = 0; k < tau.size(); ++k)
      out[k] =
          theta[2] * internal::arma11_unit_wv(ar1, theta[0], theta[1], internal::haar_half_scale(tau[k], "ARMA11::wv"));
  }
  template <class J>
  void derivatives(std::span<const double> theta, std::span<const double> tau, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) const {
    const J phi = J::variable(theta[0], 0);
    const J th = J::variable(theta[1], 1);
    const J s = J::variable(theta[2], 2);
    const internal::Ar1UnitWv<J> ar1(phi);
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const double m = internal::haar_half_scale(tau[k], "ARMA11::wv");
      internal::store_jet_row(s * internal::arma11_unit_wv(ar1, phi, th, m), static_cast<Eigen::Index>(k), jac, hess,
                              value);
    }
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    if (out.empty()) return;
    const double phi = theta[0], th = theta[1], s = theta[2];
    const double d = (1.0 - phi) * (1.0 + phi);
    out[0] = s * (1.0 + 2.0 * th * phi + th * th) / d;
    double c = s * (1.0 + th * phi) * (phi + th) / d;
    for (std::size_t h = 1; h < out.size(); ++h) {
      out[h] = c;
      c *= phi;
    }
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    const double phi = theta[0], th = theta[1];
    const double sd = std::sqrt(theta[2]);
    double start[2];
    rng.unit_normals(start, 2);
    double e_prev = sd * scaled_normal(start[0], 1.0);
    double x_prev =
        e_prev + sd * std::fabs(phi + th) / std::sqrt((1.0 - phi) * (1.0 + phi)) * scaled_normal(start[1], 1.0);
    double* o = out.data();
    for_unit_normals(rng, out.size(), [&](const double* z, std::size_t t, std::size_t m) {
      double xp = x_prev, ep = e_prev;  // locals: captured ones might alias o[]
      for (std::size_t k = 0; k < m; ++k) {
        const double e = sd * scaled_normal(z[k], 1.0);
        const double x = phi * xp + e + th * ep;
        o[t + k] += x;
        xp = x;
        ep = e;
      }
      x_prev = xp, e_prev = ep;
    });
  }
  // ARMA11(phi, 0) is AR1(phi); ARMA11(0, theta) is MA1(theta), hence WN and QN too.
  std::optional<std::vector<double>> represent(const Process& other,
                                               std::span<const double> other_theta) const override {
    if (other.name() == "AR1") return std::vector<double>{other_theta[0], 0.0, other_theta[1]};
    if (other.name() == "MA1") return std::vector<double>{0.0, other_theta[0], other_theta[1]};
    if (other.name() == "WN") return std::vector<double>{0.0, 0.0, other_theta[0]};
    if (other.name() == "QN") return std::vector<double>{0.0, -internal::phi_at_bound(), other_theta[0]};
    return Process::represent(other, other_theta);
  }
  std::vector<SimplerForm> simpler_forms(std::span<const double> theta) const override {
    const double phi = theta[0], th = theta[1], s2 = theta[2];
    return {{make_process("AR1", context()), {phi, s2 * (1.0 + th) * (1.0 + th)}, "AR1-like"},
            {make_process("MA1", context()), {th, s2}, "MA1-like"},
            {make_process("WN", context()), {s2 * (1.0 + th) * (1.0 + th) / ((1.0 - phi) * (1.0 - phi))}, "WN-like"}};
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    const auto g = internal::ar1_initial_guess(ctx, kArma11GuessPhiMin);
    return {g.phi, 0.0, g.sigma2};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(Arma11Process, "ARMA11", "ARMA(1,1): ARMA11(phi, theta, sigma2)");

}  // namespace gmwm
