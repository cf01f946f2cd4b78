#include "gmwm/engine/quantization.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gmwm {
namespace {

// At least this share of the first differences must be integer multiples (to
// kLatticeTolerance) of the smallest non-zero one for the data to count as rounded.
constexpr double kLatticeShare = 0.99;
constexpr double kLatticeTolerance = 1e-6;
// 1.5 x 2^52: adding and taking it away rounds a double below 2^51 to a whole number.
constexpr double kRoundingShift = 6755399441055744.0;
constexpr double kLargeRatio = 2251799813685248.0;  // 2^51

}  // namespace

Quantization detect_quantization(const double* x, std::int64_t n) {
  Quantization q;
  double dmin = std::numeric_limits<double>::infinity();
  constexpr double kNone = std::numeric_limits<double>::infinity();
  for (std::int64_t t = 1; t < n; ++t) {  // branch-free: a rounded record's zero steps are frequent
    const double d = std::abs(x[t] - x[t - 1]);
    dmin = std::min(dmin, d > 0.0 ? d : kNone);
  }
  if (!std::isfinite(dmin)) return q;
  // r rounded to the nearest whole number by adding and taking away 1.5 x 2^52 (exact for
  // r < 2^51, and vectorised, unlike std::round: 40% of the detection's instructions went
  // to it); above 2^51 r is within the tolerance of a whole number anyway.
  const double inverse = 1.0 / dmin;
  std::int64_t on = 0;
  for (std::int64_t t = 1; t < n; ++t) {
    const double r = std::abs(x[t] - x[t - 1]) * inverse;
    const double nearest = (r + kRoundingShift) - kRoundingShift;
    on += r >= kLargeRatio || std::abs(r - nearest) <= kLatticeTolerance * std::max(1.0, r);
  }
  q.on_lattice_share = n > 1 ? static_cast<double>(on) / static_cast<double>(n - 1) : 0.0;
  if (q.on_lattice_share >= kLatticeShare) {
    q.detected = true;
    q.quantum = dmin;
  }
  return q;
}

}  // namespace gmwm
