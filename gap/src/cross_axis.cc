#include "gmwm/gap/cross_axis.h"

#include <cmath>
#include <cstdint>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/parallel.h"

namespace gmwm::gap {

std::vector<CrossAxisPair> cross_axis_correlation(const std::vector<std::span<const double>>& signals, int levels,
                                                  double alpha) {
  const std::size_t K = signals.size();
  if (K < 2) return {};
  const auto n = static_cast<std::int64_t>(signals[0].size());
  for (std::size_t k = 1; k < K; ++k)
    if (static_cast<std::int64_t>(signals[k].size()) != n)
      throw InputError("cross-axis correlation: signal " + std::to_string(k + 1) + " has " +
                       std::to_string(signals[k].size()) + " samples, signal 1 has " + std::to_string(n));
  if (n < 2) return {};
  std::vector<HaarModwt> modwt;
  modwt.reserve(K);
  for (const auto& s : signals) modwt.emplace_back(s.data(), n);
  int J = modwt[0].max_levels();
  if (levels > 0) J = std::min(J, levels);
  // Levels with enough effective samples.
  std::vector<int> tested;
  for (int j = 1; j <= J; ++j)
    if (static_cast<double>(modwt[0].count(j)) / std::ldexp(1.0, j) >= kCrossAxisMinEffective) tested.push_back(j);
  const std::size_t P = K * (K - 1) / 2;
  const double z_crit = boost::math::quantile(boost::math::complement(
      boost::math::normal(), alpha / (2.0 * static_cast<double>(P * std::max<std::size_t>(1, tested.size())))));
  std::vector<std::vector<CrossAxisPair>> per_level(tested.size());
  gmwm::parallel_for(std::size_t{0}, tested.size(), [&](std::size_t i) {
    const int j = tested[i];
    std::vector<std::vector<double>> w(K);
    for (std::size_t k = 0; k < K; ++k) modwt[k].coefficients(j, w[k]);
    std::vector<double> ss(K, 0.0);
    for (std::size_t k = 0; k < K; ++k)
      for (double v : w[k]) ss[k] += v * v;
    const double n_eff = static_cast<double>(w[0].size()) / std::ldexp(1.0, j);
    for (std::size_t a = 0; a < K; ++a)
      for (std::size_t b = a + 1; b < K; ++b) {
        double cross = 0.0;
        for (std::size_t t = 0; t < w[a].size(); ++t) cross += w[a][t] * w[b][t];
        CrossAxisPair p;
        p.level = j;
        p.tau = std::ldexp(1.0, j);
        p.a = static_cast<int>(a);
        p.b = static_cast<int>(b);
        p.rho = ss[a] > 0.0 && ss[b] > 0.0 ? cross / std::sqrt(ss[a] * ss[b]) : 0.0;
        p.rho = std::clamp(p.rho, -1.0 + 1e-15, 1.0 - 1e-15);
        p.z = std::atanh(p.rho) * std::sqrt(std::max(n_eff - 3.0, 0.0));
        p.significant = std::abs(p.z) > z_crit && std::abs(p.rho) >= kCrossAxisMinRho;
        per_level[i].push_back(p);
      }
  });
  std::vector<CrossAxisPair> out;
  for (auto& v : per_level) out.insert(out.end(), v.begin(), v.end());
  return out;
}

}  // namespace gmwm::gap
