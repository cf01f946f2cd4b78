#include "gmwm/engine/error.h"

#include <cstdio>

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

std::string printable_line(std::string_view message) {
  std::string out = escape_controls(message, Breaks::kSpace);
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string printable_text(std::string_view text) { return escape_controls(text, Breaks::kKeepNewlineAndTab); }

}  // namespace gmwm
