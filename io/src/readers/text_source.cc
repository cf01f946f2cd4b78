#include "text_source.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "gmwm/engine/error.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

namespace {

// Compressed bytes read from the file at a time.
constexpr std::size_t kInputChunk = 1 << 18;
// Text read or inflated at a time: large enough to amortise the per-chunk work, small enough to
// stay in the L2 cache while the parser reads it right after inflate wrote it.
constexpr std::size_t kTextChunk = 1 << 18;
// Eight bytes of '\n' read as one word (any byte order).
constexpr std::uint64_t kEightNewlines = 0x0A0A0A0A0A0A0A0AULL;
// Typical compression ratio of gzip on text of numbers (the ADIS files: 7.6), used only to
// reserve memory for the columns; a wrong guess costs nothing but a reallocation.
constexpr std::uint64_t kTypicalGzipRatio = 8;

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw InputError(path + ": " + what); }

// A FIFO or pipe as a blocking stream, opened with the bounded wait every input gets
// (io::detail::open_pipe_bounded, side_file.h: kPipeWriterWaitMs), so that a FIFO no writer
// opens stops the run instead of hanging, while a slow writer is waited for.
std::FILE* open_fifo(const std::string& path) {
  int early = -1;  // a byte read while probing, given back to the stream
  const int fd = open_pipe_bounded(path, "data", early);
  std::FILE* f = ::fdopen(fd, "rb");
  if (!f) {
    ::close(fd);
    fail(path, std::string("cannot open: ") + std::strerror(errno));
  }
  if (early >= 0) std::ungetc(early, f);
  return f;
}

}  // namespace

// Inflates a gzip file (one or more concatenated members) chunk by chunk.
class GzipStream {
 public:
  // `prefix`: the bytes already read from `file` (the sniffed magic), inflated first.
  GzipStream(std::string path, std::FILE* file, const unsigned char* prefix, std::size_t prefix_size)
      : path_(std::move(path)), file_(file) {
    std::memset(&zs_, 0, sizeof zs_);
    // 15 + 32: largest window, automatic gzip/zlib header detection.
    if (inflateInit2(&zs_, 15 + 32) != Z_OK) fail(path_, "cannot initialise zlib");
    in_.resize(kInputChunk);
    std::memcpy(in_.data(), prefix, prefix_size);
    zs_.next_in = reinterpret_cast<Bytef*>(in_.data());
    zs_.avail_in = static_cast<uInt>(prefix_size);
    total_in_ = prefix_size;
  }
  ~GzipStream() { inflateEnd(&zs_); }
  GzipStream(const GzipStream&) = delete;
  GzipStream& operator=(const GzipStream&) = delete;

  /// Inflates up to `cap` bytes into `dst`; returns 0 only at the end of the data.
  std::size_t read(char* dst, std::size_t cap) {
    zs_.next_out = reinterpret_cast<Bytef*>(dst);
    zs_.avail_out = static_cast<uInt>(cap);
    while (zs_.avail_out > 0 && !done_) {
      if (zs_.avail_in == 0 && !fill_input()) {
        if (in_member_)
          fail(path_, "gzip stream ends early after " + std::to_string(text_bytes(cap)) +
                          " bytes of text (truncated file?), expected a complete gzip stream");
        done_ = true;
        break;
      }
      if (!in_member_) {
        // Between members: another member starts with the magic byte 0x1f. Zero bytes to
        // the end are padding (tape blocks), which gzip ignores too; anything else (plain
        // rows appended to a .gz, say) would be lost without a word, and is refused.
        if (zs_.next_in[0] != 0x1f) {
          expect_only_padding();
          done_ = true;
          break;
        }
        inflateReset(&zs_);
        in_member_ = true;
      }
      const int rc = inflate(&zs_, Z_NO_FLUSH);
      if (rc == Z_STREAM_END) {
        in_member_ = false;
      } else if (rc == Z_BUF_ERROR) {
        if (zs_.avail_in > 0) fail(path_, "corrupt gzip data, expected a valid gzip stream");
      } else if (rc != Z_OK) {
        fail(path_, std::string("corrupt gzip data (zlib: ") + (zs_.msg ? zs_.msg : "error") +
                        "), expected a valid gzip stream");
      }
    }
    const std::size_t produced = cap - zs_.avail_out;
    total_out_ += produced;
    if (inflation_exceeds(total_in_, total_out_)) {
      char ratio[32];
      std::snprintf(ratio, sizeof ratio, "%.0f", kMaxInflationRatio);
      fail(path_, "gzip data inflates to " + std::to_string(total_out_) + " bytes from " + std::to_string(total_in_) +
                      ", more than " + ratio + " times (a decompression bomb?), expected compressed text of numbers");
    }
    return produced;
  }

