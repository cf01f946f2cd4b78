#include "gmwm/io/output_set.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <optional>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <sys/random.h>
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

// --- Staged files that no kill leaves behind ------------------------------------------
// A staged file is normally invisible: opened with O_TMPFILE in its target's folder (an
// inode with no name, freed by the kernel however the process ends, SIGKILL and the OOM
// killer included) and given a name only at commit(), just before it is renamed over its
// target. Where the filesystem refuses O_TMPFILE it is a named ".NAME.gmwm-XXXXXX" file,
// removed on the signals that can be caught: the handler may only call async-signal-safe
// functions, hence fixed slots with C strings and unlink(2). The slots also hold the names
// that exist only during commit() (an invisible file's link, a replaced target's backup).
constexpr int kCleanupSlots = 256;
constexpr std::size_t kCleanupPath = PATH_MAX;
// The signals whose default action ends the process and that a handler can catch: the
// terminal's (SIGINT, SIGQUIT, SIGHUP), kill's default (SIGTERM), a closed pipe (SIGPIPE,
// when the program has not ignored it) and alarm(2)/timeout(1) (SIGALRM).
constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT, SIGALRM};
// Attempts at a fresh random name for a staged file before giving up (each collision is
// a file of that exact name already there: one in 62^6 per attempt).
constexpr int kNameAttempts = 100;

struct CleanupSlot {
  std::atomic<bool> used{false};
  char path[kCleanupPath];
};
CleanupSlot g_cleanup[kCleanupSlots];

extern "C" void remove_staged_and_reraise(int sig) {
  const int saved = errno;
  for (auto& s : g_cleanup)
    if (s.used.load()) ::unlink(s.path);
  errno = saved;
  // Back to the default action, delivered once this handler returns (the signal is
  // blocked while it runs): the process ends as it would have without the handler.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);
}

void install_cleanup_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : kCleanupSignals) {
      struct sigaction current {};
      if (::sigaction(sig, nullptr, &current) != 0) continue;
      // Only where nobody else handles the signal (an embedding program keeps its own, and
      // an ignored SIGPIPE stays ignored: the write then fails with EPIPE).
      if ((current.sa_flags & SA_SIGINFO) || current.sa_handler != SIG_DFL) continue;
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

/// ".NAME.gmwm-" followed by six random letters or digits, in `dir`.
std::string random_staged_name(const fs::path& dir, const std::string& filename) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  unsigned char r[6] = {};
  if (::getrandom(r, sizeof r, GRND_NONBLOCK) != static_cast<ssize_t>(sizeof r)) {
    static std::atomic<unsigned> counter{0};
    const unsigned long long x = static_cast<unsigned long long>(::getpid()) * 2654435761ULL + ++counter +
                                 static_cast<unsigned long long>(::time(nullptr));
    for (std::size_t i = 0; i < sizeof r; ++i) r[i] = static_cast<unsigned char>(x >> (8 * i));
  }
  std::string name = "." + filename + ".gmwm-";
  for (unsigned char c : r) name += kAlphabet[c % (sizeof kAlphabet - 1)];
  return (dir / name).string();
}

/// An unnamed file in `dir` (O_TMPFILE), or -1 with errno set. errno EOPNOTSUPP, EISDIR
/// or EINVAL: the filesystem or the kernel does not offer O_TMPFILE.
int open_invisible(const fs::path& dir) { return ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600); }

bool no_invisible_files(int err) { return err == EOPNOTSUPP || err == EISDIR || err == EINVAL; }

/// Gives the unnamed file `fd` the name `name` (which must not exist): through /proc (any
/// user), else linkat(AT_EMPTY_PATH) (where the kernel permits it). 0 or an errno.
int link_invisible(int fd, const std::string& name) {
  char proc[64];
  std::snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
  if (::linkat(AT_FDCWD, proc, AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) return 0;
  const int first = errno;
  if (first == EEXIST) return first;
  if (::linkat(fd, "", AT_FDCWD, name.c_str(), AT_EMPTY_PATH) == 0) return 0;
  // Without /proc (ENOENT there) the second attempt's reason is the one that matters.
  return first == ENOENT ? errno : first;
}

/// Copies the whole content of `from` (from its start) to `to`; 0 or an errno.
int copy_file(int from, int to) {
  std::vector<char> buf(kFileBuffer);
  off_t at = 0;
  for (;;) {
    const ssize_t n = ::pread(from, buf.data(), buf.size(), at);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) break;
    for (ssize_t done = 0; done < n;) {
      const ssize_t w = ::write(to, buf.data() + done, static_cast<std::size_t>(n - done));
      if (w < 0) {
        if (errno == EINTR) continue;
        return errno;
      }
      done += w;
    }
    at += n;
  }
  return ::fsync(to) != 0 && errno != EINVAL && errno != EROFS ? errno : 0;
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

bool gzip_by_name(const std::string& path) { return path.size() >= 3 && path.compare(path.size() - 3, 3, ".gz") == 0; }

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
    std::string path;     // the target
    int fd = -1;          // the unnamed (O_TMPFILE) file, until commit() names it
    std::string tmp;      // the named temporary file beside the target ("" while unnamed, and for standard output)
    std::string content;  // standard output's bytes
    int slot = -1;        // cleanup registration of tmp
    bool to_stdout() const { return path == "-"; }
  };

  std::vector<Input> inputs;
  std::vector<Declared> declared;
  std::vector<Staged> staged;
  bool named_staging = false;  // force_named_staging()

  const Declared* find(const std::string& path) const {
    for (const auto& d : declared)
      if (d.path == path) return &d;
    return nullptr;
  }

  void discard() {
    for (auto& s : staged) {
      if (s.fd >= 0) ::close(s.fd);  // an unnamed file: freed with its last descriptor
      s.fd = -1;
      if (!s.tmp.empty()) ::unlink(s.tmp.c_str());
      release_cleanup(s.slot);
    }
    staged.clear();
  }
};

