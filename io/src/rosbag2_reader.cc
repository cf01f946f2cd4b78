// rosbag2 input, sqlite3 storage (docs/cli.md "Inputs"): a sensor_msgs/msg/Imu topic of a
// ROS 2 bag as signals, without a ROS installation.
//
// The storage (rosbag2_storage_default_plugins, sqlite3): table topics(id, name, type,
// serialization_format, ...) and messages(id, topic_id, timestamp, data), one row per
// message, `data` the CDR serialisation. The message (OMG CDR, little-endian encapsulation
// 00 01, every primitive aligned to its size from the end of the 4-byte encapsulation
// header): std_msgs/Header {int32 sec, uint32 nanosec, string frame_id (uint32 length with
// the NUL, the bytes)}, orientation (4 doubles), its covariance (9), angular_velocity (3),
// its covariance (9), linear_acceleration (3), its covariance (9).
//
// angular_velocity -> gyro_x..z (rad/s), linear_acceleration -> accel_x..z (m/s^2); times
// from the header stamps (ns), which must increase in the order the bag stores them.

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <sqlite3.h>

#include "gmwm/engine/error.h"
#include "log_signals.h"
#include "rosbag2_reader.h"

namespace gmwm::io::detail {
namespace {

constexpr char kSqliteMagic[] = "SQLite format 3";  // the first 16 bytes, NUL included
constexpr const char* kImuType = "sensor_msgs/msg/Imu";
constexpr std::size_t kEncapsulation = 4;

struct Db {
  sqlite3* db = nullptr;
  ~Db() { sqlite3_close(db); }
};
struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
};

// Little-endian CDR cursor over one message's bytes (after the encapsulation header).
class Cdr {
 public:
  Cdr(const unsigned char* p, std::size_t n) : p_(p), n_(n) {}
  bool ok() const { return ok_; }
  template <typename T>
  T get() {
    pos_ = (pos_ + sizeof(T) - 1) / sizeof(T) * sizeof(T);  // alignment to the primitive's size
    T v{};
    if (pos_ + sizeof(T) > n_) {
      ok_ = false;
      return v;
    }
    std::memcpy(&v, p_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  void skip_string() {
    const auto len = get<std::uint32_t>();
    if (!ok_ || len > n_ - pos_) {
      ok_ = false;
      return;
    }
    pos_ += len;
  }

 private:
  const unsigned char* p_;
  std::size_t n_, pos_ = 0;
  bool ok_ = true;
};

}  // namespace

bool is_rosbag2_sqlite(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // never sniff a pipe
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kSqliteMagic] = {};
  return in && in.read(head, sizeof head) && std::memcmp(head, kSqliteMagic, sizeof head) == 0;
}

SignalSet read_rosbag2_sqlite(const std::string& path, const ReadOptions& options) {
  Db db;
  if (sqlite3_open_v2(path.c_str(), &db.db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
    throw InputError(path + ": cannot open the rosbag2 database: " + sqlite3_errmsg(db.db));
  // The topics; the IMU one named by --topic, or the only one.
  Statement topics;
  if (sqlite3_prepare_v2(db.db, "SELECT id, name, type, serialization_format FROM topics", -1, &topics.s, nullptr) !=
      SQLITE_OK)
    throw InputError(path + ": found an SQLite file without a rosbag2 'topics' table, expected a rosbag2 .db3 bag");
  std::int64_t topic_id = -1;
  std::string topic, imu_topics, all_topics;
  while (sqlite3_step(topics.s) == SQLITE_ROW) {
    const auto text = [&](int c) {
      const unsigned char* t = sqlite3_column_text(topics.s, c);
      return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
    };
    const std::string name = text(1), type = text(2), format = text(3);
    all_topics += (all_topics.empty() ? "" : ", ") + name + " (" + type + ")";
    const bool imu = type == kImuType;
    if (imu) imu_topics += (imu_topics.empty() ? "" : ", ") + name;
    if (options.topic.empty() ? imu : name == options.topic) {
      if (!options.topic.empty() && !imu)
        throw InputError(path + ": topic " + name + " is " + type + ", expected " + kImuType + " messages");
      if (format != "cdr")
        throw InputError(path + ": topic " + name + " is serialised as '" + format + "', expected cdr");
      if (topic_id >= 0)
        throw InputError(path + ": several " + std::string(kImuType) + " topics (" + imu_topics +
                         "): name one with --topic");
      topic_id = sqlite3_column_int64(topics.s, 0);
      topic = name;
    }
  }
  if (topic_id < 0)
    throw InputError(path + (options.topic.empty() ? ": no " + std::string(kImuType) + " topic"
                                                   : ": no topic " + options.topic) +
                     " in this bag (it has " + (all_topics.empty() ? std::string("no topic") : all_topics) + ")");

  Statement messages;
  if (sqlite3_prepare_v2(db.db, "SELECT data FROM messages WHERE topic_id = ? ORDER BY timestamp, id", -1,
                         &messages.s, nullptr) != SQLITE_OK)
    throw InputError(path + ": found no rosbag2 'messages' table: " + sqlite3_errmsg(db.db));
  sqlite3_bind_int64(messages.s, 1, topic_id);
  std::vector<LogAxis> axes = {{"gyro_x", "rad/s", {}},  {"gyro_y", "rad/s", {}},  {"gyro_z", "rad/s", {}},
                               {"accel_x", "m/s^2", {}}, {"accel_y", "m/s^2", {}}, {"accel_z", "m/s^2", {}}};
  std::vector<double> stamps;
  std::int64_t first_sec = 0;
  for (std::int64_t index = 1;; ++index) {
    const int rc = sqlite3_step(messages.s);
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW) throw InputError(path + ": reading message " + std::to_string(index) + " of " + topic + ": " +
                                           sqlite3_errmsg(db.db));
    const auto* blob = static_cast<const unsigned char*>(sqlite3_column_blob(messages.s, 0));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(messages.s, 0));
    const std::string where = path + ": topic " + topic + " message " + std::to_string(index) + ": ";
    if (size < kEncapsulation || !blob) throw InputError(where + "found " + std::to_string(size) + " bytes, expected a CDR " + kImuType);
    if (blob[0] != 0x00 || blob[1] != 0x01)
      throw InputError(where + "found CDR encapsulation " + std::to_string(blob[0]) + " " + std::to_string(blob[1]) +
                       ", expected 0 1 (little-endian CDR)");
    Cdr c(blob + kEncapsulation, size - kEncapsulation);
    const auto sec = c.get<std::int32_t>();
    const auto nsec = c.get<std::uint32_t>();
    c.skip_string();  // frame_id
    double v[37];
    for (double& x : v) x = c.get<double>();
    if (!c.ok()) throw InputError(where + "truncated: " + std::to_string(size) + " bytes do not hold a " + kImuType);
    if (nsec >= 1000000000u) throw InputError(where + "header stamp nanosec " + std::to_string(nsec) + ", expected < 1e9");
    if (stamps.empty()) first_sec = sec;
    const double t = static_cast<double>(sec - first_sec) * 1e9 + static_cast<double>(nsec);
    if (!stamps.empty() && t <= stamps.back())
    {
      char stamp[40];
      std::snprintf(stamp, sizeof stamp, "%d.%09u", static_cast<int>(sec), static_cast<unsigned>(nsec));
      throw InputError(where + "header stamp " + stamp + " s is not after the previous message's: unsorted stamps");
    }
    stamps.push_back(t);
    // orientation 0-3, its covariance 4-12, angular_velocity 13-15, covariance 16-24,
    // linear_acceleration 25-27, covariance 28-36.
    for (int a = 0; a < 3; ++a) {
      axes[static_cast<std::size_t>(a)].values.push_back(v[13 + a]);
      axes[static_cast<std::size_t>(3 + a)].values.push_back(v[25 + a]);
    }
    for (int a = 0; a < 6; ++a)
      if (!std::isfinite(axes[static_cast<std::size_t>(a)].values.back()))
        throw InputError(where + axes[static_cast<std::size_t>(a)].name + " is not a finite number");
  }
  return log_signal_set(path, "rosbag2:" + topic, "topic " + topic, std::move(axes), stamps, TimeUnit{1e-9, "ns"},
                        "rosbag2 header stamps (ns)", options);
}

}  // namespace gmwm::io::detail
