#include "gmwm/engine/error.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace gmwm {
namespace {

// The length of the valid UTF-8 sequence starting at s[i] (RFC 3629: no overlong forms,
// no surrogates, at most U+10FFFF), or 0.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const auto cont = [&](std::size_t k) { return i + k < s.size() && (b(k) & 0xC0) == 0x80; };
  const unsigned char c = b(0);
  if (c >= 0xC2 && c <= 0xDF) return cont(1) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    if (!cont(1) || !cont(2)) return 0;
    if (c == 0xE0 && b(1) < 0xA0) return 0;   // overlong
    if (c == 0xED && b(1) >= 0xA0) return 0;  // surrogate
    return 3;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    if (!cont(1) || !cont(2) || !cont(3)) return 0;
    if (c == 0xF0 && b(1) < 0x90) return 0;   // overlong
    if (c == 0xF4 && b(1) >= 0x90) return 0;  // above U+10FFFF
    return 4;
  }
  return 0;
}

// A cut at `p` moved back so that it splits no UTF-8 character and no \xNN escape.
std::size_t safe_cut(std::string_view s, std::size_t p) {
  while (p > 0 && p < s.size() && (static_cast<unsigned char>(s[p]) & 0xC0) == 0x80) --p;
  for (std::size_t q = p >= 3 ? p - 3 : 0; q < p; ++q)
    if (s[q] == '\\' && q + 1 < s.size() && s[q + 1] == 'x') return q;
  return p;
}

// "...[N more bytes]": what replaces an omitted run of N bytes.
std::string omission(std::size_t n) { return "...[" + std::to_string(n) + " more bytes]"; }

// The quoted spans of a line: the text between a quote character and the next same one.
struct Span {
  std::size_t begin = 0, end = 0;  // the text inside the quotes
  std::size_t size() const { return end - begin; }
};

std::vector<Span> quoted_spans(std::string_view s) {
  std::vector<Span> out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '\'' && s[i] != '"') continue;
    const std::size_t close = s.find(s[i], i + 1);
    if (close == std::string_view::npos) break;
    out.push_back({i + 1, close});
    i = close;
  }
  return out;
}

// Control bytes (but line breaks, as `breaks` says, and tabs when kept), DEL, C1 controls
// and bytes that are not valid UTF-8 as \xNN.
enum class Breaks { kSpace, kKeepNewlineAndTab };

std::string escape_controls(std::string_view message, Breaks breaks) {
  std::string out;
  out.reserve(message.size());
  for (std::size_t i = 0; i < message.size();) {
    const auto c = static_cast<unsigned char>(message[i]);
    const bool keep = breaks == Breaks::kKeepNewlineAndTab && (c == '\n' || c == '\t');
    if (keep) {
      out += static_cast<char>(c);
      ++i;
    } else if (breaks == Breaks::kSpace && (c == '\n' || c == '\r')) {
      out += ' ';
      ++i;
    } else if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? utf8_length(message, i) : 0;
               n > 0 && !(n == 2 && c == 0xC2 && static_cast<unsigned char>(message[i + 1]) < 0xA0)) {
      // Valid UTF-8 but the C1 controls U+0080..U+009F (CSI U+009B starts a terminal
      // escape sequence as ESC [ does).
      out.append(message.substr(i, n));
      i += n;
    } else {
      char buf[5];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
      ++i;
    }
  }
  return out;
}

}  // namespace

std::string capped_line(std::string_view line, std::size_t max) {
  if (line.size() <= max) return std::string(line);
  // Shorten the longest quoted text first (a cell, a path, an option's value): the
  // sentence around it says where and what was expected.
  std::vector<Span> spans = quoted_spans(line);
  std::string out(line);
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.size() > b.size(); });
  // Each shortened span keeps at least this much of its head.
  constexpr std::size_t kKeep = 40;
  std::vector<std::pair<Span, std::size_t>> cuts;  // span, bytes kept
  std::size_t excess = line.size() - max;
  for (const Span& sp : spans) {
    if (excess == 0) break;
    if (sp.size() <= kKeep + 32) continue;  // the note would cost more than it saves
    const std::size_t removable = sp.size() - kKeep;
    const std::size_t remove = std::min(removable, excess + 32);  // 32: room for the note
    cuts.push_back({sp, sp.size() - remove});
    excess -= std::min(excess, remove - std::min(remove, std::size_t{32}));
  }
  if (!cuts.empty()) {
    // Applied from the end of the line, so that earlier offsets stay valid.
    std::sort(cuts.begin(), cuts.end(), [](const auto& a, const auto& b) { return a.first.begin > b.first.begin; });
    for (const auto& [sp, keep] : cuts) {
      const std::size_t at = safe_cut(out, sp.begin + keep);
      out.replace(at, sp.end - at, omission(sp.end - at));
    }
  }
  if (out.size() <= max + 32) return out;
  // Still too long: the middle goes, the head (what and where) and the end (what was
  // expected) stay.
  const std::size_t tail = max / 3;
  std::size_t head = safe_cut(out, max - tail);
  std::size_t from = out.size() - tail;
  while (from < out.size() && (static_cast<unsigned char>(out[from]) & 0xC0) == 0x80) ++from;
  for (std::size_t q = from >= 3 ? from - 3 : 0; q < from; ++q)
    if (out[q] == '\\' && q + 1 < out.size() && out[q + 1] == 'x') from = std::min(out.size(), q + 4);
  return out.substr(0, head) + omission(from - head) + out.substr(from);
}

std::string printable_line(std::string_view message) {
  std::string out = escape_controls(message, Breaks::kSpace);
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string printable_text(std::string_view text) { return escape_controls(text, Breaks::kKeepNewlineAndTab); }

}  // namespace gmwm
