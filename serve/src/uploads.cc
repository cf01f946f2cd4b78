#include "uploads.h"

#include <cstdlib>
#include <system_error>

#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "jobs.h"

namespace gmwm::serve::detail {

namespace fs = std::filesystem;

namespace {

// The name an upload keeps: its base name, control characters as '_', at most
// kMaxUploadNameBytes from its end (the ending names the format), never starting inside a
// UTF-8 character; empty when there is none.
std::string kept_name(const std::string& name) {
  std::string base = fs::path(name).filename().string();
  if (base == "." || base == ".." || base.find('\0') != std::string::npos) return {};
  for (char& c : base)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '_';
  if (base.size() > kMaxUploadNameBytes) {
    std::size_t start = base.size() - kMaxUploadNameBytes;
    while (start < base.size() && (static_cast<unsigned char>(base[start]) & 0xC0) == 0x80) ++start;
    base = base.substr(start);
  }
  return base;
}

std::string mb(std::int64_t bytes) { return std::to_string(bytes) + " bytes"; }

}  // namespace

struct Uploads::Upload {
  std::string id, name;
  fs::path path;
  std::ofstream out;
  std::int64_t size = 0;
  std::string refused;  ///< why it was refused (413 or 500 text); empty while it goes on
  int refused_status = 0;
  bool kept = false;  ///< finished and listed; otherwise its file goes with it
  Uploads* owner = nullptr;
  ~Upload() {
    if (kept) return;
    if (out.is_open()) out.close();
    std::error_code ec;
    if (!path.empty()) fs::remove(path, ec);
    std::lock_guard lock(owner->mutex_);
    owner->arriving_bytes_ -= size;  // what it held is free again
  }
};

Uploads::Uploads(std::string root, std::int64_t max_bytes, std::int64_t max_total_bytes)
    : root_(std::move(root)), max_bytes_(max_bytes), max_total_(max_total_bytes) {}

Uploads::~Uploads() {
  std::error_code ec;
  if (!folder_.empty()) fs::remove_all(folder_, ec);
}

fs::path Uploads::folder_locked() {
  if (!folder_.empty()) return folder_;
  std::error_code ec;
  const fs::path root = root_.empty() ? fs::temp_directory_path(ec) : fs::path(root_);
  std::string pattern = (root / "gmwm-serve-uploads-XXXXXX").string();
  if (ec || !mkdtemp(pattern.data())) throw HttpError(500, "/api/upload: cannot make a folder to keep uploads in");
  folder_ = pattern;
  return folder_;
}

bool Uploads::reserve_locked(std::int64_t bytes) {
  while (kept_bytes_ + arriving_bytes_ + bytes > max_total_ && !kept_.empty()) {
    auto oldest = kept_.begin();
    for (auto it = kept_.begin(); it != kept_.end(); ++it)
      if (it->second.finished < oldest->second.finished) oldest = it;
    std::error_code ec;
    fs::remove(oldest->second.stored.path, ec);
    kept_bytes_ -= oldest->second.stored.size;
    spdlog::info("serve: upload {} removed to make room ({} bytes)", oldest->first, oldest->second.stored.size);
    kept_.erase(oldest);
  }
  if (kept_bytes_ + arriving_bytes_ + bytes > max_total_) return false;
  arriving_bytes_ += bytes;
  return true;
}

std::shared_ptr<Uploads::Upload> Uploads::begin(const std::string& name, std::int64_t declared_bytes) {
  if (declared_bytes > max_bytes_)
    throw HttpError(413, "/api/upload: the file has " + mb(declared_bytes) + ", more than the limit of " +
                             mb(max_bytes_) + " (--max-upload)");
  const std::string base = kept_name(name);
  if (base.empty()) throw HttpError(400, "/api/upload: query 'name': expected the file's name (e.g. imu.csv.gz)");
  auto u = std::make_shared<Upload>();
  u->owner = this;
  u->id = random_id("u");
  u->name = base;
  {
    std::lock_guard lock(mutex_);
    u->path = folder_locked() / (u->id + "-" + base);
  }
  u->out.open(u->path, std::ios::binary | std::ios::trunc);
  if (!u->out) throw HttpError(500, "/api/upload: cannot write the upload to the temporary folder");
  return u;
}

bool Uploads::append(Upload& u, const char* data, std::size_t size) {
  if (!u.refused.empty()) return false;
  const auto n = static_cast<std::int64_t>(size);
  bool room = false;
  if (u.size + n <= max_bytes_) {
    std::lock_guard lock(mutex_);
    room = reserve_locked(n);
    if (!room) {
      u.refused_status = 413;
      u.refused = "/api/upload: the uploads would hold more than " + mb(max_total_) +
                  " at once (--max-upload-total), even with every finished upload removed";
    }
  } else {
    u.refused_status = 413;
    u.refused = "/api/upload: the file exceeds the limit of " + mb(max_bytes_) + " (--max-upload)";
  }
  if (!room) {
    u.out.close();
    std::error_code ec;
    fs::remove(u.path, ec);
    return false;
  }
  u.size += n;
  u.out.write(data, static_cast<std::streamsize>(size));
  if (!u.out) {
    u.refused_status = 500;
    u.refused = "/api/upload: the upload could not be written (is the temporary folder full?)";
    return false;
  }
  return true;
}

Json Uploads::finish(const std::shared_ptr<Upload>& u, bool complete) {
  if (!u->refused.empty()) throw HttpError(u->refused_status, u->refused);
  if (!complete)
    throw HttpError(400,
                    "/api/upload: the upload ended after " + mb(u->size) +
                        ", before its last byte (the connection was cut, or the body was malformed); nothing kept");
  u->out.close();
  if (!u->out) throw HttpError(500, "/api/upload: the upload could not be written (is the temporary folder full?)");
  std::lock_guard lock(mutex_);
  arriving_bytes_ -= u->size;
  kept_bytes_ += u->size;
  kept_[u->id] = {{u->name, u->path, u->size}, std::chrono::steady_clock::now()};
  u->kept = true;
  return {{"upload", u->id}, {"name", u->name}, {"size", u->size}};
}

std::optional<Uploads::Stored> Uploads::find(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = kept_.find(id);
  if (it == kept_.end()) return std::nullopt;
  return it->second.stored;
}

fs::path Uploads::folder() const {
  std::lock_guard lock(mutex_);
  return folder_;
}

std::int64_t Uploads::held_bytes() const {
  std::lock_guard lock(mutex_);
  return kept_bytes_ + arriving_bytes_;
}

std::size_t Uploads::count() const {
  std::lock_guard lock(mutex_);
  return kept_.size();
}

}  // namespace gmwm::serve::detail
