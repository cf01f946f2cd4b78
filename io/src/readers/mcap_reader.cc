// MCAP input (docs/cli.md "Inputs"): a sensor_msgs/msg/Imu topic of a ROS 2 bag in MCAP
// storage, as signals, without a ROS installation.
//
// The format (mcap.dev, "MCAP format specification", version 0): the magic 0x89 "MCAP0\r\n",
// then records {uint8 opcode, uint64 length, content}, all integers little-endian, strings
// and byte arrays prefixed by a uint32 length. The records read here:
//   0x03 Schema   uint16 id, string name, string encoding, bytes data
//   0x04 Channel  uint16 id, uint16 schema_id, string topic, string message_encoding, map metadata
//   0x05 Message  uint16 channel_id, uint32 sequence, uint64 log_time, uint64 publish_time, data (the rest)
//   0x06 Chunk    uint64 start, uint64 end, uint64 uncompressed_size, uint32 uncompressed_crc
//                 (CRC-32, 0: not computed), string compression ("" none, "lz4" an LZ4 frame,
//                 "zstd" a zstd frame), uint64 length + records (schemas, channels, messages)
//   0x0F DataEnd  the end of the data section (the summary and footer follow)
//   0x02 Footer   the end of the file
// Other opcodes are skipped, as the specification asks. One pass over the data section in
// storage order: messages of every sensor_msgs/msg/Imu channel are decoded (CDR, ros_imu.cc)
// and kept per topic; the topic named by --topic (or the only IMU one) is checked and
// returned at the end. A file without DataEnd or footer (an interrupted recording) is
// refused, naming the byte where it ends ("mcap recover" rewrites such a file).

#include "mcap_reader.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <zlib.h>

#include "checked_size.h"
#include "decompress.h"
#include "input_file.h"
#include "gmwm/engine/error.h"
#include "ros_imu.h"

