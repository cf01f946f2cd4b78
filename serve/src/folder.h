#pragma once
// The folder `gmwm serve` offers: its recordings and simulator files listed, and a relative
// path resolved to a file inside it, or refused. The rule (docs/serve.md, "Limits and
// safety"): a path is resolved with every symbolic link followed and taken only when the
// result stays inside the folder's own resolved path; absolute paths, ".." that leaves it,
// links that point out of it, and anything but a regular file are refused.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gmwm::serve::detail {

class Folder {
 public:
  /// Throws InputError when `path` is not a readable folder.
  explicit Folder(const std::string& path);

  /// The folder's name as given on the command line (shown on the page).
  const std::string& name() const { return name_; }
  /// Its resolved path.
  const std::filesystem::path& root() const { return root_; }

  /// The regular file `relative` names inside the folder, resolved; nullopt when refused.
  std::optional<std::filesystem::path> resolve(const std::string& relative) const;

  struct Entry {
    std::string path;  ///< relative to the folder, '/'-separated
    std::uintmax_t size = 0;
  };
  struct Listing {
    std::vector<Entry> recordings;  ///< what io::read_signals reads (by extension)
    std::vector<Entry> configs;     ///< simulator and datasheet files (yaml, sdf, xml)
    bool truncated = false;         ///< more than kMaxListedFiles, or deeper than kMaxListedDepth
  };
  /// The files under the folder (links followed only when they stay inside), sorted.
  Listing list() const;

 private:
  std::string name_;
  std::filesystem::path root_;
};

/// True when `resolved` is `root` or lies under it (both already resolved).
bool is_inside(const std::filesystem::path& root, const std::filesystem::path& resolved);

}  // namespace gmwm::serve::detail
