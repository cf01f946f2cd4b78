// ROS 1 bag input (docs/cli.md "Inputs"): a sensor_msgs/Imu topic of a ROS 1 bag, format
// 2.0, as signals, without a ROS installation.
//
// The format (ROS wiki, "Bags/Format/2.0"): the line "#ROSBAG V2.0\n", then records. A
// record is {uint32 header length, header, uint32 data length, data}; a header is a list of
// fields {uint32 length, "name=value"}, op (uint8) giving the record's kind:
//   0x03 bag header   index_pos (uint64: where the index section starts), conn_count, chunk_count
//   0x05 chunk        compression ("none", "bz2", "lz4": an LZ4 frame), size (uncompressed);
//                     its data: records (connections and messages), compressed
//   0x07 connection   conn (uint32), topic; its data: a connection header with type, md5sum
//   0x02 message      conn, time; its data: the serialised message (ros_imu.cc)
//   0x04 index data   (inside the chunks' sequence; not needed here)
//   0x06 chunk info   chunk_pos (uint64), start_time, end_time, count; its data: count
//                     pairs {uint32 conn, uint32 messages in the chunk}
// The index section (from index_pos: every connection record, then every chunk info) names
// the topics before any chunk is read, so a bag without one (index_pos 0: an interrupted
// recording) is refused, as rosbag itself does ("rosbag reindex" writes it).
//
// Chunks holding the topic are read and decompressed in parallel (each into its own
// messages), then the messages are taken in chunk order: the result does not depend on
// the thread count.

#include "rosbag1_reader.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "gmwm/engine/parallel.h"
#include "gmwm/engine/error.h"
#include "checked_size.h"
#include "decompress.h"
#include "ros_imu.h"

