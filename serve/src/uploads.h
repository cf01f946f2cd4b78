#pragma once
// The files pages upload (docs/serve.md, "Limits and safety"): streamed to a folder of the
// app's own under the temporary folder, each under a random id (its name kept only to name
// the file, whose ending tells the reader its format), counted as its bytes arrive against
// the upload limit and against the bytes all uploads may hold at once (the oldest finished
// uploads removed to make room; what is still arriving is never removed). An upload that
// does not finish (refused, its client gone before its last byte, the disk full) leaves
// nothing behind. The folder is removed with the app.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "request.h"

namespace gmwm::serve::detail {

/// The longest name an upload keeps (bytes, the ending kept): with its id and a dash the
/// file's name stays under the 255 bytes a file name may have (NAME_MAX).
inline constexpr std::size_t kMaxUploadNameBytes = 200;

class Uploads {
 public:
  /// `root`: where the folder is made (empty: the system's temporary folder).
  Uploads(std::string root, std::int64_t max_bytes, std::int64_t max_total_bytes);
  ~Uploads();
  Uploads(const Uploads&) = delete;
  Uploads& operator=(const Uploads&) = delete;

  struct Upload;  ///< one arriving

  /// Starts an upload named `name` (a file name: only its base name is kept) that declares
  /// `declared_bytes` (-1: unknown, chunked). HttpError 400 for no name, 413 beyond the
  /// limits, 500 when its file cannot be made.
  std::shared_ptr<Upload> begin(const std::string& name, std::int64_t declared_bytes);
  /// The next bytes; false once the upload is refused (beyond a limit, or not written): its
  /// file is removed then, and the rest of the body must not be read.
  bool append(Upload& u, const char* data, std::size_t size);
  /// Ends the upload: `complete` when its body arrived whole. Its answer {"upload", "name",
  /// "size"}, or HttpError (413 beyond a limit, 400 cut short, 500 not written).
  Json finish(const std::shared_ptr<Upload>& u, bool complete);

  struct Stored {
    std::string name;
    std::filesystem::path path;
    std::int64_t size = 0;
  };
  /// A finished upload; nullopt when unknown or removed to make room.
  std::optional<Stored> find(const std::string& id) const;
  /// The folder, empty until the first upload.
  std::filesystem::path folder() const;
  /// Bytes held: finished uploads and what is arriving.
  std::int64_t held_bytes() const;
  std::size_t count() const;
  std::int64_t max_total_bytes() const { return max_total_; }

 private:
  std::filesystem::path folder_locked();
  /// Makes room for `bytes` more by removing the oldest finished uploads; false when what
  /// is arriving alone would pass the total.
  bool reserve_locked(std::int64_t bytes);

  std::string root_;
  std::int64_t max_bytes_, max_total_;
  mutable std::mutex mutex_;
  std::filesystem::path folder_;
  struct Kept {
    Stored stored;
    std::chrono::steady_clock::time_point finished;
  };
  std::map<std::string, Kept> kept_;
  std::int64_t kept_bytes_ = 0, arriving_bytes_ = 0;
};

}  // namespace gmwm::serve::detail
