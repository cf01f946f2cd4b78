#include "gmwm/engine/samples.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "gmwm/engine/error.h"

namespace gmwm {

namespace {

// Values buffered before a write(2) to a sample file.
constexpr std::size_t kWriteBufferValues = std::size_t{1} << 17;  // 1 MiB

// The address ranges of the live sample files and temporary arrays: only these may have
// their pages released (release_file_pages), since their contents stay in the file.
std::mutex g_ranges_mutex;
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> g_ranges;

void add_range(const void* p, std::size_t bytes) {
  const std::lock_guard<std::mutex> lock(g_ranges_mutex);
  const auto b = reinterpret_cast<std::uintptr_t>(p);
  g_ranges.emplace_back(b, b + bytes);
}

void remove_range(const void* p) {
  const std::lock_guard<std::mutex> lock(g_ranges_mutex);
  const auto b = reinterpret_cast<std::uintptr_t>(p);
  g_ranges.erase(std::remove_if(g_ranges.begin(), g_ranges.end(), [&](const auto& r) { return r.first == b; }),
                 g_ranges.end());
}

bool in_ranges(const void* p, std::size_t bytes) {
  const std::lock_guard<std::mutex> lock(g_ranges_mutex);
  const auto b = reinterpret_cast<std::uintptr_t>(p);
  return std::any_of(g_ranges.begin(), g_ranges.end(),
                     [&](const auto& r) { return b >= r.first && b + bytes <= r.second; });
}

[[noreturn]] void fail_temporary(const std::string& what, int err) {
  throw InputError("temporary folder '" + detail::temporary_folder() + "': " + what + ": " + std::strerror(err) +
                   "; expected a folder with room for 8 bytes a sample (set TMPDIR)");
}

// An unlinked temporary file, open for reading and writing.
int open_temporary() {
  const std::string dir = detail::temporary_folder();
  int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
  // Filesystems without O_TMPFILE: a named file, unlinked at once.
  std::string name = dir + "/gmwm-samples-XXXXXX";
  fd = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd < 0) fail_temporary("cannot create a file", errno);
  ::unlink(name.c_str());
  return fd;
}

// Reserves `bytes` in the file, so that a full disk is an error now rather than a SIGBUS
// when a mapped page is written back.
void reserve(int fd, std::size_t bytes) {
  if (bytes == 0) return;
  const int rc = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes));
  if (rc != 0) {
    ::close(fd);
    fail_temporary("cannot reserve " + std::to_string(bytes) + " bytes", rc);
  }
}

}  // namespace

struct Samples::Mapping {
  void* address = nullptr;
  std::size_t bytes = 0;
  Mapping(void* a, std::size_t b) : address(a), bytes(b) { add_range(a, b); }
  ~Mapping() {
    remove_range(address);
    ::munmap(address, bytes);
  }
  Mapping(const Mapping&) = delete;
  Mapping& operator=(const Mapping&) = delete;
};

Samples::Samples(std::vector<double> values)
    : vector_(std::make_shared<const std::vector<double>>(std::move(values))),
      data_(vector_->data()),
      size_(vector_->size()) {}

bool operator==(const Samples& a, const Samples& b) {
  return a.size_ == b.size_ && std::equal(a.begin(), a.end(), b.begin());
}

SampleFileWriter::SampleFileWriter() : fd_(open_temporary()) { buffer_.reserve(kWriteBufferValues); }

SampleFileWriter::~SampleFileWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void SampleFileWriter::append(const double* values, std::size_t count) {
  while (count > 0) {
    const std::size_t take = std::min(count, kWriteBufferValues - buffer_.size());
    buffer_.insert(buffer_.end(), values, values + take);
    values += take;
    count -= take;
    count_ += take;
    if (buffer_.size() == kWriteBufferValues) flush();
  }
}

void SampleFileWriter::flush() {
  const char* p = reinterpret_cast<const char*>(buffer_.data());
  std::size_t left = buffer_.size() * sizeof(double);
  while (left > 0) {
    const ssize_t w = ::write(fd_, p, left);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail_temporary("cannot write " + std::to_string(count_ * sizeof(double)) + " bytes of samples", errno);
    }
    p += w;
    left -= static_cast<std::size_t>(w);
  }
  buffer_.clear();
}

Samples SampleFileWriter::finish() {
  flush();
  Samples s;
  const std::size_t bytes = count_ * sizeof(double);
  if (bytes > 0) {
    void* a = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, fd_, 0);
    if (a == MAP_FAILED) fail_temporary("cannot map " + std::to_string(bytes) + " bytes of samples", errno);
    ::madvise(a, bytes, MADV_SEQUENTIAL);
    s.file_ = std::make_shared<const Samples::Mapping>(a, bytes);
    s.data_ = static_cast<const double*>(a);
    s.size_ = count_;
  }
  ::close(fd_);
  fd_ = open_temporary();
  count_ = 0;
  return s;
}

namespace detail {

std::string temporary_folder() {
  const char* t = std::getenv("TMPDIR");
  return t && *t ? std::string(t) : std::string("/tmp");
}

bool in_sample_file(const double* p, std::size_t count) { return count > 0 && in_ranges(p, count * sizeof(double)); }

void release_file_pages(const double* begin, const double* end) {
  if (end <= begin || !in_ranges(begin, static_cast<std::size_t>(end - begin) * sizeof(double))) return;
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t b = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
  const std::uintptr_t e = reinterpret_cast<std::uintptr_t>(end) / page * page;
  // Shared file mappings keep their contents in the file (dirty pages are written back).
  if (e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_DONTNEED);
}

TemporaryArray::TemporaryArray(std::size_t count) : count_(count) {
  if (count == 0) return;
  const int fd = open_temporary();
  const std::size_t bytes = count * sizeof(double);
  reserve(fd, bytes);
  void* a = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int err = errno;
  ::close(fd);
  if (a == MAP_FAILED) fail_temporary("cannot map " + std::to_string(bytes) + " bytes", err);
  data_ = static_cast<double*>(a);
  add_range(a, bytes);
}

TemporaryArray::~TemporaryArray() {
  if (!data_) return;
  remove_range(data_);
  ::munmap(data_, count_ * sizeof(double));
}

}  // namespace detail

}  // namespace gmwm
