// PX4 ULog input (docs/cli.md "Inputs"): the IMU topics of a flight log as signals.
//
// The format (PX4's published ULog specification): a 16-byte header (magic "ULog" 01 12 35,
// a version byte, the start time in us), then messages of a 3-byte header (uint16 payload
// size, uint8 type) and a payload, little-endian. Definitions: 'F' formats
// ("name:type field;type field;..." with int8_t..uint64_t, float, double, bool, char,
// arrays "type[n]" and other formats as field types; padding is explicit, "_padding0"
// fields), 'A' subscriptions (multi_id, msg_id, name), 'R' unsubscriptions (msg_id); data:
// 'D' (msg_id, the packed fields). A topic instance may be subscribed more than once (a
// logger restart, a new msg_id): the data of every subscription are read, in file order.
// Other types ('B', 'I', 'M', 'P', 'Q', 'L', 'C', 'S', 'O') are skipped.
//
// Topics read, with the signals they give (timestamps from the "timestamp" field, in us):
//   sensor_combined: gyro_rad[3] -> gyro_x..z (rad/s), accelerometer_m_s2[3] -> accel_x..z (m/s^2)
//   sensor_gyro:  x, y, z -> gyro_x..z (rad/s)      sensor_accel: x, y, z -> accel_x..z (m/s^2)
// `--topic NAME` picks one (NAME:K its instance K, default 0); without it sensor_combined.
//
// The file is read once, in order, through a window (input_file.h), never whole: the axes
// are kept within the memory budget and in temporary files beyond it (LogColumns).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "checked_size.h"
#include "gmwm/engine/error.h"
#include "input_file.h"
#include "log_signals.h"
#include "timestamp.h"
#include "ulog_reader.h"

