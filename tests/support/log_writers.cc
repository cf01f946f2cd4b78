#include "log_writers.h"

#include <cmath>
#include <stdexcept>

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <sqlite3.h>
#include <zstd.h>

namespace gmwm::test {
namespace {

constexpr std::uint32_t kFirstSec = 1700000000;

std::string u32_string(const std::string& s) {
  LeBytes b;
  b.put(static_cast<std::uint32_t>(s.size())).text(s);
  return b.b;
}

// A message's stamp: (sec, nsec).
std::pair<std::uint32_t, std::uint32_t> stamp(int i, std::uint64_t step_ns) {
  const std::uint64_t t = static_cast<std::uint64_t>(i) * step_ns;
  return {kFirstSec + static_cast<std::uint32_t>(t / 1000000000u), static_cast<std::uint32_t>(t % 1000000000u)};
}

// The 37 doubles of sensor_msgs Imu after the header.
std::vector<double> imu_doubles(int i, bool zero_accel = false, bool zero_gyro = false) {
  std::vector<double> v = imu_values(i);
  if (zero_accel) std::fill(v.begin() + 3, v.end(), 0.0);
  if (zero_gyro) std::fill(v.begin(), v.begin() + 3, 0.0);
  std::vector<double> d(37, 0.0);
  d[3] = 1.0;  // orientation w
  for (int a = 0; a < 3; ++a) {
    d[static_cast<std::size_t>(13 + a)] = v[static_cast<std::size_t>(a)];
    d[static_cast<std::size_t>(25 + a)] = v[static_cast<std::size_t>(3 + a)];
  }
  return d;
}

std::string imu_ros1(int i, std::uint64_t step_ns, bool zero_accel, bool zero_gyro) {
  LeBytes b;
  const auto [sec, nsec] = stamp(i, step_ns);
  b.put(static_cast<std::uint32_t>(i)).put(sec).put(nsec).text(u32_string("imu"));
  for (double x : imu_doubles(i, zero_accel, zero_gyro)) b.put(x);
  return b.b;
}

constexpr const char* kImuMd5 = "6a62c6daae103f4ff57a132d6f95cec2";

}  // namespace

std::vector<double> imu_values(int i) {
  const double x = static_cast<double>(i);
  return {std::sin(x * 0.1) * 1e-3, std::cos(x * 0.37) * 2e-3, (i % 11) * 1e-4,
          9.81 + (i % 7) * 1e-3,    std::sin(x * 0.05) * 0.02, -(i % 5) * 3e-3};
}

std::string bz2_compress(const std::string& in) {
  std::string out(in.size() + in.size() / 100 + 600, '\0');
  auto n = static_cast<unsigned int>(out.size());
  if (BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(in.data()), static_cast<unsigned int>(in.size()), 9, 0,
                               0) != BZ_OK)
    throw std::runtime_error("bz2 compression failed");
  out.resize(n);
  return out;
}

std::string lz4_frame_compress(const std::string& in) {
  std::string out(LZ4F_compressFrameBound(in.size(), nullptr), '\0');
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr);
  if (LZ4F_isError(n)) throw std::runtime_error("lz4 compression failed");
  out.resize(n);
  return out;
}

std::string zstd_compress(const std::string& in) {
  std::string out(ZSTD_compressBound(in.size()), '\0');
  const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3);
  if (ZSTD_isError(n)) throw std::runtime_error("zstd compression failed");
  out.resize(n);
  return out;
}

// --- ROS 1 ---------------------------------------------------------------------------------------

std::string ros1_record(const std::vector<std::string>& fields, const std::string& data) {
  std::string header;
  for (const std::string& f : fields) header += u32_string(f);
  return u32_string(header) + u32_string(data);
}

namespace {

/// Appends a bag's index section (the connection record, then one chunk info record per
/// chunk) and records where each part starts.
void append_index_section(Ros1Bag& bag, const std::string& connection, const std::vector<std::string>& infos) {
  std::string& out = bag.bytes;
  bag.index_pos = out.size();
  bag.connection_at = out.size();
  out += connection;
  for (const std::string& info : infos) {
    bag.chunk_info_at.push_back(out.size());
    out += info;
  }
}

}  // namespace

