#include "gmwm/engine/allan.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/samples.h"

namespace gmwm {

std::string AllanOptions::Validate() const {
  if (points_per_octave < 1 || points_per_octave > 64)
    return "Allan deviation: points per octave must be in [1, 64], got " + std::to_string(points_per_octave);
  if (!(alpha > 0.0 && alpha < 1.0)) return "Allan deviation: alpha must be in (0, 1), got " + std::to_string(alpha);
  return {};
}

std::vector<std::int64_t> allan_factors(std::int64_t n, int points_per_octave) {
  std::vector<std::int64_t> out;
  const std::int64_t top = n / 2;
  for (int k = 0;; ++k) {
    const double v = std::round(std::exp2(static_cast<double>(k) / points_per_octave));
    if (v > static_cast<double>(top)) break;
    const auto m = static_cast<std::int64_t>(v);
    if (out.empty() || m > out.back()) out.push_back(m);
  }
  return out;
}

AllanDeviation allan_deviation(std::span<const double> x, double freq, const AllanOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_positive("allan_deviation", "freq", freq);
  const auto n = static_cast<std::int64_t>(x.size());
  check_at_least("allan_deviation", "samples", static_cast<double>(n), 2.0);
  bool finite = true;
  for_each_block(x, [&](std::span<const double> part, std::size_t) {
    for (double v : part) finite = finite && std::isfinite(v);
  });
  if (!finite) throw InvalidArgument("allan_deviation: the series holds a non-finite sample");
  // The Haar transform's mean-centred prefix sums (accumulated in long double, stored in
  // double): the Allan variance at m is twice the mean square of the width-2m filter.
  const HaarModwt modwt(x.data(), n);

  AllanDeviation a;
  a.freq = freq;
  a.n = n;
  a.alpha = options.alpha;
  a.m = allan_factors(n, options.points_per_octave);
  const std::size_t K = a.m.size();
  a.tau.resize(K);
  a.adev.resize(K);
  a.ci_low.resize(K);
  a.ci_high.resize(K);
  a.edf.resize(K);
  gmwm::parallel_for(std::size_t{0}, K, [&](std::size_t k) {
    const std::int64_t m = a.m[k];
    const std::int64_t count = n - 2 * m + 1;
    const double avar = 2.0 * modwt.sum_of_squares_half_width(m) / static_cast<double>(count);
    const double eta = std::max(static_cast<double>(count) / static_cast<double>(2 * m), 1.0);
    const boost::math::chi_squared chi(eta);
    a.tau[k] = static_cast<double>(m) / freq;
    a.adev[k] = std::sqrt(avar);
    a.edf[k] = eta;
    a.ci_low[k] = std::sqrt(eta * avar / boost::math::quantile(chi, 1.0 - options.alpha / 2.0));
    a.ci_high[k] = std::sqrt(eta * avar / boost::math::quantile(chi, options.alpha / 2.0));
  });
  return a;
}

std::vector<double> model_allan_deviation(const Model& model, const Eigen::VectorXd& theta,
                                          std::span<const std::int64_t> m) {
  std::vector<double> tau(m.size());
  for (std::size_t k = 0; k < m.size(); ++k) tau[k] = 2.0 * static_cast<double>(m[k]);
  const Eigen::VectorXd nu = model.wv(theta, tau);
  std::vector<double> out(m.size());
  for (std::size_t k = 0; k < m.size(); ++k) out[k] = std::sqrt(std::max(2.0 * nu(static_cast<Eigen::Index>(k)), 0.0));
  return out;
}

std::vector<double> component_allan_variances(const Model& model, const Eigen::VectorXd& theta, std::int64_t m) {
  const double tau[1] = {2.0 * static_cast<double>(m)};
  std::vector<double> out;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    double v = 0.0;
    p.wv({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, tau, {&v, 1});
    out.push_back(2.0 * v);
  }
  return out;
}

}  // namespace gmwm
