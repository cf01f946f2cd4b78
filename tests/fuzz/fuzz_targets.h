#pragma once
// The fuzz targets (tests/fuzz/README.md): each feeds one input to one parser and accepts
// only a result or gmwm::InputError / gmwm::InvalidArgument; anything else (a crash, a
// sanitizer report, another exception) is a finding. The same functions replay the kept
// corpora in the normal test suite (fuzz_replay_test.cc).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "size_fields.h"

namespace gmwm::fuzz {

struct Target {
  const char* name;
  void (*run)(const std::uint8_t* data, std::size_t size);
  /// The input's size fields, which the fuzzers' mutator drives to extremes (size_fields.h);
  /// nullptr: random mutations only.
  std::vector<SizeField> (*size_fields)(const std::uint8_t* data, std::size_t size) = nullptr;
};

/// Delimited text and gzip (io::read_signals on a file holding the bytes).
void delimited(const std::uint8_t* data, std::size_t size);
/// The model syntax (parse_model), at a known and an unknown rate.
void model_syntax(const std::uint8_t* data, std::size_t size);
/// A Kalibr imu.yaml (io::read_kalibr_imu_yaml), with and without a chain's IMU name.
void kalibr_yaml(const std::uint8_t* data, std::size_t size);
/// An SDF / RotorS XML (io::read_gazebo_sdf).
void gazebo_sdf(const std::uint8_t* data, std::size_t size);
/// A fit/select result as an export source (io::read_result_columns).
void export_source(const std::uint8_t* data, std::size_t size);
/// The binary logs: the first byte picks PX4 ULog, ROS 1 bag or MCAP, whose magic is put
/// before the rest (io::read_signals).
void binary_logs(const std::uint8_t* data, std::size_t size);
/// One binary reader each, on whole files (seeds: valid small logs of every codec), with
/// their size fields driven to extremes: a PX4 ULog (default topic, sensor_gyro:1, and with
/// a one-byte memory budget); a ROS 1 bag; an MCAP file; a sensor_msgs Imu message in CDR and
/// in ROS 1's serialisation (ros_imu.h).
void ulog(const std::uint8_t* data, std::size_t size);
void rosbag1(const std::uint8_t* data, std::size_t size);
void mcap(const std::uint8_t* data, std::size_t size);
void cdr(const std::uint8_t* data, std::size_t size);

inline constexpr Target kTargets[] = {
    {"delimited", delimited},         {"model_syntax", model_syntax},
    {"kalibr_yaml", kalibr_yaml},     {"gazebo_sdf", gazebo_sdf},
    {"export_source", export_source}, {"binary_logs", binary_logs},
    {"ulog", ulog, ulog_size_fields}, {"rosbag1", rosbag1, rosbag1_size_fields},
    {"mcap", mcap, mcap_size_fields}, {"cdr", cdr, cdr_size_fields},
};

}  // namespace gmwm::fuzz
