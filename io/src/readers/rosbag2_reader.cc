// rosbag2 input, sqlite3 storage (docs/cli.md "Inputs"): a sensor_msgs/msg/Imu topic of a
// ROS 2 bag as signals, without a ROS installation.
//
// The storage (rosbag2_storage_default_plugins, sqlite3): table topics(id, name, type,
// serialization_format, ...) and messages(id, topic_id, timestamp, data), one row per
// message, `data` the CDR serialisation (decoded in ros_imu.cc). Times from the header
// stamps (ns), which must increase in the order the bag stores them.
//
// A database is a program as much as data: a view, a virtual table or a generated column
// runs code when it is read (a recursive view named `messages` never ends). So the file is
// opened read-only and immutable (nothing is locked or created beside it: no -shm or -wal
// file, and read-only media read as well), only real tables with rosbag2's columns are
// accepted (sqlite_master type 'table', not virtual, the columns stored), no value may
// exceed kMaxValueBytes, and the queries are stopped past a number of steps of SQLite's
// virtual machine proportional to the file's size (kStepsPerFileByte).

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include <sqlite3.h>
#include <sys/stat.h>

#include "gmwm/engine/error.h"
#include "ros_imu.h"
#include "rosbag2_reader.h"

namespace gmwm::io::detail {
namespace {

constexpr char kSqliteMagic[] = "SQLite format 3";  // the first 16 bytes, NUL included
constexpr const char* kImuType = "sensor_msgs/msg/Imu";
// The largest string or blob SQLite may hand over (SQLITE_LIMIT_LENGTH): an IMU message is
// about 300 bytes and a topic row's strings (its QoS profiles) a few kB.
constexpr int kMaxValueBytes = 16 << 20;
// The queries' budget of virtual machine steps: reading the messages of a real table takes
// 12 steps a row, 0.03 a byte of the file (measured on python/tests/test_rosbag2.py's bag of
// 1e5 messages), so 64 a byte is 2000 times what a bag needs, while a query that runs away
// (a recursive view that slipped through) stops within seconds; the floor covers a small
// file's schema lookups. Past it the query is interrupted (sqlite3_progress_handler).
constexpr std::uint64_t kStepsPerFileByte = 64;
constexpr std::uint64_t kStepsFloor = 10000000;
// Steps between two calls of the progress handler.
constexpr int kStepsPerCheck = 10000;

struct Db {
  sqlite3* db = nullptr;
  ~Db() { sqlite3_close(db); }
};
struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
};

// The steps the queries may take, counted by the progress handler.
struct StepBudget {
  std::uint64_t limit = 0, used = 0;
  bool exceeded = false;
};

int on_progress(void* p) {
  auto* b = static_cast<StepBudget*>(p);
  b->used += kStepsPerCheck;
  if (b->used > b->limit) b->exceeded = true;
  return b->exceeded ? 1 : 0;  // non-zero: interrupt the query
}

// `path` as an SQLite URI ("file:" and the path with every byte but the unreserved ones and
// '/' percent-encoded), read-only and immutable.
std::string immutable_uri(const std::string& path) {
  std::string uri = "file:";
  for (unsigned char c : std::filesystem::absolute(path).string()) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      uri += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      uri += hex;
    }
  }
  return uri + "?mode=ro&immutable=1";
}

// The size of `file`, 0 when it does not exist.
std::uint64_t size_of(const std::string& file) {
  struct stat st {};
  return ::stat(file.c_str(), &st) == 0 ? static_cast<std::uint64_t>(st.st_size) : 0;
}

class Bag {
 public:
  explicit Bag(std::string path) : path_(std::move(path)) {
    // Pages still in a write-ahead log or a rollback journal beside the file are part of
    // the database: an immutable read would miss them, and reading them would create or
    // change files beside the input. A bag left so (a recording still open or interrupted)
    // is refused with the way out.
    for (const char* side : {"-wal", "-journal"})
      if (size_of(path_ + side) > 0)
        throw InputError(path_ + ": found " + path_ + side + " beside it with changes not yet in the database (a " +
                         "recording still open or interrupted), expected a closed bag: let the recorder finish, or " +
                         "merge them with: sqlite3 '" + path_ + "' 'PRAGMA wal_checkpoint(TRUNCATE)'");
    budget_.limit = kStepsFloor + kStepsPerFileByte * size_of(path_);
    if (sqlite3_open_v2(immutable_uri(path_).c_str(), &db_.db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) !=
        SQLITE_OK)
      throw InputError(path_ + ": cannot open the rosbag2 database: " + sqlite3_errmsg(db_.db));
    sqlite3_limit(db_.db, SQLITE_LIMIT_LENGTH, kMaxValueBytes);
    sqlite3_progress_handler(db_.db, kStepsPerCheck, on_progress, &budget_);
    // No mapping of the file (a file that shrinks under a mapping is a SIGBUS).
    sqlite3_exec(db_.db, "PRAGMA mmap_size=0", nullptr, nullptr, nullptr);
  }

  sqlite3* db() const { return db_.db; }
  const std::string& path() const { return path_; }

