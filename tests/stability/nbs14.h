#pragma once
// NBS14's test sets (W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065,
// section 12.2), for the stability tests.
#include <cmath>
#include <cstdint>
#include <vector>

#include "gmwm/stability/deviation.h"

namespace gmwm::stability::testing {

// NBS14's 1000-point set: n0 = 1234567890, n(i+1) = 16807 n(i) mod 2147483647, each n(i) /
// 2147483647 a frequency sample (Stable32's PHASE.DAT is its phase, the mean removed, which
// no deviation, noise identification or interval here sees).
inline std::vector<double> nbs1000() {
  std::vector<double> y;
  std::int64_t n = 1234567890;
  for (int i = 0; i < 1000; ++i) {
    y.push_back(static_cast<double>(n) / 2147483647.0);
    n = (16807 * n) % 2147483647;
  }
  return y;
}

// PHASE.DAT: the phase of the 1000-point set less its mean frequency (tau0 = 1 s), 1001 points.
inline std::vector<double> phase_dat() {
  std::vector<double> y = nbs1000();
  double mean = 0.0;
  for (const double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  for (double& v : y) v -= mean;
  return phase_from_frequency(y, 1.0);
}

// Half a unit in the last of the 5 significant digits Stable32 prints.
inline double printed_half_unit(double v) { return 0.5e-4 * std::pow(10.0, std::floor(std::log10(std::abs(v)))); }

}  // namespace gmwm::stability::testing
