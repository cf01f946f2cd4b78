#pragma once
// Numbers as text, for messages, tables, reports and configs: the one helper every module's
// local spelling (num, fmt, g) forwards to.

#include <string>

namespace gmwm {

/// How a figure that is not finite reads.
enum class NonFinite {
  kAsPrintf,  ///< "nan", "inf", "-inf", as printf's %g writes them (messages, configs)
  kDash,      ///< "-" (a table cell without a value)
};

/// x with `digits` significant digits as printf's "%.*g" writes it ("1.5e-05", "0.25");
/// 17 digits read back to the same double. digits is clamped to 1..17.
std::string significant(double x, int digits = 6, NonFinite non_finite = NonFinite::kAsPrintf);

}  // namespace gmwm
