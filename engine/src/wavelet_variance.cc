#include "gmwm/engine/wavelet_variance.h"

#include <algorithm>
#include <cmath>

#include "gmwm/engine/number_text.h"

namespace gmwm {
namespace {

std::string num(double x) { return significant(x, 3); }

}  // namespace

std::string wv_range_problem(const WaveletVariance& wv, std::span<const double> x, bool for_fit) {
  const std::string rescale = "; rescale the values (another unit) so that they are of ordinary size";
  for (int j = 0; j < wv.levels(); ++j) {
    const auto l = static_cast<std::size_t>(j);
    if (std::isfinite(wv.wv[l])) continue;
    // An estimator that says why it has no value (a robust equation without a root: many
    // coefficients exactly zero) is not an overflow: say what happened and what works.
    if (l < wv.notes.size() && !wv.notes[l].empty())
      return "the " + wv.estimator + " wavelet variance has no value at level " + std::to_string(j + 1) + " (" +
             wv.notes[l] + ")" +
             (for_fit ? "; a fit needs every level: the Huber estimator (--estimator huber), whose equation has a root "
                        "whenever the coefficients vary, or the classical WV (without --robust)"
                      : "");
    return "the wavelet variance at level " + std::to_string(j + 1) +
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
      return "the wavelet variance at level " + std::to_string(j + 1) + " is " + num(w) + ", outside " + num(low) +
             " .. " + num(high) +
             (for_fit ? ", the range a fit can take (its variances are exp(u), |u| <= 100)"
                      : ", the range doubles hold with the variance of the estimate") +
             rescale;
  }
  return {};
}

}  // namespace gmwm