Ros1Bag ros1_bag(const Ros1BagOptions& o) { return ros1_bag_of_topics({o}); }

Ros1Bag ros1_bag_of_topics(const std::vector<Ros1BagOptions>& topics) {
  Ros1Bag bag;
  const auto conn_count = static_cast<std::uint32_t>(topics.size());
  std::vector<std::string> connections;
  for (std::uint32_t c = 0; c < conn_count; ++c) {
    const std::string& topic = topics[c].topic;
    const std::string conn_header = u32_string("topic=" + topic) + u32_string("type=sensor_msgs/Imu") +
                                    u32_string(std::string("md5sum=") + kImuMd5) +
                                    u32_string("message_definition=std_msgs/Header header\n...");
    connections.push_back(
        ros1_record({ros1_field("op", std::uint8_t{0x07}), ros1_field("conn", c), "topic=" + topic}, conn_header));
  }
  // The bag header is padded to 4096 bytes, as rosbag writes it; its fields are patched at the end.
  std::string& out = bag.bytes;
  out = "#ROSBAG V2.0\n";
  const std::size_t header_at = out.size();
  const auto bag_header = [&](std::uint64_t index_pos, std::uint32_t chunks) {
    const std::vector<std::string> fields = {ros1_field("op", std::uint8_t{0x03}), ros1_field("index_pos", index_pos),
                                             ros1_field("conn_count", conn_count), ros1_field("chunk_count", chunks)};
    return ros1_record(fields, std::string(4096 - ros1_record(fields, "").size(), ' '));
  };
  out += bag_header(0, 0);
  std::vector<std::string> infos;
  // Each topic's messages in chunks of their own, one topic after the other.
  for (std::uint32_t c = 0; c < conn_count; ++c) {
    const Ros1BagOptions& o = topics[c];
    for (int first = 0; first < o.messages; first += o.per_chunk) {
      const int last = std::min(o.messages, first + o.per_chunk);
      std::string records = connections[c];
      LeBytes index;
      for (int i = first; i < last; ++i) {
        const auto [sec, nsec] = stamp(i, o.step_ns);
        const std::uint64_t time = sec | (std::uint64_t{nsec} << 32);
        index.put(time).put(static_cast<std::uint32_t>(records.size()));
        const std::string data = imu_ros1(i, o.step_ns, o.zero_accel, o.zero_gyro);
        const std::string h =
            ros1_record({ros1_field("op", std::uint8_t{0x02}), ros1_field("conn", c), ros1_field("time", time)}, "");
        if (i == 0 && c == 0) bag.first_message_data_at = records.size() + h.size();
        records +=
            ros1_record({ros1_field("op", std::uint8_t{0x02}), ros1_field("conn", c), ros1_field("time", time)}, data);
      }
      const std::string stored = o.compression == "bz2"   ? bz2_compress(records)
                                 : o.compression == "lz4" ? lz4_frame_compress(records)
                                                          : records;
      const std::uint64_t chunk_pos = out.size();
      bag.chunk_pos.push_back(chunk_pos);
      const std::vector<std::string> fields = {ros1_field("op", std::uint8_t{0x05}), "compression=" + o.compression,
                                               ros1_field("size", static_cast<std::uint32_t>(records.size()))};
      // The 'size' value: after the header length (4) and the first two fields (4 + length each) and "size=".
      bag.chunk_size_at.push_back(chunk_pos + 4 + (4 + fields[0].size()) + (4 + fields[1].size()) + 4 + 5);
      out += ros1_record(fields, stored);
      out += ros1_record({ros1_field("op", std::uint8_t{0x04}), ros1_field("ver", std::uint32_t{1}),
                          ros1_field("conn", c), ros1_field("count", static_cast<std::uint32_t>(last - first))},
                         index.b);
      const auto [s0, n0] = stamp(first, o.step_ns);
      const auto [s1, n1] = stamp(last - 1, o.step_ns);
      LeBytes per;
      per.put(c).put(static_cast<std::uint32_t>(last - first));
      infos.push_back(
          ros1_record({ros1_field("op", std::uint8_t{0x06}), ros1_field("ver", std::uint32_t{1}),
                       ros1_field("chunk_pos", chunk_pos), ros1_field("start_time", s0 | (std::uint64_t{n0} << 32)),
                       ros1_field("end_time", s1 | (std::uint64_t{n1} << 32)), ros1_field("count", std::uint32_t{1})},
                      per.b));
    }
  }
  std::string all_connections;
  for (const std::string& c : connections) all_connections += c;
  append_index_section(bag, all_connections, infos);
  const std::string h = bag_header(bag.index_pos, static_cast<std::uint32_t>(bag.chunk_pos.size()));
  out.replace(header_at, h.size(), h);
  return bag;
}

