// ARMA(p, q), registered as "ARMA" with structural arguments p and q:
//   x_t = sum_{i=1}^p phi_i x_{t-i} + e_t + sum_{j=1}^q theta_j e_{t-j}, e_t ~ N(0, sigma2).
// Parameters phi1..phip, theta1..thetaq (identity transform; validate() rejects a
// non-stationary AR or non-invertible MA polynomial), sigma2 (log).
// WV and autocovariance are exact (arma_math.h: covariance equations, no truncated
// MA(infinity) sums), with exact first and second derivatives.
//
// Simulation draws the initial state (x_{-1..-p}, e_{-1..-q}) from its exact stationary
// distribution (covariances gamma(|i - j|), sigma2 psi_{j-i}, sigma2 I), so the path is
// stationary from its first sample: this is the limit of an infinitely long burn-in,
// and the burn-in rule is therefore "none needed", whatever the AR roots.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "ar1_math.h"
#include "arma_math.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

/// Lowest phi1 an initial guess proposes (as for AR1).
constexpr double kArmaGuessPhiMin = -0.9;

long structural_order(const ProcessArgs& args, const char* key) {
  const auto it = args.structural.find(key);
  if (it == args.structural.end()) {
    std::ostringstream os;
    os << "ARMA needs the structural arguments p and q, e.g. ARMA(p=2,q=1): " << key << " is missing";
    throw InputError(os.str());
  }
  if (it->second < 0 || it->second > internal::kArmaMaxOrder) {
    std::ostringstream os;
    os << "ARMA: " << key << " must be an integer between 0 and " << internal::kArmaMaxOrder << " (got " << it->second
       << ")";
    throw InputError(os.str());
  }
  return it->second;
}

class ArmaProcess final : public Process {
 public:
  explicit ArmaProcess(const ProcessArgs& args) {
    for (const auto& [key, value] : args.structural)
      if (key != "p" && key != "q")
        throw InputError("ARMA: unknown structural argument '" + key + "' (expected p and q)");
    p_ = static_cast<int>(structural_order(args, "p"));
    q_ = static_cast<int>(structural_order(args, "q"));
    if (p_ + q_ == 0) throw InputError("ARMA(p=0,q=0) is a white noise: use WN instead");
    for (int i = 1; i <= p_; ++i)
      specs_.push_back({"phi" + std::to_string(i), Transform::kIdentity, "AR coefficient at lag " + std::to_string(i)});
    for (int j = 1; j <= q_; ++j)
      specs_.push_back(
          {"theta" + std::to_string(j), Transform::kIdentity, "MA coefficient at lag " + std::to_string(j)});
    specs_.push_back({"sigma2", Transform::kLog, "innovation variance per sample"});
  }
  std::string name() const override { return "ARMA"; }
  std::string structure() const override { return "p=" + std::to_string(p_) + ",q=" + std::to_string(q_); }
  int canonical_rank() const override { return 45; }
  const std::vector<ParameterSpec>& parameters() const override { return specs_; }
  bool needs_whole_scales() const override { return true; }  // sums its autocovariance over lags

  std::span<const double> phi(std::span<const double> t) const { return t.subspan(0, p_); }
  std::span<const double> theta(std::span<const double> t) const { return t.subspan(p_, q_); }

  std::string validate(std::span<const double> t) const override {
    std::string why = Process::validate(t);
    if (!why.empty()) return why;
    if (internal::first_unstable_reflection(phi(t)) != 0)
      return polynomial_message("phi", p_, "non-stationary", "1 - phi1 z - ...");
    std::vector<double> neg(theta(t).begin(), theta(t).end());
    for (double& x : neg) x = -x;
    if (internal::first_unstable_reflection(neg) != 0)
      return polynomial_message("theta", q_, "non-invertible", "1 + theta1 z + ...");
    return {};
  }
  std::string polynomial_message(const char* what, int order, const char* property, const char* poly) const {
    std::ostringstream os;
    os << "ARMA(" << structure() << "): " << what << "1";
    if (order > 1) os << ".." << what << order;
    os << " make the " << (what[0] == 'p' ? "AR" : "MA") << " polynomial " << property << " (a root of " << poly
       << " lies on or inside the unit circle)";
    return os.str();
  }

