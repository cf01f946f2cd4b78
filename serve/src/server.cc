#include "gmwm/serve/server.h"

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <sys/socket.h>

#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "guard.h"

namespace gmwm::serve {

struct Server::Impl {
  explicit Impl(ServeOptions o) : app(std::move(o)) {}
  App app;
  httplib::Server http;
  int port = 0;
  int socket = -1;  ///< the listening socket (set_socket_options sees it before bind)
};

namespace {

// The request as the App reads it: headers by lower-case name, a header sent twice as its
// values joined by ", " (as HTTP combines them: a second Host then names no server).
HttpRequest request_of(const httplib::Request& req) {
  HttpRequest r;
  r.method = req.method;
  r.path = req.path;
  for (const auto& [k, v] : req.params) r.query[k] = v;
  r.body = req.body;
  for (const auto& [k, v] : req.headers) {
    std::string name = k;
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    auto [it, added] = r.headers.emplace(name, v);
    if (!added) it->second += ", " + v;
  }
  return r;
}

void answer(httplib::Response& res, const HttpResponse& a) {
  res.status = a.status;
  res.set_content(a.body, a.content_type.c_str());
  for (const auto& [k, v] : a.headers) res.set_header(k.c_str(), v);
}

// An answer after which the connection is closed, whatever the request asked: the rest of a
// refused body is never read. (cpp-httplib keeps a connection open unless the request said
// "Connection: close"; a response whose content provider reports failure after writing the
// whole answer ends the connection.)
void answer_and_close(httplib::Response& res, const HttpResponse& a) {
  answer(res, a);
  res.set_header("Connection", "close");
  const auto body = std::make_shared<std::string>(std::move(res.body));
  res.body.clear();
  res.headers.erase("Content-Type");  // set again by the provider
  res.set_content_provider(body->size(), a.content_type.c_str(),
                           [body](std::size_t offset, std::size_t, httplib::DataSink& sink) {
                             sink.write(body->data() + offset, body->size() - offset);
                             return false;
                           });
}

// The declared body length: -1 when none is declared (chunked, or no body), -2 when the
// header is not a byte count.
std::int64_t content_length(const httplib::Request& req) {
  if (!req.has_header("Content-Length")) return -1;
  const std::string v = req.get_header_value("Content-Length");
  if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos) return -2;
  return std::stoll(v);
}

// A thread for each connection, up to kMaxConnectionThreads at once (beyond, connections wait
// for one to end): a client that sends slowly, or holds its connection open, holds only its
// own thread, and the page's requests find a free one. (cpp-httplib's fixed pool let 40
// slow clients hold all 16 threads while the page waited.) Threads are made as connections
// need them and kept for the next ones.
class ConnectionThreads : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override {
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(std::move(fn));
      if (queue_.size() > idle_ && threads_.size() < kMaxConnectionThreads) threads_.emplace_back([this] { work(); });
    }
    wake_.notify_one();
  }
  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

 private:
  void work() {
    std::unique_lock lock(mutex_);
    for (;;) {
      ++idle_;
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      --idle_;
      if (queue_.empty()) return;  // stopping, nothing left
      std::function<void()> fn = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      fn();
      lock.lock();
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> queue_;
  std::vector<std::thread> threads_;
  std::size_t idle_ = 0;
  bool stopping_ = false;
};

// The body of a JSON request, read up to `limit` bytes: nullopt and `status` 413 beyond it
// (the rest is never read), 400 when the body ends before its declared length.
std::optional<std::string> read_bounded(const httplib::ContentReader& read, std::int64_t limit, int& status) {
  std::string body;
  bool too_large = false;
  const bool whole = read([&](const char* data, std::size_t size) {
    if (static_cast<std::int64_t>(body.size() + size) > limit) {
      too_large = true;
      return false;
    }
    body.append(data, size);
    return true;
  });
  if (whole) return body;
  status = too_large ? 413 : 400;
  return std::nullopt;
}

HttpResponse error_answer(int status, const std::string& message) {
  return detail::Guard::stamped(
      {status, "application/json", nlohmann::ordered_json{{"error", printable_line(message)}}.dump()});
}

}  // namespace

