// The fleet's cache of records (fleet_cache.h): SHA-256 keys (OpenSSL's EVP digest), one file
// per key, written whole through io::write_file_atomically.
#include "gmwm/fleet/fleet_cache.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>
#include <vector>

#include <openssl/evp.h>
#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "gmwm/fleet/fleet_record.h"
#include "gmwm/io/atomic_file.h"

namespace gmwm::fleet {
namespace {

namespace fs = std::filesystem;

// Bytes read per call while hashing a recording: large enough that the digest, not the
// calls, sets the pace (SHA-256 runs at ~1.5 GB/s with the CPU's SHA extensions).
constexpr std::size_t kHashChunk = std::size_t{1} << 20;

struct DigestDeleter {
  void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
};

class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new()) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1)
      throw std::runtime_error("SHA-256: OpenSSL could not start a digest");
  }
  void update(const void* data, std::size_t size) {
    if (EVP_DigestUpdate(ctx_.get(), data, size) != 1) throw std::runtime_error("SHA-256: OpenSSL digest failed");
  }
  std::string hex() {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int len = 0;
    if (EVP_DigestFinal_ex(ctx_.get(), md, &len) != 1) throw std::runtime_error("SHA-256: OpenSSL digest failed");
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < len; ++i) {
      out += kHex[md[i] >> 4];
      out += kHex[md[i] & 15];
    }
    return out;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, DigestDeleter> ctx_;
};

void hash_file(Sha256& h, const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path + ": cannot read it to hash its content: " + std::strerror(errno));
  std::vector<unsigned char> buf(kHashChunk);
  while (true) {
    const std::size_t got = std::fread(buf.data(), 1, buf.size(), f.get());
    if (got > 0) h.update(buf.data(), got);
    if (got < buf.size()) {
      if (std::ferror(f.get())) throw InputError(path + ": read error while hashing its content");
      break;
    }
  }
}

}  // namespace

std::string file_sha256(const std::string& path) {
  Sha256 h;
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    hash_file(h, path);
    return h.hex();
  }
  // A recording held in a folder (a rosbag2 folder): every regular file in it, in the order
  // of their relative names, each preceded by its name and size.
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path());
  if (ec) throw InputError(path + ": cannot list the folder to hash its content: " + ec.message());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    const std::string header = fs::relative(f, path, ec).generic_string() + "\n" +
                                std::to_string(fs::file_size(f, ec)) + "\n";
    h.update(header.data(), header.size());
    hash_file(h, f.string());
  }
  return h.hex();
}

std::string text_sha256(const std::string& text) {
  Sha256 h;
  h.update(text.data(), text.size());
  return h.hex();
}

std::string default_fleet_cache_dir(const std::string& manifest_path) {
  return (fs::path(manifest_path).parent_path() / ".gmwm-cache").string();
}

FleetCache::FleetCache(std::string dir) : dir_(std::move(dir)) {}

std::string FleetCache::key(const io::FleetRecording& recording, const FleetStudyOptions& options) const {
  return text_sha256(file_sha256(recording.path) + "\n" + fleet_result_key_text(recording, options));
}

std::string FleetCache::path_of(const std::string& key) const { return (fs::path(dir_) / (key + ".json")).string(); }

std::optional<std::string> FleetCache::load(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  const std::string path = path_of(key);
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (ec || !fs::is_regular_file(st)) return std::nullopt;
  const auto size = fs::file_size(path, ec);
  if (ec || size > kMaxCacheEntryBytes) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size))) return std::nullopt;
  return text;
}

void FleetCache::store(const std::string& key, const std::string& text) const {
  if (!enabled() || store_failed_) return;
  try {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw InputError(dir_ + ": cannot make the cache folder: " + ec.message());
    io::write_file_atomically(path_of(key), text);
  } catch (const std::exception& e) {
    store_failed_ = true;
    spdlog::warn("fleet cache: {}; this run goes on without caching its records", printable_line(e.what()));
  }
}

void FleetCache::forget(const std::string& key) const {
  if (!enabled()) return;
  std::error_code ec;
  fs::remove(path_of(key), ec);
}

}  // namespace gmwm::fleet
