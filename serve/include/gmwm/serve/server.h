#pragma once
// gmwm serve's HTTP server: an App (app.h) on a TCP port with cpp-httplib (Debian's
// libcpp-httplib-dev). Loopback by default; request bodies bounded before they are read
// (a JSON body beyond ServeOptions::max_json_bytes and an upload beyond max_upload_bytes
// are answered 413 from their Content-Length, and an upload is also counted as it streams
// to its file); the page's requests are served by a pool of threads while the analyses run
// on the App's job workers, so a slow job never holds a request.
//
//   gmwm::serve::Server server(options);   // InputError: bad options or folder
//   const int port = server.bind();        // InputError: the address cannot be bound
//   std::thread t([&] { server.run(); });  // until stop()
//   ...; server.stop(); t.join();

#include <cstddef>
#include <memory>
#include <string>

#include "gmwm/serve/app.h"

namespace gmwm::serve {

/// Connections served at once, a thread each (made as needed, kept for the next ones;
/// beyond, a connection waits for one to end): a browser keeps up to 6 connections per host,
/// so this holds two tabs, scripts and hundreds of slow or hostile clients beside them, and
/// stays below the 1024 descriptors select() can watch.
inline constexpr std::size_t kMaxConnectionThreads = 512;
/// An idle keep-alive connection is closed after this many seconds (frees its thread).
inline constexpr int kKeepAliveSeconds = 2;
/// Connections waiting to be accepted (the kernel caps it at net.core.somaxconn): a
/// hundred clients connecting at once all get through.
inline constexpr int kListenBacklog = 512;
/// A connection on which nothing arrives for this many seconds mid-request (a client gone
/// mid-body or mid-headers) is dropped: a page on loopback never pauses that long.
inline constexpr int kReadTimeoutSeconds = 10;

class Server {
 public:
  /// Throws InputError for invalid options or a folder that is not one.
  explicit Server(ServeOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds the address and port (port 0: a free one); the port bound. InputError when it
  /// cannot be bound (in use, not an address of this machine).
  int bind();
  /// Serves until stop(); call after bind().
  void run();
  /// True while run() serves.
  bool running() const;
  /// Stops run() once it serves (thread-safe; from a signal-waiting thread).
  void stop();
  /// "http://HOST:PORT/" once bound (loopback's address when listening on every interface).
  std::string address() const;
  /// The address to open: address() with the access token, "http://HOST:PORT/?token=T"
  /// (opening it keeps the token in a cookie; docs/serve.md, "Threat model").
  std::string url() const;
  App& app();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gmwm::serve
