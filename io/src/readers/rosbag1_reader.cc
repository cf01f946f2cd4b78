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
#include "input_file.h"
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
// Limits against hostile files (docs/cli.md "Memory and limits"): a record header
// (connection headers carry the message definition, a few kB); a chunk's uncompressed size
// and the inflation of the chunks are limited as in MCAP files (decompress.h).
constexpr std::uint32_t kMaxHeaderBytes = 16u << 20;
// Chunks read and decompressed at a time (in parallel), and at most this many bytes of
// theirs uncompressed (at least one chunk): enough to keep the cores busy with rosbag's
// 768 kB chunks, while the memory in flight stays bounded whatever the bag's size.
constexpr std::size_t kChunksInFlight = 16;
// A message record of an IMU takes more than this many bytes of the file (its 37 doubles
// alone 296): what the index's counts may claim is bounded by the file's size.
constexpr std::uint64_t kMinMessageBytes = 300;
constexpr std::uint64_t kBytesInFlight = std::uint64_t{32} << 20;

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

// A record's header, read from the file at `offset` (its data are read apart, when needed).
struct RecordHead {
  Fields header;
  std::uint8_t op = 0;
  std::uint64_t offset = 0, data_at = 0, data_len = 0;
  std::uint64_t end() const { return data_at + data_len; }
};

// Reads the header of the record at `offset`; the errors name the file and the byte offset.
RecordHead read_head(const InputFile& f, std::uint64_t offset) {
  const auto fail = [&](const std::string& what) {
    return InputError(f.path() + ": record at byte " + std::to_string(offset) + ": " + what);
  };
  RecordHead r;
  r.offset = offset;
  std::uint32_t header_len = 0, data_len = 0;
  if (!fits(offset, 4, f.size())) throw fail("truncated (the file ends inside it)");
  f.read(offset, &header_len, 4);
  if (header_len > kMaxHeaderBytes || !fits(offset + 4, header_len, f.size()))
    throw fail("header length " + std::to_string(header_len) + " runs past the end of the file or the limit of " +
               std::to_string(kMaxHeaderBytes) + " bytes: truncated or not a bag");
  std::vector<unsigned char> header(header_len);
  f.read(offset + 4, header.data(), header_len);
  if (!parse_fields(header.data(), header_len, r.header))
    throw fail("found a malformed record header (a field without '=' or overrunning the header)");
  const auto op = field<std::uint8_t>(r.header, "op");
  if (!op) throw fail("found a record header without a one-byte 'op' field");
  r.op = *op;
  const std::uint64_t length_at = offset + 4 + header_len;
  if (!fits(length_at, 4, f.size())) throw fail("truncated (no data length)");
  f.read(length_at, &data_len, 4);
  if (!fits(length_at + 4, data_len, f.size()))
    throw fail("data of " + std::to_string(data_len) + " bytes runs past the end of the file: truncated");
  r.data_at = length_at + 4;
  r.data_len = data_len;
  return r;
}

// The data of a record whose header was read; at most `max_data` bytes.
std::vector<unsigned char> read_data(const InputFile& f, const RecordHead& r, std::uint64_t max_data) {
  if (r.data_len > max_data)
    throw InputError(f.path() + ": record at byte " + std::to_string(r.offset) + ": data of " +
                     std::to_string(r.data_len) + " bytes, above the limit of " + std::to_string(max_data));
  std::vector<unsigned char> data(static_cast<std::size_t>(r.data_len));
  f.read(r.data_at, data.data(), data.size());
  return data;
}

struct Connection {
  std::uint32_t id;
  std::string topic, type, md5;
};

// A chunk that holds the topic: where it is, what its header says, and how many of the
// topic's messages the index gives it.
struct ChunkInfo {
  std::uint64_t pos;
  std::uint64_t messages;  // of the chosen topic's connections
  RecordHead head = {};
  Compression compression = Compression::kNone;
  std::uint64_t size = 0;  // uncompressed, as its header states
};

// One chunk's messages of the chosen connections, or the first error met in it.
struct ChunkMessages {
  std::vector<ImuMessage> messages;
  std::string error;              // empty: none
  bool error_in_message = false;  // the error belongs to message (messages.size() + 1) of the chunk
};

// The chunk compressions of the format.
constexpr CompressionName kCompressions[] = {
    {"none", Compression::kNone}, {"bz2", Compression::kBz2}, {"lz4", Compression::kLz4Frame}};