OutputSet::OutputSet() : impl_(std::make_unique<Impl>()) { install_cleanup_handlers(); }

OutputSet::~OutputSet() { impl_->discard(); }

void OutputSet::force_named_staging() { impl_->named_staging = true; }

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
        throw InputError(what + ": " + d.option +
                         " already writes to standard output; expected at most one "
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
  if (s.to_stdout()) {
    StringOutput out(s.content);
    produce(out);
    impl_->staged.push_back(std::move(s));
    return;
  }
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  int fd = impl_->named_staging ? -1 : open_invisible(dir);
  if (fd < 0 && !impl_->named_staging && !no_invisible_files(errno))
    throw InputError("cannot write '" + path + "': " + errno_text(errno));
  if (fd < 0) {
    // No O_TMPFILE here: a named file, removed on failure and on the catchable signals.
    std::string tmpl = (dir / ("." + target.filename().string() + ".gmwm-XXXXXX")).string();
    fd = ::mkostemp(tmpl.data(), O_CLOEXEC);
    if (fd < 0) throw InputError("cannot write '" + path + "': " + errno_text(errno));
    s.tmp = tmpl;
    s.slot = register_cleanup(s.tmp);
  }
  // Until it is staged, any failure closes (and so frees, or removes) the file.
  auto abandon = [&] {
    ::close(fd);
    if (!s.tmp.empty()) ::unlink(s.tmp.c_str());
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
  if (s.tmp.empty()) {
    s.fd = fd;  // unnamed: kept open until commit() links it
  } else if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(s.tmp.c_str());
    release_cleanup(s.slot);
    throw InputError("cannot write '" + path + "': " + errno_text(err));
  }
  impl_->staged.push_back(std::move(s));
}

namespace {

/// Gives a staged unnamed file a fresh hidden name beside its target (registered for
/// removal on a signal), or copies it to a named file where it cannot be linked. 0 or an errno.
int name_staged(int& fd, const std::string& target, std::string& tmp, int& slot) {
  const fs::path t(target);
  const fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
  int err = EEXIST;
  for (int attempt = 0; attempt < kNameAttempts && err == EEXIST; ++attempt) {
    const std::string name = random_staged_name(dir, t.filename().string());
    err = link_invisible(fd, name);
    if (err == 0) {
      tmp = name;
      slot = register_cleanup(name);
    }
  }
  if (err != 0 && err != EEXIST) {
    // Not linkable here (no /proc and no permission for AT_EMPTY_PATH): a named copy.
    std::string tmpl = (dir / ("." + t.filename().string() + ".gmwm-XXXXXX")).string();
    const int named = ::mkostemp(tmpl.data(), O_CLOEXEC);
    if (named < 0) return errno;
    slot = register_cleanup(tmpl);
    struct stat st {};
    err = ::fstat(fd, &st) != 0 ? errno : ::fchmod(named, st.st_mode & 07777) != 0 ? errno : copy_file(fd, named);
    if (::close(named) != 0 && err == 0) err = errno;
    if (err != 0) {
      ::unlink(tmpl.c_str());
      release_cleanup(slot);
      slot = -1;
      return err;
    }
    tmp = tmpl;
  }
  if (err != 0) return err;
  ::close(fd);
  fd = -1;
  return 0;
}

}  // namespace

void OutputSet::commit() {
  auto& staged = impl_->staged;
  // The targets may have changed since declare(): check them all before touching any.
  for (const auto& s : staged)
    if (!s.to_stdout())
      if (const std::string why = unusable_target(s.path); !why.empty())
        throw InputError("output '" + s.path + "': " + why);
  // Standard output first: a write error there (a full disk, a closed pipe) leaves the files.
  for (const auto& s : staged) {
    if (!s.to_stdout()) continue;
    const auto* d = impl_->find("-");
    const std::string what = (d ? d->option : std::string("output")) + " -: cannot write to standard output: ";
    auto failed = [&](int err) {
      std::clearerr(stdout);
      return InputError(what + errno_text(err) + (err == EPIPE ? " (its reader closed it)" : "") +
                        "; no output file was written");
    };
    std::fflush(stdout);
    if (!s.content.empty() && std::fwrite(s.content.data(), 1, s.content.size(), stdout) != s.content.size())
      throw failed(errno);
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) throw failed(errno);
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
    if (s.to_stdout()) continue;
    // An unnamed file gets its name now, right before the rename: the only moment a kill
    // that cannot be caught (SIGKILL) could leave it behind.
    if (s.fd >= 0)
      if (const int err = name_staged(s.fd, s.path, s.tmp, s.slot); err != 0) {
        roll_back();
        impl_->discard();
        throw InputError("cannot write '" + s.path + "': " + errno_text(err));
      }
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