  void wv(std::span<const double> t, std::span<const double> tau, std::span<double> out) const override {
    const auto r = internal::arma_unit_wv(phi(t), theta(t), tau, 0);
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = t[static_cast<std::size_t>(p_ + q_)] * r[k].v;
  }
  void wv_jacobian(std::span<const double> t, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    const int n = p_ + q_;
    const double s = t[static_cast<std::size_t>(n)];
    const auto r = internal::arma_unit_wv(phi(t), theta(t), tau, 1);
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      for (int l = 0; l < n; ++l) jac(row, l) = s * r[k].g(l);
      jac(row, n) = r[k].v;
    }
  }
  void wv_hessian(std::span<const double> t, std::span<const double> tau,
                  Eigen::Ref<Eigen::MatrixXd> hess) const override {
    const int n = p_ + q_, np = n + 1;
    const double s = t[static_cast<std::size_t>(n)];
    const auto r = internal::arma_unit_wv(phi(t), theta(t), tau, 2);
    for (std::size_t k = 0; k < tau.size(); ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      for (int l = 0; l < n; ++l) {
        for (int m = 0; m < n; ++m) hess(row, l * np + m) = s * r[k].h(l, m);
        hess(row, l * np + n) = r[k].g(l);  // d2 / d coef_l d sigma2
        hess(row, n * np + l) = r[k].g(l);
      }
      hess(row, n * np + n) = 0.0;
    }
  }
  void generalized_autocovariance(std::span<const double> t, std::span<double> out) const override {
    internal::arma_unit_autocovariance(phi(t), theta(t), out);
    for (double& v : out) v *= t[static_cast<std::size_t>(p_ + q_)];
  }

  void simulate(std::span<const double> t, Rng& rng, std::span<double> out) const override {
    const double s = t[static_cast<std::size_t>(p_ + q_)];
    const auto ph = phi(t), th = theta(t);
    // Stationary covariance of the state (x_{-1}..x_{-p}, e_{-1}..e_{-q}).
    const int d = p_ + q_;
    std::vector<double> gamma(static_cast<std::size_t>(std::max(p_, 1)));
    internal::arma_unit_autocovariance(ph, th, gamma);
    const auto psi = internal::arma_psi_weights(ph, th, static_cast<std::size_t>(std::max(q_, 1)));
    // Per unit sigma2, its root times sqrt(sigma2): sigma2 times the unit covariance (1e3
    // for phi1 = 0.999) overflowed for sigma2 near 1e308, and the eigen solver's NaN
    // became every sample.
    Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(d, d);
    for (int i = 0; i < p_; ++i)
      for (int j = 0; j < p_; ++j) cov(i, j) = gamma[static_cast<std::size_t>(std::abs(i - j))];
    for (int j = 0; j < q_; ++j) cov(p_ + j, p_ + j) = 1.0;
    for (int i = 0; i < p_; ++i)  // Cov(x_{-1-i}, e_{-1-j}) = sigma2 psi_{j-i}, j >= i
      for (int j = i; j < q_; ++j) cov(i, p_ + j) = cov(p_ + j, i) = psi[static_cast<std::size_t>(j - i)];
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
    const Eigen::MatrixXd root =
        std::sqrt(s) * eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    Eigen::VectorXd draw(d);
    rng.unit_normals(draw.data(), static_cast<std::size_t>(d));
    for (int i = 0; i < d; ++i) draw(i) = scaled_normal(draw(i), 1.0);
    const Eigen::VectorXd state = root * draw;
    // x_hist[i] = x_{t-1-i}, e_hist[j] = e_{t-1-j}.
    std::vector<double> x_hist(state.data(), state.data() + p_);
    std::vector<double> e_hist(state.data() + p_, state.data() + d);
    const double sd = std::sqrt(s);
    double* o = out.data();
    for_unit_normals(rng, out.size(), [&](const double* z, std::size_t t0, std::size_t m) {
      for (std::size_t k = 0; k < m; ++k) {
        const double e = sd * scaled_normal(z[k], 1.0);
        double x = e;
        for (int i = 0; i < p_; ++i) x += ph[static_cast<std::size_t>(i)] * x_hist[static_cast<std::size_t>(i)];
        for (int j = 0; j < q_; ++j) x += th[static_cast<std::size_t>(j)] * e_hist[static_cast<std::size_t>(j)];
        o[t0 + k] += x;
        if (p_ > 0) {
          std::rotate(x_hist.rbegin(), x_hist.rbegin() + 1, x_hist.rend());
          x_hist[0] = x;
        }
        if (q_ > 0) {
          std::rotate(e_hist.rbegin(), e_hist.rbegin() + 1, e_hist.rend());
          e_hist[0] = e;
        }
      }
    });
  }

  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // phi1 as an AR1 peaking at the hint, other coefficients 0, sigma2 matching ctx.wv.
    std::vector<double> g(static_cast<std::size_t>(p_ + q_ + 1), 0.0);
    if (p_ > 0) g[0] = internal::ar1_initial_guess(ctx, kArmaGuessPhiMin).phi;
    g.back() = 1.0;
    if (std::min(ctx.tau.size(), ctx.wv.size()) > 0) {
      const std::size_t k = internal::guess_level(ctx);
      const double tau = std::max(2.0, 2.0 * std::round(0.5 * ctx.tau[k]));
      const double unit = internal::arma_unit_wv(phi(g), theta(g), std::span(&tau, 1), 0)[0].v;
      g.back() = internal::positive_or(ctx.wv[k] / unit, 1.0);
    }
    return g;
  }

 private:
  int p_ = 0;
  int q_ = 0;
  std::vector<ParameterSpec> specs_;
};

}  // namespace

GMWM_REGISTER_PROCESS(ArmaProcess, "ARMA", "ARMA(p,q): ARMA(p=.., q=..) with phi1..phip, theta1..thetaq, sigma2", "p",
                      "q");

}  // namespace gmwm
