#pragma once
// What the ROS readers (ROS 1 bag, rosbag2 sqlite3, MCAP) share: the sensor_msgs Imu message
// in its two wire formats, and a topic's messages gathered into a signal set.
//
// sensor_msgs/Imu fields, in order: header {stamp, frame_id}, orientation (4 doubles) and
// its covariance (9), angular_velocity (3) and its covariance (9), linear_acceleration (3)
// and its covariance (9). angular_velocity -> gyro_x..z (rad/s), linear_acceleration ->
// accel_x..z (m/s^2); times from the header stamps.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "log_signals.h"

namespace gmwm::io::detail {

/// One decoded sensor_msgs Imu message.
struct ImuMessage {
  std::int64_t sec = 0;
  std::uint32_t nanosec = 0;
  double gyro[3] = {};
  double accel[3] = {};
};

/// ROS 2 (sensor_msgs/msg/Imu) in CDR: a 4-byte encapsulation header (00 01: little-endian
/// CDR), then the fields, each primitive aligned to its size from the end of that header;
/// header = {int32 sec, uint32 nanosec, string frame_id (uint32 length with the NUL, bytes)}.
/// Returns the message, or an error text ("truncated: ...") without the file's name.
std::optional<ImuMessage> decode_imu_cdr(const unsigned char* data, std::size_t size, std::string& error);

/// ROS 1 (sensor_msgs/Imu) serialisation: little-endian, packed (no alignment); header =
/// {uint32 seq, uint32 sec, uint32 nsec, string frame_id (uint32 length, bytes)}.
std::optional<ImuMessage> decode_imu_ros1(const unsigned char* data, std::size_t size, std::string& error);

/// The messages of one IMU topic in storage order. add() refuses (InputError naming the
/// file, topic and 1-based message index) a stamp that does not increase and a value that
/// is not finite, and keeps the axes --columns picks within the memory budget (LogColumns);
/// signals() builds the signal set. Neither copied nor moved (the budget's sink refers to
/// its columns).
class ImuTopic {
 public:
  ImuTopic(std::string path, std::string topic, const ReadOptions& options);
  ImuTopic(const ImuTopic&) = delete;
  ImuTopic& operator=(const ImuTopic&) = delete;

  const std::string& topic() const { return topic_; }
  std::int64_t size() const { return columns_.size(); }
  /// "FILE: topic T message N: ", the prefix of a message's errors.
  std::string where(std::int64_t index) const;
  /// Index: the message's 1-based place among the topic's messages.
  void add(const ImuMessage& m, std::int64_t index);
  /// Room for up to n messages (within the budget).
  void reserve(std::uint64_t n) { columns_.reserve(n); }

  /// `preset` names the source in outputs ("rosbag:/imu"); `stamp_source` says where the
  /// times come from in the timing report.
  SignalSet signals(const std::string& preset, const std::string& stamp_source) &&;

 private:
  std::string path_, topic_;
  std::int64_t first_sec_ = 0;
  LogColumns columns_;
};

}  // namespace gmwm::io::detail