std::vector<Ros1BagOptions> realsense_topics(int gyro_messages, int accel_messages) {
  Ros1BagOptions gyro, accel;
  gyro.topic = "/camera/gyro/sample";
  gyro.messages = gyro_messages;
  gyro.step_ns = 2500000;  // 400 Hz
  gyro.zero_accel = true;
  accel.topic = "/camera/accel/sample";
  accel.messages = accel_messages;
  accel.step_ns = 4000000;  // 250 Hz
  accel.zero_gyro = true;
  return {gyro, accel};
}

// --- MCAP ------------------------------------------------------------------------------------------

std::string mcap_record(std::uint8_t op, const std::string& content) {
  LeBytes b;
  b.put(op).put(static_cast<std::uint64_t>(content.size())).text(content);
  return b.b;
}

std::string imu_cdr(int i, std::uint64_t step_ns, const std::string& frame) {
  const auto [sec, nsec] = stamp(i, step_ns);
  LeBytes body;
  body.put(static_cast<std::int32_t>(sec)).put(nsec).put(static_cast<std::uint32_t>(frame.size() + 1)).text(frame);
  body.b += '\0';
  while (body.b.size() % 8) body.b += '\0';
  for (double x : imu_doubles(i)) body.put(x);
  return std::string("\x00\x01\x00\x00", 4) + body.b;
}

Mcap mcap_file(const McapOptions& o) {
  Mcap m;
  std::string& out = m.bytes;
  out = std::string("\x89MCAP0\r\n", 8);
  out += mcap_record(0x01, u32_string("ros2") + u32_string("gmwm tests"));
  LeBytes schema;
  schema.put(std::uint16_t{1}).text(u32_string("sensor_msgs/msg/Imu")).text(u32_string("ros2msg"));
  schema.text(u32_string("std_msgs/Header header\n..."));
  LeBytes channel;
  channel.put(std::uint16_t{1}).put(std::uint16_t{1}).text(u32_string(o.topic)).text(u32_string("cdr"));
  channel.put(std::uint32_t{0});  // metadata: an empty map
  const std::string definitions = mcap_record(0x03, schema.b) + mcap_record(0x04, channel.b);
  const auto message = [&](int i) {
    const auto [sec, nsec] = stamp(i, o.step_ns);
    const std::uint64_t t = std::uint64_t{sec} * 1000000000u + nsec;
    LeBytes b;
    b.put(std::uint16_t{1}).put(static_cast<std::uint32_t>(i)).put(t).put(t).text(imu_cdr(i, o.step_ns));
    return mcap_record(0x05, b.b);
  };
  if (o.per_chunk <= 0) {
    out += definitions;
    for (int i = 0; i < o.messages; ++i) out += message(i);
  } else {
    for (int first = 0; first < o.messages; first += o.per_chunk) {
      const int last = std::min(o.messages, first + o.per_chunk);
      std::string records = first == 0 ? definitions : std::string();
      for (int i = first; i < last; ++i) records += message(i);
      const std::string stored = o.compression == "lz4"    ? lz4_frame_compress(records)
                                 : o.compression == "zstd" ? zstd_compress(records)
                                                           : records;
      const auto [s0, n0] = stamp(first, o.step_ns);
      const auto [s1, n1] = stamp(last - 1, o.step_ns);
      LeBytes c;
      c.put(std::uint64_t{s0} * 1000000000u + n0).put(std::uint64_t{s1} * 1000000000u + n1);
      c.put(static_cast<std::uint64_t>(records.size()));
      const uLong crc = crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(records.data()), records.size());
      c.put(o.crc ? static_cast<std::uint32_t>(crc) : std::uint32_t{0});
      c.text(u32_string(o.compression)).put(static_cast<std::uint64_t>(stored.size())).text(stored);
      m.chunk_at.push_back(out.size());
      out += mcap_record(0x06, c.b);
    }
  }
  m.data_end_at = out.size();
  out += mcap_record(0x0F, LeBytes().put(std::uint32_t{0}).b);
  LeBytes footer;
  footer.put(std::uint64_t{0}).put(std::uint64_t{0}).put(std::uint32_t{0});
  out += mcap_record(0x02, footer.b);
  out += std::string("\x89MCAP0\r\n", 8);
  return m;
}

