#include "gmwm/io/signal_writer.h"

#include <charconv>
#include <cstring>

#include <zlib.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/atomic_file.h"

namespace gmwm::io {

namespace {

// zlib's default level (as gzip's): a good size/speed balance for text of numbers.
constexpr int kGzipLevel = 6;
// Longest shortest-round-trip double, e.g. "-2.2250738585072014e-308" (24 chars), plus slack.
constexpr std::size_t kMaxNumberChars = 32;

void append_name(std::string& out, const std::string& name) {
  if (name.find_first_of(",\"\r\n") == std::string::npos) {
    out += name;
    return;
  }
  out += '"';
  for (char c : name) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void append_number(std::string& out, double x) {
  char buf[kMaxNumberChars];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, ptr);
}

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string gzip(const std::string& path, const std::string& text) {
  z_stream zs;
  std::memset(&zs, 0, sizeof zs);
  // 15 + 16: largest window with a gzip (not zlib) wrapper.
  if (deflateInit2(&zs, kGzipLevel, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw InputError("cannot write '" + path + "': zlib initialisation failed");
  std::string out(deflateBound(&zs, static_cast<uLong>(text.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw InputError("cannot write '" + path + "': gzip compression failed");
  return out;
}

}  // namespace

std::string format_signals_csv(const std::vector<Signal>& signals, std::optional<double> freq) {
  if (freq) check_positive("write_signals", "freq", *freq);
  const std::size_t n = signals.empty() ? 0 : signals.front().values.size();
  for (const Signal& s : signals)
    check_size_match("write_signals", signals.front().name, n, s.name, s.values.size());
  std::string out;
  out.reserve((n + 1) * (signals.size() + 1) * 12);
  bool first = true;
  if (freq) {
    out += "time";
    first = false;
  }
  for (const Signal& s : signals) {
    if (!first) out += ',';
    append_name(out, s.name);
    first = false;
  }
  out += '\n';
  for (std::size_t i = 0; i < n; ++i) {
    first = true;
    if (freq) {
      append_number(out, static_cast<double>(i) / *freq);
      first = false;
    }
    for (const Signal& s : signals) {
      if (!first) out += ',';
      append_number(out, s.values[i]);
      first = false;
    }
    out += '\n';
  }
  return out;
}

void write_signals(const std::string& path, const std::vector<Signal>& signals,
                   std::optional<double> freq) {
  std::string text = format_signals_csv(signals, freq);
  if (ends_with(path, ".gz")) text = gzip(path, text);
  write_file_atomically(path, text);
}

}  // namespace gmwm::io