 private:
  // The rest of the file after the last member: zeros only, else InputError naming the
  // byte offset of the first other byte.
  void expect_only_padding() {
    do {
      const auto* p = static_cast<const unsigned char*>(zs_.next_in);
      for (uInt i = 0; i < zs_.avail_in; ++i)
        if (p[i] != 0)
          fail(path_, "found bytes that are not gzip data after the end of the gzip stream, at byte offset " +
                          std::to_string(total_in_ - zs_.avail_in + i) +
                          ", expected only gzip members (plain text appended to a .gz file? decompress the gzip part "
                          "and join them as text)");
      zs_.avail_in = 0;
    } while (fill_input());
  }

  bool fill_input() {
    const std::size_t n = std::fread(in_.data(), 1, in_.size(), file_);
    if (n == 0) {
      if (std::ferror(file_)) fail(path_, std::string("read error: ") + std::strerror(errno));
      return false;
    }
    zs_.next_in = reinterpret_cast<Bytef*>(in_.data());
    zs_.avail_in = static_cast<uInt>(n);
    total_in_ += n;
    return true;
  }
  std::uint64_t text_bytes(std::size_t cap) const { return total_out_ + (cap - zs_.avail_out); }

  std::string path_;
  std::FILE* file_;
  z_stream zs_;
  std::vector<unsigned char> in_;
  bool in_member_ = true;
  bool done_ = false;
  std::uint64_t total_in_ = 0;   // compressed bytes read
  std::uint64_t total_out_ = 0;  // text bytes inflated
};

