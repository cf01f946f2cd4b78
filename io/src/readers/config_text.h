#pragma once
// Text helpers shared by the simulator-configuration readers (Kalibr yaml, Gazebo SDF,
// datasheet yaml): trimming and the two ways they print a figure.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "gmwm/engine/number_text.h"

namespace gmwm::io::detail {

/// s without leading and trailing blanks (spaces, tabs, CR, LF).
inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

/// A figure for a message or a conversion line (%g, 6 significant digits by default).
inline std::string g(double x, int digits = 6) { return significant(x, digits); }

/// A figure that reads back to the same double (a model string's value).
inline std::string exact(double x) { return g(x, 17); }

/// True for a nonzero figure or a variance derived from one that a model can take: finite
/// and at least the smallest normal double (below it a value has lost its precision or
/// underflowed to 0). The readers refuse anything else naming the figure's line.
inline bool within_double(double v) { return std::isfinite(v) && std::fabs(v) >= std::numeric_limits<double>::min(); }

}  // namespace gmwm::io::detail
