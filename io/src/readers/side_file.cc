// Side files read whole, with the main input's protections (gmwm/io/side_file.h).
#include "gmwm/io/side_file.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gmwm/engine/error.h"

namespace gmwm::io {

namespace {

// Bytes read per read(2) call of a side file.
constexpr std::size_t kReadChunk = std::size_t{1} << 16;
// While a pipe holds fewer bytes than peek() asked for and its writer is still there, it
// is looked at again after this long (peeking cannot wait for "more" data in poll(2),
// which reports the bytes already there).
constexpr auto kPeekRetry = std::chrono::milliseconds(5);

std::string errno_text(int err) { return std::strerror(err); }

/// What a file that is not regular is, for messages; "" for a regular file, FIFO or pipe.
const char* unreadable_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode) || S_ISFIFO(mode)) return "";
  return "not a regular file";
}

/// What tee_peek() saw at the head of a pipe.
struct Peeked {
  std::string bytes;
  bool eof = false;  // no writer and nothing more to come
  int error = 0;     // errno when tee(2) failed for another reason than an empty pipe
};

/// Up to `n` bytes at the head of pipe `fd`, copied by tee(2) into a pipe of our own and
/// read from there: the bytes stay in `fd` for whoever reads it next.
Peeked tee_peek(int fd, std::size_t n) {
  Peeked out;
  int scratch[2];
  if (::pipe2(scratch, O_CLOEXEC | O_NONBLOCK) != 0) {
    out.error = errno;
    return out;
  }
  const ssize_t got = ::tee(fd, scratch[1], n, SPLICE_F_NONBLOCK);
  if (got == 0) {
    out.eof = true;  // no data and no writer
  } else if (got < 0) {
    if (errno != EAGAIN) out.error = errno;  // EAGAIN: a writer, no data yet
  } else {
    out.bytes.resize(static_cast<std::size_t>(got));
    std::size_t have = 0;
    while (have < out.bytes.size()) {
      const ssize_t r = ::read(scratch[0], out.bytes.data() + have, out.bytes.size() - have);
      if (r <= 0) break;
      have += static_cast<std::size_t>(r);
    }
    out.bytes.resize(have);
  }
  ::close(scratch[0]);
  ::close(scratch[1]);
  return out;
}

}  // namespace

namespace detail {

int open_pipe_bounded(const std::string& path, const std::string& expected, int& early) {
  early = -1;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open: " + errno_text(errno) + ", expected " + expected);
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, kPipeWriterWaitMs) == 0) {
    // Nothing after the wait: no writer at all (end of file), or a silent one. Told apart
    // without consuming a byte where tee(2) can look (a pipe), else by reading one.
    const Peeked probe = tee_peek(fd, 1);
    bool no_writer = probe.eof;
    if (probe.error != 0) {
      unsigned char c;
      const ssize_t n = ::read(fd, &c, 1);
      no_writer = n == 0;
      if (n == 1) early = c;
    }
    if (no_writer) {
      ::close(fd);
      throw InputError(path + ": is a FIFO that no writer opened within " + std::to_string(kPipeWriterWaitMs / 1000) +
                       " s, expected " + expected + " (start the writer first)");
    }
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

}  // namespace detail

SideFile::SideFile(std::string path, std::string expected) : path_(std::move(path)), expected_(std::move(expected)) {
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) {
    if (errno == ENOENT) fail("file not found, expected " + expected_);
    fail("cannot open: " + errno_text(errno) + ", expected " + expected_);
  }
  if (const char* kind = unreadable_kind(st.st_mode); *kind)
    fail(std::string("is ") + kind + ", expected " + expected_ + " (a regular file or a pipe)");
  pipe_ = S_ISFIFO(st.st_mode);
  if (pipe_) {
    int early = -1;
    fd_ = detail::open_pipe_bounded(path_, expected_, early);
    if (early >= 0) {
      // A byte was consumed to probe the writer: only where tee(2) cannot look, which a
      // FIFO always allows; refused rather than read without its first byte.
      ::close(fd_);
      fd_ = -1;
      fail("cannot read it as a pipe, expected " + expected_ + " in a regular file or a pipe");
    }
    return;
  }
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) fail("cannot open: " + errno_text(errno) + ", expected " + expected_);
  // The file may have been replaced between stat and open: judge what was opened.
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    fail("is not a regular file, expected " + expected_ + " (a regular file or a pipe)");
  }
}

SideFile::~SideFile() {
  if (fd_ >= 0) ::close(fd_);
}

void SideFile::fail(const std::string& what) const { throw InputError(path_ + ": " + what); }

std::string SideFile::peek(std::size_t n) {
  if (!pipe_) {
    std::string out(n, '\0');
    std::size_t have = 0;
    while (have < n) {
      const ssize_t r = ::pread(fd_, out.data() + have, n - have, static_cast<off_t>(have));
      if (r < 0) {
        if (errno == EINTR) continue;
        fail("read error: " + errno_text(errno));
      }
      if (r == 0) break;
      have += static_cast<std::size_t>(r);
    }
    out.resize(have);
    return out;
  }
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, -1) < 0) {
      if (errno == EINTR) continue;
      fail("read error: " + errno_text(errno));
    }
    const Peeked got = tee_peek(fd_, n);
    if (got.error != 0) fail("cannot read it as a pipe: " + errno_text(got.error) + ", expected " + expected_);
    // Enough, or all there will be (the writer gone: POLLHUP with the data still queued).
    if (got.eof || got.bytes.size() >= n || (p.revents & POLLHUP)) return got.bytes;
    std::this_thread::sleep_for(kPeekRetry);
  }
}

std::string SideFile::read(std::size_t limit) {
  auto too_large = [&] {
    fail("holds more than " + std::to_string(limit) + " bytes, expected " + expected_ + " of at most " +
         std::to_string(limit >> 20) + " MiB (a side file is read whole)");
  };
  if (!pipe_) {
    struct stat st {};
    if (::fstat(fd_, &st) == 0 && static_cast<std::size_t>(st.st_size) > limit) too_large();
  }
  std::string out;
  for (;;) {
    const std::size_t want = std::min(kReadChunk, limit + 1 - std::min(limit + 1, out.size()));
    if (want == 0) too_large();
    const std::size_t at = out.size();
    out.resize(at + want);
    const ssize_t r = ::read(fd_, out.data() + at, want);
    if (r < 0) {
      out.resize(at);
      if (errno == EINTR) continue;
      fail("read error: " + errno_text(errno));
    }
    out.resize(at + static_cast<std::size_t>(r));
    if (r == 0) break;
    if (out.size() > limit) too_large();
  }
  return out;
}

std::string read_side_file(const std::string& path, const std::string& expected, std::size_t limit) {
  return SideFile(path, expected).read(limit);
}

}  // namespace gmwm::io
