#pragma once
// The folder `gmwm serve` offers: its recordings and simulator files listed, and a relative
// path resolved to a file inside it, or refused. The rule (docs/serve.md, "Limits and
// safety"), one for the listing and for every read: a file is offered when its path and the
// path it resolves to (every symbolic link followed) both lie inside the folder's own
// resolved path, have no hidden part (a name starting with '.': .git, .env, .ssh), and end
// as the kind asked for does (a recording: what io::read_signals reads; a config: yaml, yml,
// sdf, xml); absolute paths, ".." that leaves it, links that point out of it, and anything
// but a regular file are refused. Nothing else under the folder is ever opened.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gmwm::serve::detail {

/// What a file is offered as.
enum class FileKind { kRecording, kConfig };

class Folder {
 public:
  /// Throws InputError when `path` is not a readable folder. The listing walks at most
  /// `max_walked` entries.
  Folder(const std::string& path, std::size_t max_walked);

  /// The folder's own name (its last part, shown on the page: never the machine's path).
  const std::string& name() const { return name_; }
  /// Its resolved path.
  const std::filesystem::path& root() const { return root_; }

  /// The regular file `relative` names inside the folder, resolved, when it is offered as
  /// `kind`; nullopt when refused.
  std::optional<std::filesystem::path> resolve(const std::string& relative, FileKind kind) const;

  struct Entry {
    std::string path;  ///< relative to the folder, '/'-separated
    std::uintmax_t size = 0;
  };
  struct Listing {
    std::vector<Entry> recordings;  ///< what io::read_signals reads (by extension)
    std::vector<Entry> configs;     ///< simulator and datasheet files (yaml, sdf, xml)
    bool truncated = false;         ///< more than kMaxListedFiles, deeper than kMaxListedDepth, or max_walked walked
  };
  /// The files under the folder (links followed only when they stay inside), sorted.
  Listing list() const;

 private:
  std::string name_;
  std::filesystem::path root_;
  std::size_t max_walked_;
};

/// True when `resolved` is `root` or lies under it (both already resolved).
bool is_inside(const std::filesystem::path& root, const std::filesystem::path& resolved);

/// The kind a file of this name is offered as (by its ending; nullopt: not offered), when
/// no part of the relative path is hidden.
std::optional<FileKind> offered_kind(const std::filesystem::path& relative);

}  // namespace gmwm::serve::detail
