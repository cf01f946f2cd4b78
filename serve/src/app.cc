// The app's routes (docs/serve.md): the page and its files, the folder's listing, uploads,
// opening a recording, the analysis jobs (wv, fit, select, stability), the overlay and the
// export. Every refusal is an HttpError turned into {"error": "one line"}; nothing a request
// sends stops the app.

#include "gmwm/serve/app.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <system_error>

#include <spdlog/spdlog.h>

#include "datasets.h"
#include "folder.h"
#include "gmwm/engine/error.h"
#include "guard.h"
#include "gmwm/io/option_wording.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"
#include "gmwm/report/html_fragment.h"
#include "gmwm/report/json_output.h"
#include "gmwm/report/report_data.h"
#include "jobs.h"
#include "request.h"
#include "studies.h"
#include "uploads.h"
#include "web_assets.h"

namespace gmwm::serve {

namespace fs = std::filesystem;
using detail::HttpError;
using detail::Json;
using detail::RequestBody;

std::string ServeOptions::Validate() const {
  if (folder.empty()) return "folder: expected a folder of recordings";
  if (host.empty()) return "host: expected an address to listen on (127.0.0.1 by default)";
  if (port < 0 || port > 65535) return "port: found " + std::to_string(port) + ", expected 0 (any free port) to 65535";
  if (max_upload_bytes < 1) return "max_upload_bytes: expected at least 1 byte";
  if (max_upload_total_bytes < max_upload_bytes)
    return "max_upload_total_bytes: found " + std::to_string(max_upload_total_bytes) +
           ", expected at least max_upload_bytes (" + std::to_string(max_upload_bytes) + ")";
  if (max_queued_jobs < 1) return "max_queued_jobs: expected at least 1";
  if (max_walked_entries < 1) return "max_walked_entries: expected at least 1";
  if (!(listing_seconds >= 0.0)) return "listing_seconds: expected 0 or more seconds";
  if (max_json_bytes < 1) return "max_json_bytes: expected at least 1 byte";
  if (job_workers < 1) return "job_workers: expected at least 1";
  if (max_datasets < 1) return "max_datasets: expected at least 1";
  if (!(max_dataset_bytes > 0.0)) return "max_dataset_bytes: expected a positive size";
  if (!(job_idle_seconds > 0.0)) return "job_idle_seconds: expected a positive time";
  if (memory_budget != 0.0 && !io::memory_problem(memory_budget / 1e6, std::to_string(memory_budget / 1e6)).empty())
    return "memory_budget: expected 0 (the reader's default) or 1e6 to 1e18 bytes (1 MB to 1e12 MB, as --memory)";
  if (!token.empty() && (token.size() < kMinTokenChars ||
                         token.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_") !=
                             std::string::npos))
    return "token: expected at least " + std::to_string(kMinTokenChars) + " letters, digits, '-' or '_'";
  for (const std::string& h : allowed_hosts)
    if (h.empty() || h.find_first_of(" /:?#@,\t") != std::string::npos)
      if (!(h.size() > 2 && h.front() == '[' && h.back() == ']'))
        return "allowed_hosts: found '" + h + "', expected a host name or address without port";
  return {};
}

struct App::Upload {
  std::shared_ptr<detail::Uploads::Upload> arriving;
};

struct App::State {
  State(ServeOptions o)
      : options(std::move(o)),
        folder(options.folder, options.max_walked_entries),
        guard(options),
        datasets(options.max_datasets, options.max_dataset_bytes),
        uploads(options.upload_root, options.max_upload_bytes, options.max_upload_total_bytes),
        jobs(options.job_workers, options.job_idle_seconds, options.max_queued_jobs,
             [this](const std::string& m) { return public_text(m); }) {}

  ServeOptions options;
  detail::Folder folder;
  detail::Guard guard;
  detail::Datasets datasets;
  detail::Uploads uploads;
  std::string page;
  std::string vega_script, vega_missing;  ///< Vega's modules as one script, or why they are missing
  detail::Jobs jobs;                      // last: destroyed first, so no job outlives what it uses

