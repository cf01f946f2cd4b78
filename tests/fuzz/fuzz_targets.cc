#include "fuzz_targets.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "mcap_reader.h"
#include "ros_imu.h"
#include "rosbag1_reader.h"
#include "ulog_reader.h"

namespace gmwm::fuzz {
namespace {

// The readers take paths: each process writes its input to one scratch file of its own
// (in /dev/shm when it exists: no disk traffic).
std::string scratch(const char* suffix) {
  const std::string dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  return dir + "/gmwm-fuzz-" + std::to_string(::getpid()) + suffix;
}

std::string write_input(const std::uint8_t* data, std::size_t size, const char* suffix,
                        const std::string& prefix = {}) {
  const std::string path = scratch(suffix);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(prefix.data(), static_cast<std::streamsize>(prefix.size()));
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs f; the library's refusals (bad input) are expected outcomes.
template <typename F>
void expect_result_or_refusal(F&& f) {
  try {
    f();
  } catch (const InputError&) {
  } catch (const InvalidArgument&) {
  }
}

}  // namespace

void delimited(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, ".csv");
  expect_result_or_refusal([&] { io::read_signals(path, {}); });
  io::ReadOptions o;
  o.freq = 100.0;
  expect_result_or_refusal([&] { io::read_signals(path, o); });
  // A budget of one byte: from row 65,536 on, the columns go on in temporary files.
  o.memory_budget = 1.0;
  expect_result_or_refusal([&] { io::read_signals(path, o); });
  std::remove(path.c_str());
}

void model_syntax(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  expect_result_or_refusal([&] { parse_model(text, ProcessContext{100.0, true}); });
  expect_result_or_refusal([&] { parse_model(text, ProcessContext{1.0, false}); });
}

void kalibr_yaml(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, ".yaml");
  expect_result_or_refusal([&] { io::read_kalibr_imu_yaml(path, 100.0, io::parse_units(""), ""); });
  expect_result_or_refusal([&] { io::read_kalibr_imu_yaml(path, 200.0, io::parse_units("gyro=deg/s"), "imu1"); });
  std::remove(path.c_str());
}

void gazebo_sdf(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, ".sdf");
  expect_result_or_refusal([&] { io::read_gazebo_sdf(path, 100.0, io::parse_units("")); });
  std::remove(path.c_str());
}

void export_source(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, ".json");
  expect_result_or_refusal([&] { io::read_result_columns(path, {}); });
  std::remove(path.c_str());
}

void binary_logs(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  static const std::string magics[] = {std::string("ULog\x01\x12\x35\x01", 8), "#ROSBAG V2.0\n",
                                       std::string("\x89MCAP0\r\n", 8)};
  const std::string path = write_input(data + 1, size - 1, ".log", magics[data[0] % 3]);
  expect_result_or_refusal([&] { io::read_signals(path, {}); });
  std::remove(path.c_str());
}

namespace {

// A reader on a whole file: as given, then with a one-byte memory budget (the spill stage).
template <typename Read>
void whole_file(const std::uint8_t* data, std::size_t size, const char* suffix, Read read, const char* topic = "") {
  const std::string path = write_input(data, size, suffix);
  io::ReadOptions o;
  o.topic = topic;
  expect_result_or_refusal([&] { read(path, o); });
  o.memory_budget = 1.0;
  expect_result_or_refusal([&] { read(path, o); });
  std::remove(path.c_str());
}

}  // namespace

void ulog(const std::uint8_t* data, std::size_t size) {
  whole_file(data, size, ".ulg", io::detail::read_ulog);
  whole_file(data, size, ".ulg", io::detail::read_ulog, "sensor_gyro:1");
}

void rosbag1(const std::uint8_t* data, std::size_t size) { whole_file(data, size, ".bag", io::detail::read_rosbag1); }

void mcap(const std::uint8_t* data, std::size_t size) { whole_file(data, size, ".mcap", io::detail::read_mcap); }

void cdr(const std::uint8_t* data, std::size_t size) {
  std::string error;
  (void)io::detail::decode_imu_cdr(data, size, error);
  (void)io::detail::decode_imu_ros1(data, size, error);
}

}  // namespace gmwm::fuzz
