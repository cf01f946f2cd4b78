#pragma once
// gmwm serve's web app (docs/serve.md): the HTTP API of a local page on which an engineer
// builds a noise model by hand, over the same library calls as the command line. App is
// the API without sockets (a request in, a response out; what the tests drive); Server
// (server.h) puts it on a loopback port with cpp-httplib.
//
//   gmwm::serve::ServeOptions o;
//   o.folder = "recordings";
//   gmwm::serve::App app(o);                       // InputError for a folder that is not one
//   auto r = app.handle({.method = "GET", .path = "/api/files"});
//   // r.status == 200, r.body == {"folder": "recordings", "files": [...]}
//
// Floor: above report/ (it renders through the report's documents, texts and fragments),
// beside the CLI; nothing below includes it.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gmwm/engine/random.h"

namespace gmwm::serve {

/// The request body limit of the JSON endpoints: the largest JSON a page sends is an
/// export's fit/select document (a few tens of kB for six axes) or an overlay's file text;
/// 1 MB holds forty times that and bounds what a request can make the server hold.
inline constexpr std::int64_t kMaxJsonBytes = 1'000'000;
/// The default upload limit (--max-upload): a 1 kHz six-axis CSV of a day is ~0.5 GB.
inline constexpr std::int64_t kDefaultMaxUploadBytes = 512'000'000;
/// What all uploads may hold at once, on disk (--max-upload-total): four of the largest; the
/// oldest finished ones are removed to make room for a new one.
inline constexpr std::int64_t kDefaultMaxUploadTotalBytes = 4 * kDefaultMaxUploadBytes;
/// Analyses waiting for a worker at once (beyond: 429 with a Retry-After): two tabs never
/// queue more than a few; a script that queues hundreds would hold the machine for hours.
inline constexpr std::size_t kDefaultMaxQueuedJobs = 16;
/// Datasets kept open at once (least recently used dropped beyond), and their bytes.
inline constexpr std::size_t kDefaultMaxDatasets = 8;
inline constexpr double kDefaultMaxDatasetBytes = 4e9;
/// A job nobody polled for this long is cancelled and forgotten (a tab that was closed).
inline constexpr double kDefaultJobIdleSeconds = 600.0;
/// Jobs run at once; the others queue. Each job's study is itself parallel (TBB), so two
/// are enough for two tabs to progress side by side without oversubscribing the cores.
inline constexpr int kDefaultJobWorkers = 2;
/// The shortest token a user may choose: 16 characters of 64 kinds, 96 bits.
inline constexpr std::size_t kMinTokenChars = 16;
/// Recordings listed at most, and how deep the listing goes under FOLDER.
inline constexpr std::size_t kMaxListedFiles = 10'000;
inline constexpr int kMaxListedDepth = 10;
/// Entries (files and folders of any kind) the listing walks at most by default: a folder
/// holding a build tree or a dataset of millions of small files is listed in a bounded time
/// and said to be truncated.
inline constexpr std::size_t kDefaultMaxWalkedEntries = 100'000;
/// A listing is walked at most once in this many seconds by default, however many pages ask
/// (the others get the last one, at most this old).
inline constexpr double kDefaultListingSeconds = 2.0;

struct ServeOptions {
  std::string folder = ".";        ///< the recordings offered; nothing outside it is read
  std::string host = "127.0.0.1";  ///< the address listened on (Server)
  int port = 8080;                 ///< 0: a free port (Server::port() tells which)
  std::int64_t max_upload_bytes = kDefaultMaxUploadBytes;
  std::int64_t max_upload_total_bytes = kDefaultMaxUploadTotalBytes;  ///< at least max_upload_bytes
  std::size_t max_queued_jobs = kDefaultMaxQueuedJobs;
  std::size_t max_walked_entries = kDefaultMaxWalkedEntries;  ///< the listing's walk
  double listing_seconds = kDefaultListingSeconds;            ///< a listing's age at most
  std::int64_t max_json_bytes = kMaxJsonBytes;
  int job_workers = kDefaultJobWorkers;
  std::size_t max_datasets = kDefaultMaxDatasets;
  double max_dataset_bytes = kDefaultMaxDatasetBytes;
  double job_idle_seconds = kDefaultJobIdleSeconds;
  /// Bytes a recording's values may take in memory before they go to temporary files
  /// (io::ReadOptions::memory_budget); 0: the reader's default share of physical memory.
  double memory_budget = 0.0;
  std::uint64_t seed = kDefaultSeed;  ///< every study's seed, as the CLI's --seed
  /// Where uploads are kept while the app runs (a fresh folder under it, removed at the
  /// end); empty: the system's temporary folder.
  std::string upload_root;
  /// Names besides the loopback ones (localhost, 127.0.0.1, [::1]) and `host` under which
  /// the app may be reached: a request's Host must be one of them with the port
  /// (docs/serve.md, "Threat model"). A machine's name or address when serving beyond
  /// loopback.
  std::vector<std::string> allowed_hosts;
  /// The access token every request carries (docs/serve.md, "Threat model"): empty, a
  /// fresh random one (128 bits) each launch; else at least kMinTokenChars letters, digits,
  /// '-' or '_' (a script's own, e.g. from GMWM_SERVE_TOKEN).
  std::string token;

  /// Empty when valid, else one line naming the field.
  std::string Validate() const;
};

struct HttpRequest {
  std::string method;                        ///< GET, POST, DELETE
  std::string path;                          ///< decoded path, no query
  std::map<std::string, std::string> query;  ///< decoded query parameters
  std::string body;
  std::map<std::string, std::string> headers = {};  ///< by lower-case name (Host, Origin, ...)
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers = {};  ///< beyond the content type
};

/// The app: its folder, its open datasets, uploads and jobs. Thread-safe: handle() is
/// called from the server's threads at once. Every failure is an HTTP answer with
/// {"error": "one line"}; handle() never throws.
class App {
 public:
  /// Throws InputError when the options do not validate or FOLDER is not a readable folder.
  explicit App(ServeOptions options);
  /// Cancels the running jobs, waits for them, removes the uploads.
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  /// The answer to `request`: a refusal when it fails the rules every request passes
  /// (screen()), else its route's answer. Every answer carries answer_headers().
  HttpResponse handle(const HttpRequest& request);

  /// The rules every request passes before it is routed (docs/serve.md, "Threat model"):
  /// the answer to give instead, or nullopt when it may go on. The server calls it on a
  /// request's headers before reading its body.
  std::optional<HttpResponse> screen(const HttpRequest& request) const;

  /// The port requests must name in their Host (the server's, once bound; the options'
  /// until then).
  void set_port(int port);
  /// The access token requests must carry (the start-up address's ?token=).
  const std::string& token() const;
  /// Why the page has no plots (Vega could not be read; its tables and numbers still work);
  /// empty when it has them.
  const std::string& plots_unavailable() const;

  /// An upload's bytes arrive in pieces (the server streams them to a file): begin() names
  /// it, or sets an error response (limit already exceeded, bad name) and returns nullptr;
  /// append() false once a limit is passed (the partial file is then removed);
  /// finish() the answer to the request: `complete` when the body arrived whole (an upload
  /// cut short is removed, never kept).
  struct Upload;
  std::shared_ptr<Upload> begin_upload(const std::string& name, std::int64_t declared_bytes, HttpResponse& refusal);
  bool append_upload(Upload& upload, const char* data, std::size_t size);
  HttpResponse finish_upload(const std::shared_ptr<Upload>& upload, bool complete);

  const ServeOptions& options() const;

 private:
  HttpResponse answer(const HttpRequest& request);
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace gmwm::serve