namespace gmwm::io::detail {
namespace {

constexpr char kMagicPrefix[] = "#ROSBAG V";
constexpr char kMagic20[] = "#ROSBAG V2.0\n";
constexpr std::size_t kMagicSize = sizeof kMagic20 - 1;
constexpr const char* kImuType = "sensor_msgs/Imu";
// The MD5 of sensor_msgs/Imu's full definition (ROS 1 `rosmsg md5 sensor_msgs/Imu`): a
// topic with another is a different layout under the same name.
constexpr const char* kImuMd5 = "6a62c6daae103f4ff57a132d6f95cec2";
// Limits against hostile files (docs/cli.md "Limits"): a record header (connection headers
// carry the message definition, a few kB) and a chunk's uncompressed size (rosbag's default
// chunk is 768 kB; `rosbag record --chunksize` takes kB up to a few MB).
constexpr std::uint32_t kMaxHeaderBytes = 16u << 20;
constexpr std::uint64_t kMaxChunkBytes = 1ull << 30;

enum Op : std::uint8_t { kMessage = 0x02, kBagHeader = 0x03, kChunk = 0x05, kChunkInfo = 0x06, kConnection = 0x07 };

// The fields of a record header (or a connection header): name -> raw value bytes.
using Fields = std::map<std::string, std::string>;

// Parses `n` bytes of header fields; false on a field that overruns or has no '='.
bool parse_fields(const unsigned char* p, std::size_t n, Fields& out) {
  std::size_t pos = 0;
  while (pos < n) {
    if (n - pos < 4) return false;
    std::uint32_t len;
    std::memcpy(&len, p + pos, 4);
    pos += 4;
    if (len > n - pos) return false;
    const auto* f = reinterpret_cast<const char*>(p + pos);
    const auto* eq = static_cast<const char*>(std::memchr(f, '=', len));
    if (!eq) return false;
    out[std::string(f, eq)] = std::string(eq + 1, f + len);
    pos += len;
  }
  return true;
}

template <typename T>
std::optional<T> field(const Fields& f, const std::string& name) {
  const auto it = f.find(name);
  if (it == f.end() || it->second.size() != sizeof(T)) return std::nullopt;
  T v;
  std::memcpy(&v, it->second.data(), sizeof(T));
  return v;
}

std::optional<std::string> text_field(const Fields& f, const std::string& name) {
  const auto it = f.find(name);
  if (it == f.end()) return std::nullopt;
  return it->second;
}

struct File {
  int fd = -1;
  std::uint64_t size = 0;
  ~File() {
    if (fd >= 0) ::close(fd);
  }
};

// One record read from the file at `offset`: its header fields and data.
struct Record {
  Fields header;
  std::vector<unsigned char> data;
  std::uint64_t end = 0;  // the offset after it
  std::uint8_t op = 0;
};

bool read_at(const File& f, std::uint64_t offset, void* out, std::size_t n) {
  auto* p = static_cast<unsigned char*>(out);
  while (n > 0) {
    const ssize_t r = ::pread(f.fd, p, n, static_cast<off_t>(offset));
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
    offset += static_cast<std::uint64_t>(r);
  }
  return true;
}

// Reads the record at `offset`; the error names the file and the byte offset.
Record read_record(const std::string& path, const File& f, std::uint64_t offset, std::uint64_t max_data) {
  const auto fail = [&](const std::string& what) {
    return InputError(path + ": record at byte " + std::to_string(offset) + ": " + what);
  };
  Record r;
  std::uint32_t header_len = 0, data_len = 0;
  if (offset > f.size || f.size - offset < 4 || !read_at(f, offset, &header_len, 4))
    throw fail("truncated (the file ends inside it)");
  if (header_len > kMaxHeaderBytes || header_len > f.size - offset - 4)
    throw fail("header length " + std::to_string(header_len) + " runs past the end of the file or the limit of " +
               std::to_string(kMaxHeaderBytes) + " bytes: truncated or not a bag");
  std::vector<unsigned char> header(header_len);
  if (!read_at(f, offset + 4, header.data(), header_len) || !parse_fields(header.data(), header_len, r.header))
    throw fail("found a malformed record header (a field without '=' or overrunning the header)");
  const auto op = field<std::uint8_t>(r.header, "op");
  if (!op) throw fail("found a record header without a one-byte 'op' field");
  r.op = *op;
  const std::uint64_t data_at = offset + 4 + header_len;
  if (f.size - data_at < 4 || !read_at(f, data_at, &data_len, 4)) throw fail("truncated (no data length)");
  if (data_len > f.size - data_at - 4) throw fail("data of " + std::to_string(data_len) + " bytes runs past the end of the file: truncated");
  if (data_len > max_data) throw fail("data of " + std::to_string(data_len) + " bytes, above the limit of " + std::to_string(max_data));
  r.data.resize(data_len);
  if (!read_at(f, data_at + 4, r.data.data(), data_len)) throw fail("cannot read its data");
  r.end = data_at + 4 + data_len;
  return r;
}

struct Connection {
  std::uint32_t id;
  std::string topic, type, md5;
};

struct ChunkInfo {
  std::uint64_t pos;
  std::uint64_t messages;  // of the chosen topic's connections
};

// One chunk's messages of the chosen connections, or the first error met in it.
struct ChunkMessages {
  std::vector<ImuMessage> messages;
  std::string error;          // empty: none
  bool error_in_message = false;  // the error belongs to message (messages.size() + 1) of the chunk
};

// The chunk compressions of the format.
constexpr CompressionName kCompressions[] = {
    {"none", Compression::kNone}, {"bz2", Compression::kBz2}, {"lz4", Compression::kLz4Frame}};

// The chunk's data decompressed; `error` set on failure.
std::vector<unsigned char> chunk_body(const std::string& compression, const std::vector<unsigned char>& in,
                                      std::uint64_t size, std::string& error) {
  const Compression* c = compression_named(kCompressions, compression);
  if (!c) {
    error = "chunk compression '" + compression + "', expected " + compression_list(kCompressions);
    return {};
  }
  return decompress(*c, in.data(), in.size(), size, error);
}

// Reads the chunk at `pos` and decodes the messages of `conns` in it.
ChunkMessages read_chunk(const std::string& path, const File& f, std::uint64_t pos, const std::set<std::uint32_t>& conns) {
  ChunkMessages out;
  try {
    const Record chunk = read_record(path, f, pos, kMaxChunkBytes);
    const auto size = field<std::uint32_t>(chunk.header, "size");
    const auto compression = text_field(chunk.header, "compression");
    if (chunk.op != kChunk || !size || !compression) {
      out.error = path + ": record at byte " + std::to_string(pos) + ": the index names a chunk there, found op " +
                  std::to_string(chunk.op) + ": a damaged bag";
      return out;
    }
    std::string error;
    const std::vector<unsigned char> body = chunk_body(*compression, chunk.data, *size, error);
    if (!error.empty()) {
      out.error = path + ": chunk at byte " + std::to_string(pos) + ": " + error;
      return out;
    }
    // The records inside: {uint32 header length, header, uint32 data length, data}.
    std::size_t at = 0;
    while (at < body.size()) {
      const auto bad = [&](const std::string& what) {
        out.error = path + ": chunk at byte " + std::to_string(pos) + ", record at " + std::to_string(at) + " of it: " + what;
      };
      const std::string chunk_bytes = " the chunk's " + std::to_string(body.size()) + " bytes";
      std::uint32_t hl = 0, dl = 0;
      if (!fits(at, 4, body.size())) return bad("truncated: its header length runs past" + chunk_bytes), out;
      std::memcpy(&hl, body.data() + at, 4);
      if (!fits(at + 4, hl, body.size()))
        return bad("its header of " + std::to_string(hl) + " bytes runs past" + chunk_bytes + ", expected a record inside the chunk"), out;
      Fields h;
      if (!parse_fields(body.data() + at + 4, hl, h))
        return bad("malformed record header (a field without '=' or overrunning the header)"), out;
      const std::size_t data_at = at + 4 + hl;
      if (!fits(data_at, 4, body.size())) return bad("truncated: its data length runs past" + chunk_bytes), out;
      std::memcpy(&dl, body.data() + data_at, 4);
      if (!fits(data_at + 4, dl, body.size()))
        return bad("its data of " + std::to_string(dl) + " bytes runs past" + chunk_bytes + ", expected a record inside the chunk"), out;
      const auto op = field<std::uint8_t>(h, "op");
      const auto conn = field<std::uint32_t>(h, "conn");
      if (op && *op == kMessage && conn && conns.count(*conn)) {
        const auto m = decode_imu_ros1(body.data() + data_at + 4, dl, error);
        if (!m) {
          out.error = error;
          out.error_in_message = true;
          return out;
        }
        out.messages.push_back(*m);
      }
      at = data_at + 4 + dl;
    }
  } catch (const InputError& e) {
    out.error = e.what();
  }
  return out;
}

}  // namespace

bool is_rosbag1(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // never sniff a pipe
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kMagicPrefix - 1] = {};
  return in && in.read(head, sizeof head) && std::memcmp(head, kMagicPrefix, sizeof head) == 0;
}