namespace gmwm::io::detail {
namespace {

constexpr std::array<unsigned char, 7> kMagic = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35};
constexpr std::size_t kHeaderBytes = 16;
// The largest payload of a data message ('D': a uint16 payload size, of which the msg_id takes
// 2 bytes): a topic's format must fit in it.
constexpr std::uint64_t kMaxPayloadBytes = 0xffff - 2;
// Formats nested in formats: PX4's nest a few levels; far beyond that a format most likely
// contains itself (directly or through others).
constexpr int kMaxNesting = 16;

struct Field {
  std::string type, name;
  int count = 1;           // array length
  std::size_t offset = 0;  // in the message's payload (after msg_id)
  std::size_t size = 0;    // of one element
};

struct Format {
  std::vector<Field> fields;
  std::size_t size = 0;
};

std::size_t basic_size(const std::string& t) {
  static const std::map<std::string, std::size_t> sizes = {
      {"int8_t", 1},  {"uint8_t", 1},  {"bool", 1},  {"char", 1},    {"int16_t", 2},  {"uint16_t", 2},
      {"int32_t", 4}, {"uint32_t", 4}, {"float", 4}, {"int64_t", 8}, {"uint64_t", 8}, {"double", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

template <typename T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // ULog is little-endian, as every host this builds on
  return v;
}

double number(const Field& f, const unsigned char* p) {
  const std::string& t = f.type;
  if (t == "float") return load<float>(p);
  if (t == "double") return load<double>(p);
  if (t == "int8_t") return load<std::int8_t>(p);
  if (t == "uint8_t" || t == "bool") return load<std::uint8_t>(p);
  if (t == "int16_t") return load<std::int16_t>(p);
  if (t == "uint16_t") return load<std::uint16_t>(p);
  if (t == "int32_t") return load<std::int32_t>(p);
  if (t == "uint32_t") return load<std::uint32_t>(p);
  if (t == "int64_t") return static_cast<double>(load<std::int64_t>(p));
  if (t == "uint64_t") return static_cast<double>(load<std::uint64_t>(p));
  return 0.0;
}

// What one topic gives: the fields and element indices of each signal.
struct Wanted {
  std::string name, field, unit;
  int element = 0;
};

std::vector<Wanted> wanted_of(const std::string& topic) {
  if (topic == "sensor_combined")
    return {{"gyro_x", "gyro_rad", "rad/s", 0},
            {"gyro_y", "gyro_rad", "rad/s", 1},
            {"gyro_z", "gyro_rad", "rad/s", 2},
            {"accel_x", "accelerometer_m_s2", "m/s^2", 0},
            {"accel_y", "accelerometer_m_s2", "m/s^2", 1},
            {"accel_z", "accelerometer_m_s2", "m/s^2", 2}};
  if (topic == "sensor_gyro")
    return {{"gyro_x", "x", "rad/s", 0}, {"gyro_y", "y", "rad/s", 0}, {"gyro_z", "z", "rad/s", 0}};
  if (topic == "sensor_accel")
    return {{"accel_x", "x", "m/s^2", 0}, {"accel_y", "y", "m/s^2", 0}, {"accel_z", "z", "m/s^2", 0}};
  return {};
}

class Parser {
 public:
  explicit Parser(std::string path) : path_(std::move(path)) {}

  SignalSet read(const ReadOptions& options) {
    const InputFile file(path_, "ULog file");
    unsigned char head[kHeaderBytes] = {};
    if (file.size() >= kHeaderBytes) file.read(0, head, kHeaderBytes);
    if (std::memcmp(head, kMagic.data(), kMagic.size()) != 0)
      throw InputError(path_ + ": found no ULog header, expected the magic bytes 'ULog' 01 12 35");
    std::string topic = options.topic.empty() ? "sensor_combined" : options.topic;
    int instance = 0;
    if (const auto colon = topic.find(':'); colon != std::string::npos) {
      const std::string k = topic.substr(colon + 1);
      if (k.empty() || k.size() > 3 || k.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(path_ + ": --topic " + topic + ": expected NAME or NAME:INSTANCE (e.g. sensor_gyro:1)");
      instance = std::stoi(k);
      topic.resize(colon);
    }
    const std::vector<Wanted> wanted = wanted_of(topic);
    if (wanted.empty())
      throw InputError(path_ + ": --topic " + topic +
                       ": expected an IMU topic: sensor_combined, sensor_gyro or sensor_accel");
    std::vector<LogAxis> axes;
    for (const Wanted& w : wanted) axes.push_back({w.name, w.unit});
    LogColumns columns(path_, "topic " + topic, std::move(axes), options);
    scan(file, topic, instance, wanted, columns);
    return std::move(columns).finish("ulog:" + topic + (instance ? ":" + std::to_string(instance) : ""),
                                     TimeUnit{1e-6, "us"}, "ULog (microseconds)");
  }

 private:
  [[noreturn]] void fail(std::uint64_t at, std::size_t index, const std::string& what) const {
    throw InputError(path_ + ": message " + std::to_string(index) + " at byte " + std::to_string(at) + ": " + what);
  }

  // A format definition "name:type field;type field;...".
  void define(const std::string& text, std::uint64_t at, std::size_t index) {
    const auto colon = text.find(':');
    if (colon == std::string::npos || colon == 0) fail(at, index, "format '" + text + "' has no 'name:'");
    // A format defined again (a logger restart) with another layout: the layouts worked out
    // so far may have used the old one.
    std::string& raw = raw_formats_[text.substr(0, colon)];
    if (raw != text.substr(colon + 1)) formats_.clear();
    raw = text.substr(colon + 1);
  }

  // The layout of a format (resolving nested types), memoised. Sizes are summed with
  // overflow checks and a format must fit in a data message (kMaxPayloadBytes): a crafted
  // nest of arrays would otherwise wrap around to a small size and send the field offsets
  // far outside the message. Errors name the message (`at`, `index`) that needs the layout.
  const Format& layout(const std::string& name, std::uint64_t at, std::size_t index, int depth = 0) {
    if (const auto it = formats_.find(name); it != formats_.end()) return it->second;
    const auto raw = raw_formats_.find(name);
    if (raw == raw_formats_.end()) fail(at, index, "format '" + name + "' is used but never defined");
    if (depth > kMaxNesting)
      fail(at, index,
           "format '" + name + "' nests deeper than " + std::to_string(kMaxNesting) +
               " levels (a format that contains itself?), expected at most " + std::to_string(kMaxNesting));
    Format f;
    std::size_t start = 0;
    const std::string& s = raw->second;
    while (start < s.size()) {
      auto end = s.find(';', start);
      if (end == std::string::npos) end = s.size();
      const std::string item = s.substr(start, end - start);
      start = end + 1;
      if (item.empty()) continue;
      const auto space = item.find(' ');
      if (space == std::string::npos) fail(at, index, "format '" + name + "': field '" + item + "' has no type");
      Field fd;
      fd.type = item.substr(0, space);
      fd.name = item.substr(space + 1);
      if (const auto br = fd.type.find('['); br != std::string::npos) {
        const std::string n = fd.type.back() == ']' ? fd.type.substr(br + 1, fd.type.size() - br - 2) : std::string();
        if (n.empty() || n.find_first_not_of("0123456789") != std::string::npos || n.size() > 6)
          fail(at, index, "format '" + name + "': field '" + item + "' has a bad array length, expected [1..999999]");
        fd.count = std::stoi(n);
        fd.type.resize(br);
      }
      fd.size = basic_size(fd.type);
      if (fd.size == 0) fd.size = layout(fd.type, at, index, depth + 1).size;  // a nested message
      fd.offset = f.size;
      const auto bytes = checked_mul(fd.size, static_cast<std::uint64_t>(fd.count));
      const auto total = bytes ? checked_add(f.size, *bytes) : std::nullopt;
      if (!total || *total > kMaxPayloadBytes)
        fail(at, index,
             "format '" + name + "': field '" + item + "' makes it larger than " + std::to_string(kMaxPayloadBytes) +
                 " bytes, expected a format that fits in a data message");
      f.size = static_cast<std::size_t>(*total);
      f.fields.push_back(fd);
    }
    return formats_.emplace(name, std::move(f)).first->second;
  }

  // What a subscription of the topic instance gives: where the wanted fields and the
  // timestamp are in its data messages (copies: a later 'F' may redefine the format).
  struct Subscription {
    std::size_t payload_size = 0;
    std::vector<Field> fields;  // one per wanted axis
    Field stamp;
  };

  Subscription subscription(const std::string& topic, const std::vector<Wanted>& wanted, std::uint64_t at,
                            std::size_t index) {
    const Format& f = layout(topic, at, index);
    Subscription s;
    s.payload_size = f.size;
    for (const Wanted& w : wanted) {
      const Field* found = nullptr;
      for (const Field& fd : f.fields)
        if (fd.name == w.field) found = &fd;
      if (!found || w.element >= found->count || basic_size(found->type) == 0)
        fail(at, index,
             "topic " + topic + " has no numeric field " + w.field +
                 (w.element ? "[" + std::to_string(w.element) + "]" : "") + ", expected IMU messages");
      s.fields.push_back(*found);
    }
    const Field* stamp = nullptr;
    for (const Field& fd : f.fields)
      if (fd.name == "timestamp" && fd.type == "uint64_t") stamp = &fd;
    if (!stamp) fail(at, index, "topic " + topic + " has no uint64_t timestamp field");
    s.stamp = *stamp;
    return s;
  }

  // Every subscription ('A') of the topic instance counts: a log may subscribe it again
  // (a logger restart, a new msg_id), and the data of all of them are the topic's, in
  // file order. A msg_id that another topic's subscription takes over, or that an 'R'
  // (unsubscription) names, stops counting.
  //
  // The file is read once, in order, through a window (input_file.h): a message's header,
  // then its payload when it is needed (formats, subscriptions, and the data of the topic).
  void scan(const InputFile& file, const std::string& topic, int instance, const std::vector<Wanted>& wanted,
            LogColumns& columns) {
    InputWindow window(file);
    const std::uint64_t end = file.size();
    std::uint64_t at = kHeaderBytes;
    std::map<std::uint16_t, Subscription> subscriptions;
    bool subscribed = false, listed_topic = false;
    std::vector<double> values(wanted.size());
    std::uint64_t previous_stamp = 0;
    for (std::size_t index = 1; at < end; ++index) {
      if (end - at < 3)
        fail(at, index, "truncated message header (" + std::to_string(end - at) + " bytes left, expected 3)");
      const unsigned char* h = window.view(at, 3);
      const std::uint16_t size = load<std::uint16_t>(h);
      const char type = static_cast<char>(h[2]);
      const std::uint64_t body = at + 3;
      if (end - body < size)
        fail(at, index,
             "truncated: a '" + std::string(1, type) + "' message of " + std::to_string(size) + " bytes with " +
                 std::to_string(end - body) + " left");
      if (type != 'F' && type != 'A' && type != 'R' && type != 'D') {
        at = body + size;  // other messages: skipped unread
        continue;
      }
      // The payload: whole, but for data messages only their msg_id until it is the topic's.
      const unsigned char* p = window.view(body, type == 'D' ? std::min<std::size_t>(size, 2) : size);
      if (type == 'F') {
        define(std::string(reinterpret_cast<const char*>(p), size), at, index);
      } else if (type == 'A') {
        if (size < 4) fail(at, index, "an 'A' message shorter than 4 bytes");
        const int multi = p[0];
        const std::uint16_t id = load<std::uint16_t>(p + 1);
        const std::string name(reinterpret_cast<const char*>(p + 3), size - 3);
        if (name == topic) listed_topic = true;
        if (name == topic && multi == instance) {
          subscriptions[id] = subscription(topic, wanted, at, index);
          subscribed = true;
        } else {
          subscriptions.erase(id);
        }
      } else if (type == 'R') {
        if (size < 2) fail(at, index, "an 'R' message shorter than 2 bytes");
        subscriptions.erase(load<std::uint16_t>(p));
      } else if (type == 'D' && !subscriptions.empty()) {
        if (size < 2) fail(at, index, "a 'D' message shorter than 2 bytes");
        const auto sub = subscriptions.find(load<std::uint16_t>(p));
        if (sub != subscriptions.end()) {
          const Subscription& s = sub->second;
          if (static_cast<std::size_t>(size - 2) < s.payload_size)
            fail(at, index,
                 topic + " data of " + std::to_string(size - 2) + " bytes, expected " + std::to_string(s.payload_size));
          if (columns.size() == 0) columns.reserve((end - at) / (s.payload_size + 5));  // at most this many
          const unsigned char* d = window.view(body, size) + 2;
          // The stamp as read is named in messages: its double may round to 2^64, which no
          // uint64 holds (a fuzzer's finding).
          const std::uint64_t stamp = load<std::uint64_t>(d + s.stamp.offset);
          const double t = static_cast<double>(stamp);
          if (columns.size() > 0 && t <= columns.last())
            fail(at, index,
                 topic + " timestamp " + std::to_string(stamp) + " us is not after the previous one (" +
                     std::to_string(previous_stamp) + " us): unsorted stamps");
          previous_stamp = stamp;
          for (std::size_t k = 0; k < s.fields.size(); ++k) {
            const Field& fd = s.fields[k];
            values[k] = number(fd, d + fd.offset + fd.size * static_cast<std::size_t>(wanted[k].element));
            if (!std::isfinite(values[k])) fail(at, index, topic + " " + wanted[k].name + " is not a finite number");
          }
          columns.add(t, values.data(), [&] {
            return path_ + ": message " + std::to_string(index) + " at byte " + std::to_string(at) + ": ";
          });
        }
      }
      at = body + size;
    }
    if (!subscribed)
      throw InputError(path_ + ": no topic " + topic + (listed_topic ? " instance " + std::to_string(instance) : "") +
                       " in this log" + topics_hint());
  }

  std::string topics_hint() const {
    std::string imu;
    for (const char* t : {"sensor_combined", "sensor_gyro", "sensor_accel"})
      if (raw_formats_.count(t)) imu += (imu.empty() ? "" : ", ") + std::string(t);
    return imu.empty() ? " (it logs none of sensor_combined, sensor_gyro, sensor_accel)" : " (it has " + imu + ")";
  }

  std::string path_;
  std::map<std::string, std::string> raw_formats_;
  std::map<std::string, Format> formats_;
};

}  // namespace

bool is_ulog(const std::string& path) {
  // Regular files only: sniffing a pipe here would consume its first bytes.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, kMagic.size()> head{};
  return in && in.read(reinterpret_cast<char*>(head.data()), head.size()) && head == kMagic;
}

SignalSet read_ulog(const std::string& path, const ReadOptions& options) { return Parser(path).read(options); }

}  // namespace gmwm::io::detail
