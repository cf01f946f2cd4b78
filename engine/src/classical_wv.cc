#include "gmwm/engine/classical_wv.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/parallel.h"

namespace gmwm {

std::string WvOptions::Validate() const {
  std::ostringstream os;
  if (!(alpha > 0.0 && alpha < 1.0))
    os << "alpha must be in (0, 1), got " << alpha;
  else if (alpha < kMinAlpha)
    os << "alpha must be at least 1e-10 (the level 1 - alpha/2 rounds to 1 below ~1e-16), got " << alpha;
  else if (levels < 0)
    os << "levels must be positive (or 0 for all), got " << levels;
  return os.str();
}

double wv_eta(std::int64_t coefficients, double tau) { return std::max(static_cast<double>(coefficients) / tau, 1.0); }

std::pair<double, double> chi_square_ci(double wv, double eta, double alpha) {
  check_positive("chi_square_ci", "eta", eta);
  check_probability("chi_square_ci", "alpha", alpha);
  boost::math::chi_squared dist(eta);
  const double q_hi = boost::math::quantile(dist, 1.0 - alpha / 2.0);
  const double q_lo = boost::math::quantile(dist, alpha / 2.0);
  return {eta * wv / q_hi, eta * wv / q_lo};
}

namespace {

void check_series(const char* fn, std::int64_t n, const WvOptions& options) {
  if (n < kMinSeriesLength)
    detail::throw_check(fn, "series length", static_cast<double>(n), "at least " + std::to_string(kMinSeriesLength));
  const std::string why = options.Validate();
  if (!why.empty()) throw InvalidArgument(std::string(fn) + ": " + why);
}

WaveletVariance empty_wv(std::int64_t n, int J, double alpha) {
  WaveletVariance w;
  w.n = n;
  w.alpha = alpha;
  const auto sz = static_cast<std::size_t>(J);
  w.tau.resize(sz);
  w.wv.resize(sz);
  w.ci_low.resize(sz);
  w.ci_high.resize(sz);
  w.variance.resize(sz);
  w.eta.resize(sz);
  w.coefficients.resize(sz);
  w.notes.resize(sz);
  return w;
}

int levels_for(const HaarModwt& modwt, const WvOptions& options) {
  const int J = modwt.max_levels();
  return options.levels > 0 ? std::min(options.levels, J) : J;
}

// Level j of w from its sum of squares (HaarModwt::sum_of_squares(j)).
void fill_level(const HaarModwt& modwt, int j, double sum_of_squares, WaveletVariance& w) {
  const auto i = static_cast<std::size_t>(j - 1);
  const std::int64_t M = modwt.count(j);
  const double tau = std::ldexp(1.0, j);
  const double v = sum_of_squares / static_cast<double>(M);
  const double eta = wv_eta(M, tau);
  w.tau[i] = tau;
  w.wv[i] = v;
  w.coefficients[i] = M;
  w.eta[i] = eta;
  w.variance[i] = 2.0 * v * v / eta;
  std::tie(w.ci_low[i], w.ci_high[i]) = chi_square_ci(v, eta, w.alpha);
}

}  // namespace

WaveletVariance classical_wv(const double* x, std::int64_t n, const WvOptions& options) {
  check_series("classical_wv", n, options);
  return classical_wv(HaarModwt(x, n), options);
}

WaveletVariance classical_wv(const HaarModwt& modwt, const WvOptions& options) {
  const std::int64_t n = modwt.size();
  check_series("classical_wv", n, options);
  const int J = levels_for(modwt, options);
  WaveletVariance w = empty_wv(n, J, options.alpha);
  // Every level's sum in blocked passes shared by the levels over the prefix sums
  // (HaarModwt::sums_of_squares_half_width: each level's sum to the bit of its own pass,
  // kept levels read, not recomputed): one pass per level was a fifth of a parametric
  // bootstrap's CPU (issue 44).
  std::vector<std::int64_t> half_widths;
  for (int j = 1; j <= J; ++j) half_widths.push_back(std::int64_t{1} << (j - 1));
  const std::vector<double> sums = modwt.sums_of_squares_half_width(half_widths);
  for (int j = 1; j <= J; ++j) fill_level(modwt, j, sums[static_cast<std::size_t>(j - 1)], w);
  return w;
}

std::vector<WaveletVariance> classical_wv(const std::vector<std::span<const double>>& series,
                                          const WvOptions& options) {
  for (const auto& s : series) check_series("classical_wv", static_cast<std::int64_t>(s.size()), options);
  return classical_wv(haar_transforms(series), options);
}

std::vector<WaveletVariance> classical_wv(const std::vector<std::unique_ptr<HaarModwt>>& transforms,
                                          const WvOptions& options, std::vector<std::vector<double>>* level_sums) {
  std::vector<WaveletVariance> out(transforms.size());
  std::vector<std::vector<double>> sums(transforms.size());
  for (std::size_t c = 0; c < transforms.size(); ++c) {
    check_series("classical_wv", transforms[c]->size(), options);
    out[c] = empty_wv(transforms[c]->size(), levels_for(*transforms[c], options), options.alpha);
  }
  // Every level's sum (level j: half-width 2^(j-1)) in shared passes over the prefix sums.
  std::vector<std::vector<std::int64_t>> half_widths(transforms.size());
  for (std::size_t c = 0; c < transforms.size(); ++c)
    for (int j = 1; j <= out[c].levels(); ++j) half_widths[c].push_back(std::int64_t{1} << (j - 1));
  sums = sums_of_squares_half_width(transforms, half_widths);
  for (std::size_t c = 0; c < transforms.size(); ++c)
    for (int j = 1; j <= out[c].levels(); ++j)
      fill_level(*transforms[c], j, sums[c][static_cast<std::size_t>(j - 1)], out[c]);
  if (level_sums) *level_sums = std::move(sums);
  return out;
}

std::vector<std::pair<double, double>> allan_variance(const WaveletVariance& wv) {
  std::vector<std::pair<double, double>> out;
  for (std::size_t j = 0; j < wv.wv.size(); ++j) out.emplace_back(wv.tau[j] / 2.0, 2.0 * wv.wv[j]);
  return out;
}

WaveletVariance ClassicalWvEstimator::compute(const double* x, std::int64_t n, int levels, double alpha) const {
  WvOptions o;
  o.levels = levels;
  o.alpha = alpha;
  return classical_wv(x, n, o);
}

WaveletVariance ClassicalWvEstimator::compute(const HaarModwt& modwt, const double* x, std::int64_t n, int levels,
                                              double alpha) const {
  static_cast<void>(x);
  check_size_match("ClassicalWvEstimator", "transform length", static_cast<std::size_t>(modwt.size()), "series length",
                   static_cast<std::size_t>(n));
  WvOptions o;
  o.levels = levels;
  o.alpha = alpha;
  return classical_wv(modwt, o);
}

}  // namespace gmwm
