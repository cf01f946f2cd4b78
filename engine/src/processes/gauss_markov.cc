// GM: first-order Gauss-Markov process with inverse correlation time beta (1/s) and
// stationary variance sigma2_gm, sampled at context().freq Hz. It is an AR1 with
//   phi = exp(-beta / f),  sigma2 = sigma2_gm (1 - exp(-2 beta / f)),
// evaluated through L = beta / f directly (ar1_math.h), so no precision is lost in
// forming 1 - phi when beta << f. Derivatives are exact (Jet, jet.h).
#include <cmath>
#include <sstream>

#include "ar1_math.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

using internal::Jet;

/// beta / f where GM stands for a white noise (phi = e^-40 = 4e-18, zero in double) and
/// for a random walk (1 - phi = 1e-15: its WV is RW's within ~tau 1e-15 relative).
constexpr double kGmWhiteL = 40.0;
constexpr double kGmWalkL = 1e-15;

/// Lowest phi = exp(-beta/f) an initial guess proposes (beta = 3 f).
constexpr double kGmGuessPhiMin = 0.05;

class GaussMarkov final : public internal::JetDifferentiated<GaussMarkov, 2>, public internal::Ar1PathSource {
 public:
  explicit GaussMarkov(const ProcessArgs& args) {
    const double f = args.context.freq;
    if (!(f > 0.0) || !std::isfinite(f)) {
      std::ostringstream os;
      os << "GM needs a positive, finite sampling rate (got " << f << " Hz)";
      throw InputError(os.str());
    }
  }
  std::string name() const override { return "GM"; }
  ProcessRole role() const override { return ProcessRole::kBias; }
  // T = 1 / beta seconds, f / beta samples.
  std::optional<double> correlation_samples(std::span<const double> theta) const override {
    if (!(theta[0] > 0.0)) return std::nullopt;
    return rate() / theta[0];
  }
  int canonical_rank() const override { return 20; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"beta", Transform::kLog, "inverse correlation time (1/s at the sampling rate)"},
        {"sigma2_gm", Transform::kLog, "stationary variance"}};
    return specs;
  }
  double rate() const { return context().freq; }
  // The data times sqrt(c): the stationary variance times c, the correlation time as it is.
  std::vector<double> scaled(std::span<const double> theta, double c) const override {
    return {theta[0], theta[1] * c};
  }

  /// nu^2 at every tau: sigma2_gm (1 - phi^2) x the AR1 unit WV, phi = exp(-beta / rate).
  template <class T, class Store>
  void wv_levels(const T& beta, const T& s2gm, std::span<const double> tau, Store store) const {
    using std::expm1;
    const T L = beta / rate();
    const T stationary = s2gm * (-expm1(-2.0 * L));
    const internal::Ar1LogForm<T> unit(L);
    for (std::size_t k = 0; k < tau.size(); ++k)
      store(k, stationary * unit.at(internal::haar_half_scale(tau[k], "GM::wv")));
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    wv_levels(theta[0], theta[1], tau, [&](std::size_t k, double v) { out[k] = v; });
  }
  template <class J>
  void derivatives(std::span<const double> theta, std::span<const double> tau, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) const {
    const J beta = J::variable(theta[0], 0);
    const J s = J::variable(theta[1], 1);
    wv_levels(beta, s, tau, [&](std::size_t k, const J& v) {
      internal::store_jet_row(v, static_cast<Eigen::Index>(k), jac, hess, value);
    });
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    const double L = theta[0] / rate();
    for (std::size_t h = 0; h < out.size(); ++h) out[h] = theta[1] * std::exp(-L * static_cast<double>(h));
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    if (out.empty()) return;
    const internal::Ar1Path p = ar1_path(theta);
    internal::simulate_ar1_path(p.phi, p.sd, p.start_sd, rng, out);
  }
  // phi = exp(-beta / f), innovation sd sqrt(sigma2_gm (1 - phi^2)), a stationary start.
  internal::Ar1Path ar1_path(std::span<const double> theta) const override {
    const double L = theta[0] / rate();
    return {std::exp(-L), std::sqrt(theta[1] * -std::expm1(-2.0 * L)), std::sqrt(theta[1])};
  }
  // beta and sigma2_gm are continuous already: T = 1 / beta (= -1 / (f ln phi) of the
  // equivalent AR1, phi = exp(-beta / f)), sigma = sqrt(sigma2_gm). freq is not needed.
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double, double filter_rate) const override {
    return {gauss_markov_term(1.0 / theta[0], theta[1], filter_rate)};
  }
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    return gauss_markov_form(1.0 / theta[0], theta[1], 1.0 / freq);
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double) const override {
    return {{"correlation time", 1.0 / theta[0], "s", "T = 1 / beta (autocovariance sigma^2 exp(-|lag| / T))",
             PhysicalKind::kCorrelationTime},
            {"stationary sigma", std::sqrt(theta[1]), "U", "sigma = sqrt(sigma2_gm), the process's standard deviation",
             PhysicalKind::kStationarySigma}};
  }
  // GM is AR1 through the rate: phi = exp(-beta / f), sigma2 = sigma2_gm (1 - phi^2).
  // A very short correlation time (beta / f = kGmWhiteL) is WN(sigma2_gm); a very long one
  // (beta / f = kGmWalkL) with sigma2_gm = gamma2 / (1 - exp(-2 beta / f)) is RW(gamma2).
  std::optional<std::vector<double>> represent(const Process& other,
                                               std::span<const double> other_theta) const override {
    const double f = rate();
    if (other.name() == "WN") return std::vector<double>{kGmWhiteL * f, other_theta[0]};
    if (other.name() == "RW") return std::vector<double>{kGmWalkL * f, other_theta[0] / -std::expm1(-2.0 * kGmWalkL)};
    if (other.name() == "AR1" && other_theta[0] > 0.0) {
      const double L = -std::log(other_theta[0]);
      return std::vector<double>{L * f, other_theta[1] / -std::expm1(-2.0 * L)};
    }
    return Process::represent(other, other_theta);
  }
  // Its shapes: an AR1's with phi > 0 (ar1_math.h), as beta = -f ln(phi).
  std::vector<std::vector<double>> shape_family(std::span<const double> theta,
                                                std::span<const double> tau) const override {
    std::vector<std::vector<double>> out;
    for (double phi : internal::ar1_shape_phis(tau))
      if (phi > 0.0) out.push_back({-std::log(phi) * rate(), theta[1]});
    return out;
  }
  std::vector<SimplerForm> simpler_forms(std::span<const double> theta) const override {
    const double L = theta[0] / rate(), phi = std::exp(-L);
    const double innovation = theta[1] * -std::expm1(-2.0 * L);
    return {{make_process("WN", context()), {theta[1] * (1.0 + phi) / (1.0 - phi)}, "WN-like"},
            {make_process("RW", context()), {innovation}, "RW-like"}};
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    const auto g = internal::ar1_initial_guess(ctx, kGmGuessPhiMin);
    const double L = -std::log1p(g.phi - 1.0);
    return {L * rate(), g.sigma2 / -std::expm1(-2.0 * L)};
  }
};

}  // namespace

GMWM_REGISTER_PROCESS(GaussMarkov, "GM", "Gauss-Markov: GM(beta, sigma2_gm), an AR1 through the sampling rate");

}  // namespace gmwm
