#include "ros_imu.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "checked_size.h"
#include "gmwm/engine/error.h"

namespace gmwm::io::detail {
namespace {

constexpr std::size_t kCdrEncapsulation = 4;
constexpr int kImuDoubles = 37;  // 4 + 9 + 3 + 9 + 3 + 9
constexpr int kGyroFirst = 13;   // after orientation (4) and its covariance (9)
constexpr int kAccelFirst = 25;  // after angular_velocity (3) and its covariance (9)

// A bounds-checked little-endian cursor. `align` true: CDR, each primitive aligned to its
// size; false: ROS 1, packed. Every position is checked before it is used (fits(): no sum
// of a stated length and a position can wrap around); the first failure is kept as text.
class Cursor {
 public:
  Cursor(const unsigned char* p, std::size_t n, bool align, std::size_t origin)
      : p_(p), n_(n), origin_(origin), align_(align) {}
  bool ok() const { return ok_; }
  const std::string& failure() const { return failure_; }
  template <typename T>
  T get(const char* what) {
    T v{};
    if (!ok_) return v;
    const std::size_t at = align_ ? (pos_ + sizeof(T) - 1) / sizeof(T) * sizeof(T) : pos_;
    if (!fits(at, sizeof(T), n_)) {
      fail(std::string(what) + " (" + std::to_string(sizeof(T)) + " bytes at byte " + std::to_string(origin_ + at) +
           ") runs past its end");
      return v;
    }
    std::memcpy(&v, p_ + at, sizeof(T));
    pos_ = at + sizeof(T);
    return v;
  }
  void skip_string(const char* what) {
    const auto len = get<std::uint32_t>(what);
    if (!ok_) return;
    if (!fits(pos_, len, n_)) {
      fail(std::string(what) + " (a string of " + std::to_string(len) + " bytes at byte " +
           std::to_string(origin_ + pos_) + ") runs past its end");
      return;
    }
    pos_ += len;
  }

 private:
  void fail(std::string what) {
    ok_ = false;
    failure_ = std::move(what);
  }
  const unsigned char* p_;
  std::size_t n_, pos_ = 0, origin_;
  bool align_;
  bool ok_ = true;
  std::string failure_;
};

std::optional<ImuMessage> decode_body(Cursor& c, ImuMessage m, std::size_t size, std::string& error) {
  c.skip_string("frame_id");
  double v[kImuDoubles];
  for (double& x : v) x = c.get<double>("the orientation, angular_velocity and linear_acceleration fields");
  if (!c.ok()) {
    error =
        "truncated: " + c.failure() + " (" + std::to_string(size) + " bytes), expected a whole sensor_msgs Imu message";
    return std::nullopt;
  }
  if (m.nanosec >= 1000000000u) {
    error = "header stamp nanoseconds " + std::to_string(m.nanosec) + ", expected < 1e9";
    return std::nullopt;
  }
  for (int a = 0; a < 3; ++a) {
    m.gyro[a] = v[kGyroFirst + a];
    m.accel[a] = v[kAccelFirst + a];
  }
  return m;
}

}  // namespace

std::optional<ImuMessage> decode_imu_cdr(const unsigned char* data, std::size_t size, std::string& error) {
  if (size < kCdrEncapsulation) {
    error = "found " + std::to_string(size) + " bytes, expected a CDR sensor_msgs/msg/Imu";
    return std::nullopt;
  }
  if (data[0] != 0x00 || data[1] != 0x01) {
    error = "found CDR encapsulation " + std::to_string(data[0]) + " " + std::to_string(data[1]) +
            ", expected 0 1 (little-endian CDR)";
    return std::nullopt;
  }
  Cursor c(data + kCdrEncapsulation, size - kCdrEncapsulation, true, kCdrEncapsulation);
  ImuMessage m;
  m.sec = c.get<std::int32_t>("the header stamp");
  m.nanosec = c.get<std::uint32_t>("the header stamp");
  return decode_body(c, m, size, error);
}

std::optional<ImuMessage> decode_imu_ros1(const unsigned char* data, std::size_t size, std::string& error) {
  Cursor c(data, size, false, 0);
  c.get<std::uint32_t>("the header seq");
  ImuMessage m;
  m.sec = c.get<std::uint32_t>("the header stamp");
  m.nanosec = c.get<std::uint32_t>("the header stamp");
  return decode_body(c, m, size, error);
}

ImuTopic::ImuTopic(std::string path, std::string topic, const ReadOptions& options)
    : path_(std::move(path)),
      topic_(std::move(topic)),
      columns_(path_, "topic " + topic_,
               {{"gyro_x", "rad/s"},
                {"gyro_y", "rad/s"},
                {"gyro_z", "rad/s"},
                {"accel_x", "m/s^2"},
                {"accel_y", "m/s^2"},
                {"accel_z", "m/s^2"}},
               options) {}

std::string ImuTopic::where(std::int64_t index) const {
  return path_ + ": topic " + topic_ + " message " + std::to_string(index) + ": ";
}

void ImuTopic::add(const ImuMessage& m, std::int64_t index) {
  if (columns_.size() == 0) first_sec_ = m.sec;
  const double t = static_cast<double>(m.sec - first_sec_) * 1e9 + static_cast<double>(m.nanosec);
  if (columns_.size() > 0 && t <= columns_.last()) {
    char stamp[48];
    std::snprintf(stamp, sizeof stamp, "%lld.%09u", static_cast<long long>(m.sec), static_cast<unsigned>(m.nanosec));
    throw InputError(where(index) + "header stamp " + stamp +
                     " s is not after the previous message's: unsorted stamps");
  }
  static const char* const kNames[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  const double values[6] = {m.gyro[0], m.gyro[1], m.gyro[2], m.accel[0], m.accel[1], m.accel[2]};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(values[a])) throw InputError(where(index) + kNames[a] + " is not a finite number");
    if (!std::isfinite(values[3 + a])) throw InputError(where(index) + kNames[3 + a] + " is not a finite number");
  }
  columns_.add(t, values, [&] { return where(index); });
}

SignalSet ImuTopic::signals(const std::string& preset, const std::string& stamp_source) && {
  return std::move(columns_).finish(preset, TimeUnit{1e-9, "ns"}, stamp_source);
}

}  // namespace gmwm::io::detail