Ros1Bag ros1_bag_of_chunks(const std::vector<Ros1StoredChunk>& chunks) {
  Ros1Bag bag;
  std::string& out = bag.bytes;
  const std::string conn_header =
      u32_string("topic=/imu") + u32_string("type=sensor_msgs/Imu") + u32_string(std::string("md5sum=") + kImuMd5);
  const std::string connection = ros1_record(
      {ros1_field("op", std::uint8_t{0x07}), ros1_field("conn", std::uint32_t{0}), "topic=/imu"}, conn_header);
  const auto bag_header = [&](std::uint64_t index_pos) {
    return ros1_record({ros1_field("op", std::uint8_t{0x03}), ros1_field("index_pos", index_pos),
                        ros1_field("conn_count", std::uint32_t{1}),
                        ros1_field("chunk_count", static_cast<std::uint32_t>(chunks.size()))},
                       std::string(64, ' '));
  };
  out = "#ROSBAG V2.0\n" + bag_header(0);
  std::vector<std::string> infos;
  for (const Ros1StoredChunk& c : chunks) {
    const std::uint64_t pos = out.size();
    bag.chunk_pos.push_back(pos);
    out += ros1_record(
        {ros1_field("op", std::uint8_t{0x05}), "compression=" + c.compression, ros1_field("size", c.size)}, c.stored);
    LeBytes per;
    per.put(std::uint32_t{0}).put(std::uint32_t{1});
    infos.push_back(
        ros1_record({ros1_field("op", std::uint8_t{0x06}), ros1_field("ver", std::uint32_t{1}),
                     ros1_field("chunk_pos", pos), ros1_field("start_time", std::uint64_t{kFirstSec}),
                     ros1_field("end_time", std::uint64_t{kFirstSec}), ros1_field("count", std::uint32_t{1})},
                    per.b));
  }
  append_index_section(bag, connection, infos);
  const std::string h = bag_header(bag.index_pos);
  out.replace(13, h.size(), h);
  return bag;
}

Mcap mcap_of_chunks(const std::vector<McapStoredChunk>& chunks) {
  Mcap m;
  std::string& out = m.bytes;
  out = std::string("\x89MCAP0\r\n", 8);
  out += mcap_record(0x01, u32_string("ros2") + u32_string("gmwm tests"));
  for (const McapStoredChunk& c : chunks) {
    LeBytes b;
    b.put(std::uint64_t{0}).put(std::uint64_t{0}).put(c.size).put(std::uint32_t{0});
    b.text(u32_string(c.compression)).put(static_cast<std::uint64_t>(c.stored.size())).text(c.stored);
    m.chunk_at.push_back(out.size());
    out += mcap_record(0x06, b.b);
  }
  m.data_end_at = out.size();
  out += mcap_record(0x0F, LeBytes().put(std::uint32_t{0}).b);
  out += mcap_record(0x02, LeBytes().put(std::uint64_t{0}).put(std::uint64_t{0}).put(std::uint32_t{0}).b);
  out += std::string("\x89MCAP0\r\n", 8);
  return m;
}