TextSource::TextSource(const std::string& path) : path_(path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(path, "is a folder, expected a data file");
  struct stat st {};
  const bool fifo = ::stat(path.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
  file_ = fifo ? open_fifo(path) : std::fopen(path.c_str(), "rb");
  if (!file_) {
    const int err = errno;
    if (err == ENOENT) fail(path, "file not found, expected an existing data file");
    fail(path, std::string("cannot open: ") + std::strerror(err) + ", expected a readable file");
  }
  // The format is sniffed from the first bytes, which are kept (never re-read: a pipe
  // or a FIFO cannot rewind).
  unsigned char magic[2] = {0, 0};
  const std::size_t got = std::fread(magic, 1, 2, file_);
  empty_ = got == 0;
  const bool regular = std::filesystem::is_regular_file(path, ec);
  const auto size = regular ? std::filesystem::file_size(path, ec) : 0;
  const bool known_size = regular && !ec;
  if (got == 2 && magic[0] == 0x1f && magic[1] == 0x8b) {
    size_hint_ = known_size ? size * kTypicalGzipRatio : 0;
    gzip_ = std::make_unique<GzipStream>(path_, file_, magic, got);
    return;
  }
  // Plain text: read chunk by chunk like inflated text (memory independent of the
  // file's size).
  size_hint_ = known_size ? size : 0;
  reserve(kTextChunk);
  std::memcpy(buf_.get(), magic, got);
  end_ = got;
  eof_ = got < 2;
}

TextSource::~TextSource() {
  gzip_.reset();
  if (file_) std::fclose(file_);
}

void TextSource::reserve(std::size_t bytes) {
  if (bytes <= cap_) return;
  std::unique_ptr<char[]> bigger(new char[bytes]);
  if (end_ > pos_) std::memcpy(bigger.get(), buf_.get() + pos_, end_ - pos_);
  end_ -= pos_;
  pos_ = 0;
  buf_ = std::move(bigger);
  cap_ = bytes;
}

void TextSource::refill() {
  // Keep the unread tail (a partial line), then append freshly inflated text.
  const std::size_t tail = end_ - pos_;
  if (pos_ > 0 && tail > 0) std::memmove(buf_.get(), buf_.get() + pos_, tail);
  pos_ = 0;
  end_ = tail;
  if (tail > kMaxLineBytes) fail_long_line();
  if (cap_ < tail + kTextChunk) reserve(std::max(tail + kTextChunk, 2 * cap_));
  std::size_t n = 0;
  if (gzip_) {
    n = gzip_->read(buf_.get() + end_, cap_ - end_);
  } else {
    n = std::fread(buf_.get() + end_, 1, cap_ - end_, file_);
    if (n == 0 && std::ferror(file_)) fail(path_, std::string("read error: ") + std::strerror(errno));
  }
  if (n == 0) eof_ = true;
  end_ += n;
}

void TextSource::check_encoding(std::string_view first) const {
  const auto starts = [&](const char* magic) { return first.rfind(magic, 0) == 0; };
  if (starts("\xFF\xFE") || starts("\xFE\xFF") || first.find('\0') != std::string_view::npos)
    throw InputError(path_ + ":1: found " +
                     (starts("\xFF\xFE") || starts("\xFE\xFF") ? std::string("a UTF-16 byte-order mark")
                                                               : std::string("NUL bytes in the header line")) +
                     ", expected UTF-8 or ASCII text (UTF-16 text? convert it: iconv -f UTF-16 -t UTF-8)");
  if (first.find('\r') != std::string_view::npos)
    throw InputError(path_ +
                     ":1: found carriage returns (CR) inside the first line, expected lines ending in LF or CR LF "
                     "(a file with CR-only line endings? convert it: tr '\\r' '\\n')");
}

void TextSource::fail_long_line() const {
  if (line_ == 0 && std::memchr(buf_.get() + pos_, '\r', std::min(end_ - pos_, kMaxLineBytes)))
    check_encoding(std::string_view(buf_.get() + pos_, std::min(end_ - pos_, kMaxLineBytes)));
  throw InputError(path_ + ":" + std::to_string(line_ + 1) + ": found a line longer than " +
                   std::to_string(kMaxLineBytes) + " bytes, expected rows of at most " +
                   std::to_string(kMaxLineBytes >> 20) + " MiB each (is this a text file of numbers?)");
}

bool TextSource::next_line(std::string_view& line) {
  for (;;) {
    const char* b = buf_.get() + pos_;
    const std::size_t avail = end_ - pos_;
    if (line_ == 0 && pos_ == 0 && avail >= 3 && std::memcmp(b, "\xEF\xBB\xBF", 3) == 0) {
      pos_ += 3;  // UTF-8 byte-order mark (spreadsheet exports)
      continue;
    }
    const void* nl = avail ? std::memchr(b, '\n', avail) : nullptr;
    std::size_t len;
    if (nl) {
      len = static_cast<std::size_t>(static_cast<const char*>(nl) - b);
      pos_ += len + 1;
    } else if (eof_) {
      if (avail == 0) return false;
      len = avail;
      pos_ = end_;
    } else {
      refill();
      continue;
    }
    if (len > kMaxLineBytes) fail_long_line();
    if (len > 0 && b[len - 1] == '\r') --len;
    line = std::string_view(b, len);
    if (line_ == 0) check_encoding(line);
    ++line_;
    return true;
  }
}

std::int64_t TextSource::skip_blank_lines() {
  std::int64_t skipped = 0;
  for (;;) {
    const char* b = buf_.get() + pos_;
    std::size_t avail = end_ - pos_;
    // Bare "\n"s, eight at a time (a bomb's padding is nothing else).
    std::size_t run = 0;
    for (std::uint64_t word; run + 8 <= avail; run += 8) {
      std::memcpy(&word, b + run, 8);
      if (word != kEightNewlines) break;
    }
    if (run > 0) {
      pos_ += run;
      line_ += static_cast<std::int64_t>(run);
      skipped += static_cast<std::int64_t>(run);
      b += run;
      avail -= run;
    }
    std::size_t i = 0;
    while (i < avail && (b[i] == ' ' || b[i] == '\t')) ++i;
    if (i < avail && b[i] == '\r' && i + 1 < avail && b[i + 1] == '\n') ++i;
    if (i < avail && b[i] == '\n') {  // a blank line: past it
      pos_ += i + 1;
      ++line_;
      ++skipped;
      continue;
    }
    if (i < avail && !(b[i] == '\r' && i + 1 == avail)) return skipped;  // a line with text
    // The buffer ends inside what may still be a blank line (or on a lone '\r').
    if (eof_) {
      if (avail == 0) return skipped;
      if (i + 1 < avail || (i < avail && b[i] != '\r')) return skipped;
      pos_ = end_;  // the last line, blank and without "\n"
      ++line_;
      return skipped + 1;
    }
    refill();
  }
}

}  // namespace gmwm::io::detail
