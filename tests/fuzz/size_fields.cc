#include "size_fields.h"

#include <cstring>
#include <string>

namespace gmwm::fuzz {
namespace {

template <typename T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

bool fits(std::size_t at, std::uint64_t n, std::size_t size) { return at <= size && n <= size - at; }

// A ROS 1 record list in [begin, end): each record's lengths, its header fields' lengths and
// the values of the fields that state sizes, counts or offsets; recursing into a chunk's data
// when it is stored uncompressed, and into messages (their frame_id length at byte 12).
void ros1_records(const std::uint8_t* d, std::size_t begin, std::size_t end, std::vector<SizeField>& out, int depth) {
  static const char* const kValues[][2] = {{"index_pos", "8"}, {"chunk_pos", "8"},  {"size", "4"},
                                           {"count", "4"},     {"conn_count", "4"}, {"chunk_count", "4"}};
  std::size_t at = begin;
  while (fits(at, 4, end)) {
    const std::uint32_t hl = load<std::uint32_t>(d + at);
    out.push_back({at, 4});
    if (!fits(at + 4, hl, end)) return;
    bool chunk_none = false, message = false;
    for (std::size_t f = at + 4; fits(f, 4, at + 4 + hl);) {
      const std::uint32_t fl = load<std::uint32_t>(d + f);
      out.push_back({f, 4});
      if (!fits(f + 4, fl, at + 4 + hl)) break;
      const std::string text(reinterpret_cast<const char*>(d + f + 4), fl);
      const auto eq = text.find('=');
      if (eq != std::string::npos) {
        const std::string name = text.substr(0, eq);
        for (const auto& v : kValues)
          if (name == v[0] && text.size() - eq - 1 == static_cast<std::size_t>(v[1][0] - '0'))
            out.push_back({f + 4 + eq + 1, static_cast<std::size_t>(v[1][0] - '0')});
        if (text == std::string("compression=none")) chunk_none = true;
        if (name == "op" && text.size() == eq + 2 && text[eq + 1] == '\x02') message = true;
      }
      f += 4 + fl;
    }
    const std::size_t data_len_at = at + 4 + hl;
    if (!fits(data_len_at, 4, end)) return;
    const std::uint32_t dl = load<std::uint32_t>(d + data_len_at);
    out.push_back({data_len_at, 4});
    if (!fits(data_len_at + 4, dl, end)) return;
    if (chunk_none && depth == 0) ros1_records(d, data_len_at + 4, data_len_at + 4 + dl, out, depth + 1);
    if (message && dl >= 16) out.push_back({data_len_at + 4 + 12, 4});  // frame_id's length
    at = data_len_at + 4 + dl;
  }
}

// MCAP records in [begin, end); `in_chunk` records are a chunk's.
void mcap_records(const std::uint8_t* d, std::size_t begin, std::size_t end, std::vector<SizeField>& out,
                  bool in_chunk) {
  std::size_t at = begin;
  while (fits(at, 9, end)) {
    const std::uint8_t op = d[at];
    const std::uint64_t len = load<std::uint64_t>(d + at + 1);
    out.push_back({at + 1, 8});
    if (!fits(at + 9, len, end)) return;
    const std::size_t c = at + 9, ce = c + static_cast<std::size_t>(len);
    // A string or byte array at `p`: its uint32 length; returns the offset after it, or ce.
    const auto string_at = [&](std::size_t p) -> std::size_t {
      if (!fits(p, 4, ce)) return ce;
      out.push_back({p, 4});
      const std::uint32_t n = load<std::uint32_t>(d + p);
      return fits(p + 4, n, ce) ? p + 4 + n : ce;
    };
    if (op == 0x03) {  // schema: id, name, encoding, data
      string_at(string_at(string_at(c + 2)));
    } else if (op == 0x04) {  // channel: id, schema_id, topic, encoding, metadata
      string_at(string_at(string_at(c + 4)));
    } else if (op == 0x05) {  // message: channel, sequence, times, then CDR (frame_id length at 12)
      if (fits(c + 22 + 12, 4, ce)) out.push_back({c + 22 + 12, 4});
    } else if (op == 0x06 && !in_chunk && fits(c, 28, ce)) {  // chunk
      out.push_back({c + 16, 8});                             // uncompressed_size
      const std::size_t compression = c + 28;
      if (fits(compression, 4, ce)) {
        out.push_back({compression, 4});
        const std::uint32_t cl = load<std::uint32_t>(d + compression);
        const std::size_t records = compression + 4 + cl;
        if (fits(compression + 4, cl, ce) && fits(records, 8, ce)) {
          out.push_back({records, 8});
          const std::uint64_t rl = load<std::uint64_t>(d + records);
          if (cl == 0 && fits(records + 8, rl, ce))
            mcap_records(d, records + 8, records + 8 + static_cast<std::size_t>(rl), out, true);
        }
      }
    }
    at = ce;
  }
}

}  // namespace

std::vector<SizeField> ulog_size_fields(const std::uint8_t* d, std::size_t size) {
  std::vector<SizeField> out;
  for (std::size_t at = 16; fits(at, 3, size);) {
    const std::uint16_t n = load<std::uint16_t>(d + at);
    out.push_back({at, 2});
    const char type = static_cast<char>(d[at + 2]);
    if (!fits(at + 3, n, size)) break;
    if (type == 'F') {
      for (std::size_t k = at + 3; k < at + 3 + n; ++k)
        if (d[k] == '[') out.push_back({k + 1, 0});
    } else if ((type == 'A' && n >= 3) || (type == 'D' && n >= 2)) {
      out.push_back({at + 3 + (type == 'A' ? 1 : 0), 2});  // msg_id
    }
    at += 3 + n;
  }
  return out;
}

std::vector<SizeField> rosbag1_size_fields(const std::uint8_t* d, std::size_t size) {
  std::vector<SizeField> out;
  if (size > 13) ros1_records(d, 13, size, out, 0);
  return out;
}

std::vector<SizeField> mcap_size_fields(const std::uint8_t* d, std::size_t size) {
  std::vector<SizeField> out;
  if (size > 8) mcap_records(d, 8, size, out, false);
  return out;
}

std::vector<SizeField> cdr_size_fields(const std::uint8_t*, std::size_t size) {
  std::vector<SizeField> out;
  if (size >= 16) out.push_back({12, 4});  // encapsulation 4, sec 4, nanosec 4, then frame_id's length
  return out;
}

bool drive_to_extreme(std::uint8_t* data, std::size_t size, const std::vector<SizeField>& fields, std::uint64_t seed) {
  if (fields.empty()) return false;
  const SizeField f = fields[seed % fields.size()];
  seed /= fields.size();
  if (f.width == 0) {  // ASCII digits up to ']'
    static const char* const kLengths[] = {"0", "1", "65535", "65536", "999999", "4294967296", "18446744073709551615"};
    const std::string v = kLengths[seed % (sizeof kLengths / sizeof *kLengths)];
    for (std::size_t k = 0; k < v.size() && f.offset + k < size && data[f.offset + k] != ']'; ++k)
      data[f.offset + k] = static_cast<std::uint8_t>(v[k]);
    return true;
  }
  if (f.offset + f.width > size) return false;
  std::uint64_t current = 0;
  std::memcpy(&current, data + f.offset, f.width);
  const std::uint64_t top = f.width == 8 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * f.width)) - 1;
  const std::uint64_t extremes[] = {0,
                                    1,
                                    top,
                                    top - 1,
                                    top >> 1,
                                    (top >> 1) + 1,
                                    current + 1,
                                    current - 1,
                                    current * 2,
                                    current + 4096,
                                    std::uint64_t{1} << 30,
                                    std::uint64_t{1} << 32,
                                    std::uint64_t{1} << 40,
                                    std::uint64_t{1} << 63,
                                    std::uint64_t{size},
                                    std::uint64_t{size} + 1};
  const std::uint64_t v = extremes[seed % (sizeof extremes / sizeof *extremes)] & top;
  std::memcpy(data + f.offset, &v, f.width);
  return true;
}

}  // namespace gmwm::fuzz