// --- rosbag2 ---------------------------------------------------------------------------------------

void rosbag2_db(const std::string& path, const Rosbag2Options& o) {
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) throw std::runtime_error("cannot create " + path);
  const auto exec = [&](const std::string& sql, bool must) {
    char* err = nullptr;
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK && must) {
      const std::string why = err ? err : "?";
      sqlite3_free(err);
      sqlite3_close(db);
      throw std::runtime_error(path + ": " + sql + ": " + why);
    }
    sqlite3_free(err);
  };
  if (o.wal) exec("PRAGMA journal_mode=WAL", true);
  exec("CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL)", true);
  exec(o.topics_sql.empty() ? "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
                              "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)"
                            : o.topics_sql,
       true);
  exec(o.messages_sql.empty() ? "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
                                "timestamp INTEGER NOT NULL, data BLOB NOT NULL)"
                              : o.messages_sql,
       true);
  exec("INSERT INTO topics VALUES (1, '/imu', 'sensor_msgs/msg/Imu', 'cdr', '')", false);
  exec("BEGIN", true);
  sqlite3_stmt* insert = nullptr;
  if (sqlite3_prepare_v2(db, "INSERT INTO messages(id, topic_id, timestamp, data) VALUES (?, 1, ?, ?)", -1, &insert,
                         nullptr) == SQLITE_OK) {
    for (int i = 0; i < o.messages; ++i) {
      const std::string blob = o.blob ? o.blob(i) : imu_cdr(i, 5000000);
      sqlite3_bind_int(insert, 1, i + 1);
      sqlite3_bind_int64(insert, 2, 1700000000000000000LL + i * 5000000LL);
      sqlite3_bind_blob(insert, 3, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT);
      sqlite3_step(insert);
      sqlite3_reset(insert);
    }
  }
  sqlite3_finalize(insert);
  exec("COMMIT", true);
  sqlite3_close(db);
}

// --- ULog ------------------------------------------------------------------------------------------

UlogBuilder::UlogBuilder() {
  bytes = std::string("ULog\x01\x12\x35\x01", 8);
  bytes += LeBytes().put(std::uint64_t{1000000}).b;  // start time, us
}

UlogBuilder& UlogBuilder::add(char type, const std::string& payload) {
  bytes += LeBytes().put(static_cast<std::uint16_t>(payload.size())).put(static_cast<std::uint8_t>(type)).b + payload;
  return *this;
}

UlogBuilder& UlogBuilder::subscribe(std::uint8_t multi, std::uint16_t id, const std::string& name) {
  return add('A', LeBytes().put(multi).put(id).text(name).b);
}

UlogBuilder& UlogBuilder::data(std::uint16_t id, const std::string& payload) {
  return add('D', LeBytes().put(id).text(payload).b);
}

std::string ulog_sensor_combined(int n) {
  UlogBuilder u;
  u.format(
      "sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;"
      "int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;uint32_t accelerometer_integral_dt;"
      "uint8_t accelerometer_clipping;uint8_t gyro_clipping;uint8_t accel_calibration_count;"
      "uint8_t gyro_calibration_count;");
  u.subscribe(0, 0, "sensor_combined");
  for (int i = 0; i < n; ++i) {
    const std::vector<double> v = imu_values(i);
    LeBytes d;
    d.put(std::uint64_t{1000000} + 5000u * static_cast<std::uint64_t>(i));
    for (int a = 0; a < 3; ++a) d.put(static_cast<float>(v[static_cast<std::size_t>(a)]));
    d.put(std::uint32_t{5000}).put(std::int32_t{0});
    for (int a = 3; a < 6; ++a) d.put(static_cast<float>(v[static_cast<std::size_t>(a)]));
    d.put(std::uint32_t{5000}).put(std::uint32_t{0});
    u.data(0, d.b);
  }
  return u.bytes;
}

}  // namespace gmwm::test
