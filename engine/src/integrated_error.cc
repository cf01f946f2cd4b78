#include "gmwm/engine/integrated_error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>

#include "gmwm/engine/check.h"
#include "gmwm/engine/process.h"

namespace gmwm {
namespace {

/// Relative difference between the freq argument and a component's known rate beyond
/// which they are taken to be different rates (rounding of a rate written in decimal).
constexpr double kRateTolerance = 1e-9;

/// Neumaier's compensated sum: the recursions below add up to kMaxIntegratedSamples
/// terms of both signs (SIN, QN), where plain summation would lose digits.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    comp_ += std::fabs(sum_) >= std::fabs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + comp_; }

 private:
  double sum_ = 0.0, comp_ = 0.0;
};

std::vector<std::int64_t> sample_counts(double freq, std::span<const double> horizons) {
  constexpr const char* kFn = "integrated_error";
  check_positive(kFn, "freq", freq);
  std::vector<std::int64_t> counts;
  for (double h : horizons) {
    check_positive(kFn, "horizon_seconds", h);
    const double samples = h * freq;
    check_at_least(kFn, "horizon_seconds * freq (samples)", samples, 0.5);
    if (!(samples < static_cast<double>(kMaxIntegratedSamples) + 0.5))
      detail::throw_check(kFn, "horizon_seconds * freq (samples)", samples,
                          "at most " + std::to_string(kMaxIntegratedSamples));
    counts.push_back(std::llround(samples));
  }
  return counts;
}

void check_model(const Model& model, const Eigen::VectorXd& theta, double freq) {
  const std::string why = model.validate(theta);
  if (!why.empty()) throw InvalidArgument("integrated_error: " + why);
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    const ProcessContext& ctx = p.context();
    if (ctx.freq_known && std::fabs(ctx.freq - freq) > kRateTolerance * ctx.freq) {
      std::ostringstream req;
      req.precision(17);
      req << "the rate component " << c + 1 << " (" << p.name() << ") was built with, " << ctx.freq << " Hz";
      detail::throw_check("integrated_error", "freq", freq, req.str());
    }
  }
}

}  // namespace

std::vector<SumMoments> Process::sum_moments(std::span<const double> theta,
                                             std::span<const std::int64_t> counts) const {
  std::vector<SumMoments> out(counts.size());
  if (counts.empty()) return out;
  for (std::int64_t k : counts) check_at_least("Process::sum_moments", "K", static_cast<double>(k), 1.0);
  // Counts in increasing order, walked through once.
  std::vector<std::size_t> order(counts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return counts[a] < counts[b]; });
  const auto kmax = static_cast<std::size_t>(counts[order.back()]);
  std::vector<double> g(kmax);
  generalized_autocovariance(theta, g);
  // V(n) = Var(x_1 + ... + x_n) = V(n-1) + 2 G(n-1) - g(0), G(n-1) = g(0) + ... + g(n-1):
  // the new sample's variance plus twice its covariances with the n-1 before it. Equals
  // n g(0) + 2 sum_{h=1}^{n-1} (n - h) g(h).
  CompensatedSum v, cum;
  std::size_t next = 0;
  for (std::size_t n = 1; n <= kmax && next < order.size(); ++n) {
    cum.add(g[n - 1]);
    v.add(2.0 * cum.value() - g[0]);
    while (next < order.size() && static_cast<std::size_t>(counts[order[next]]) == n)
      out[order[next++]].variance = std::max(0.0, v.value());
  }
  return out;
}

std::vector<IntegratedError> integrated_error(const Model& model, const Eigen::VectorXd& theta, double freq,
                                              std::span<const double> horizons_seconds) {
  const std::vector<std::int64_t> counts = sample_counts(freq, horizons_seconds);
  check_model(model, theta, freq);
  const std::size_t nh = counts.size();
  const auto nc = static_cast<std::size_t>(model.num_components());
  std::vector<IntegratedError> out(nh);
  std::vector<double> variance(nh, 0.0), mean(nh, 0.0);
  for (std::size_t h = 0; h < nh; ++h) {
    out[h].horizon_seconds = horizons_seconds[h];
    out[h].samples = counts[h];
    out[h].per_component_sd.assign(nc, 0.0);
    out[h].per_component_deterministic.assign(nc, 0.0);
  }
  for (std::size_t c = 0; c < nc; ++c) {
    const Process& p = *model.components()[c].process;
    const std::span<const double> t{theta.data() + model.offset(static_cast<int>(c)),
                                    static_cast<std::size_t>(p.size())};
    const std::vector<SumMoments> m = p.sum_moments(t, counts);
    for (std::size_t h = 0; h < nh; ++h) {
      variance[h] += m[h].variance;
      mean[h] += m[h].mean;
      out[h].per_component_sd[c] = std::sqrt(m[h].variance) / freq;
      out[h].per_component_deterministic[c] = std::fabs(m[h].mean) / freq;
    }
  }
  for (std::size_t h = 0; h < nh; ++h) {
    out[h].sd_random = std::sqrt(variance[h]) / freq;
    out[h].deterministic = std::fabs(mean[h]) / freq;
    out[h].total_rms = std::hypot(out[h].sd_random, out[h].deterministic);
  }
  return out;
}

IntegratedError integrated_error(const Model& model, const Eigen::VectorXd& theta, double freq,
                                 double horizon_seconds) {
  return integrated_error(model, theta, freq, std::span<const double>(&horizon_seconds, 1)).front();
}

double integrated_error_sd(const Model& model, const Eigen::VectorXd& theta, double freq, double horizon_seconds) {
  return integrated_error(model, theta, freq, horizon_seconds).sd_random;
}

}  // namespace gmwm
