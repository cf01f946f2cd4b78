#pragma once
// The files one run writes, all or none.
//
// Every output is declared before any work (declare()), which refuses at once what could
// lose data or cannot work: a path in a missing folder, a folder, a device, a FIFO or a
// socket (a rename would replace the device by a regular file), a symbolic link (its
// target would not be written, the link would be replaced), a file the run reads (same
// inode, so hard links and other spellings count), two outputs naming the same file, and
// standard output ("-") twice. Results are then staged (stage()): each goes to a new
// unnamed file in its target's folder (O_TMPFILE: nothing of it can be left behind, even
// by SIGKILL or the OOM killer), every write and the fsync checked. commit() gives each a
// hidden name and renames it over its target only once every one of them was written; a
// failure at any point leaves every target as it was and frees the staged files (the
// destructor does the same for a set that was never committed, e.g. on an exception).
// Where the filesystem has no O_TMPFILE the staged files are named ".NAME.gmwm-XXXXXX" and
// removed on failure and on SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT and SIGALRM (when the
// program left those at their default action).
//
//   gmwm::io::OutputSet out;
//   out.add_input("data.csv");
//   out.declare("--json", json_path);          // before any work
//   ... compute ...
//   out.stage(json_path, text);
//   out.commit();
//
// Standard output ("-") is written at commit() (first, so that a write error there, a
// closed pipe included, leaves every file untouched), with the write and the flush checked.

#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace gmwm::io {

/// Where staged bytes go. write() throws InputError naming the output on any failure.
class OutputStream {
 public:
  virtual ~OutputStream() = default;
  virtual void write(std::string_view bytes) = 0;
};

/// gzip-compresses what is written into another stream (RFC 1952, one member). Sizes are
/// 64-bit throughout, so streams past 4 GB are complete. finish() must be called once at
/// the end (it writes the trailer); a GzipOutput destroyed unfinished writes nothing more.
class GzipOutput final : public OutputStream {
 public:
  /// zlib's default level 6 (as the gzip program's) unless given; `name` is used in messages.
  GzipOutput(OutputStream& sink, std::string name, int level = 6);
  ~GzipOutput() override;
  GzipOutput(const GzipOutput&) = delete;
  GzipOutput& operator=(const GzipOutput&) = delete;
  void write(std::string_view bytes) override;
  void finish();

 private:
  struct State;
  void pump(int flush);
  std::unique_ptr<State> state_;
};

/// True when `path` ends in ".gz" (outputs compressed by name, as the gzip program would).
bool gzip_by_name(const std::string& path);

class OutputSet {
 public:
  OutputSet();
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  /// A file the run reads: an output naming the same file is refused (here when it was
  /// declared already, else by declare()). "-" and paths that do not exist are ignored
  /// (the reader reports those).
  void add_input(const std::string& path);

  /// Checks an output path before any work; `option` names it in messages ("--json").
  /// Throws InputError with one line naming the option, the path and what was expected.
  /// Declaring the same option and path again is a no-op.
  void declare(const std::string& option, const std::string& path);

  /// Stages `content` for `path` (declared first; an undeclared path is declared here as
  /// "output"). Throws InputError when the temporary file cannot be written.
  void stage(const std::string& path, std::string_view content);
  /// Stages what `produce` writes, streamed to the temporary file (no copy in memory).
  void stage(const std::string& path, const std::function<void(OutputStream&)>& produce);

  /// Writes standard output, then renames every staged file over its target. On a failure
  /// the targets already replaced are restored and InputError is thrown.
  void commit();

  /// True when nothing is staged.
  bool empty() const;

  /// Stages in named files as on a filesystem without O_TMPFILE (tests of that path).
  void force_named_staging();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gmwm::io
