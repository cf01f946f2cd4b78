#include "gmwm/engine/number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gmwm {

namespace {
// The most significant digits a double carries (17 read back to the same double).
constexpr int kMaxSignificantDigits = 17;
}  // namespace

std::string significant(double x, int digits, NonFinite non_finite) {
  if (non_finite == NonFinite::kDash && !std::isfinite(x)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", std::clamp(digits, 1, kMaxSignificantDigits), x);
  return buf;
}

}  // namespace gmwm
