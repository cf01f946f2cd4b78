#include "gmwm/serve/server.h"

#include <httplib.h>

#include <algorithm>
#include <cctype>

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
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
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
  res.set_content_provider(body->size(), a.content_type.c_str(),
                           [body](std::size_t offset, std::size_t, httplib::DataSink& sink) {
                             sink.write(body->data() + offset, body->size() - offset);
                             return false;
                           });
}

std::int64_t content_length(const httplib::Request& req) {
  if (!req.has_header("Content-Length")) return -1;
  try {
    return std::stoll(req.get_header_value("Content-Length"));
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace

Server::Server(ServeOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  httplib::Server& http = impl_->http;
  App& app = impl_->app;
  const ServeOptions& o = app.options();
  http.new_task_queue = [] { return new httplib::ThreadPool(kHttpThreads); };
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
  // Bodies beyond their endpoint's limit are refused from their declared length, before a
  // byte of them is read; the connection is then closed (the unread body cannot be skipped).
  http.set_pre_routing_handler([&o, &app](const httplib::Request& req, httplib::Response& res) {
    // The rules every request passes (guard.h), on its headers alone: a refused request's
    // body is never read.
    HttpRequest headers_only = request_of(req);
    headers_only.body.clear();
    if (auto refused = app.screen(headers_only)) {
      answer_and_close(res, detail::Guard::stamped(*refused));
      return httplib::Server::HandlerResponse::Handled;
    }
    const std::int64_t length = content_length(req);
    const bool upload = req.path == "/api/upload";
    const std::int64_t limit = upload ? o.max_upload_bytes : o.max_json_bytes;
    if (length <= limit) return httplib::Server::HandlerResponse::Unhandled;
    const nlohmann::ordered_json error = {{"error", printable_line(req.path + ": the request body has " + std::to_string(length) +
                                                           " bytes, expected at most " + std::to_string(limit) +
                                                           (upload ? " (--max-upload)" : ""))}};
    answer_and_close(res, detail::Guard::stamped({413, "application/json", error.dump()}));
    return httplib::Server::HandlerResponse::Handled;
  });
  http.Post("/api/upload", [&app](const httplib::Request& req, httplib::Response& res,
                                  const httplib::ContentReader& read) {
    HttpResponse refusal;
    auto u = app.begin_upload(req.has_param("name") ? req.get_param_value("name") : "", content_length(req), refusal);
    if (!u) return answer_and_close(res, detail::Guard::stamped(refusal));
    read([&](const char* data, std::size_t size) { return app.append_upload(*u, data, size); });
    const HttpResponse a = detail::Guard::stamped(app.finish_upload(u));
    if (a.status != 200) return answer_and_close(res, a);  // the rest of the body is not read
    answer(res, a);
  });
  const auto handler = [&app](const httplib::Request& req, httplib::Response& res) {
    answer(res, app.handle(request_of(req)));
  };
  http.Get(".*", handler);
  http.Post(".*", handler);
  http.Delete(".*", handler);
  http.Put(".*", handler);
  http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown error";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    spdlog::error("serve: {} {}: {}", req.method, req.path, what);
    answer(res, detail::Guard::stamped({500, "application/json", "{\"error\":\"internal error\"}"}));
  });
}

Server::~Server() { stop(); }

int Server::bind() {
  const ServeOptions& o = impl_->app.options();
  const int port = o.port == 0 ? impl_->http.bind_to_any_port(o.host) : (impl_->http.bind_to_port(o.host, o.port) ? o.port : -1);
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
