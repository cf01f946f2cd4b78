#include "gmwm/engine/wavelet_variance.h"

#include <algorithm>
#include <cmath>

#include "gmwm/engine/check.h"
#include "gmwm/engine/number_text.h"

namespace gmwm {
namespace {

std::string num(double x) { return significant(x, 3); }

// The entries of a per-level field from index `from` on (a field the estimator left empty
// stays empty).
template <class T>
std::vector<T> tail_of(const std::vector<T>& v, std::size_t from, std::size_t levels) {
  if (v.size() != levels) return v;
  return std::vector<T>(v.begin() + static_cast<std::ptrdiff_t>(from), v.end());
}

}  // namespace

int first_level(const WaveletVariance& wv) {
  if (wv.tau.empty() || !(wv.tau.front() >= 2.0)) return 1;
  return static_cast<int>(std::lround(std::log2(wv.tau.front())));
}

WaveletVariance drop_fine_levels(const WaveletVariance& wv, int level) {
  const int first = first_level(wv), last = first + wv.levels() - 1;
  if (level < first || level > last)
    throw InvalidArgument("drop_fine_levels: level " + std::to_string(level) + " is outside the WV's levels " +
                          std::to_string(first) + ".." + std::to_string(last));
  if (level == first) return wv;
  const auto from = static_cast<std::size_t>(level - first), J = static_cast<std::size_t>(wv.levels());
  WaveletVariance out = wv;
  out.tau = tail_of(wv.tau, from, J);
  out.wv = tail_of(wv.wv, from, J);
  out.ci_low = tail_of(wv.ci_low, from, J);
  out.ci_high = tail_of(wv.ci_high, from, J);
  out.variance = tail_of(wv.variance, from, J);
  out.eta = tail_of(wv.eta, from, J);
  out.coefficients = tail_of(wv.coefficients, from, J);
  if (!wv.partial.empty()) out.partial = tail_of(wv.partial, from, J);
  out.notes = tail_of(wv.notes, from, J);
  if (wv.covariance && wv.covariance->rows() == static_cast<Eigen::Index>(J)) {
    const auto k = static_cast<Eigen::Index>(J - from);
    out.covariance = Eigen::MatrixXd(wv.covariance->bottomRightCorner(k, k));
  }
  return out;
}

FromLevelEstimator::FromLevelEstimator(const WvEstimator& inner, int level) : inner_(inner), level_(level) {
  if (level < 1) throw InvalidArgument("FromLevelEstimator: level " + std::to_string(level) + " is below 1");
}

WaveletVariance FromLevelEstimator::compute(const double* x, std::int64_t n, int levels, double alpha) const {
  return drop_fine_levels(inner_.compute(x, n, levels + level_ - 1, alpha), level_);
}

WaveletVariance FromLevelEstimator::compute(const HaarModwt& modwt, const double* x, std::int64_t n, int levels,
                                            double alpha) const {
  return drop_fine_levels(inner_.compute(modwt, x, n, levels + level_ - 1, alpha), level_);
}

std::string wv_range_problem(const WaveletVariance& wv, std::span<const double> x, bool for_fit) {
  const std::string rescale = "; rescale the values (another unit) so that they are of ordinary size";
  for (int j = 0; j < wv.levels(); ++j) {
    const auto l = static_cast<std::size_t>(j);
    if (std::isfinite(wv.wv[l])) continue;
    // An estimator that says why it has no value (a robust equation without a root: many
    // coefficients exactly zero) is not an overflow: say what happened and what works.
    if (l < wv.notes.size() && !wv.notes[l].empty())
      return "the " + wv.estimator + " wavelet variance has no value at level " + std::to_string(first_level(wv) + j) +
             " (" + wv.notes[l] + ")" +
             (for_fit ? "; a fit needs every level: the Huber estimator (--estimator huber), whose equation has a root "
                        "whenever the coefficients vary, or the classical WV (without --robust)"
                      : "");
    return "the wavelet variance at level " + std::to_string(first_level(wv) + j) +
           " is not a finite number (sums of squares of values this large overflow a double)" + rescale;
  }
  if (std::all_of(wv.wv.begin(), wv.wv.end(), [](double w) { return w == 0.0; })) {
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
    if (lo != x.end() && *lo == *hi)
      return "found all " + std::to_string(x.size()) + " values equal to " + num(*lo) +
             ", expected a varying signal (a constant has a wavelet variance of zero)";
    return "the wavelet variance is zero at every level although the values vary: their squares underflow a double "
           "(values of magnitude " +
           num(std::max(std::fabs(*lo), std::fabs(*hi))) + ")" + rescale;
  }
  const double low = for_fit ? kMinFittableWv : kMinRepresentableWv;
  const double high = for_fit ? kMaxFittableWv : kMaxRepresentableWv;
  for (int j = 0; j < wv.levels(); ++j) {
    const double w = wv.wv[static_cast<std::size_t>(j)];
    if (w < low || w > high)
      return "the wavelet variance at level " + std::to_string(first_level(wv) + j) + " is " + num(w) + ", outside " +
             num(low) + " .. " + num(high) +
             (for_fit ? ", the range a fit can take (its variances are exp(u), |u| <= 100)"
                      : ", the range doubles hold with the variance of the estimate") +
             rescale;
  }
  return {};
}

}  // namespace gmwm
