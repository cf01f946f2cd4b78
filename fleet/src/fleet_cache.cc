// The fleet's cache of records (fleet_cache.h): SHA-256 keys (OpenSSL's EVP digest), one file
// per key, written whole through io::write_file_atomically, each verified when read back
// (its header line: format, key, length, digest).
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

#include <nlohmann/json.hpp>
#include <openssl/evp.h>

#include "gmwm/engine/error.h"
#include "gmwm/fleet/fleet_record.h"
#include "gmwm/io/atomic_file.h"

namespace gmwm::fleet {
namespace {

namespace fs = std::filesystem;

// Bytes read per call while hashing a recording: large enough that the digest, not the
// calls, sets the pace (SHA-256 runs at ~1.5 GB/s with the CPU's SHA extensions).
constexpr std::size_t kHashChunk = std::size_t{1} << 20;

// The longest header line read: its four fields take ~200 bytes (two 64-digit digests).
constexpr std::size_t kMaxHeaderBytes = 1024;

// Hex digits of a key quoted in a message: enough to tell keys apart by eye.
constexpr std::size_t kKeyDigitsSaid = 12;

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

// The digest an entry records: the SHA-256 of its key, a line break and its record's text,
// so that a record copied under another key's name does not verify.
std::string entry_digest(const std::string& key, std::string_view record) {
  Sha256 h;
  h.update(key.data(), key.size());
  h.update("\n", 1);
  h.update(record.data(), record.size());
  return h.hex();
}

std::string entry_header(const std::string& key, const std::string& record) {
  const nlohmann::json header = {{"gmwm_fleet_cache", kFleetCacheFormat},
                                 {"key", key},
                                 {"bytes", record.size()},
                                 {"sha256", entry_digest(key, record)}};
  return header.dump();
}

// Why an entry's text does not hold `key`'s record (empty when it does), the record set.
std::string verify_entry(const std::string& key, const std::string& text, std::string& record) {
  const std::size_t nl = text.find('\n');
  const std::string not_ours = "found no header line of a gmwm fleet cache entry (format " +
                               std::to_string(kFleetCacheFormat) + "): written by another gmwm, or not by gmwm";
  if (nl == std::string::npos || nl > kMaxHeaderBytes) return not_ours;
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(std::string_view(text).substr(0, nl));
  } catch (const nlohmann::json::exception&) {
    return not_ours;
  }
  const auto field = [&h](const char* name) -> const nlohmann::json* {
    return h.is_object() && h.contains(name) ? &h.at(name) : nullptr;
  };
  const nlohmann::json* format = field("gmwm_fleet_cache");
  if (!format || !format->is_number_integer()) return not_ours;
  if (format->get<std::int64_t>() != kFleetCacheFormat)
    return "found cache format " + std::to_string(format->get<std::int64_t>()) + ", expected " +
           std::to_string(kFleetCacheFormat) + " (written by another gmwm)";
  const nlohmann::json* k = field("key");
  const nlohmann::json* bytes = field("bytes");
  const nlohmann::json* digest = field("sha256");
  if (!k || !k->is_string() || !bytes || !bytes->is_number_unsigned() || !digest || !digest->is_string())
    return "found a header without its key, bytes and sha256, expected all three";
  if (k->get<std::string>() != key)
    return "found the record of another key (" + printable_line(k->get<std::string>().substr(0, kKeyDigitsSaid)) +
           "...), expected the one its name says (copied or swapped)";
  const std::size_t have = text.size() - nl - 1, want = bytes->get<std::uint64_t>();
  if (have != want)
    return "found " + std::to_string(have) + " bytes of record, expected the " + std::to_string(want) +
           " its header says (" + (have < want ? "cut short" : "grown") + ", or edited)";
  record = text.substr(nl + 1);
  if (digest->get<std::string>() != entry_digest(key, record))
    return "found a record whose SHA-256 is not the one its header says, expected it unchanged since it was "
           "written (edited)";
  return {};
}

}  // namespace

void check_fleet_cache_dir(const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  // The path itself, then (when it is not there yet) the nearest folder above it that is.
  fs::path p = dir;
  bool itself = true;
  while (!p.empty()) {
    const fs::file_status st = fs::symlink_status(p, ec);
    if (st.type() == fs::file_type::not_found) {
      const fs::path parent = p.parent_path();
      if (parent == p) return;
      p = parent;
      itself = false;
      continue;
    }
    if (ec) throw InputError(dir + ": cannot look at the cache folder: " + ec.message());
    const std::string what = itself ? dir : dir + "'s parent " + p.string();
    if (fs::is_symlink(st) && !fs::exists(p, ec))
      throw InputError(what + ": found a link to nothing, expected the folder of the fleet's cached records");
    if (fs::is_directory(p, ec)) return;
    throw InputError(what + ": found " + (fs::is_regular_file(p, ec) ? "a file" : "a special file") +
                     ", expected the folder of the fleet's cached records");
  }
}

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
    const std::string header =
        fs::relative(f, path, ec).generic_string() + "\n" + std::to_string(fs::file_size(f, ec)) + "\n";
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

std::optional<std::string> FleetCache::load(const std::string& key, std::string* why) const {
  if (!enabled()) return std::nullopt;
  const std::string path = path_of(key);
  const auto refuse = [&](const std::string& what) -> std::optional<std::string> {
    if (why) *why = printable_line(path + ": " + what);
    return std::nullopt;
  };
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found) return std::nullopt;
  if (ec) return refuse("cannot look at the entry: " + ec.message());
  if (!fs::is_regular_file(st)) return refuse("found a folder, link or special file, expected a cache entry (a file)");
  const auto size = fs::file_size(path, ec);
  if (ec) return refuse("cannot look at the entry: " + ec.message());
  if (size > kMaxCacheEntryBytes)
    return refuse("found " + std::to_string(size) + " bytes, expected at most " + std::to_string(kMaxCacheEntryBytes));
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size)) || in.peek() != std::char_traits<char>::eof())
    return refuse("cannot read the entry whole (it changed while read)");
  std::string record;
  if (const std::string problem = verify_entry(key, text, record); !problem.empty()) return refuse(problem);
  return record;
}

void FleetCache::store(const std::string& key, const std::string& text) const {
  if (!enabled() || !store_problem_.empty()) return;
  try {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw InputError(dir_ + ": cannot make the cache folder: " + ec.message());
    io::write_file_atomically(path_of(key), entry_header(key, text) + "\n" + text);
  } catch (const std::exception& e) {
    store_problem_ = printable_line(e.what());
  }
}

void FleetCache::forget(const std::string& key) const {
  if (!enabled()) return;
  std::error_code ec;
  fs::remove(path_of(key), ec);
}

}  // namespace gmwm::fleet
