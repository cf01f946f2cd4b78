#pragma once
// rosbag2 input, sqlite3 storage (rosbag2_reader.cc): an IMU topic of a ROS 2 bag.

#include <string>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

/// True when `path` is a regular file that starts with the SQLite 3 magic.
bool is_rosbag2_sqlite(const std::string& path);

/// Reads the sensor_msgs/msg/Imu topic options.topic (empty: the bag's only one). Throws
/// InputError naming the file, topic and message index for a bag that is not rosbag2, an
/// absent or non-IMU topic, a truncated or big-endian message, or unsorted stamps.
SignalSet read_rosbag2_sqlite(const std::string& path, const ReadOptions& options);

}  // namespace gmwm::io::detail