  // Refuses `table` unless it is a real table with `columns` stored (not generated).
  void require_table(const char* table, std::initializer_list<const char*> columns) {
    Statement s;
    prepare(s, "SELECT type, sql FROM sqlite_master WHERE name = ?1 COLLATE NOCASE", table);
    sqlite3_bind_text(s.s, 1, table, -1, SQLITE_STATIC);
    const int rc = step(s, table);
    if (rc != SQLITE_ROW)
      throw InputError(path_ + ": found an SQLite file without a rosbag2 '" + table +
                       "' table, expected a rosbag2 .db3 bag");
    const std::string type = text(s, 0), sql = text(s, 1);
    if (type != "table")
      throw InputError(path_ + ": '" + table + "' is a " + type + ", expected the rosbag2 table (a " + type +
                       " runs code when it is read)");
    if (sql.size() >= 14 && sqlite3_strnicmp(sql.c_str(), "CREATE VIRTUAL", 14) == 0)
      throw InputError(path_ + ": '" + table + "' is a virtual table, expected the rosbag2 table");
    Statement cols;
    prepare(cols, "SELECT name, hidden FROM pragma_table_xinfo(?1)", table);
    sqlite3_bind_text(cols.s, 1, table, -1, SQLITE_STATIC);
    std::vector<std::pair<std::string, int>> found;
    while (step(cols, table) == SQLITE_ROW) found.emplace_back(text(cols, 0), sqlite3_column_int(cols.s, 1));
    for (const char* c : columns) {
      auto it = found.begin();
      while (it != found.end() && sqlite3_stricmp(it->first.c_str(), c) != 0) ++it;
      if (it == found.end())
        throw InputError(path_ + ": table '" + table + "' has no column '" + c + "', expected rosbag2's columns");
      if (it->second != 0)
        throw InputError(path_ + ": column '" + c + "' of table '" + table +
                         "' is generated, expected a stored column (a generated column runs code when it is read)");
    }
  }

  void prepare(Statement& s, const char* sql, const std::string& what) {
    if (sqlite3_prepare_v2(db_.db, sql, -1, &s.s, nullptr) != SQLITE_OK)
      throw InputError(path_ + ": cannot query the rosbag2 '" + what + "' table: " + sqlite3_errmsg(db_.db));
  }

  // sqlite3_step, throwing on an error (`what` names the table) other than in the messages.
  int step(Statement& s, const std::string& what) {
    const int rc = sqlite3_step(s.s);
    if (rc == SQLITE_ROW || rc == SQLITE_DONE) return rc;
    throw InputError(path_ + ": cannot read the rosbag2 '" + what + "' table: " + problem());
  }

  // What stopped a query: the step budget, or SQLite's message.
  std::string problem() const {
    if (budget_.exceeded)
      return "more than " + std::to_string(budget_.limit) + " steps of SQLite's virtual machine for a file of " +
             std::to_string(size_of(path_)) + " bytes, expected at most " + std::to_string(kStepsPerFileByte) +
             " a byte (a crafted database?)";
    return sqlite3_errmsg(db_.db);
  }

  static std::string text(Statement& s, int c) {
    const unsigned char* t = sqlite3_column_text(s.s, c);
    return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
  }

 private:
  std::string path_;
  Db db_;
  StepBudget budget_;
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
  Bag bag(path);
  bag.require_table("topics", {"id", "name", "type", "serialization_format"});
  bag.require_table("messages", {"id", "topic_id", "timestamp", "data"});
  // The topics; the IMU one named by --topic, or the only one.
  Statement topics;
  bag.prepare(topics, "SELECT id, name, type, serialization_format FROM topics", "topics");
  std::int64_t topic_id = -1;
  std::string topic, imu_topics, all_topics;
  while (bag.step(topics, "topics") == SQLITE_ROW) {
    const std::string name = Bag::text(topics, 1), type = Bag::text(topics, 2), format = Bag::text(topics, 3);
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
    throw InputError(
        path + (options.topic.empty() ? ": no " + std::string(kImuType) + " topic" : ": no topic " + options.topic) +
        " in this bag (it has " + (all_topics.empty() ? std::string("no topic") : all_topics) + ")");

  Statement messages;
  bag.prepare(messages, "SELECT data FROM messages WHERE topic_id = ? ORDER BY timestamp, id", "messages");
  sqlite3_bind_int64(messages.s, 1, topic_id);
  ImuTopic imu(path, topic, options);
  for (std::int64_t index = 1;; ++index) {
    const int rc = sqlite3_step(messages.s);
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW) throw InputError(imu.where(index) + "cannot read it: " + bag.problem());
    const auto* blob = static_cast<const unsigned char*>(sqlite3_column_blob(messages.s, 0));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(messages.s, 0));
    std::string error;
    const auto m = decode_imu_cdr(blob, blob ? size : 0, error);
    if (!m) throw InputError(imu.where(index) + error);
    imu.add(*m, index);
  }
  return std::move(imu).signals("rosbag2:" + topic, "rosbag2 header stamps (ns)");
}

}  // namespace gmwm::io::detail
