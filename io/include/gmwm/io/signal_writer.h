#pragma once
// Writes signals as CSV that read_signals() reads back exactly.

#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io {

/// Writes `signals` (all of the same length) to `path` as comma-separated text with a
/// header row; with `freq`, a leading column "time" holds i / freq in seconds. Numbers are
/// written in the shortest form that reads back to the same double (std::to_chars), so a
/// round trip through read_signals() is exact. A path ending in ".gz" is gzip-compressed.
/// Names containing a comma, a double quote or a line break are double-quoted.
/// All-or-nothing (write_file_atomically); throws InputError when the file cannot be
/// written and gmwm::InvalidArgument when the signals differ in length or freq is not
/// positive.
void write_signals(const std::string& path, const std::vector<Signal>& signals,
                   std::optional<double> freq);

/// The CSV text write_signals() writes (uncompressed).
std::string format_signals_csv(const std::vector<Signal>& signals, std::optional<double> freq);

}  // namespace gmwm::io
