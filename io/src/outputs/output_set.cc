#include "gmwm/io/output_set.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "gmwm/engine/error.h"

namespace gmwm::io {

namespace fs = std::filesystem;

namespace {

// Bytes buffered before a write(2) to a staged file: large enough that system calls cost
// nothing next to formatting, small enough to be irrelevant for memory.
constexpr std::size_t kFileBuffer = 1 << 20;
// Largest single write(2) (Linux caps one call at 0x7ffff000 bytes anyway).
constexpr std::size_t kMaxWriteCall = 1 << 30;
// Bytes handed to deflate() per call, and the size of its output buffer: zlib counts in
// 32-bit uInt, so a stream of any size is fed in chunks well below 2^32.
constexpr std::size_t kDeflateChunk = 1 << 20;

std::string errno_text(int err) { return std::strerror(err); }

// --- Temporary files removed on SIGINT / SIGTERM / SIGHUP -------------------------------
// A run interrupted while it stages its outputs must not leave ".name.gmwm-XXXXXX" files
// behind. The handler may only call async-signal-safe functions, hence fixed slots with
// C strings and unlink(2).
constexpr int kCleanupSlots = 256;
constexpr std::size_t kCleanupPath = PATH_MAX;

struct CleanupSlot {
  std::atomic<bool> used{false};
  char path[kCleanupPath];
};
CleanupSlot g_cleanup[kCleanupSlots];

extern "C" void remove_staged_and_reraise(int sig) {
  for (auto& s : g_cleanup)
    if (s.used.load()) ::unlink(s.path);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_cleanup_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction current {};
      if (::sigaction(sig, nullptr, &current) != 0) continue;
      // Only where nobody else handles the signal (an embedding program keeps its own).
      if (current.sa_handler != SIG_DFL) continue;
      struct sigaction ours {};
      ours.sa_handler = remove_staged_and_reraise;
      sigemptyset(&ours.sa_mask);
      ::sigaction(sig, &ours, nullptr);
    }
  });
}

/// A slot for `path`, or -1 when none is free or the path is too long (then an
/// interruption may leave the temporary file behind; nothing else changes).
int register_cleanup(const std::string& path) {
  if (path.size() + 1 > kCleanupPath) return -1;
  static std::mutex claim;
  std::lock_guard lock(claim);
  for (int i = 0; i < kCleanupSlots; ++i) {
    auto& s = g_cleanup[i];
    if (s.used.load()) continue;
    std::memcpy(s.path, path.c_str(), path.size() + 1);
    s.used.store(true);  // published after the path is complete
    return i;
  }
  return -1;
}

void release_cleanup(int slot) {
  if (slot >= 0) g_cleanup[slot].used.store(false);
}

// --- What a path is ------------------------------------------------------------------

struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  bool operator==(const FileId&) const = default;
};

std::optional<FileId> file_id(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

/// Why `path` cannot be replaced by a rename, or empty when it is missing or a regular file.
std::string unusable_target(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {};
  if (S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const fs::path to = fs::read_symlink(path, ec);
    return "is a symbolic link" + (ec ? std::string() : " to '" + to.string() + "'") +
           " (writing would replace the link, not its target); expected a regular file or a new path";
  }
  if (S_ISREG(st.st_mode)) return {};
  const char* what = S_ISDIR(st.st_mode)    ? "a folder"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISFIFO(st.st_mode) ? "a FIFO"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a regular file";
  return std::string("is ") + what + ", expected a regular file or a new path ('-' for standard output)";
}

/// The path with its folder resolved (symlinks, "..", "."), so that two spellings of a file
/// that does not exist yet compare equal.
std::string canonical_target(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  if (ec) return path;
  const fs::path dir = fs::weakly_canonical(p.parent_path(), ec);
  if (ec) return p.lexically_normal().string();
  return (dir / p.filename()).lexically_normal().string();
}

mode_t new_file_mode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

// --- Streams -------------------------------------------------------------------------

/// Buffered writes to a file descriptor, every call checked.
class FileOutput final : public OutputStream {
 public:
  FileOutput(int fd, std::string name) : fd_(fd), name_(std::move(name)) { buf_.reserve(kFileBuffer); }
  void write(std::string_view bytes) override {
    if (buf_.size() + bytes.size() > kFileBuffer) {
      flush();
      if (bytes.size() >= kFileBuffer) {
        write_all(bytes);
        return;
      }
    }
    buf_.append(bytes);
  }
  void flush() {
    write_all(buf_);
    buf_.clear();
  }

 private:
  void write_all(std::string_view bytes) {
    const char* p = bytes.data();
    std::size_t left = bytes.size();
    while (left > 0) {
      const ssize_t w = ::write(fd_, p, std::min(left, kMaxWriteCall));
      if (w < 0) {
        if (errno == EINTR) continue;
        throw InputError("cannot write '" + name_ + "': " + errno_text(errno));
      }
      p += w;
      left -= static_cast<std::size_t>(w);
    }
  }
  int fd_;
  std::string name_;
  std::string buf_;
};

class StringOutput final : public OutputStream {
 public:
  explicit StringOutput(std::string& out) : out_(out) {}
  void write(std::string_view bytes) override { out_.append(bytes); }

 private:
  std::string& out_;
};

}  // namespace

