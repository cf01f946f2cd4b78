// AR1: x_t = phi x_{t-1} + e_t, e_t ~ N(0, sigma2), |phi| < 1.
// WV: the closed form of docs/statistics.md section 3, evaluated stably near phi = 1 (ar1_math.h);
// jacobian and Hessian are the exact derivatives of that evaluation (Jet, jet.h).
// Autocovariance g(h) = sigma2 phi^h / (1 - phi^2). Simulation starts from the
// stationary distribution x_0 ~ N(0, sigma2 / (1 - phi^2)) (docs/statistics.md section 7).
#include <cmath>

#include "ar1_math.h"
#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

using internal::Jet;

/// Lowest phi an initial guess proposes (a WV peaking at the finest scale).
constexpr double kAr1GuessPhiMin = -0.9;

class Ar1Process final : public internal::JetDifferentiated<Ar1Process, 2>, public internal::Ar1PathSource {
 public:
  explicit Ar1Process(const ProcessArgs&) {}
  std::string name() const override { return "AR1"; }
  ProcessRole role() const override { return ProcessRole::kBias; }
  std::optional<double> correlation_samples(std::span<const double> theta) const override {
    if (!(theta[0] > 0.0 && theta[0] < 1.0)) return std::nullopt;
    return -1.0 / std::log(theta[0]);
  }
  int canonical_rank() const override { return 10; }
  int sort_key() const override { return 0; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{{"phi", Transform::kAtanh, "AR1 coefficient"},
                                                  {"sigma2", Transform::kLog, "AR1 innovation variance per sample"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    const internal::Ar1UnitWv<double> unit(theta[0]);
    for (std::size_t k = 0; k < tau.size(); ++k)
      out[k] = theta[1] * unit.at(internal::haar_half_scale(tau[k], "AR1::wv"));
  }
  template <class J>
  void derivatives(std::span<const double> theta, std::span<const double> tau, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) const {
    const J phi = J::variable(theta[0], 0);
    const J s = J::variable(theta[1], 1);
    const internal::Ar1UnitWv<J> unit(phi);
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const double m = internal::haar_half_scale(tau[k], "AR1::wv");
      internal::store_jet_row(s * unit.at(m), static_cast<Eigen::Index>(k), jac, hess, value);
    }
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    const double phi = theta[0];
    double c = theta[1] / ((1.0 - phi) * (1.0 + phi));
    for (double& v : out) {
      v = c;
      c *= phi;
    }
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    if (out.empty()) return;
    const internal::Ar1Path p = ar1_path(theta);
    internal::simulate_ar1_path(p.phi, p.sd, p.start_sd, rng, out);
  }
  // x_0 from the stationary sd sigma / sqrt(1 - phi^2), then phi x + sigma z.
  internal::Ar1Path ar1_path(std::span<const double> theta) const override {
    const double phi = theta[0];
    const double sd = std::sqrt(theta[1]);
    return {phi, sd, sd / std::sqrt((1.0 - phi) * (1.0 + phi))};
  }
  // The autocovariance decays as |phi|^h = exp(-h / (f T)): T = -1 / (f ln|phi|) seconds
  // (the envelope's when phi < 0; 0 at phi = 0, inf at |phi| = 1); the stationary sd is
  // sqrt(g(0)). ln|phi| = log1p(|phi| - 1) keeps its digits as |phi| -> 1.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    const double a = std::fabs(theta[0]);
    if (theta[0] <= 0.0 || a >= 1.0) return Process::kalman_impl(theta, freq, filter_rate);
    const double T = 1.0 / (freq * -std::log(a));
    return {gauss_markov_term(T, theta[1] / ((1.0 - a) * (1.0 + a)), filter_rate)};
  }
  // A first-order Gauss-Markov state, T = -1 / (f ln phi), s2 = sigma2 / (1 - phi^2): the
  // AR1's values at the samples exactly. A negative phi (an oscillating AR1) has none.
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    const double a = theta[0];
    if (!(a > 0.0 && a < 1.0)) return std::nullopt;
    return gauss_markov_form(1.0 / (freq * -std::log(a)), theta[1] / ((1.0 - a) * (1.0 + a)), 1.0 / freq);
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const override {
    const double a = std::fabs(theta[0]);
    const double T = a >= 1.0 ? INFINITY : 1.0 / (freq * -std::log1p(a - 1.0));
    return {{"correlation time", T, "s",
             "T = -1 / (f ln|phi|) (autocovariance ~ exp(-|lag| / T); for phi < 0 its envelope)",
             PhysicalKind::kCorrelationTime},
            {"stationary sigma", std::sqrt(theta[1] / ((1.0 - a) * (1.0 + a))), "U",
             "sigma = sqrt(sigma2 / (1 - phi^2)), the process's standard deviation", PhysicalKind::kStationarySigma}};
  }
  // AR1(phi = 0, sigma2) is WN(sigma2); as phi -> 1 with sigma2 fixed its WV tends to
  // RW(gamma2 = sigma2)'s (the AR1 forgets nothing over the record, a constant aside).
  std::optional<std::vector<double>> represent(const Process& other,
                                               std::span<const double> other_theta) const override {
    if (other.name() == "WN") return std::vector<double>{0.0, other_theta[0]};
    if (other.name() == "RW") return std::vector<double>{internal::phi_at_bound(), other_theta[0]};
    return Process::represent(other, other_theta);
  }
  // WN-like: the same long-run variance sigma2 / (1 - phi)^2 (the spectral density at 0,
  // which sets the WV at scales beyond the correlation time); RW-like: gamma2 = sigma2.
  std::vector<SimplerForm> simpler_forms(std::span<const double> theta) const override {
    const double phi = theta[0], s2 = theta[1];
    return {{make_process("WN", context()), {s2 / ((1.0 - phi) * (1.0 - phi))}, "WN-like"},
            {make_process("RW", context()), {s2}, "RW-like"}};
  }
  // Its shapes: phi over correlation times covering the scales (ar1_math.h).
  std::vector<std::vector<double>> shape_family(std::span<const double> theta,
                                                std::span<const double> tau) const override {
    std::vector<std::vector<double>> out;
    for (double phi : internal::ar1_shape_phis(tau)) out.push_back({phi, theta[1]});
    return out;
  }
  // Two AR1s at one phi are one AR1 (sigma2 adds); at different phis the candidate takes
  // the long-run-variance-weighted phi, for the caller to test.
  std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const override {
    const double wa = a[1] / ((1.0 - a[0]) * (1.0 - a[0])), wb = b[1] / ((1.0 - b[0]) * (1.0 - b[0]));
    const double phi = (wa * a[0] + wb * b[0]) / (wa + wb);
    if (!(std::fabs(phi) < 1.0)) return std::nullopt;
    return std::vector<double>{phi, a[1] + b[1]};
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    const auto g = internal::ar1_initial_guess(ctx, kAr1GuessPhiMin);
    return {g.phi, g.sigma2};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(Ar1Process, "AR1", "first-order autoregression: AR1(phi, sigma2)");

}  // namespace gmwm