// Reads the header of the chunk at `c.pos` into `c`, checking what it states against the
// limits (kMaxChunkBytes, the file's inflation budget) before anything is allocated.
void check_chunk(const InputFile& f, ChunkInfo& c, ChunkBudget& budget) {
  const std::string where = f.path() + ": chunk at byte " + std::to_string(c.pos) + ": ";
  c.head = read_head(f, c.pos);
  const auto size = field<std::uint32_t>(c.head.header, "size");
  const auto compression = text_field(c.head.header, "compression");
  if (c.head.op != kChunk || !size || !compression)
    throw InputError(f.path() + ": record at byte " + std::to_string(c.pos) +
                     ": the index names a chunk there, found op " + std::to_string(c.head.op) + ": a damaged bag");
  const Compression* kind = compression_named(kCompressions, *compression);
  if (!kind)
    throw InputError(where + "chunk compression '" + *compression + "', expected " + compression_list(kCompressions));
  if (const std::string why = budget.add(c.head.data_len, *size); !why.empty()) throw InputError(where + why);
  c.compression = *kind;
  c.size = *size;
}

// Reads the chunk `c` (checked by check_chunk) and decodes the messages of `conns` in it.
ChunkMessages read_chunk(const InputFile& f, const ChunkInfo& c, const std::set<std::uint32_t>& conns) {
  const std::string& path = f.path();
  const std::uint64_t pos = c.pos;
  ChunkMessages out;
  try {
    const std::vector<unsigned char> stored = read_data(f, c.head, kMaxChunkBytes);
    std::string error;
    const ByteBuffer body = decompress(c.compression, stored.data(), stored.size(), c.size, error);
    if (!error.empty()) {
      out.error = path + ": chunk at byte " + std::to_string(pos) + ": " + error;
      return out;
    }
    // The records inside: {uint32 header length, header, uint32 data length, data}.
    std::size_t at = 0;
    while (at < body.size()) {
      const auto bad = [&](const std::string& what) {
        out.error =
            path + ": chunk at byte " + std::to_string(pos) + ", record at " + std::to_string(at) + " of it: " + what;
      };
      const std::string chunk_bytes = " the chunk's " + std::to_string(body.size()) + " bytes";
      std::uint32_t hl = 0, dl = 0;
      if (!fits(at, 4, body.size())) return bad("truncated: its header length runs past" + chunk_bytes), out;
      std::memcpy(&hl, body.data() + at, 4);
      if (!fits(at + 4, hl, body.size()))
        return bad("its header of " + std::to_string(hl) + " bytes runs past" + chunk_bytes +
                   ", expected a record inside the chunk"),
               out;
      Fields h;
      if (!parse_fields(body.data() + at + 4, hl, h))
        return bad("malformed record header (a field without '=' or overrunning the header)"), out;
      const std::size_t data_at = at + 4 + hl;
      if (!fits(data_at, 4, body.size())) return bad("truncated: its data length runs past" + chunk_bytes), out;
      std::memcpy(&dl, body.data() + data_at, 4);
      if (!fits(data_at + 4, dl, body.size()))
        return bad("its data of " + std::to_string(dl) + " bytes runs past" + chunk_bytes +
                   ", expected a record inside the chunk"),
               out;
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
  const InputFile f(path, "ROS bag");
  char magic[kMagicSize] = {};
  f.read(0, magic,
         static_cast<std::size_t>(std::min<std::uint64_t>(f.size(), kMagicSize)));  // a shorter file: its bytes
  if (std::memcmp(magic, kMagic20, kMagicSize) != 0) {
    std::string line(magic, strnlen(magic, kMagicSize));
    if (!line.empty() && line.back() == '\n') line.pop_back();
    const std::size_t version = sizeof kMagicPrefix - 1;  // is_rosbag1() saw the prefix
    throw InputError(path + ": found a ROS bag of version '" + (line.size() > version ? line.substr(version) : "") +
                     "', expected 2.0 (rosbag migrate / rosbag fix convert older bags)");
  }
  const RecordHead header = read_head(f, kMagicSize);
  const auto index_pos = field<std::uint64_t>(header.header, "index_pos");
  const auto conn_count = field<std::uint32_t>(header.header, "conn_count");
  const auto chunk_count = field<std::uint32_t>(header.header, "chunk_count");
  if (header.op != kBagHeader || !index_pos || !conn_count || !chunk_count)
    throw InputError(path + ": the first record is not a bag header (op 3 with index_pos, conn_count, chunk_count)");
  if (*index_pos == 0)
    throw InputError(path + ": the bag has no index (an interrupted recording): run 'rosbag reindex' on it first");
  if (*index_pos < header.end() || *index_pos > f.size())
    throw InputError(path + ": the bag header's index_pos " + std::to_string(*index_pos) +
                     " is outside the file: truncated");

  // The index section: connections, then chunk infos.
  std::vector<Connection> connections;
  std::vector<std::pair<std::uint64_t, std::map<std::uint32_t, std::uint32_t>>> chunks;  // pos, conn -> messages
  for (std::uint64_t at = *index_pos; at < f.size();) {
    const RecordHead r = read_head(f, at);
    if (r.op == kConnection) {
      const std::vector<unsigned char> data = read_data(f, r, kMaxHeaderBytes);
      const auto conn = field<std::uint32_t>(r.header, "conn");
      const auto topic = text_field(r.header, "topic");
      Fields c;
      if (!conn || !topic || !parse_fields(data.data(), data.size(), c))
        throw InputError(path + ": connection record at byte " + std::to_string(at) + " is malformed");
      connections.push_back(
          {*conn, *topic, text_field(c, "type").value_or("?"), text_field(c, "md5sum").value_or("?")});
    } else if (r.op == kChunkInfo) {
      const auto pos = field<std::uint64_t>(r.header, "chunk_pos");
      const auto count = field<std::uint32_t>(r.header, "count");
      if (!pos || !count || r.data_len != std::uint64_t{*count} * 8)
        throw InputError(path + ": chunk info record at byte " + std::to_string(at) + " is malformed");
      const std::vector<unsigned char> data = read_data(f, r, kMaxHeaderBytes);
      std::map<std::uint32_t, std::uint32_t> per;
      for (std::uint32_t k = 0; k < *count; ++k) {
        std::uint32_t c, n;
        std::memcpy(&c, data.data() + 8 * k, 4);
        std::memcpy(&n, data.data() + 8 * k + 4, 4);
        per[c] = n;
      }
      chunks.emplace_back(*pos, std::move(per));
    }
    at = r.end();
  }
  if (connections.size() != *conn_count || chunks.size() != *chunk_count)
    throw InputError(path + ": the index holds " + std::to_string(connections.size()) + " connections and " +
                     std::to_string(chunks.size()) + " chunk infos, the bag header says " +
                     std::to_string(*conn_count) + " and " + std::to_string(*chunk_count) + ": a damaged bag");

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
      throw InputError(
          path + (imu_topics.empty()
                      ? ": no " + std::string(kImuType) + " topic in this bag (it has " +
                            (all_topics.empty() ? std::string("no topic") : all_topics) + ")"
                      : ": several " + std::string(kImuType) + " topics (" + imu_topics + "): name one with --topic"));
    topic = imu_topics;
  }
  std::set<std::uint32_t> conns;
  for (const Connection& c : connections) {
    if (c.topic != topic) continue;
    if (c.type != kImuType)
      throw InputError(path + ": topic " + topic + " is " + c.type + ", expected " + kImuType + " messages");
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
  // What every chunk states is checked first, in file order, before any is inflated.
  ChunkBudget budget;
  for (ChunkInfo& c : wanted) check_chunk(f, c, budget);

  ImuTopic imu(path, topic, options);
  std::uint64_t expected = 0;
  for (const ChunkInfo& c : wanted) expected += c.messages;
  imu.reserve(std::min<std::uint64_t>(expected, f.size() / kMinMessageBytes));
  std::int64_t index = 0;
  // The chunks in windows of at most kChunksInFlight and kBytesInFlight, each window read in
  // parallel, then its messages taken in chunk order.
  for (std::size_t first = 0; first < wanted.size();) {
    std::size_t last = first + 1;
    std::uint64_t bytes = wanted[first].size;
    while (last < wanted.size() && last - first < kChunksInFlight &&
           wanted[last].size <= kBytesInFlight - std::min(bytes, kBytesInFlight))
      bytes += wanted[last++].size;
    std::vector<ChunkMessages> read(last - first);
    gmwm::parallel_for(first, last, [&](std::size_t k) { read[k - first] = read_chunk(f, wanted[k], conns); });
    for (std::size_t k = first; k < last; ++k) {
      ChunkMessages& r = read[k - first];
      for (const ImuMessage& m : r.messages) imu.add(m, ++index);
      if (!r.error.empty()) throw InputError(r.error_in_message ? imu.where(index + 1) + r.error : r.error);
      if (r.messages.size() != wanted[k].messages)
        throw InputError(path + ": chunk at byte " + std::to_string(wanted[k].pos) + " holds " +
                         std::to_string(r.messages.size()) + " messages of " + topic + ", the index says " +
                         std::to_string(wanted[k].messages) + ": a damaged bag");
      r = {};
    }
    first = last;
  }
  return std::move(imu).signals("rosbag:" + topic, "ROS bag header stamps (ns)");
}

}  // namespace gmwm::io::detail
