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
  if (!(max_missing_share >= 0.0 && max_missing_share < 0.5))
    return "Allan deviation: the missing share of a half window must be in [0, 0.5), got " +
           std::to_string(max_missing_share);
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

namespace {

// The deviation's grid, its intervals and, point by point, its values from the sums of
// squares `sum(k)` of the width-2m Haar filter (HaarModwt::sum_of_squares_half_width).
AllanDeviation empty_deviation(std::int64_t n, double freq, const AllanOptions& options) {
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
  return a;
}

void fill_point(AllanDeviation& a, std::size_t k, double sum_of_squares) {
  const std::int64_t m = a.m[k];
  const std::int64_t count = a.n - 2 * m + 1;
  const double avar = 2.0 * sum_of_squares / static_cast<double>(count);
  const double eta = std::max(static_cast<double>(count) / static_cast<double>(2 * m), 1.0);
  const boost::math::chi_squared chi(eta);
  a.tau[k] = static_cast<double>(m) / a.freq;
  a.adev[k] = std::sqrt(avar);
  a.edf[k] = eta;
  a.ci_low[k] = std::sqrt(eta * avar / boost::math::quantile(chi, 1.0 - a.alpha / 2.0));
  a.ci_high[k] = std::sqrt(eta * avar / boost::math::quantile(chi, a.alpha / 2.0));
}

// The level j with 2^(j-1) = m, or 0 when m is not a power of two.
int octave_level(std::int64_t m) {
  if (m < 1 || (m & (m - 1)) != 0) return 0;
  int j = 1;
  while ((std::int64_t{1} << (j - 1)) < m) ++j;
  return j;
}

}  // namespace

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
  // The Haar transform's mean-centred prefix sums (compensated sums, stored in double): the
  // Allan variance at m is twice the mean square of the width-2m filter.
  std::vector<std::unique_ptr<HaarModwt>> modwt;
  modwt.push_back(std::make_unique<HaarModwt>(x.data(), n));
  return std::move(allan_deviation(modwt, freq, options).front());
}

std::vector<AllanDeviation> allan_deviation(const std::vector<std::unique_ptr<HaarModwt>>& transforms, double freq,
                                            const AllanOptions& options,
                                            const std::vector<std::vector<double>>& level_sums) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_positive("allan_deviation", "freq", freq);
  std::vector<AllanDeviation> out;
  // An octave point whose level sum is given takes it; the others are computed in shared
  // passes over each series' prefix sums.
  std::vector<std::vector<std::size_t>> points(transforms.size());
  std::vector<std::vector<std::int64_t>> half_widths(transforms.size());
  for (std::size_t c = 0; c < transforms.size(); ++c) {
    check_at_least("allan_deviation", "samples", static_cast<double>(transforms[c]->size()), 2.0);
    out.push_back(empty_deviation(transforms[c]->size(), freq, options));
    for (std::size_t k = 0; k < out[c].size(); ++k) {
      const auto j = static_cast<std::size_t>(octave_level(out[c].m[k]));
      if (c < level_sums.size() && j >= 1 && j <= level_sums[c].size()) {
        fill_point(out[c], k, level_sums[c][j - 1]);
      } else {
        points[c].push_back(k);
        half_widths[c].push_back(out[c].m[k]);
      }
    }
  }
  const std::vector<std::vector<double>> sums = sums_of_squares_half_width(transforms, half_widths);
  for (std::size_t c = 0; c < transforms.size(); ++c)
    for (std::size_t i = 0; i < points[c].size(); ++i) fill_point(out[c], points[c][i], sums[c][i]);
  return out;
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
