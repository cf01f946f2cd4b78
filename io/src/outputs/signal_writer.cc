#include "gmwm/io/signal_writer.h"

#include <charconv>
#include <cstring>
#include <string>
#include <string_view>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/output_set.h"

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

// Text formatted before it is handed to the stream: one system call (or deflate call)
// per megabyte keeps their cost out of the profile without holding the file in memory.
constexpr std::size_t kRowBuffer = 1 << 20;

void check_signals(const std::vector<Signal>& signals, std::optional<double> freq) {
  if (freq) check_positive("write_signals", "freq", *freq);
  const std::size_t n = signals.empty() ? 0 : signals.front().values.size();
  for (const Signal& s : signals) check_size_match("write_signals", signals.front().name, n, s.name, s.values.size());
}

}  // namespace

std::string csv_field(const std::string& text) {
  // A cell starting with = + - @ (or a tab or CR) is a formula to a spreadsheet
  // (OWASP, "CSV injection"): a leading ' makes it text, and the cell is quoted.
  std::string out;
  if (!text.empty() && std::string_view("=+-@\t\r").find(text.front()) != std::string_view::npos) {
    std::string quoted = "\"'";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
  }
  append_name(out, text);
  return out;
}

void write_signals_csv(OutputStream& out, const std::vector<Signal>& signals, std::optional<double> freq) {
  check_signals(signals, freq);
  const std::size_t n = signals.empty() ? 0 : signals.front().values.size();
  std::string buf;
  buf.reserve(kRowBuffer + 4096);
  bool first = true;
  if (freq) {
    // The unit in the header: without it a reader guesses it from the step, and a step of
    // 1000 s (--freq 0.001) reads as 1000 us.
    buf += "time [s]";
    first = false;
  }
  for (const Signal& s : signals) {
    if (!first) buf += ',';
    append_name(buf, s.name);
    first = false;
  }
  buf += '\n';
  for (std::size_t i = 0; i < n; ++i) {
    first = true;
    if (freq) {
      append_number(buf, static_cast<double>(i) / *freq);
      first = false;
    }
    for (const Signal& s : signals) {
      if (!first) buf += ',';
      append_number(buf, s.values[i]);
      first = false;
    }
    buf += '\n';
    if (buf.size() >= kRowBuffer) {
      out.write(buf);
      buf.clear();
    }
  }
  out.write(buf);
}

std::string format_signals_csv(const std::vector<Signal>& signals, std::optional<double> freq) {
  std::string text;
  struct ToString final : OutputStream {
    std::string& s;
    explicit ToString(std::string& t) : s(t) {}
    void write(std::string_view b) override { s.append(b); }
  } sink(text);
  write_signals_csv(sink, signals, freq);
  return text;
}

void stage_signals(OutputSet& outputs, const std::string& path, const std::vector<Signal>& signals,
                   std::optional<double> freq) {
  check_signals(signals, freq);
  outputs.stage(path, [&](OutputStream& file) {
    if (!gzip_by_name(path)) {
      write_signals_csv(file, signals, freq);
      return;
    }
    GzipOutput gz(file, path, kGzipLevel);
    write_signals_csv(gz, signals, freq);
    gz.finish();
  });
}

void write_signals(const std::string& path, const std::vector<Signal>& signals, std::optional<double> freq) {
  OutputSet outputs;
  outputs.declare("output", path);
  stage_signals(outputs, path, signals, freq);
  outputs.commit();
}

}  // namespace gmwm::io
