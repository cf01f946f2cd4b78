#pragma once
// Writes signals as CSV that read_signals() reads back exactly.

#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/output_set.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::io {

/// Writes `signals` (all of the same length) to `path` as comma-separated text with a
/// header row; with `freq`, a leading column "time [s]" holds i / freq in seconds. Numbers are
/// written in the shortest form that reads back to the same double (std::to_chars), so a
/// round trip through read_signals() is exact. A path ending in ".gz" is gzip-compressed.
/// Names containing a comma, a double quote or a line break are double-quoted.
/// All-or-nothing (an OutputSet of one file); the text is streamed (gzip included), so the
/// file may be of any size (past 4 GB) without being held in memory. Throws InputError
/// when the file cannot be written and gmwm::InvalidArgument when the signals differ in
/// length or freq is not positive.
void write_signals(const std::string& path, const std::vector<Signal>& signals, std::optional<double> freq);

/// As write_signals(), staged in `outputs` (committed with the run's other outputs).
void stage_signals(OutputSet& outputs, const std::string& path, const std::vector<Signal>& signals,
                   std::optional<double> freq);

/// A CSV field of a result table: as it is, or double-quoted (quotes doubled) when it
/// holds a comma, a double quote or a line break (RFC 4180); a field a spreadsheet would
/// run as a formula (starting with = + - @, a tab or a CR) is quoted with a leading '.
std::string csv_field(const std::string& text);

/// The CSV text, streamed into `out` (uncompressed; wrap `out` in a GzipOutput to compress).
void write_signals_csv(OutputStream& out, const std::vector<Signal>& signals, std::optional<double> freq);

/// The CSV text write_signals() writes (uncompressed).
std::string format_signals_csv(const std::vector<Signal>& signals, std::optional<double> freq);

}  // namespace gmwm::io
