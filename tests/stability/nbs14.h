#pragma once
// NBS14's test sets (W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065,
// section 12.2), for the stability tests.
#include <cstdint>
#include <vector>

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

}  // namespace gmwm::stability::testing