SignalSet read_rosbag1(const std::string& path, const ReadOptions& options) {
  File f;
  f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (f.fd < 0) throw InputError(path + ": cannot open the ROS bag");
  f.size = std::filesystem::file_size(path);
  char magic[kMagicSize] = {};
  if (!read_at(f, 0, magic, kMagicSize) || std::memcmp(magic, kMagic20, kMagicSize) != 0) {
    std::string line(magic, strnlen(magic, kMagicSize));
    if (!line.empty() && line.back() == '\n') line.pop_back();
    throw InputError(path + ": found a ROS bag of version '" + line.substr(sizeof kMagicPrefix - 1) +
                     "', expected 2.0 (rosbag migrate / rosbag fix convert older bags)");
  }
  const Record header = read_record(path, f, kMagicSize, kMaxHeaderBytes);
  const auto index_pos = field<std::uint64_t>(header.header, "index_pos");
  const auto conn_count = field<std::uint32_t>(header.header, "conn_count");
  const auto chunk_count = field<std::uint32_t>(header.header, "chunk_count");
  if (header.op != kBagHeader || !index_pos || !conn_count || !chunk_count)
    throw InputError(path + ": the first record is not a bag header (op 3 with index_pos, conn_count, chunk_count)");
  if (*index_pos == 0)
    throw InputError(path + ": the bag has no index (an interrupted recording): run 'rosbag reindex' on it first");
  if (*index_pos < header.end || *index_pos > f.size)
    throw InputError(path + ": the bag header's index_pos " + std::to_string(*index_pos) + " is outside the file: truncated");

  // The index section: connections, then chunk infos.
  std::vector<Connection> connections;
  std::vector<std::pair<std::uint64_t, std::map<std::uint32_t, std::uint32_t>>> chunks;  // pos, conn -> messages
  for (std::uint64_t at = *index_pos; at < f.size;) {
    const Record r = read_record(path, f, at, kMaxHeaderBytes);
    if (r.op == kConnection) {
      const auto conn = field<std::uint32_t>(r.header, "conn");
      const auto topic = text_field(r.header, "topic");
      Fields c;
      if (!conn || !topic || !parse_fields(r.data.data(), r.data.size(), c))
        throw InputError(path + ": connection record at byte " + std::to_string(at) + " is malformed");
      connections.push_back({*conn, *topic, text_field(c, "type").value_or("?"), text_field(c, "md5sum").value_or("?")});
    } else if (r.op == kChunkInfo) {
      const auto pos = field<std::uint64_t>(r.header, "chunk_pos");
      const auto count = field<std::uint32_t>(r.header, "count");
      if (!pos || !count || r.data.size() != std::uint64_t{*count} * 8)
        throw InputError(path + ": chunk info record at byte " + std::to_string(at) + " is malformed");
      std::map<std::uint32_t, std::uint32_t> per;
      for (std::uint32_t k = 0; k < *count; ++k) {
        std::uint32_t c, n;
        std::memcpy(&c, r.data.data() + 8 * k, 4);
        std::memcpy(&n, r.data.data() + 8 * k + 4, 4);
        per[c] = n;
      }
      chunks.emplace_back(*pos, std::move(per));
    }
    at = r.end;
  }
  if (connections.size() != *conn_count || chunks.size() != *chunk_count)
    throw InputError(path + ": the index holds " + std::to_string(connections.size()) + " connections and " +
                     std::to_string(chunks.size()) + " chunk infos, the bag header says " + std::to_string(*conn_count) +
                     " and " + std::to_string(*chunk_count) + ": a damaged bag");

  // The topic: named by --topic, or the only sensor_msgs/Imu one.
  std::string topic = options.topic, all_topics, imu_topics;
  std::set<std::string> seen;
  for (const Connection& c : connections) {
    if (!seen.insert(c.topic).second) continue;
    all_topics += (all_topics.empty() ? "" : ", ") + c.topic + " (" + c.type + ")";
    if (c.type == kImuType) imu_topics += (imu_topics.empty() ? "" : ", ") + c.topic;
  }
  if (topic.empty()) {
    if (imu_topics.empty() || imu_topics.find(", ") != std::string::npos)
      throw InputError(path + (imu_topics.empty() ? ": no " + std::string(kImuType) + " topic in this bag (it has " +
                                                        (all_topics.empty() ? std::string("no topic") : all_topics) + ")"
                                                  : ": several " + std::string(kImuType) + " topics (" + imu_topics +
                                                        "): name one with --topic"));
    topic = imu_topics;
  }
  std::set<std::uint32_t> conns;
  for (const Connection& c : connections) {
    if (c.topic != topic) continue;
    if (c.type != kImuType) throw InputError(path + ": topic " + topic + " is " + c.type + ", expected " + kImuType + " messages");
    if (c.md5 != kImuMd5)
      throw InputError(path + ": topic " + topic + " has " + kImuType + " md5sum " + c.md5 + ", expected " + kImuMd5 +
                       " (another definition of the message)");
    conns.insert(c.id);
  }
  if (conns.empty())
    throw InputError(path + ": no topic " + topic + " in this bag (it has " +
                     (all_topics.empty() ? std::string("no topic") : all_topics) + ")");

  // The chunks that hold the topic, in file order, read in parallel.
  std::vector<ChunkInfo> wanted;
  for (const auto& [pos, per] : chunks) {
    std::uint64_t n = 0;
    for (const auto& [c, k] : per)
      if (conns.count(c)) n += k;
    if (n > 0) wanted.push_back({pos, n});
  }
  std::sort(wanted.begin(), wanted.end(), [](const ChunkInfo& a, const ChunkInfo& b) { return a.pos < b.pos; });
  std::vector<ChunkMessages> read(wanted.size());
  gmwm::parallel_for(std::size_t{0}, wanted.size(), [&](std::size_t k) { read[k] = read_chunk(path, f, wanted[k].pos, conns); });

  ImuTopic imu(path, topic);
  std::uint64_t expected = 0;
  for (const ChunkInfo& c : wanted) expected += c.messages;
  imu.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(expected, f.size / sizeof(double))));
  std::int64_t index = 0;
  for (std::size_t k = 0; k < read.size(); ++k) {
    for (const ImuMessage& m : read[k].messages) imu.add(m, ++index);
    if (!read[k].error.empty())
      throw InputError(read[k].error_in_message ? imu.where(index + 1) + read[k].error : read[k].error);
    if (read[k].messages.size() != wanted[k].messages)
      throw InputError(path + ": chunk at byte " + std::to_string(wanted[k].pos) + " holds " +
                       std::to_string(read[k].messages.size()) + " messages of " + topic + ", the index says " +
                       std::to_string(wanted[k].messages) + ": a damaged bag");
    read[k] = {};
  }
  return std::move(imu).signals("rosbag:" + topic, "ROS bag header stamps (ns)", options);
}

}  // namespace gmwm::io::detail