  /// `message` with no path of the machine in it (docs/serve.md, "Threat model"): the
  /// folder's as its name, the uploads' and the temporary folder's by what they are.
  std::string public_text(std::string message);
  std::string render_page() const;
  Json files();
  detail::Folder::Listing current_listing();
  // The last listing and when it was walked (listing_seconds), one walk at a time.
  std::mutex listing_mutex, walk_mutex;
  std::optional<detail::Folder::Listing> listing;
  std::chrono::steady_clock::time_point listed_at;
  Json open(const RequestBody& b);
  HttpResponse route(const HttpRequest& r);
};

namespace {

HttpResponse json_response(const Json& j, int status = 200) {
  return {status, "application/json", report::dump_json(j)};
}

HttpResponse error_response(int status, const std::string& message) {
  return json_response({{"error", printable_line(message)}}, status);
}

// A reader's message names the resolved path: the page reads the name it sent (never the
// machine's folders), and the fields it can set instead of the CLI's options.
std::string renamed(std::string message, const std::string& path, const std::string& name) {
  for (std::size_t p = message.find(path); !path.empty() && p != std::string::npos;
       p = message.find(path, p + name.size()))
    message.replace(p, path.size(), name);
  return io::option_wording(std::move(message), io::Face::kWeb);
}

std::string kind_of(const std::string& column) {
  try {
    return io::to_string(io::sensor_kind_of_column(column));
  } catch (const InputError&) {
    return "";
  }
}

}  // namespace

std::string App::State::public_text(std::string message) {
  std::vector<std::pair<std::string, std::string>> paths;
  if (const fs::path u = uploads.folder(); !u.empty()) paths.emplace_back(u.string(), "the uploads");
  paths.emplace_back(folder.root().string(), folder.name());
  std::error_code ec;
  if (const fs::path t = fs::temp_directory_path(ec); !ec && !t.empty())
    paths.emplace_back(t.string(), "the temporary folder");
  if (const fs::path given = options.folder; given.is_absolute()) paths.emplace_back(given.string(), folder.name());
  for (const auto& [path, said] : paths) {
    if (path.size() < 2) continue;  // "/" is every path's start, not a place
    for (std::size_t p = message.find(path); p != std::string::npos; p = message.find(path, p + said.size()))
      message.replace(p, path.size(), said);
  }
  return message;
}

std::string App::State::render_page() const {
  std::string html(detail::web_asset("index.html"));
  const auto replace = [&html](const std::string& placeholder, const std::string& with) {
    if (const auto p = html.find(placeholder); p != std::string::npos) html.replace(p, placeholder.size(), with);
  };
  replace("<!--GMWM_REPORT_STYLE-->", "<style>\n" + report::report_style_sheet() + "\n</style>");
  // Vega is its own deferred script (/vega.js, 1 MB): inlined, its parsing held the first
  // paint back by ~0.9 s; deferred, the page paints at once (the page loads its own script
  // first and draws the plots once Vega is there).
  // Without Vega the page says why in a meta element (the page's policy runs no inline script).
  replace("<!--GMWM_VEGA-->",
          vega_script.empty() ? "<meta name=\"gmwm-vega-missing\" content=\"" + report::html_text(vega_missing) + "\">"
                              : "<script src=\"/vega.js\" defer></script>");
  return html;
}

detail::Folder::Listing App::State::current_listing() {
  const auto fresh = [this] {
    return listing && std::chrono::duration<double>(std::chrono::steady_clock::now() - listed_at).count() <
                          options.listing_seconds;
  };
  std::optional<detail::Folder::Listing> last;
  {
    std::lock_guard lock(listing_mutex);
    if (fresh()) return *listing;
    last = listing;
  }
  // One walk at a time: a page that asks while another walks gets the last listing at once;
  // only the very first listing is waited for.
  std::unique_lock walk(walk_mutex, std::try_to_lock);
  if (!walk.owns_lock()) {
    if (last) return *last;
    walk.lock();
  }
  {
    std::lock_guard lock(listing_mutex);
    if (fresh()) return *listing;  // walked while this one waited
  }
  detail::Folder::Listing walked = folder.list();
  std::lock_guard lock(listing_mutex);
  listing = walked;
  listed_at = std::chrono::steady_clock::now();
  return walked;
}

Json App::State::files() {
  const detail::Folder::Listing l = current_listing();
  const auto rows = [](const std::vector<detail::Folder::Entry>& v) {
    Json a = Json::array();
    for (const auto& e : v) a.push_back({{"path", e.path}, {"size", e.size}});
    return a;
  };
  return {{"folder", folder.name()},
          {"files", rows(l.recordings)},
          {"configs", rows(l.configs)},
          {"truncated", l.truncated},
          {"max_upload", options.max_upload_bytes}};
}

Json App::State::open(const RequestBody& b) {
  fs::path path;
  std::string name;
  if (b.has("file")) {
    name = b.text("file");
    const auto p = folder.resolve(name, detail::FileKind::kRecording);
    if (!p)
      throw HttpError(404, "/api/open: no recording '" + name + "' in " + folder.name() +
                               " (a recording is a csv, txt, tsv, dat, gz, ulg, bag, db3 or mcap file, not hidden, "
                               "inside the folder)");
    path = *p;
  } else if (b.has("upload")) {
    const std::string id = b.text("upload");
    const auto u = uploads.find(id);
    if (!u)
      throw HttpError(404, "/api/open: unknown upload '" + id + "' (uploads are kept while the app runs, up to " +
                               std::to_string(uploads.max_total_bytes()) +
                               " bytes in all: the oldest are removed to make room; upload it again)");
    path = u->path;
    name = u->name;
  } else {
    b.fail("file", "missing, expected a recording's path in the folder (or \"upload\": an upload's id)");
  }
  io::ReadRequest request;
  request.path = path.string();
  request.columns = b.list("columns");
  request.freq = b.number("freq");
  request.topic = b.text("topic");
  const std::string gaps = b.text("gaps", "windows");
  if (!io::gap_handling_from_name(gaps))
    b.fail("gaps", "found '" + gaps + "', expected " + io::gap_handling_expected());
  request.gaps = io::gap_handling_of(gaps);
  const std::string data = b.text("data", "rate");
  try {
    request.data = io::data_kind_of(data);
    request.decimate_filter = io::decimation_filter_of(b.text("decimate_filter", "average"));
  } catch (const InputError& e) {
    throw HttpError(400, "/api/open: " + std::string(e.what()));
  }
  if (const std::optional<std::int64_t> k = b.whole("decimate", 1, io::kMaxDecimation))
    request.decimate = static_cast<int>(*k);
  if (options.memory_budget > 0.0) request.memory_mb = options.memory_budget / 1e6;
  detail::Dataset d;
  d.name = name;
  try {
    d.set = io::read_request(request);
  } catch (const InputError& e) {
    throw HttpError(400, renamed(e.what(), path.string(), name));
  }
  d.set.path = name;  // the documents name the recording as the page does
  Json columns = Json::array();
  std::int64_t n = 0;
  for (const io::Signal& s : d.set.signals) {
    n = static_cast<std::int64_t>(s.values.size());
    d.bytes += 8.0 * static_cast<double>(s.values.size());
    columns.push_back({{"name", s.name}, {"kind", kind_of(s.name)}, {"unit", s.unit}, {"n", n}});
  }
  const auto kept = datasets.add(std::move(d));
  Json out = {{"dataset", kept->id},
              {"name", kept->name},
              {"freq", kept->set.freq},
              {"freq_known", kept->set.freq_known},
              {"n", n},
              {"columns", columns},
              {"spilled", kept->set.spilled}};
  if (kept->set.timing) out["timing"] = kept->set.timing->summary();
  out["notes"] = report::record_notes(kept->set);  // what reading said, as the report's header
  return out;
}

HttpResponse App::State::route(const HttpRequest& r) {
  const std::string& p = r.path;
  if (r.method == "GET") {
    if (p == "/" || p == "/index.html") return {200, "text/html; charset=utf-8", page};
    if (p == "/app.js") return {200, "text/javascript; charset=utf-8", std::string(detail::web_asset("app.js"))};
    if (p == "/app.css") return {200, "text/css; charset=utf-8", std::string(detail::web_asset("app.css"))};
    if (p == "/vega.js") {
      if (vega_script.empty()) throw HttpError(404, "/vega.js: this gmwm was built without Vega: " + vega_missing);
      return {200, "text/javascript; charset=utf-8", vega_script};
    }
    if (p == "/favicon.ico") return {204, "image/x-icon", ""};  // none: the browser asks anyway
    if (p == "/api/files") return json_response(files());
    if (p == "/api/status")
      return json_response({{"datasets", datasets.size()},
                            {"uploads", uploads.count()},
                            {"upload_bytes", uploads.held_bytes()},
                            {"jobs", jobs.size()},
                            {"queued", jobs.queued()}});
    if (p == "/api/stability") return json_response(detail::stability_choices());
    if (p.starts_with("/api/jobs/") && p.find("/ranking/") != std::string::npos) {
      const std::string id = p.substr(10, p.find("/ranking/") - 10);
      const std::string row = p.substr(p.find("/ranking/") + 9);
      return json_response(detail::ranking_row(jobs.attachment(id), id, row));
    }
    if (p.starts_with("/api/jobs/")) {
      const auto s = jobs.status(p.substr(10));
      if (!s) throw HttpError(404, "unknown job '" + p.substr(10) + "' (finished jobs are kept 10 minutes)");
      return json_response(*s);
    }
    throw HttpError(404, "GET " + p + ": no such page");
  }
  if (r.method == "DELETE" && p.starts_with("/api/jobs/")) {
    if (!jobs.cancel(p.substr(10))) throw HttpError(404, "unknown job '" + p.substr(10) + "'");
    return json_response(*jobs.status(p.substr(10)));
  }
  if (r.method != "POST") throw HttpError(405, r.method + " " + p + ": not allowed here");
  const RequestBody body(r.body, p, options.max_json_bytes);
  detail::StudyContext context{options, folder, datasets};
  if (p == "/api/open") return json_response(open(body));
  if (p == "/api/wv") return json_response({{"job", jobs.submit("wv", detail::wv_work(body, context))}});
  if (p == "/api/fit") return json_response({{"job", jobs.submit("fit", detail::fit_work(body, context))}});
  if (p == "/api/select") return json_response({{"job", jobs.submit("select", detail::select_work(body, context))}});
  if (p == "/api/stability")
    return json_response({{"job", jobs.submit("stability", detail::stability_work(body, context))}});
  if (p == "/api/overlay") return json_response(detail::overlay(body, context));
  if (p == "/api/export") return json_response(detail::export_model(body));
  throw HttpError(404, "POST " + p + ": no such endpoint");
}

App::App(ServeOptions options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("serve: " + why);
  state_ = std::make_unique<State>(std::move(options));
  try {
    state_->vega_script = report::vega_inline_script();
  } catch (const std::exception& e) {
    // The page still works (tables, numbers, exports); it says why it has no plots.
    state_->vega_missing = e.what();
  }
  state_->page = state_->render_page();
}

App::~App() = default;  // the jobs end first (State's last member), then the uploads go

const ServeOptions& App::options() const { return state_->options; }

std::optional<HttpResponse> App::screen(const HttpRequest& request) const { return state_->guard.screen(request); }

void App::set_port(int port) { state_->guard.set_port(port); }

const std::string& App::token() const { return state_->guard.token(); }

const std::string& App::plots_unavailable() const { return state_->vega_missing; }

HttpResponse App::handle(const HttpRequest& request) { return detail::Guard::stamped(answer(request)); }

HttpResponse App::answer(const HttpRequest& request) {
  if (auto refused = screen(request)) return *refused;
  try {
    if (request.method == "POST" && request.path == "/api/upload") {
      HttpResponse refusal;
      auto u = begin_upload(request.query.count("name") ? request.query.at("name") : "",
                            static_cast<std::int64_t>(request.body.size()), refusal);
      if (!u) return refusal;
      append_upload(*u, request.body.data(), request.body.size());
      return finish_upload(u, true);
    }
    return state_->route(request);
  } catch (const HttpError& e) {
    HttpResponse a = error_response(e.status(), state_->public_text(e.what()));
    if (e.retry_after_seconds() > 0) a.headers.emplace_back("Retry-After", std::to_string(e.retry_after_seconds()));
    return a;
  } catch (const InputError& e) {
    return error_response(400, state_->public_text(e.what()));
  } catch (const std::exception& e) {
    spdlog::error("serve: {} {}: {}", request.method, request.path, e.what());
    return error_response(500, state_->public_text(request.path + ": " + e.what()));
  }
}

std::shared_ptr<App::Upload> App::begin_upload(const std::string& name, std::int64_t declared_bytes,
                                               HttpResponse& refusal) {
  try {
    return std::make_shared<Upload>(Upload{state_->uploads.begin(name, declared_bytes)});
  } catch (const HttpError& e) {
    refusal = error_response(e.status(), state_->public_text(e.what()));
    return nullptr;
  }
}

bool App::append_upload(Upload& u, const char* data, std::size_t size) {
  return state_->uploads.append(*u.arriving, data, size);
}

HttpResponse App::finish_upload(const std::shared_ptr<Upload>& u, bool complete) {
  try {
    Json answer = state_->uploads.finish(u->arriving, complete);
    u->arriving.reset();
    return json_response(answer);
  } catch (const HttpError& e) {
    u->arriving.reset();  // the partial file goes now
    return error_response(e.status(), state_->public_text(e.what()));
  }
}

}  // namespace gmwm::serve
