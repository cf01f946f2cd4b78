#pragma once
// Binary inputs (MCAP, PX4 ULog) read with pread() at the offsets their records state, never
// mapped into memory: a mapped file that shrinks while it is read kills the process with
// SIGBUS at the first page past its new end (issue 25), and no check of its size beforehand
// closes that race. A short read is an InputError naming the file and the byte instead.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace gmwm::io::detail {

class InputFile {
 public:
  /// Opens `path` for reading; `kind` names the format in the message when it cannot be
  /// opened ("MCAP file"). Its size is taken once, here: the readers read up to it.
  InputFile(std::string path, const std::string& kind);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size() const { return size_; }

  /// Reads n bytes at `offset` into `out`. Throws InputError ("FILE: the file ends at byte
  /// E, expected N bytes at byte O (it was S bytes when opened: it shrank while being read)")
  /// when the file gives fewer; `offset + n` must be within size().
  void read(std::uint64_t offset, void* out, std::size_t n) const;

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Sequential reads of small pieces through a buffer of kWindowBytes (a record header, a
/// ULog message): view() returns the n bytes at `offset`, valid until the next call.
class InputWindow {
 public:
  /// Bytes read from the file at a time: large enough that a pass over a log costs few
  /// system calls, small enough to stay in the L2 cache.
  static constexpr std::size_t kWindowBytes = std::size_t{1} << 18;

  explicit InputWindow(const InputFile& file) : file_(file) {}
  const unsigned char* view(std::uint64_t offset, std::size_t n);

 private:
  const InputFile& file_;
  std::unique_ptr<unsigned char[]> buf_;
  std::size_t cap_ = 0;
  std::uint64_t start_ = 0;  // the file offset of buf_[0]
  std::size_t filled_ = 0;
};

namespace testing {
/// Called before every read of an InputFile with the file's path and the offset (tests make
/// a file shrink at a chosen point with it); empty: none. Not for concurrent use with reads.
void set_read_hook(std::function<void(const std::string& path, std::uint64_t offset)> hook);
}  // namespace testing

}  // namespace gmwm::io::detail
