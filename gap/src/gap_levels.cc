#include "gap_levels.h"

#include <cmath>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/classical_wv.h"

namespace gmwm::gap::detail {

int levels_from(const std::vector<GapLevel>& levels) {
  return levels.empty() ? 1 : std::ilogb(levels.front().tau);  // tau = 2^level exactly
}

std::vector<GapBand> find_bands(const std::vector<GapLevel>& levels, double z_threshold, double min_effect) {
  std::vector<GapBand> bands;
  const int first = levels_from(levels);
  for (std::size_t j = 0; j < levels.size();) {
    const GapLevel& l = levels[j];
    const int sign = l.z > 0 ? 1 : -1;
    auto in_band = [&](const GapLevel& x, int sg) {
      return std::abs(x.z) > z_threshold && std::abs(x.ratio - 1.0) > min_effect && (x.z > 0 ? 1 : -1) == sg;
    };
    if (!in_band(l, sign)) {
      ++j;
      continue;
    }
    GapBand b;
    b.first_level = static_cast<int>(j) + first;
    b.direction = sign > 0 ? "excess" : "deficit";
    b.peak_ratio = l.ratio;
    std::size_t k = j;
    while (k < levels.size() && in_band(levels[k], sign)) {
      if (std::abs(std::log(levels[k].ratio)) > std::abs(std::log(b.peak_ratio))) b.peak_ratio = levels[k].ratio;
      ++k;
    }
    b.last_level = static_cast<int>(k) - 1 + first;
    b.tau_from = levels[j].tau;
    b.tau_to = levels[k - 1].tau;
    bands.push_back(b);
    j = k;
  }
  return bands;
}

std::vector<GapLevel> map_levels(const WaveletVariance& wv, const Eigen::VectorXd& nuhat, const Reference& ref,
                                 const Eigen::VectorXd& nu_model, const Eigen::VectorXd& shift, double alpha) {
  const double zp = boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / 2.0));
  std::vector<GapLevel> out;
  for (int j = 0; j < wv.levels(); ++j) {
    GapLevel l;
    l.tau = wv.tau[static_cast<std::size_t>(j)];
    l.ratio = nuhat(j) / nu_model(j);
    const double m = ref.mean_log(j) + shift(j), s = ref.sd_log(j);
    l.z = (std::log(nuhat(j)) - m) / s;
    l.ref_low = std::exp(m - zp * s);
    l.ref_high = std::exp(m + zp * s);
    l.outside = nuhat(j) < l.ref_low || nuhat(j) > l.ref_high;
    const double eta = wv_eta(wv.n - static_cast<std::int64_t>(l.tau) + 1, l.tau);
    const boost::math::chi_squared chi(eta);
    l.analytic_low = nu_model(j) * boost::math::quantile(chi, alpha / 2.0) / eta;
    l.analytic_high = nu_model(j) * boost::math::quantile(boost::math::complement(chi, alpha / 2.0)) / eta;
    out.push_back(l);
  }
  return out;
}

double rms_log_ratio(const Eigen::VectorXd& nuhat, const Eigen::VectorXd& nu, const std::vector<GapBand>& bands,
                     int first) {
  double s = 0.0;
  int n = 0;
  for (const auto& b : bands)
    for (int j = b.first_level - first; j <= b.last_level - first; ++j) {
      const double r = std::log(nuhat(j) / nu(j));
      s += r * r;
      ++n;
    }
  return n ? std::sqrt(s / n) : 0.0;
}

}  // namespace gmwm::gap::detail