// --- GzipOutput ------------------------------------------------------------------------

struct GzipOutput::State {
  OutputStream& sink;
  std::string name;
  z_stream zs{};
  std::vector<unsigned char> out;
  bool open = false;
  bool finished = false;
  State(OutputStream& s, std::string n) : sink(s), name(std::move(n)), out(kDeflateChunk) {}
};

GzipOutput::GzipOutput(OutputStream& sink, std::string name, int level)
    : state_(std::make_unique<State>(sink, std::move(name))) {
  // 15 + 16: the largest window, with a gzip (not zlib) wrapper.
  if (deflateInit2(&state_->zs, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw InputError("cannot write '" + state_->name + "': zlib initialisation failed");
  state_->open = true;
}

GzipOutput::~GzipOutput() {
  if (state_ && state_->open) deflateEnd(&state_->zs);
}

void GzipOutput::pump(int flush) {
  z_stream& zs = state_->zs;
  for (;;) {
    zs.next_out = state_->out.data();
    zs.avail_out = static_cast<uInt>(state_->out.size());
    const int rc = deflate(&zs, flush);
    if (rc == Z_STREAM_ERROR) throw InputError("cannot write '" + state_->name + "': gzip compression failed");
    const std::size_t produced = state_->out.size() - zs.avail_out;
    if (produced) state_->sink.write({reinterpret_cast<const char*>(state_->out.data()), produced});
    if (flush == Z_FINISH) {
      if (rc == Z_STREAM_END) return;
    } else if (zs.avail_in == 0 && zs.avail_out != 0) {
      return;
    }
  }
}

void GzipOutput::write(std::string_view bytes) {
  if (state_->finished) throw InputError("cannot write '" + state_->name + "': gzip stream already finished");
  while (!bytes.empty()) {
    const std::size_t n = std::min(bytes.size(), kDeflateChunk);
    state_->zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    state_->zs.avail_in = static_cast<uInt>(n);
    pump(Z_NO_FLUSH);
    bytes.remove_prefix(n);
  }
}

void GzipOutput::finish() {
  if (state_->finished) return;
  state_->zs.next_in = nullptr;
  state_->zs.avail_in = 0;
  pump(Z_FINISH);
  state_->finished = true;
}

bool gzip_by_name(const std::string& path) {
  return path.size() >= 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
}

// --- OutputSet -------------------------------------------------------------------------

struct OutputSet::Impl {
  struct Input {
    std::string path;
    FileId id;
  };
  struct Declared {
    std::string option;
    std::string path;
    std::string canonical;
  };
  struct Staged {
    std::string path;       // the target
    std::string tmp;        // the temporary file beside it ("" for standard output)
    std::string content;    // standard output's bytes
    int slot = -1;          // cleanup registration of tmp
  };

  std::vector<Input> inputs;
  std::vector<Declared> declared;
  std::vector<Staged> staged;

  const Declared* find(const std::string& path) const {
    for (const auto& d : declared)
      if (d.path == path) return &d;
    return nullptr;
  }

  void discard() {
    for (auto& s : staged) {
      if (!s.tmp.empty()) ::unlink(s.tmp.c_str());
      release_cleanup(s.slot);
    }
    staged.clear();
  }
};

OutputSet::OutputSet() : impl_(std::make_unique<Impl>()) { install_cleanup_handlers(); }

OutputSet::~OutputSet() { impl_->discard(); }

bool OutputSet::empty() const { return impl_->staged.empty(); }

void OutputSet::add_input(const std::string& path) {
  if (path.empty() || path == "-") return;
  const auto id = file_id(path);
  if (!id) return;
  for (const auto& d : impl_->declared)
    if (d.path != "-" && file_id(d.path) == id)
      throw InputError(d.option + " '" + d.path + "': is the input '" + path +
                       "' (the same file); expected an output path that is not read by this run");
  impl_->inputs.push_back({path, *id});
}

void OutputSet::declare(const std::string& option, const std::string& path) {
  if (path.empty()) throw InputError(option + ": expected a file path ('-' for standard output)");
  for (const auto& d : impl_->declared)
    if (d.option == option && d.path == path) return;
  const std::string what = option + " '" + path + "'";
  if (path == "-") {
    for (const auto& d : impl_->declared)
      if (d.path == "-")
        throw InputError(what + ": " + d.option + " already writes to standard output; expected at most one "
                         "output on '-'");
    impl_->declared.push_back({option, path, path});
    return;
  }
  if (const std::string why = unusable_target(path); !why.empty()) throw InputError(what + ": " + why);
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(what + ": folder '" + dir.string() + "' does not exist, expected an existing folder");
  if (p.filename().empty() || p.filename() == "." || p.filename() == "..")
    throw InputError(what + ": names a folder, expected a file path");
  const auto id = file_id(path);
  for (const auto& in : impl_->inputs)
    if (id && *id == in.id)
      throw InputError(what + ": is the input '" + in.path +
                       "' (the same file); expected an output path that is not read by this run");
  const std::string canonical = canonical_target(path);
  for (const auto& d : impl_->declared) {
    if (d.path == "-") continue;
    const auto other = file_id(d.path);
    if (d.canonical == canonical || (id && other && *id == *other))
      throw InputError(what + ": names the same file as " + d.option + " '" + d.path +
                       "'; expected a different path for each output");
  }
  impl_->declared.push_back({option, path, canonical});
}

void OutputSet::stage(const std::string& path, std::string_view content) {
  stage(path, [content](OutputStream& out) { out.write(content); });
}

void OutputSet::stage(const std::string& path, const std::function<void(OutputStream&)>& produce) {
  if (!impl_->find(path)) declare("output", path);
  for (const auto& s : impl_->staged)
    if (s.path == path) throw InputError("output '" + path + "': written twice in one run");
  Impl::Staged s;
  s.path = path;
  if (path == "-") {
    StringOutput out(s.content);
    produce(out);
    impl_->staged.push_back(std::move(s));
    return;
  }
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string tmpl = (dir / ("." + target.filename().string() + ".gmwm-XXXXXX")).string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) throw InputError("cannot write '" + path + "': " + errno_text(errno));
  s.tmp = tmpl;
  s.slot = register_cleanup(s.tmp);
  // Until it is closed, any failure removes the temporary file and the entry.
  auto abandon = [&] {
    ::close(fd);
    ::unlink(s.tmp.c_str());
    release_cleanup(s.slot);
  };
  try {
    // Keep an existing file's permissions; a new file gets the usual 0666 & ~umask.
    struct stat st {};
    const mode_t mode = ::stat(path.c_str(), &st) == 0 ? (st.st_mode & 07777) : new_file_mode();
    if (::fchmod(fd, mode) != 0) throw InputError("cannot write '" + path + "': " + errno_text(errno));
    FileOutput out(fd, path);
    produce(out);
    out.flush();
    // A delayed write error (NFS, a full disk on some filesystems) shows at fsync or close.
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS)
      throw InputError("cannot write '" + path + "': " + errno_text(errno));
  } catch (...) {
    abandon();
    throw;
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(s.tmp.c_str());
    release_cleanup(s.slot);
    throw InputError("cannot write '" + path + "': " + errno_text(err));
  }
  impl_->staged.push_back(std::move(s));
}

