#include "input_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {
namespace {

std::function<void(const std::string&, std::uint64_t)>& read_hook() {
  static std::function<void(const std::string&, std::uint64_t)> hook;
  return hook;
}

}  // namespace

namespace testing {
void set_read_hook(std::function<void(const std::string& path, std::uint64_t offset)> hook) {
  read_hook() = std::move(hook);
}
}  // namespace testing

InputFile::InputFile(std::string path, const std::string& kind) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path_ + ": cannot open the " + kind + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw InputError(path_ + ": cannot read the " + kind + " as a regular file");
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

void InputFile::read(std::uint64_t offset, void* out, std::size_t n) const {
  if (read_hook()) read_hook()(path_, offset);
  auto* p = static_cast<unsigned char*>(out);
  std::uint64_t at = offset;
  std::size_t left = n;
  while (left > 0) {
    const ssize_t r = ::pread(fd_, p, left, static_cast<off_t>(at));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0)
      throw InputError(path_ + ": cannot read " + std::to_string(n) + " bytes at byte " + std::to_string(offset) +
                       ": " + std::strerror(errno));
    if (r == 0) {
      // Nothing at `at`: the file ends there or before (fstat says where, now).
      struct stat st {};
      const std::uint64_t now =
          ::fstat(fd_, &st) == 0 ? std::min<std::uint64_t>(static_cast<std::uint64_t>(st.st_size), at) : at;
      throw InputError(path_ + ": the file ends at byte " + std::to_string(now) + ", expected " + std::to_string(n) +
                       " bytes at byte " + std::to_string(offset) + " (it was " + std::to_string(size_) +
                       " bytes when opened: it shrank while being read)");
    }
    p += r;
    left -= static_cast<std::size_t>(r);
    at += static_cast<std::uint64_t>(r);
  }
}

const unsigned char* InputWindow::view(std::uint64_t offset, std::size_t n) {
  if (offset >= start_ && n <= filled_ && offset - start_ <= filled_ - n) return buf_.get() + (offset - start_);
  // Refill from `offset`: n bytes at least, up to a window's worth, not past the file's end.
  const std::uint64_t left = file_.size() > offset ? file_.size() - offset : 0;
  const std::size_t want = std::max(n, static_cast<std::size_t>(std::min<std::uint64_t>(kWindowBytes, left)));
  if (want > cap_) {
    buf_.reset(new unsigned char[want]);
    cap_ = want;
  }
  start_ = offset;
  filled_ = 0;
  file_.read(offset, buf_.get(), want);
  filled_ = want;
  return buf_.get();
}

}  // namespace gmwm::io::detail
