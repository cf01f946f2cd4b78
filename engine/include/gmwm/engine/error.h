#pragma once
// Errors caused by the user's input or configuration. The CLI maps them to exit code 2
// and prints what() as one line. The message names the input, the place (line/column
// where it applies) and what was expected.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace gmwm {

/// A message as one printable line: line breaks become spaces, other control bytes, DEL,
/// the C1 controls and bytes that are not valid UTF-8 are shown as \xNN, so that a NUL or binary junk
/// from a file cannot cut, hide or garble what is printed; trailing spaces are dropped.
std::string printable_line(std::string_view message);

/// Text for a terminal: as printable_line but line breaks and tabs are kept, so that a name
/// read from a file cannot carry an escape sequence (ESC, CSI, a carriage return that
/// overwrites the line) into what is printed.
std::string printable_text(std::string_view text);

/// The longest error line, in bytes: five lines of a terminal, more than any message needs
/// to name a file, a place and what was expected, while a quoted 10 MB cell or option value
/// made a line of 10 MB.
inline constexpr std::size_t kMaxErrorLineBytes = 500;

/// A printable line cut to at most `max` bytes (plus the note), keeping its end ("expected
/// ..."): the longest quoted text ('...' or "...") is shortened first, to its head, "..."
/// and "[N more bytes]"; a line still too long loses its middle the same way. Never cuts a
/// UTF-8 character or a \xNN escape.
std::string capped_line(std::string_view line, std::size_t max = kMaxErrorLineBytes);

/// The message is kept as capped_line(printable_line(message)): what() is one printable
/// line of at most kMaxErrorLineBytes (and its note) whatever bytes of a file it quotes.
class InputError : public std::runtime_error {
 public:
  explicit InputError(std::string_view message) : std::runtime_error(capped_line(printable_line(message))) {}
};

/// Thrown by a progress callback to stop the computation that called it (Python's Ctrl-C:
/// python/gmwm_module.cc). Every long computation of the library reports progress through a
/// callback (a study's `progress` option), which is where it may be cancelled: the exception
/// goes through the parallel loops (gmwm::parallel_for) and the selection's flow graph,
/// which stop starting work and rethrow it, and nothing is left half-written.
class Cancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "cancelled"; }
};

}  // namespace gmwm