void OutputSet::commit() {
  auto& staged = impl_->staged;
  // The targets may have changed since declare(): check them all before touching any.
  for (const auto& s : staged)
    if (!s.tmp.empty())
      if (const std::string why = unusable_target(s.path); !why.empty())
        throw InputError("output '" + s.path + "': " + why);
  // Standard output first: a write error there (a full disk, a closed pipe) leaves the files.
  for (const auto& s : staged) {
    if (!s.tmp.empty()) continue;
    std::fflush(stdout);
    if (!s.content.empty() && std::fwrite(s.content.data(), 1, s.content.size(), stdout) != s.content.size()) {
      const int err = errno;
      std::clearerr(stdout);
      throw InputError("cannot write to standard output: " + errno_text(err));
    }
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int err = errno;
      std::clearerr(stdout);
      throw InputError("cannot write to standard output: " + errno_text(err));
    }
  }
  // Rename each staged file over its target, keeping a hard link to the old target until
  // all succeeded, so that a late failure can put every earlier target back.
  struct Done {
    std::string target;
    bool existed = false;
    std::string backup;  // the old target's hard link ("" when it did not exist or could not be linked)
    int slot = -1;
  };
  std::vector<Done> done;
  auto roll_back = [&] {
    for (auto it = done.rbegin(); it != done.rend(); ++it) {
      if (!it->backup.empty())
        ::rename(it->backup.c_str(), it->target.c_str());
      else if (!it->existed)
        ::unlink(it->target.c_str());
      release_cleanup(it->slot);
    }
  };
  for (auto& s : staged) {
    if (s.tmp.empty()) continue;
    Done d;
    d.target = s.path;
    struct stat st {};
    if (::lstat(s.path.c_str(), &st) == 0) {
      d.existed = true;
      const std::string backup = s.tmp + ".old";
      if (::link(s.path.c_str(), backup.c_str()) == 0) {
        d.backup = backup;
        d.slot = register_cleanup(backup);
      }
    }
    if (::rename(s.tmp.c_str(), s.path.c_str()) != 0) {
      const int err = errno;
      if (!d.backup.empty()) {
        ::unlink(d.backup.c_str());
        release_cleanup(d.slot);
      }
      roll_back();
      impl_->discard();
      throw InputError("cannot write '" + s.path + "': " + errno_text(err));
    }
    release_cleanup(s.slot);
    s.slot = -1;
    s.tmp.clear();  // renamed: nothing left to discard
    // A backup slot is not "staged": keep it registered until the end.
    done.push_back(std::move(d));
  }
  for (auto& d : done) {
    if (!d.backup.empty()) ::unlink(d.backup.c_str());
    release_cleanup(d.slot);
  }
  staged.clear();
}

}  // namespace gmwm::io
