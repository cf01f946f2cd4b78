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

}  // namespace

Quantization detect_quantization(const double* x, std::int64_t n) {
  Quantization q;
  double dmin = std::numeric_limits<double>::infinity();
  for (std::int64_t t = 1; t < n; ++t) {
    const double d = std::abs(x[t] - x[t - 1]);
    if (d > 0.0 && d < dmin) dmin = d;
  }
  if (!std::isfinite(dmin)) return q;
  std::int64_t on = 0;
  for (std::int64_t t = 1; t < n; ++t) {
    const double r = std::abs(x[t] - x[t - 1]) / dmin;
    on += std::abs(r - std::round(r)) <= kLatticeTolerance * std::max(1.0, r);
  }
  q.on_lattice_share = n > 1 ? static_cast<double>(on) / static_cast<double>(n - 1) : 0.0;
  if (q.on_lattice_share >= kLatticeShare) {
    q.detected = true;
    q.quantum = dmin;
  }
  return q;
}

}  // namespace gmwm