Server::Server(ServeOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  httplib::Server& http = impl_->http;
  App& app = impl_->app;
  const ServeOptions& o = app.options();
  http.new_task_queue = [] { return new ConnectionThreads(); };
  // SO_REUSEADDR only: httplib's default also sets SO_REUSEPORT, with which a second
  // server on the same port binds without error and the kernel splits the connections
  // between the two.
  // The socket is kept to raise its listen backlog once bound (bind()).
  http.set_socket_options([impl = impl_.get()](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const void*>(&yes), sizeof yes);
    impl->socket = sock;
  });
  http.set_keep_alive_timeout(kKeepAliveSeconds);
  http.set_read_timeout(kReadTimeoutSeconds, 0);
  http.set_payload_max_length(static_cast<std::size_t>(std::max(o.max_upload_bytes, o.max_json_bytes)));
  // Before a byte of the body is read: the rules every request passes (guard.h), then the
  // body's declared length against its endpoint's limit; a refused request's connection is
  // closed (its body is never read).
  http.set_pre_routing_handler([&o, &app](const httplib::Request& req, httplib::Response& res) {
    HttpRequest headers_only = request_of(req);
    headers_only.body.clear();
    if (auto refused = app.screen(headers_only)) {
      answer_and_close(res, detail::Guard::stamped(*refused));
      return httplib::Server::HandlerResponse::Handled;
    }
    const std::int64_t length = content_length(req);
    const bool upload = req.path == "/api/upload";
    const std::int64_t limit = upload ? o.max_upload_bytes : o.max_json_bytes;
    if (length == -2 || (length >= 0 && req.has_header("Transfer-Encoding"))) {
      answer_and_close(res, error_answer(400, req.path + ": Content-Length '" + req.get_header_value("Content-Length") +
                                                  "' refused, expected one byte count and no Transfer-Encoding"));
      return httplib::Server::HandlerResponse::Handled;
    }
    if (length <= limit) return httplib::Server::HandlerResponse::Unhandled;
    answer_and_close(res, error_answer(413, req.path + ": the request body has " + std::to_string(length) +
                                                " bytes, expected at most " + std::to_string(limit) +
                                                (upload ? " (--max-upload)" : "")));
    return httplib::Server::HandlerResponse::Handled;
  });
  // An upload streams to its file, counted as it arrives; one that does not arrive whole is
  // removed, never kept.
  http.Post("/api/upload", [&app](const httplib::Request& req, httplib::Response& res,
                                  const httplib::ContentReader& read) {
    HttpResponse refusal;
    auto u = app.begin_upload(req.has_param("name") ? req.get_param_value("name") : "", content_length(req), refusal);
    if (!u) return answer_and_close(res, detail::Guard::stamped(refusal));
    const bool whole = read([&](const char* data, std::size_t size) { return app.append_upload(*u, data, size); });
    const HttpResponse a = detail::Guard::stamped(app.finish_upload(u, whole));
    if (a.status != 200) return answer_and_close(res, a);  // the rest of the body is not read
    answer(res, a);
  });
  // A JSON body is read up to its limit as it arrives (a chunked body has no length to refuse
  // it by beforehand): beyond, 413 and the rest never read.
  http.Post(".*", [&app, &o](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& read) {
    int status = 0;
    const auto body = read_bounded(read, o.max_json_bytes, status);
    if (!body)
      return answer_and_close(
          res, error_answer(status, status == 413 ? req.path + ": the request body has more than " +
                                                        std::to_string(o.max_json_bytes) + " bytes"
                                                  : req.path + ": the request body ended before its last byte"));
    HttpRequest r = request_of(req);
    r.body = *body;
    answer(res, app.handle(r));
  });
  const auto handler = [&app](const httplib::Request& req, httplib::Response& res) {
    answer(res, app.handle(request_of(req)));
  };
  http.Get(".*", handler);
  http.Post(".*", handler);  // a POST without a body
  http.Delete(".*", handler);
  http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown error";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    spdlog::error("serve: {} {}: {}", req.method, req.path, what);
    answer(res, error_answer(500, "internal error"));
  });
}

Server::~Server() { stop(); }

int Server::bind() {
  const ServeOptions& o = impl_->app.options();
  const int port =
      o.port == 0 ? impl_->http.bind_to_any_port(o.host) : (impl_->http.bind_to_port(o.host, o.port) ? o.port : -1);
  if (port <= 0)
    throw InputError("serve: cannot listen on " + o.host + ":" + std::to_string(o.port) +
                     " (in use, or not an address of this machine); choose another --port or --host");
  // httplib 0.11 listens with a backlog of 5: a burst of connections beyond it (a page
  // loading, two tabs, a script) has its handshakes dropped and some requests fail with
  // a reset. listen() again on the bound socket raises the backlog (Linux keeps the socket).
  if (impl_->socket >= 0) ::listen(impl_->socket, kListenBacklog);
  impl_->port = port;
  impl_->app.set_port(port);
  return port;
}

void Server::run() { impl_->http.listen_after_bind(); }

bool Server::running() const { return impl_->http.is_running(); }

void Server::stop() {
  if (impl_->http.is_running()) impl_->http.stop();
}

std::string Server::address() const {
  std::string host = impl_->app.options().host;
  // Listening on every interface: the address to open is loopback's (a wildcard address is
  // no name a request may carry).
  if (host == "0.0.0.0") host = "127.0.0.1";
  if (host == "::" || host == "[::]") host = "::1";
  const bool v6 = host.find(':') != std::string::npos && host.front() != '[';
  return "http://" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(impl_->port) + "/";
}

std::string Server::url() const { return address() + "?token=" + impl_->app.token(); }

App& Server::app() { return impl_->app; }

}  // namespace gmwm::serve
