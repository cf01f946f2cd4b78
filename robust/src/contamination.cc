#include "gmwm/robust/contamination.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/tools/roots.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/parallel.h"

namespace gmwm::robust {
namespace {

// Beyond this many quanta of standard deviation the lattice no longer matters: the
// discretised Gaussian's robust/classical ratio is 1 to better than 1e-6 there.
constexpr double kNegligibleLatticeSd = 30.0;
// The rounding model is exact at level 1 only under its uniform-phase assumption and
// approximate beyond; the flag allows this relative slack on the expected ratio.
// Measured on the clean ADIS recordings (tools/bench/bench_robust.cc, section 4): where
// robust < classical (the direction that matters), observed / expected departs from 1 by
// up to 0.098 at levels 1-2 (accel_z of imu2); the gyro_z axes reach 0.16 the other way
// (robust above classical, a 5-sample oscillation, never flagged). The far-tail
// criterion is what keeps the flag off on rounded clean data; this slack is a second
// guard.
constexpr double kRoundingModelTolerance = 0.10;
// Far outliers: beyond 5 sd a Gaussian (or a rounded Gaussian) has a share of 5.7e-7;
// an excess of 100 times that (and of three effective windows, 3 / eta) is not noise.
constexpr double kTailSd = 5.0;
constexpr double kTailExcess = 100.0;
constexpr double kTailWindows = 3.0;

// P(K = k) for k = -kmax..kmax under Y ~ N(0, sigma^2) plus the rounding kernel of tau
// samples (triangle on [-1, 1] for tau = 2, Gaussian of variance tau/12 otherwise).
std::vector<double> lattice_pmf(double sigma, double tau, int& kmax) {
  const double kernel_var = tau <= 2.0 ? 1.0 / 6.0 : tau / 12.0;
  const double total_sd = std::sqrt(sigma * sigma + kernel_var);
  kmax = static_cast<int>(std::ceil(12.0 * total_sd)) + 2;
  std::vector<double> p(static_cast<std::size_t>(2 * kmax + 1));
  if (tau <= 2.0) {
    // E[max(0, 1 - |k - Y|)] = int_{k-1}^{k} (y - k + 1) phi + int_k^{k+1} (k + 1 - y) phi,
    // with int (y - a) phi_s(y) dy = -s^2 phi_s(y) - a Phi_s(y) on each piece.
    const boost::math::normal_distribution<double> N(0.0, std::max(sigma, 1e-300));
    auto F = [&](double y) { return boost::math::cdf(N, y); };
    auto f = [&](double y) { return boost::math::pdf(N, y); };
    auto G = [&](double y, double a) { return -sigma * sigma * f(y) - a * F(y); };  // antiderivative of (y - a) phi
    for (int k = -kmax; k <= kmax; ++k) {
      const double left = G(k, k - 1.0) - G(k - 1.0, k - 1.0);      // int (y - (k-1)) phi over [k-1, k]
      const double right = -(G(k + 1.0, k + 1.0) - G(k, k + 1.0));  // int ((k+1) - y) phi over [k, k+1]
      p[static_cast<std::size_t>(k + kmax)] = std::max(0.0, left + right);
    }
  } else {
    const boost::math::normal_distribution<double> N(0.0, total_sd);
    for (int k = -kmax; k <= kmax; ++k)
      p[static_cast<std::size_t>(k + kmax)] = boost::math::cdf(N, k + 0.5) - boost::math::cdf(N, k - 0.5);
  }
  double sum = 0.0;
  for (double v : p) sum += v;
  for (double& v : p) v /= sum;
  return p;
}

double second_moment(const std::vector<double>& p, int kmax) {
  double m = 0.0;
  for (int k = -kmax; k <= kmax; ++k) m += p[static_cast<std::size_t>(k + kmax)] * k * k;
  return m;
}

// Root in s of sum_k p_k chi(k^2 / s) = a (the upper one for bisquare), or NaN.
double lattice_scale(const Tuning& t, const std::vector<double>& p, int kmax, double start) {
  auto g = [&](double s) {
    double v = 0.0;
    for (int k = -kmax; k <= kmax; ++k)
      v += p[static_cast<std::size_t>(k + kmax)] * chi(t.kind, t.c, k * double(k) / s);
    return v - t.a;
  };
  double hi = start;
  int guard = 0;
  while (g(hi) >= 0.0 && guard++ < 200) hi *= 2.0;
  double lo = hi;
  guard = 0;
  do {
    lo *= 0.5;
  } while (g(lo) <= 0.0 && guard++ < 200);
  if (!(g(lo) > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  std::uintmax_t it = 200;
  const auto r = boost::math::tools::toms748_solve(g, lo, lo * 2.0 > hi ? hi : lo * 2.0,
                                                   boost::math::tools::eps_tolerance<double>(40), it);
  return 0.5 * (r.first + r.second);
}

}  // namespace

double rounding_ratio(const Tuning& t, double classical_wv, double tau, double quantum) {
  if (!(quantum > 0.0) || !(classical_wv > 0.0)) return 1.0;
  // Observed second moment of K = tau W / q.
  const double target = classical_wv * tau * tau / (quantum * quantum);
  if (std::sqrt(target) > kNegligibleLatticeSd) return 1.0;
  // sigma of the continuous part so that E[K^2] = target (E[K^2] increases with sigma).
  int kmax = 0;
  auto moment = [&](double sigma) {
    const auto p = lattice_pmf(sigma, tau, kmax);
    return second_moment(p, kmax) - target;
  };
  const double kernel_var = tau <= 2.0 ? 1.0 / 6.0 : tau / 12.0;
  if (moment(1e-9) >= 0.0) return 1.0;  // no room for a continuous part: model does not apply
  double hi = std::sqrt(std::max(target, kernel_var)) + 1.0;
  while (moment(hi) < 0.0) hi *= 2.0;
  std::uintmax_t it = 200;
  const auto r = boost::math::tools::toms748_solve(moment, 1e-9, hi, boost::math::tools::eps_tolerance<double>(40), it);
  const double sigma = 0.5 * (r.first + r.second);
  const auto p = lattice_pmf(sigma, tau, kmax);
  const double m2 = second_moment(p, kmax);
  const double s = lattice_scale(t, p, kmax, m2);
  return std::isfinite(s) ? s / m2 : 1.0;
}

std::vector<LevelDiagnostic> contamination_diagnostic(const double* x, std::int64_t n, const WaveletVariance& robust,
                                                      const WaveletVariance& classical,
                                                      const Quantization& quantization, const Tuning& tuning) {
  check_size_match("contamination_diagnostic", "robust levels", robust.wv.size(), "classical levels",
                   classical.wv.size());
  return contamination_diagnostic(HaarModwt(x, n), robust, classical, quantization, tuning);
}

namespace {

// The diagnostic of each level from `far_share(level, threshold)`: the share of the level's
// coefficients whose square exceeds the threshold.
template <class FarShare>
std::vector<LevelDiagnostic> diagnose(const WaveletVariance& robust, const WaveletVariance& classical,
                                      const Quantization& quantization, const Tuning& tuning, FarShare&& far_share) {
  check_size_match("contamination_diagnostic", "robust levels", robust.wv.size(), "classical levels",
                   classical.wv.size());
  std::vector<LevelDiagnostic> out(robust.wv.size());
  const double gaussian_tail =
      2.0 * boost::math::cdf(boost::math::complement(boost::math::normal_distribution<double>(), kTailSd));
  gmwm::parallel_for(std::size_t{0}, out.size(), [&](std::size_t j) {
    if (!(robust.wv[j] > 0.0)) return;
    const int level = first_level(robust) + static_cast<int>(j);  // a cut WV starts above level 1
    out[j].tail_share = far_share(level, kTailSd * kTailSd * robust.wv[j]);
  });
  for (std::size_t j = 0; j < out.size(); ++j) {
    LevelDiagnostic& d = out[j];
    d.classical_wv = classical.wv[j];
    d.robust_to_classical = robust.wv[j] / classical.wv[j];
    if (!std::isfinite(robust.wv[j])) continue;
    d.ci_disjoint = robust.ci_high[j] < classical.ci_low[j] || robust.ci_low[j] > classical.ci_high[j];
    d.expected_ratio =
        quantization.detected ? rounding_ratio(tuning, classical.wv[j], classical.tau[j], quantization.quantum) : 1.0;
    const double slack = (d.expected_ratio != 1.0) ? kRoundingModelTolerance : 0.0;
    const double classical_eta = classical.eta[j];
    const bool tails = d.tail_share > std::max(kTailExcess * gaussian_tail, kTailWindows / classical_eta);
    d.contaminated = tails && robust.ci_high[j] / (d.expected_ratio * (1.0 - slack)) < classical.ci_low[j];
  }
  return out;
}

}  // namespace

std::vector<LevelDiagnostic> contamination_diagnostic(const HaarModwt& modwt, const WaveletVariance& robust,
                                                      const WaveletVariance& classical,
                                                      const Quantization& quantization, const Tuning& tuning) {
  // Counted from the prefix sums: materialising the level's 8 MB of coefficients to count
  // them was 10% of `wv --robust` (issue 44).
  return diagnose(robust, classical, quantization, tuning, [&](int level, double threshold) {
    const std::int64_t M = modwt.count(level);
    const std::int64_t far = modwt.count_above(level, threshold);
    return M > 0 ? static_cast<double>(far) / static_cast<double>(M) : 0.0;
  });
}

std::vector<LevelDiagnostic> contamination_diagnostic_with_gaps(
    std::span<const double> observed, std::span<const MissingRun> missing, const WaveletVariance& robust,
    const WaveletVariance& classical, const Quantization& quantization, const Tuning& tuning) {
  const GappyWindows windows(observed, missing);
  return diagnose(robust, classical, quantization, tuning, [&](int level, double threshold) {
    thread_local std::vector<double> coef;
    windows.coefficients(level, coef);
    const auto far = std::count_if(coef.begin(), coef.end(), [&](double c) { return c * c > threshold; });
    return coef.empty() ? 0.0 : static_cast<double>(far) / static_cast<double>(coef.size());
  });
}

}  // namespace gmwm::robust
