#pragma once
// Line-by-line access to a text file that may be gzip-compressed (detected by its magic
// bytes). Both are read (or inflated) in chunks, so a line view points into a buffer that
// stays cache-warm while it is parsed and memory does not grow with the file. A line is at
// most kMaxLineBytes; gzip text inflates at most kMaxInflationRatio times (signal_reader.h).

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gmwm::io::detail {

class GzipStream;

class TextSource {
 public:
  /// Opens `path`. Throws InputError when it is missing, a folder or unreadable.
  explicit TextSource(const std::string& path);
  ~TextSource();
  TextSource(const TextSource&) = delete;
  TextSource& operator=(const TextSource&) = delete;

  /// The next line without its "\n" or "\r\n"; false at the end of the file. The view is
  /// valid until the next call. Throws InputError on a truncated or corrupt gzip stream.
  bool next_line(std::string_view& line);

  /// Skips the blank lines ahead (only spaces and tabs before "\n" or "\r\n", or before the
  /// end of the file), as next_line() would return them and the caller drop them one by one,
  /// but a byte at a time instead of a call a line: a run of millions of blank lines (a
  /// decompression bomb's padding) costs what its bytes cost. Returns how many were skipped;
  /// line_number() counts them. Only after the first line (whose encoding next_line checks).
  std::int64_t skip_blank_lines();

  /// 1-based number of the line last returned by next_line().
  std::int64_t line_number() const { return line_; }
  bool compressed() const { return gzip_ != nullptr; }
  /// True when the file holds no byte at all.
  bool empty() const { return empty_; }
  /// Rough size of the text in bytes (exact for plain files, estimated for gzip), to
  /// reserve memory up front.
  std::uint64_t text_size_hint() const { return size_hint_; }

 private:
  void refill();
  [[noreturn]] void fail_long_line() const;
  // Refuses a first line that shows the wrong encoding (UTF-16: a byte-order mark or NUL
  // bytes) or CR-only line endings, naming that cause rather than its consequence.
  void check_encoding(std::string_view first) const;
  void reserve(std::size_t bytes);

  std::string path_;
  std::FILE* file_ = nullptr;
  std::unique_ptr<GzipStream> gzip_;
  std::unique_ptr<char[]> buf_;  // not zero-filled: it is written before it is read
  std::size_t cap_ = 0;
  std::uint64_t size_hint_ = 0;
  std::size_t pos_ = 0;  // first unread byte in buf_
  std::size_t end_ = 0;  // one past the last valid byte in buf_
  bool eof_ = false;
  bool empty_ = false;
  std::int64_t line_ = 0;
};

}  // namespace gmwm::io::detail
