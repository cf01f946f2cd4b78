#pragma once
// Writers of small binary logs for the tests, from the published formats and independent of
// the readers in io/: ROS 1 bags (format 2.0, chunks uncompressed, bz2 or lz4) and MCAP files
// (chunks uncompressed, lz4 or zstd, or no chunks) holding one sensor_msgs Imu topic, and a
// byte builder for crafted PX4 ULog files. Each writer says where the fields that hostile
// tests tamper with are (byte offsets in the file).

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace gmwm::test {

/// Little-endian bytes.
struct LeBytes {
  std::string b;
  template <typename T>
  LeBytes& put(T v) {
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    b.append(raw, sizeof(T));
    return *this;
  }
  LeBytes& text(const std::string& s) {
    b += s;
    return *this;
  }
  std::size_t size() const { return b.size(); }
};

/// Overwrites sizeof(T) bytes of `s` at `offset` with `v` (little-endian).
template <typename T>
void patch(std::string& s, std::uint64_t offset, T v) {
  std::memcpy(s.data() + offset, &v, sizeof(T));
}

/// The IMU values of message i (gyro then accel), as the writers put them.
std::vector<double> imu_values(int i);

// --- ROS 1 bags ----------------------------------------------------------------------------

struct Ros1BagOptions {
  int messages = 256;
  int per_chunk = 64;
  std::string compression = "none";  ///< "none", "bz2" or "lz4"
  std::string topic = "/imu";
  std::uint64_t step_ns = 5000000;  ///< 200 Hz
  /// linear_acceleration 0 in every message: a gyroscope-only topic (RealSense's
  /// /camera/gyro/sample).
  bool zero_accel = false;
  /// angular_velocity 0 in every message: an accelerometer-only topic (/camera/accel/sample).
  bool zero_gyro = false;
};

struct Ros1Bag {
  std::string bytes;
  std::uint64_t index_pos = 0;               ///< where the index section starts
  std::vector<std::uint64_t> chunk_pos;      ///< the chunk records
  std::vector<std::uint64_t> chunk_size_at;  ///< each chunk header's 'size' value (uint32)
  std::vector<std::uint64_t> chunk_info_at;  ///< the chunk info records
  std::uint64_t connection_at = 0;           ///< the connection record in the index
  std::uint64_t first_message_data_at = 0;   ///< in the first chunk's uncompressed records
};

/// A bag of one sensor_msgs/Imu topic; message i has stamp 1700000000 s + i * step_ns and
/// imu_values(i).
Ros1Bag ros1_bag(const Ros1BagOptions& o = {});
/// A bag of several sensor_msgs/Imu topics, each with its own messages, rate and chunks (the
/// topics one after the other in the file; connection c is topics[c]); chunk_pos, chunk_size_at
/// and chunk_info_at list every chunk, first_message_data_at is the first topic's.
Ros1Bag ros1_bag_of_topics(const std::vector<Ros1BagOptions>& topics);
/// A RealSense D435i's two IMU topics: /camera/gyro/sample at 400 Hz (its linear_acceleration
/// 0) and /camera/accel/sample at 250 Hz (its angular_velocity 0), with these many messages.
std::vector<Ros1BagOptions> realsense_topics(int gyro_messages, int accel_messages);

/// A ROS 1 record: {uint32 header length, header fields, uint32 data length, data}; `fields`
/// are "name=value" strings (values raw bytes).
std::string ros1_record(const std::vector<std::string>& fields, const std::string& data);
/// A header field name=value with `value` the raw bytes of v.
template <typename T>
std::string ros1_field(const std::string& name, T v) {
  std::string s = name + "=";
  s.append(reinterpret_cast<const char*>(&v), sizeof(T));
  return s;
}

// --- MCAP ------------------------------------------------------------------------------------

struct McapOptions {
  int messages = 256;
  int per_chunk = 64;       ///< 0: messages outside chunks
  std::string compression;  ///< "", "lz4" or "zstd"
  std::string topic = "/imu";
  std::uint64_t step_ns = 5000000;
  bool crc = true;  ///< compute the chunks' CRC-32
};

struct Mcap {
  std::string bytes;
  std::vector<std::uint64_t> chunk_at;  ///< the chunk records (their opcode byte)
  std::uint64_t data_end_at = 0;        ///< the DataEnd record
};

/// An MCAP file of one sensor_msgs/msg/Imu channel (CDR); message i as for ros1_bag.
Mcap mcap_file(const McapOptions& o = {});

/// An MCAP record {opcode, uint64 length, content}.
std::string mcap_record(std::uint8_t op, const std::string& content);

/// sensor_msgs/msg/Imu message i in little-endian CDR, with the given frame_id.
std::string imu_cdr(int i, std::uint64_t step_ns, const std::string& frame = "imu");

/// A ROS 1 bag of one IMU connection whose chunks are given as they are stored: each with
/// its compression name, the uncompressed size its header states and its data; the index
/// gives each chunk one message. Returns the bag and the chunks' offsets.
struct Ros1StoredChunk {
  std::string compression;
  std::uint32_t size;
  std::string stored;
};
Ros1Bag ros1_bag_of_chunks(const std::vector<Ros1StoredChunk>& chunks);

/// An MCAP file whose chunks are given as they are stored (no schema or channel outside
/// them): compression name, stated uncompressed size, stored records.
struct McapStoredChunk {
  std::string compression;
  std::uint64_t size;
  std::string stored;
};
Mcap mcap_of_chunks(const std::vector<McapStoredChunk>& chunks);

// --- rosbag2 (sqlite3) --------------------------------------------------------------------------

struct Rosbag2Options {
  int messages = 64;
  std::string topics_sql;    ///< replaces the topics table's CREATE when not empty
  std::string messages_sql;  ///< replaces the messages table's CREATE when not empty
  bool wal = false;          ///< journal_mode=WAL (the database closed: no -wal left)
  /// Message i's blob; empty: imu_cdr(i, 5 ms).
  std::string (*blob)(int i) = nullptr;
};

/// A rosbag2 database (rosbag2_storage_default_plugins' schema) of one sensor_msgs/msg/Imu
/// topic /imu, written with SQLite; rows go in only where the tables take them.
void rosbag2_db(const std::string& path, const Rosbag2Options& o = {});

// --- compression --------------------------------------------------------------------------------

std::string bz2_compress(const std::string& in);
std::string lz4_frame_compress(const std::string& in);
std::string zstd_compress(const std::string& in);

// --- PX4 ULog -------------------------------------------------------------------------------------

/// A ULog file built message by message: the 16-byte header, then add() messages.
struct UlogBuilder {
  std::string bytes;
  UlogBuilder();
  UlogBuilder& add(char type, const std::string& payload);
  UlogBuilder& format(const std::string& text) { return add('F', text); }
  UlogBuilder& subscribe(std::uint8_t multi, std::uint16_t id, const std::string& name);
  /// A 'D' message: msg_id, then the payload.
  UlogBuilder& data(std::uint16_t id, const std::string& payload);
};

/// A valid ULog of n sensor_combined messages (PX4's layout) at 200 Hz.
std::string ulog_sensor_combined(int n);

}  // namespace gmwm::test
