#pragma once
// The fleet's cache of records: one file per recording's result, named by the SHA-256 of
// what decides that result (the recording's content, how it is read, the study's options and
// the library's version: fleet_result_key_text), holding the record's text (fleet_record.h).
// A re-run finds the recordings it has already done under the same key, whatever their path
// or unit id; a changed file or option is a new key. Each entry is written whole (a temporary
// file renamed over it), so a kill never leaves half an entry.
//
// Each entry verifies itself: a header line records the format, the key the entry was
// written under, the record's length and the SHA-256 of the key and the record together,
// then the record's text follows as it was computed:
//
//   {"bytes":52311,"gmwm_fleet_cache":1,"key":"9f2c...","sha256":"41d0..."}
//   {"axes":[...],"freq":100.0,...,"version":1}
//
// An entry that does not verify (edited by hand, cut short, copied under another key's
// name, of another format, not a regular file) is not used: its recording is computed again
// and `load` says why, naming the entry's file (the study reports it: FleetStudy::cache_problems).
// The digest catches changes, not forgeries: whoever can write the folder can write an entry
// that verifies (keep a cache where only you can write, as with any file you run on).
//
//   FleetCache cache(".gmwm-cache");
//   const std::string key = cache.key(recording, options);
//   std::string why;
//   if (auto text = cache.load(key, &why)) ...; else cache.store(key, run_fleet_task(task));

#include <optional>
#include <string>

#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/fleet_manifest.h"

namespace gmwm::fleet {

/// The SHA-256 of a file's bytes, as 64 lower-case hex digits. Throws InputError naming the
/// file when it cannot be read.
std::string file_sha256(const std::string& path);

/// The SHA-256 of a text, as 64 lower-case hex digits.
std::string text_sha256(const std::string& text);

/// The cache a manifest's run uses unless told otherwise: ".gmwm-cache" in the manifest's
/// folder (shared by the manifests there: entries are keyed by content, not by path).
std::string default_fleet_cache_dir(const std::string& manifest_path);

/// Largest cache entry read (a record of a recording with hundreds of columns is ~10 MB).
inline constexpr std::size_t kMaxCacheEntryBytes = std::size_t{64} << 20;

/// The format of an entry's header line (fleet_cache.h): an entry of another format is
/// computed again.
inline constexpr int kFleetCacheFormat = 1;

/// Refuses (InputError naming it) a cache folder that cannot be one: a path that is a file,
/// a special file or a link to nothing, or below a file. A folder that does not exist yet
/// is fine (the first store makes it). Empty: no cache, fine.
void check_fleet_cache_dir(const std::string& dir);

class FleetCache {
 public:
  /// `dir` is made (with its parents) at the first store; empty: a cache that holds nothing.
  explicit FleetCache(std::string dir);

  bool enabled() const { return !dir_.empty(); }
  const std::string& dir() const { return dir_; }

  /// The key of `recording` under `options`: the hash of its content and of
  /// fleet_result_key_text. Throws InputError when the recording cannot be read.
  std::string key(const io::FleetRecording& recording, const FleetStudyOptions& options) const;

  /// The record's text stored under `key` when its entry verifies; nullopt when there is no
  /// entry, or when the entry does not verify (not a regular file, larger than
  /// kMaxCacheEntryBytes, no header of this format, another key, cut short, changed): then
  /// `why`, when given, is set to one line naming the entry's file and what is wrong with it.
  std::optional<std::string> load(const std::string& key, std::string* why = nullptr) const;

  /// Writes the entry whole (its header line, then `text`). A failure (a read-only folder, a
  /// full disk) ends the caching of this run, which goes on: it costs a re-run, not this
  /// run; store_problem() then says why.
  void store(const std::string& key, const std::string& text) const;

  /// Why the cache could not be written (one line naming the file), or empty.
  const std::string& store_problem() const { return store_problem_; }

  /// Removes an entry that could not be read back (reported by the caller).
  void forget(const std::string& key) const;

  /// The file of `key`'s entry (DIR/KEY.json).
  std::string path_of(const std::string& key) const;

 private:
  std::string dir_;
  mutable std::string store_problem_;
};

}  // namespace gmwm::fleet
