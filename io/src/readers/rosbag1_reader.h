#pragma once
// ROS 1 bag input (rosbag1_reader.cc): a sensor_msgs/Imu topic of a .bag file (format 2.0;
// uncompressed, bz2 or lz4 chunks), without a ROS installation.

#include <string>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

/// True when `path` is a regular file that starts with "#ROSBAG V".
bool is_rosbag1(const std::string& path);

/// Reads the sensor_msgs/Imu topic options.topic (empty: the bag's only one). Throws
/// InputError naming the file (and the topic, message index or byte offset) for a bag of
/// another version, an unindexed or truncated bag, a chunk that does not decompress, an
/// absent or non-IMU topic, or unsorted stamps.
SignalSet read_rosbag1(const std::string& path, const ReadOptions& options);

}  // namespace gmwm::io::detail