namespace gmwm::io::detail {
namespace {

constexpr unsigned char kMagic[] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr const char* kImuSchema = "sensor_msgs/msg/Imu";
constexpr std::size_t kRecordHead = 9;  // opcode + uint64 length
// A chunk record: its fields (40 bytes and the compression's name) and at most a chunk's
// worth of stored records.
constexpr std::uint64_t kMaxChunkRecordBytes = kMaxChunkBytes + 4096;
// A schema (a message definition of a few kB), a channel or an IMU message (about 300 bytes)
// read whole: the limit of a ROS 1 record header.
constexpr std::uint64_t kMaxRecordBytes = 16u << 20;

enum Op : std::uint8_t {
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F,
};

constexpr CompressionName kCompressions[] = {
    {"", Compression::kNone}, {"lz4", Compression::kLz4Frame}, {"zstd", Compression::kZstd}};

// Bounds-checked little-endian reads over a record's content: every stated length is
// compared with what is left (fits(): no sum can wrap around); the first failure is kept as
// text naming the field.
class Reader {
 public:
  Reader(const unsigned char* p, std::uint64_t n) : p_(p), n_(n) {}
  bool ok() const { return ok_; }
  const std::string& failure() const { return failure_; }
  std::uint64_t left() const { return n_ - pos_; }
  const unsigned char* here() const { return p_ + pos_; }
  template <typename T>
  T get(const char* what) {
    T v{};
    if (!ok_) return v;
    if (!fits(pos_, sizeof(T), n_)) {
      fail(std::string("its ") + what + " (" + std::to_string(sizeof(T)) + " bytes at byte " + std::to_string(pos_) +
           " of it) runs past its " + std::to_string(n_) + " bytes");
      return v;
    }
    std::memcpy(&v, p_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string string(const char* what) {
    const auto len = get<std::uint32_t>(what);
    if (!ok_) return {};
    if (!fits(pos_, len, n_)) {
      fail(std::string("its ") + what + " (a string of " + std::to_string(len) + " bytes at byte " +
           std::to_string(pos_) + " of it) runs past its " + std::to_string(n_) + " bytes");
      return {};
    }
    std::string s(reinterpret_cast<const char*>(p_ + pos_), len);
    pos_ += len;
    return s;
  }
  /// A length-prefixed (uint64) byte run that must fit in what is left.
  std::uint64_t bytes_length(const char* what) {
    const auto len = get<std::uint64_t>(what);
    if (ok_ && len > left())
      fail(std::string("its ") + what + " (" + std::to_string(len) + " bytes at byte " + std::to_string(pos_) +
           " of it) runs past its " + std::to_string(n_) + " bytes");
    return ok_ ? len : 0;
  }

 private:
  void fail(std::string what) {
    ok_ = false;
    failure_ = std::move(what);
  }
  const unsigned char* p_;
  std::uint64_t n_, pos_ = 0;
  bool ok_ = true;
  std::string failure_;
};

struct Channel {
  std::string topic, schema, encoding;
};

// An IMU topic as the pass meets it: its messages, gathered (within the memory budget:
// ImuTopic) while it may be the topic returned, or the first error met in them, reported if
// (when) the topic is chosen.
struct TopicState {
  std::unique_ptr<ImuTopic> data;  // nullptr: not gathered (--topic names another, or several
                                   // IMU topics and no --topic: the read will be refused)
  std::string error;
  std::string encoding;
  std::int64_t messages = 0;  // gathered so far
};

class McapPass {
 public:
  McapPass(std::string path, const ReadOptions& options) : path_(std::move(path)), options_(options) {}

  // The records of `data`: the file's data section (`base`: its byte offset in the file) or,
  // `in_chunk`, a chunk's records (`base`: the chunk's byte offset, `at` counted in its
  // records). Returns false at a DataEnd or Footer record.
  bool records(const unsigned char* data, std::uint64_t n, std::uint64_t base, bool in_chunk) {
    std::uint64_t at = 0;
    while (at < n) {
      chunk_ = base;
      const std::uint64_t offset = in_chunk ? at : base + at;
      if (n - at < kRecordHead)
        throw InputError(path_ + ": " + place(offset, in_chunk) + "truncated: the " + (in_chunk ? "chunk" : "file") +
                         " ends inside a record header" + recover_hint(in_chunk));
      const std::uint8_t op = data[at];
      std::uint64_t len;
      std::memcpy(&len, data + at + 1, 8);
      if (len > n - at - kRecordHead)
        throw InputError(path_ + ": " + place(offset, in_chunk) + "record of " + std::to_string(len) +
                         " bytes runs past the end of the " + (in_chunk ? "chunk" : "file") + ": truncated" +
                         recover_hint(in_chunk));
      const unsigned char* content = data + at + kRecordHead;
      switch (op) {
        case kSchema:
          schema(content, len, offset, in_chunk);
          break;
        case kChannel:
          channel(content, len, offset, in_chunk);
          break;
        case kMessage:
          message(content, len, offset, in_chunk);
          break;
        case kChunk:
          if (in_chunk) throw InputError(path_ + ": " + place(offset, true) + "a chunk inside a chunk");
          chunk(content, len, offset);
          break;
        case kDataEnd:
        case kFooter:
          if (!in_chunk) return false;
          break;
        default:
          break;  // other records (indexes, attachments, metadata, statistics): skipped
      }
      at += kRecordHead + len;
    }
    return true;
  }

  // The records of the file's data section, read from `file` (never mapped: issue 25) up to
  // the size it had when opened. Returns false at a DataEnd or Footer record, true when the
  // file ends without one. Schema and channel records and the messages of IMU channels are
  // read whole (at most kMaxRecordBytes), chunks whole (at most kMaxChunkRecordBytes); other
  // records, and messages on other channels, are skipped without being read.
  bool file_records(const InputFile& file) {
    InputWindow window(file);
    const std::uint64_t n = file.size();
    std::vector<unsigned char> big;  // a chunk's content
    for (std::uint64_t at = sizeof kMagic; at < n;) {
      chunk_ = 0;
      if (n - at < kRecordHead)
        throw InputError(path_ + ": " + place(at, false) + "truncated: the file ends inside a record header" +
                         recover_hint(false));
      const unsigned char* head = window.view(at, kRecordHead);
      const std::uint8_t op = head[0];
      std::uint64_t len;
      std::memcpy(&len, head + 1, 8);
      if (!fits(at + kRecordHead, len, n))
        throw InputError(path_ + ": " + place(at, false) + "record of " + std::to_string(len) +
                         " bytes runs past the end of the file: truncated" + recover_hint(false));
      const std::uint64_t content = at + kRecordHead;
      const auto whole = [&](std::uint64_t limit, const char* what) {
        if (len > limit)
          throw InputError(path_ + ": " + place(at, false) + "a " + what + " record of " + std::to_string(len) +
                           " bytes, above the limit of " + std::to_string(limit) +
                           " (docs/cli.md \"Memory and limits\")");
        return window.view(content, static_cast<std::size_t>(len));
      };
      switch (op) {
        case kSchema:
          schema(whole(kMaxRecordBytes, "schema"), len, at, false);
          break;
        case kChannel:
          channel(whole(kMaxRecordBytes, "channel"), len, at, false);
          break;
        case kMessage:
          if (wanted(window.view(content, static_cast<std::size_t>(std::min<std::uint64_t>(len, 2))), len))
            message(whole(kMaxRecordBytes, "message"), len, at, false);
          break;
        case kChunk:
          if (len > kMaxChunkRecordBytes)
            throw InputError(path_ + ": " + place(at, false) + "a chunk record of " + std::to_string(len) +
                             " bytes, above the limit of " + std::to_string(kMaxChunkRecordBytes) +
                             " (a chunk of at most " + std::to_string(kMaxChunkBytes) + " bytes)");
          big.resize(static_cast<std::size_t>(len));
          file.read(content, big.data(), big.size());
          chunk(big.data(), len, at);
          break;
        case kDataEnd:
        case kFooter:
          return false;
        default:
          break;  // other records (indexes, attachments, metadata, statistics): skipped
      }
      at = content + len;
    }
    return true;
  }

  SignalSet finish() {
    std::string all, imu;
    for (const auto& [topic, c] : topics_) all += (all.empty() ? "" : ", ") + topic + " (" + c + ")";
    for (const auto& [topic, m] : imu_) imu += (imu.empty() ? "" : ", ") + topic;
    std::string topic = options_.topic;
    if (topic.empty()) {
      if (imu_.size() != 1)
        throw InputError(path_ + (imu_.empty() ? ": no " + std::string(kImuSchema) + " topic in this bag (it has " +
                                                     (all.empty() ? std::string("no topic") : all) + ")"
                                               : ": several " + std::string(kImuSchema) + " topics (" + imu +
                                                     "): name one with --topic"));
      topic = imu_.begin()->first;
    }
    const auto t = topics_.find(topic);
    if (t == topics_.end())
      throw InputError(path_ + ": no topic " + topic + " in this bag (it has " +
                       (all.empty() ? std::string("no topic") : all) + ")");
    if (t->second != kImuSchema)
      throw InputError(path_ + ": topic " + topic + " is " + t->second + ", expected " + kImuSchema + " messages");
    TopicState& m = imu_[topic];
    if (!m.encoding.empty() && m.encoding != "cdr")
      throw InputError(path_ + ": topic " + topic + " is encoded as '" + m.encoding + "', expected cdr");
    if (!m.error.empty()) throw InputError(m.error);
    if (!m.data) m.data = std::make_unique<ImuTopic>(path_, topic, options_);
    return std::move(*m.data).signals("mcap:" + topic, "MCAP header stamps (ns)");
  }

 private:
  std::string place(std::uint64_t offset, bool in_chunk) const {
    return in_chunk ? "chunk at byte " + std::to_string(chunk_) + ", record at byte " + std::to_string(offset) +
                          " of its records: "
                    : "record at byte " + std::to_string(offset) + ": ";
  }
  static std::string recover_hint(bool in_chunk) {
    return in_chunk ? "" : " (an interrupted recording? 'mcap recover' rewrites it)";
  }
  [[noreturn]] void malformed(const char* what, const Reader& r, std::uint64_t offset, bool in_chunk) const {
    throw InputError(path_ + ": " + place(offset, in_chunk) + "malformed " + what + " record: " + r.failure() +
                     ", expected a whole " + what + " record");
  }

  void schema(const unsigned char* p, std::uint64_t n, std::uint64_t offset, bool in_chunk) {
    Reader r(p, n);
    const auto id = r.get<std::uint16_t>("id");
    std::string name = r.string("name");
    if (!r.ok()) malformed("schema", r, offset, in_chunk);
    schemas_[id] = std::move(name);
  }

  void channel(const unsigned char* p, std::uint64_t n, std::uint64_t offset, bool in_chunk) {
    Reader r(p, n);
    const auto id = r.get<std::uint16_t>("id");
    const auto schema_id = r.get<std::uint16_t>("schema_id");
    Channel c;
    c.topic = r.string("topic");
    c.encoding = r.string("message_encoding");
    if (!r.ok()) malformed("channel", r, offset, in_chunk);
    const auto s = schemas_.find(schema_id);
    c.schema = schema_id == 0        ? "(no schema)"
               : s == schemas_.end() ? "(unknown schema " + std::to_string(schema_id) + ")"
                                     : s->second;
    topics_.emplace(c.topic, c.schema);
    if (c.schema == kImuSchema) {
      TopicState& t = imu_[c.topic];
      t.encoding = c.encoding;
      if (options_.topic.empty() && imu_.size() > 1) {
        for (auto& [name, other] : imu_) other.data.reset();  // several: the read will be refused
      } else if (!t.data && t.messages == 0 && (options_.topic.empty() || options_.topic == c.topic)) {
        t.data = std::make_unique<ImuTopic>(path_, c.topic, options_);
      }
    }
    channels_[id] = std::move(c);
  }

  // Whether a message record (its first bytes `p`, of `n`) is read whole: a message of an
  // IMU channel still being gathered, or one that message() must refuse.
  bool wanted(const unsigned char* p, std::uint64_t n) const {
    if (n < 2) return true;
    std::uint16_t id;
    std::memcpy(&id, p, 2);
    const auto c = channels_.find(id);
    if (c == channels_.end()) return true;
    if (c->second.schema != kImuSchema) return false;
    const auto t = imu_.find(c->second.topic);
    return t != imu_.end() && t->second.data && t->second.error.empty() && t->second.encoding == "cdr";
  }

  void message(const unsigned char* p, std::uint64_t n, std::uint64_t offset, bool in_chunk) {
    Reader r(p, n);
    const auto id = r.get<std::uint16_t>("channel_id");
    r.get<std::uint32_t>("sequence");
    r.get<std::uint64_t>("log_time");
    r.get<std::uint64_t>("publish_time");
    if (!r.ok()) malformed("message", r, offset, in_chunk);
    const auto c = channels_.find(id);
    if (c == channels_.end())
      throw InputError(path_ + ": " + place(offset, in_chunk) + "a message on channel " + std::to_string(id) +
                       ", which no channel record defines before it");
    if (c->second.schema != kImuSchema) return;
    TopicState& t = imu_[c->second.topic];
    if (!t.data || !t.error.empty() || t.encoding != "cdr") return;  // reported when (if) the topic is chosen
    std::string error;
    const std::int64_t index = t.messages + 1;
    const auto m = decode_imu_cdr(r.here(), static_cast<std::size_t>(r.left()), error);
    try {
      if (!m) throw InputError(t.data->where(index) + error);
      t.data->add(*m, index);
      t.messages = index;
    } catch (const InputError& e) {
      t.error = e.what();
      t.data.reset();
    }
  }

  void chunk(const unsigned char* p, std::uint64_t n, std::uint64_t offset) {
    Reader r(p, n);
    r.get<std::uint64_t>("message_start_time");
    r.get<std::uint64_t>("message_end_time");
    const auto size = r.get<std::uint64_t>("uncompressed_size");
    const auto crc = r.get<std::uint32_t>("uncompressed_crc");
    const std::string compression = r.string("compression");
    const auto records_len = r.bytes_length("records");
    if (!r.ok()) malformed("chunk", r, offset, false);
    const std::string where = path_ + ": chunk at byte " + std::to_string(offset) + ": ";
    const Compression* c = compression_named(kCompressions, compression);
    if (!c) throw InputError(where + "compression '" + compression + "', expected " + compression_list(kCompressions));
    // What the chunk states is checked before anything is allocated or inflated (decompress.h).
    if (const std::string why = budget_.add(records_len, size); !why.empty()) throw InputError(where + why);
    // Records stored without compression are read in place.
    if (*c == Compression::kNone) {
      if (records_len != size)
        throw InputError(where + "uncompressed records of " + std::to_string(records_len) + " bytes, its header says " +
                         std::to_string(size));
      check_crc(r.here(), size, crc, where);
      records(r.here(), size, offset, true);
      return;
    }
    std::string error;
    const ByteBuffer body = decompress(*c, r.here(), static_cast<std::size_t>(records_len), size, error);
    if (!error.empty()) throw InputError(where + error);
    check_crc(body.data(), size, crc, where);
    records(body.data(), size, offset, true);
  }

  static void check_crc(const unsigned char* p, std::uint64_t n, std::uint32_t crc, const std::string& where) {
    if (crc == 0) return;  // not computed by the writer
    uLong c = crc32_z(0L, Z_NULL, 0);
    c = crc32_z(c, p, static_cast<z_size_t>(n));
    if (static_cast<std::uint32_t>(c) != crc)
      throw InputError(where + "CRC-32 of the records is " + std::to_string(c) + ", the chunk says " +
                       std::to_string(crc) + ": a damaged file");
  }

  std::string path_;
  std::uint64_t chunk_ = 0;  // the byte offset of the chunk being read
  ChunkBudget budget_;       // what the file's chunks state, against the limits
  std::map<std::uint16_t, std::string> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  std::map<std::string, std::string> topics_;  // topic -> schema name
  std::map<std::string, TopicState> imu_;      // the IMU topics
  const ReadOptions& options_;
};

}  // namespace

bool is_mcap(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // never sniff a pipe
  std::ifstream in(path, std::ios::binary);
  unsigned char head[sizeof kMagic] = {};
  return in && in.read(reinterpret_cast<char*>(head), sizeof head) && std::memcmp(head, kMagic, sizeof head) == 0;
}

SignalSet read_mcap(const std::string& path, const ReadOptions& options) {
  const InputFile file(path, "MCAP file");
  McapPass pass(path, options);
  if (pass.file_records(file))
    throw InputError(path + ": the file ends at byte " + std::to_string(file.size()) +
                     " without a DataEnd or footer record: truncated (an interrupted recording? 'mcap recover' "
                     "rewrites it)");
  return pass.finish();
}

}  // namespace gmwm::io::detail
