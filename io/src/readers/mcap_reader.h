#pragma once
// MCAP input (mcap_reader.cc): a sensor_msgs/msg/Imu topic of a ROS 2 bag in MCAP storage
// (chunks uncompressed, lz4 or zstd), without a ROS installation.

#include <string>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

/// True when `path` is a regular file that starts with the MCAP magic (0x89 "MCAP0\r\n").
bool is_mcap(const std::string& path);

/// Reads the sensor_msgs/msg/Imu topic options.topic (empty: the file's only one). Throws
/// InputError naming the file (and the topic and message index, or the byte offset) for a
/// truncated or damaged file, a chunk that does not decompress or fails its CRC, an absent
/// or non-IMU topic, a message that is not CDR Imu, or unsorted stamps.
SignalSet read_mcap(const std::string& path, const ReadOptions& options);

}  // namespace gmwm::io::detail
