#pragma once
// Small files read whole beside the main input ("side files"): a Kalibr imu.yaml
// (--kalibr), a Gazebo SDF (--gazebo), the JSON result an export reads. One reader for all
// of them, so that each gets the main input's protections:
// - a folder, a character or block device (/dev/zero, a terminal) or a socket is refused
//   by name before anything is read;
// - a FIFO or pipe is opened without blocking and gets the main input's bounded wait: no
//   writer within kPipeWriterWaitMs is refused ("start the writer first"), a slow one is
//   waited for;
// - at most a named number of bytes is read (the limit is checked as the bytes come, so a
//   FIFO fed from /dev/zero stops there too);
// and every refusal is one line "<path>: <what is wrong>, expected <what>".
//
//   const std::string text = gmwm::io::read_side_file(path, "a Kalibr imu.yaml", gmwm::io::kMaxKalibrYamlBytes);

#include <cstddef>
#include <string>
#include <utility>

namespace gmwm::io {

/// The longest a FIFO or pipe may stay without a writer before the run stops, in ms: the
/// main input's and the side files' (docs/cli.md "Hostile input"). Long enough for a writer
/// started just after gmwm (`mkfifo p; gmwm wv p & producer > p`), short enough that a
/// forgotten writer costs seconds, not a hung run.
inline constexpr int kPipeWriterWaitMs = 5000;

/// The most a side file may hold: 64 MiB. A gmwm fit or select --json result is 20 to 60 kB
/// a column (about a thousand columns fit), a Gazebo world with its models a few MB; parsed
/// JSON costs at most about 10 bytes of memory per byte of text, so the largest accepted
/// file stays well within a machine's memory, while /dev/zero behind a pipe is refused
/// after 64 MiB instead of exhausting it.
inline constexpr std::size_t kMaxSideFileBytes = std::size_t{64} << 20;

/// The most a Kalibr imu.yaml may hold: 1 MiB. A real one is under 1 kB (an IMU chain of
/// several IMUs a few kB), while yaml-cpp spends several hundred bytes of memory per node,
/// so a 64 MiB flow sequence would cost gigabytes before the keys are even looked at.
inline constexpr std::size_t kMaxKalibrYamlBytes = std::size_t{1} << 20;

/// An open side file. `expected` says what it should be in messages ("a Kalibr imu.yaml").
/// Throws gmwm::InputError for a missing or unreadable file, a folder, a device, a socket,
/// or a FIFO that no writer opens within kPipeWriterWaitMs.
class SideFile {
 public:
  SideFile(std::string path, std::string expected);
  ~SideFile();
  SideFile(const SideFile&) = delete;
  SideFile& operator=(const SideFile&) = delete;

  /// True for a FIFO or a pipe (/dev/stdin on a pipe): it can be read only once.
  bool is_pipe() const { return pipe_; }

  /// Up to `n` bytes from the start, without consuming them: read() still returns them, and
  /// a pipe's content stays in the pipe (peeked with tee(2)) for any other reader of the
  /// same path. Fewer than `n` only at the end of the data.
  std::string peek(std::size_t n);

  /// What the file should be from now on, in messages (once the caller knows more, e.g.
  /// that it is JSON).
  void expect(std::string expected) { expected_ = std::move(expected); }

  /// The whole content; InputError "<path>: holds more than N bytes, expected <expected> of
  /// at most N bytes" beyond `limit`.
  std::string read(std::size_t limit = kMaxSideFileBytes);

 private:
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_, expected_;
  int fd_ = -1;
  bool pipe_ = false;
};

/// SideFile(path, expected).read(limit).
std::string read_side_file(const std::string& path, const std::string& expected, std::size_t limit = kMaxSideFileBytes);

namespace detail {

/// Opens a FIFO or pipe for reading without waiting forever for its writer: with nothing
/// to read after kPipeWriterWaitMs, a missing writer (end of file) is refused with
/// "<path>: is a FIFO that no writer opened within 5 s, expected <expected> (start the
/// writer first)" while a silent one is waited for. Returns a blocking descriptor; the byte
/// read while probing, if any, is stored in `early` (else -1) for the caller to keep.
int open_pipe_bounded(const std::string& path, const std::string& expected, int& early);

}  // namespace detail

}  // namespace gmwm::io
