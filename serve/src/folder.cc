#include "folder.h"

#include <algorithm>
#include <deque>
#include <system_error>

#include "gmwm/engine/error.h"
#include "gmwm/serve/app.h"

namespace gmwm::serve::detail {

namespace fs = std::filesystem;

namespace {

// The endings of what io::read_signals reads (delimited text, gzip of it, PX4 ULog, ROS 1
// bags, rosbag2's sqlite3 and MCAP), and of the baselines gap and the overlay read.
constexpr const char* kRecordingEndings[] = {".csv", ".txt", ".tsv", ".dat", ".gz", ".ulg", ".bag", ".db3", ".mcap"};
constexpr const char* kConfigEndings[] = {".yaml", ".yml", ".sdf", ".xml"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

template <std::size_t N>
bool ends_with_any(const std::string& name, const char* const (&endings)[N]) {
  const std::string l = lower(name);
  for (const char* e : endings)
    if (l.ends_with(e)) return true;
  return false;
}

}  // namespace

bool is_inside(const fs::path& root, const fs::path& resolved) {
  auto r = root.begin();
  auto p = resolved.begin();
  for (; r != root.end(); ++r, ++p) {
    if (r->empty()) continue;  // a trailing separator of the root
    if (p == resolved.end() || *p != *r) return false;
  }
  return true;
}

std::optional<FileKind> offered_kind(const fs::path& relative) {
  if (relative.empty() || relative.is_absolute() || relative.has_root_name()) return std::nullopt;
  for (const fs::path& part : relative) {
    const std::string s = part.string();
    if (s.empty() || s.front() == '.') return std::nullopt;  // hidden, ".", ".."
  }
  const std::string name = relative.filename().string();
  if (ends_with_any(name, kRecordingEndings)) return FileKind::kRecording;
  if (ends_with_any(name, kConfigEndings)) return FileKind::kConfig;
  return std::nullopt;
}

Folder::Folder(const std::string& path, std::size_t max_walked) : max_walked_(max_walked) {
  std::error_code ec;
  root_ = fs::canonical(path, ec);
  if (ec || !fs::is_directory(root_, ec))
    throw InputError("FOLDER '" + path + "': " + (ec ? ec.message() : std::string("not a folder")) +
                     ", expected the folder of recordings to offer");
  name_ = root_.filename().string();
  if (name_.empty()) name_ = "/";
}

std::optional<fs::path> Folder::resolve(const std::string& relative, FileKind kind) const {
  if (relative.empty() || relative.find('\0') != std::string::npos) return std::nullopt;
  const fs::path rel(relative);
  if (offered_kind(rel) != kind) return std::nullopt;
  std::error_code ec;
  const fs::path resolved = fs::canonical(root_ / rel, ec);  // every link followed
  if (ec || !is_inside(root_, resolved) || resolved == root_) return std::nullopt;
  // A link is offered only when what it points to is (a data.csv pointing at .env is not).
  if (offered_kind(resolved.lexically_relative(root_)) != kind) return std::nullopt;
  if (!fs::is_regular_file(resolved, ec) || ec) return std::nullopt;
  return resolved;
}

Folder::Listing Folder::list() const {
  // Breadth first: a folder's own files before its subfolders' (a subfolder of a million
  // files that are not recordings, walked first, would hide the recordings beside it once
  // the walk's bound is reached).
  Listing out;
  std::deque<std::pair<fs::path, int>> folders = {{root_, 0}};
  std::size_t walked = 0;
  while (!folders.empty() && !out.truncated) {
    const auto [dir, depth] = folders.front();
    folders.pop_front();
    std::error_code ec;
    fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
      if (++walked > max_walked_) {
        out.truncated = true;
        break;
      }
      const fs::directory_entry& e = *it;
      const std::string name = e.path().filename().string();
      if (!name.empty() && name.front() == '.') continue;  // hidden: neither listed nor walked
      std::error_code e2;
      // Links to folders are not followed (a link would make a cycle, or leave the folder).
      if (e.is_directory(e2) && !e.is_symlink(e2)) {
        if (depth + 1 < kMaxListedDepth)
          folders.emplace_back(e.path(), depth + 1);
        else
          out.truncated = true;
        continue;
      }
      const fs::path relative = e.path().lexically_relative(root_);
      const auto kind = offered_kind(relative);
      if (!kind) continue;
      // A path the walk reached without a link is its own resolved path (the walk starts at
      // the resolved root and follows no link); a link is resolved.
      std::optional<fs::path> resolved;
      if (e.is_symlink(e2))
        resolved =
            resolve(relative.string(), *kind);  // nullopt: it leaves the folder, or points at what is not offered
      else if (e.is_regular_file(e2))
        resolved = e.path();
      if (!resolved) continue;
      if (out.recordings.size() + out.configs.size() >= kMaxListedFiles) {
        out.truncated = true;
        break;
      }
      Entry entry{relative.generic_string(), fs::file_size(*resolved, e2)};
      (*kind == FileKind::kRecording ? out.recordings : out.configs).push_back(std::move(entry));
    }
  }
  const auto by_path = [](const Entry& a, const Entry& b) { return a.path < b.path; };
  std::sort(out.recordings.begin(), out.recordings.end(), by_path);
  std::sort(out.configs.begin(), out.configs.end(), by_path);
  return out;
}

}  // namespace gmwm::serve::detail
