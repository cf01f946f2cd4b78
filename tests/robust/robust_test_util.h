#pragma once
// Helpers shared by the robust test files: seeded white noise, the estimating equation,
// and small statistics.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust::test_util {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline std::vector<double> white_noise(std::int64_t n, std::uint64_t seed, std::uint64_t stream) {
  const Model m = parse_model("WN(sigma2=1)");
  return simulate(m, m.given_values(), n, seed, stream);
}

// mean chi(w^2 / s) - a: the estimating equation solve_scale finds a root of.
inline double estimating_equation(std::span<const double> w, const Tuning& t, double s) {
  double sum = 0.0;
  for (double x : w) sum += chi(t.kind, t.c, x * x / s);
  return sum / static_cast<double>(w.size()) - t.a;
}

inline double mean_of_squares(std::span<const double> w) {
  double s = 0.0;
  for (double x : w) s += x * x;
  return s / static_cast<double>(w.size());
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

// ---------------------------------------------------------------------------------

}  // namespace gmwm::robust::test_util
