#pragma once
// Timestamp columns: recognising them by name (with the unit when the name states it),
// deciding the unit otherwise, and measuring the sampling (rate, gaps, disorder).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

struct TimeUnit {
  double to_seconds = 0.0;  ///< 0 when the name gives no unit
  std::string label;        ///< "s", "ms", "us", "ns", "min", "h"
};

/// A time unit written as text ("ns", "sec", "us", "µs", "seconds", ...); nullopt if none.
std::optional<TimeUnit> parse_time_unit(std::string_view text);

/// nullopt when `name` does not name a timestamp column (timestamp, time, t, stamp,
/// time_stamp, '#timestamp [ns]', 'time (s)', time_s, timestamp_ns, %time, ...,
/// case-insensitive); otherwise the unit the name states (to_seconds 0 when none).
std::optional<TimeUnit> timestamp_name(std::string_view name);

/// The bracketed or parenthesised unit of a header name ('w_RS_S_x [rad s^-1]' ->
/// "rad s^-1") and the name without it; unit "" when there is none.
std::pair<std::string, std::string> split_unit(std::string_view name);

/// Measures the sampling from times relative to the first (`offsets`, in the file's
/// unit; `first_time` is the first raw time). `unit.to_seconds` 0: decided here from the
/// first time (a Unix time in s/ms/us/ns) or from the median step.
TimingReport analyse_timing(const std::string& column, const std::vector<double>& offsets,
                            double first_time, const TimeUnit& unit,
                            const std::string& unit_source);

}  // namespace gmwm::io::detail
