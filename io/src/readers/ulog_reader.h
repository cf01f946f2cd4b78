#pragma once
// PX4 ULog input (ulog_reader.cc): the IMU topics of a flight log as signals.

#include <string>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

/// True when `path` is a regular file that starts with the ULog magic bytes.
bool is_ulog(const std::string& path);

/// Reads options.topic (default sensor_combined) of a ULog file. Throws InputError naming
/// the file, the message index and byte offset for a truncated or malformed log, a topic
/// that is absent or not IMU messages, or unsorted stamps.
SignalSet read_ulog(const std::string& path, const ReadOptions& options);

}  // namespace gmwm::io::detail
