// rosbag2 input, sqlite3 storage (docs/cli.md "Inputs"): a sensor_msgs/msg/Imu topic of a
// ROS 2 bag as signals, without a ROS installation.
//
// The storage (rosbag2_storage_default_plugins, sqlite3): table topics(id, name, type,
// serialization_format, ...) and messages(id, topic_id, timestamp, data), one row per
// message, `data` the CDR serialisation (decoded in ros_imu.cc). Times from the header
// stamps (ns), which must increase in the order the bag stores them.

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
#include "ros_imu.h"
#include "rosbag2_reader.h"

namespace gmwm::io::detail {
namespace {

constexpr char kSqliteMagic[] = "SQLite format 3";  // the first 16 bytes, NUL included
constexpr const char* kImuType = "sensor_msgs/msg/Imu";

struct Db {
  sqlite3* db = nullptr;
  ~Db() { sqlite3_close(db); }
};
struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
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
  ImuTopic imu(path, topic);
  for (std::int64_t index = 1;; ++index) {
    const int rc = sqlite3_step(messages.s);
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW)
      throw InputError(imu.where(index) + "cannot read it: " + sqlite3_errmsg(db.db));
    const auto* blob = static_cast<const unsigned char*>(sqlite3_column_blob(messages.s, 0));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(messages.s, 0));
    std::string error;
    const auto m = decode_imu_cdr(blob, blob ? size : 0, error);
    if (!m) throw InputError(imu.where(index) + error);
    imu.add(*m, index);
  }
  return std::move(imu).signals("rosbag2:" + topic, "rosbag2 header stamps (ns)", options);
}

}  // namespace gmwm::io::detail
