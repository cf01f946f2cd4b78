// The web app on a real loopback socket (serve/server.h): what a hostile or careless client
// can send (raw traversal in the URL, an oversized body, a hundred requests at once, a
// connection dropped mid-request) and that the server keeps serving through all of it.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/engine/error.h"
#include "gmwm/serve/server.h"
#include "serve_fixture.h"
// Last: <resolv.h>, which it includes, defines a macro `_res` that breaks Eigen's headers.
#include <httplib.h>

namespace gmwm::test {
namespace {

// A server on a free loopback port, serving on its own thread for the test's duration.
class ServeServerTest : public ServeAppTest {
 protected:
  void start(serve::ServeOptions o = {}) {
    o.folder = folder_.string();
    o.upload_root = dir_.string();
    o.port = 0;
    server_ = std::make_unique<serve::Server>(o);
    port_ = server_->bind();
    thread_ = std::thread([this] { server_->run(); });
    for (int i = 0; i < 500 && !server_->running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_TRUE(server_->running());
  }
  void TearDown() override {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
    server_.reset();
    ServeAppTest::TearDown();
  }
  // A client that sends the access token, as a script does.
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(60, 0);
    c.set_default_headers({{"X-Gmwm-Token", server_->app().token()}});
    return c;
  }
  // The header lines of a request the app takes: a Host naming the server, its access token.
  std::string host_line() const {
    return "Host: 127.0.0.1:" + std::to_string(port_) + "\r\nX-Gmwm-Token: " + server_->app().token() + "\r\n";
  }
  // Sends raw bytes on a fresh connection; what the server answered (until it closes or
  // `read_answer` is false).
  std::string raw(const std::string& bytes, bool read_answer = true) const {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL), static_cast<ssize_t>(bytes.size()));
    std::string answer;
    if (read_answer) {
      timeval tv{10, 0};
      ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
      char buf[4096];
      for (ssize_t k; (k = ::recv(fd, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(k));
    }
    ::close(fd);
    return answer;
  }
  std::unique_ptr<serve::Server> server_;
  std::thread thread_;
  int port_ = 0;
};

TEST_F(ServeServerTest, ListensOnLoopbackByDefaultAndRefusesAPortInUseWithOneLine) {
  start();
  EXPECT_EQ(server_->address(), "http://127.0.0.1:" + std::to_string(port_) + "/");
  EXPECT_EQ(server_->url(), server_->address() + "?token=" + server_->app().token());
  serve::ServeOptions o;
  o.folder = folder_.string();
  o.port = port_;
  serve::Server second(o);
  try {
    second.bind();
    ADD_FAILURE() << "the port is in use";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(port_)), std::string::npos)
        << e.what();
  }
}

TEST_F(ServeServerTest, RawTraversalInTheUrlOrTheBodyReadsNothingOutsideTheFolder) {
  start();
  for (const std::string path : {"/../secret.csv", "/%2e%2e/secret.csv", "/%2E%2E%2Fsecret.csv", "/..%2fsecret.csv",
                                 "/api/../../secret.csv", "//etc/passwd"}) {
    const std::string a = raw("GET " + path + " HTTP/1.1\r\n" + host_line() + "Connection: close\r\n\r\n");
    EXPECT_EQ(a.find("0.01,2"), std::string::npos) << path << " read the file outside: " << a;
    EXPECT_TRUE(a.rfind("HTTP/1.1 404", 0) == 0 || a.rfind("HTTP/1.1 400", 0) == 0) << path << ": " << a.substr(0, 40);
  }
  auto c = client();
  const auto r = c.Post("/api/open", R"({"file": "..%2Fsecret.csv"})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_EQ(c.Get("/api/files")->status, 200);
}

TEST_F(ServeServerTest, ARebindingHostIsRefusedOnItsHeadersAndTheConnectionClosedWithItsBodyUnread) {
  start();
  // A body that would be valid, sent after the headers: the answer comes from the headers and
  // the connection is closed (the server does not read on into the body as further requests).
  const std::string body = OJson{{"file", "imu.csv"}}.dump();
  const std::string a = raw(
      "POST /api/open HTTP/1.1\r\nHost: evil.example:" + std::to_string(port_) +
      "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size() + 100) + "\r\n\r\n" + body);
  EXPECT_EQ(a.rfind("HTTP/1.1 403", 0), 0u) << a;
  EXPECT_NE(a.find("is not this server"), std::string::npos) << a;
  EXPECT_EQ(a.find("dataset"), std::string::npos) << a;
  EXPECT_EQ(a.find("HTTP/1.1", 10), std::string::npos) << "one answer, then the connection closed: " << a;
  // The same through a client that keeps its connection: refused, and the listing unread.
  httplib::Client evil("127.0.0.1", port_);
  evil.set_default_headers({{"Host", "evil.example"}});
  const auto r = evil.Get("/api/files");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403);
  EXPECT_EQ(r->body.find("imu.csv"), std::string::npos) << r->body;
}

TEST_F(ServeServerTest, AFormPostedByAnotherPageIsRefusedOnItsHeadersAndStartsNothing) {
  start();
  // What a page elsewhere makes the browser send: the app's cookie goes along (cookies do not
  // tell ports apart), with the page's Origin and a form's type.
  const std::string cookie = "Cookie: gmwm_serve_" + std::to_string(port_) + "=" + server_->app().token() + "\r\n";
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port_) + "\r\n";
  const std::string body = OJson{{"file", "imu.csv"}}.dump();
  for (const std::string& headers :
       {host + cookie + "Origin: http://evil.example\r\nContent-Type: text/plain\r\n",
        host + cookie + "Origin: http://127.0.0.1:1\r\nSec-Fetch-Site: same-site\r\nContent-Type: application/json\r\n",
        host + cookie + "Content-Type: application/x-www-form-urlencoded\r\n"}) {
    const std::string a = raw("POST /api/open HTTP/1.1\r\n" + headers +
                              "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    EXPECT_TRUE(a.rfind("HTTP/1.1 403", 0) == 0 || a.rfind("HTTP/1.1 415", 0) == 0) << a;
    EXPECT_EQ(a.find("dataset"), std::string::npos) << a;
  }
  // An upload without the token, chunked: refused on its headers, its body never read.
  const std::string u = raw("POST /api/upload?name=x.csv HTTP/1.1\r\n" + host +
                            "Content-Type: application/octet-stream\r\nTransfer-Encoding: chunked\r\n\r\n"
                            "10\r\ntimestamp,gyro_x\n\r\n");
  EXPECT_EQ(u.rfind("HTTP/1.1 401", 0), 0u) << u;
  EXPECT_EQ(u.find("\"upload\""), std::string::npos) << u;
  std::size_t kept = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir_))
    kept += e.path().filename().string().find("x.csv") != std::string::npos;
  EXPECT_EQ(kept, 0u) << "no upload was stored";
}

TEST_F(ServeServerTest, AChunkedJsonBodyIsReadOnlyUpToItsLimitAndAChunkedUploadCutShortIsNotKept) {
  serve::ServeOptions o;
  o.max_json_bytes = 100'000;
  start(o);
  // 100 chunks of 10 kB, no length declared: refused once past 100 kB, the rest never read.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port_));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  const std::string head = "POST /api/fit HTTP/1.1\r\n" + host_line() +
                           "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
  ::send(fd, head.data(), head.size(), MSG_NOSIGNAL);
  const std::string chunk = "2710\r\n" + std::string(10'000, ' ') + "\r\n";
  std::size_t sent = 0;
  for (int k = 0; k < 100; ++k) {
    if (::send(fd, chunk.data(), chunk.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(chunk.size())) break;
    sent += chunk.size();
  }
  timeval tv{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::string answer;
  char buf[4096];
  for (ssize_t k; (k = ::recv(fd, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(k));
  ::close(fd);
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer.substr(0, 300);
  EXPECT_NE(answer.find("more than 100000 bytes"), std::string::npos) << answer;
  // An upload whose client goes away mid-chunk: nothing of it stays.
  raw("POST /api/upload?name=dropped.csv HTTP/1.1\r\n" + host_line() +
          "Content-Type: application/octet-stream\r\nTransfer-Encoding: chunked\r\n\r\n4e20\r\n" +
          std::string(5000, '1'),
      false);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::size_t kept = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir_))
    kept += e.path().filename().string().find("dropped.csv") != std::string::npos;
  EXPECT_EQ(kept, 0u) << "the partial upload was kept";
  // A length that is no byte count is refused.
  const std::string bad = raw("POST /api/fit HTTP/1.1\r\n" + host_line() +
                              "Content-Type: application/json\r\nContent-Length: 1e3\r\n\r\n{}");
  EXPECT_EQ(bad.rfind("HTTP/1.1 400", 0), 0u) << bad;
}

TEST_F(ServeServerTest, SixtySlowClientsHoldingTheirConnectionsLeaveThePageAnsweredWithinASecond) {
  start();
  // Each sends half a request line and waits (cpp-httplib's fixed 16 threads were all held by
  // such clients while the page's requests queued behind them).
  std::vector<int> slow;
  for (int k = 0; k < 60; ++k) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    const std::string part = k % 2 ? "GET /api/fi" : "POST /api/upload HTTP/1.1\r\n" + host_line();
    ::send(fd, part.data(), part.size(), MSG_NOSIGNAL);
    slow.push_back(fd);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  auto c = client();
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = c.Get("/api/files");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_LT(seconds, 1.0);
  for (const int fd : slow) ::close(fd);
}

TEST_F(ServeServerTest, AnOversizedBodyIsRefusedFromItsLengthWithoutBeingRead) {
  serve::ServeOptions o;
  o.max_upload_bytes = 1'000'000;
  start(o);
  // The headers alone claim 2 GB: the answer comes at once, and no byte of the body is sent.
  const auto t0 = std::chrono::steady_clock::now();
  const std::string a = raw("POST /api/upload?name=big.csv HTTP/1.1\r\n" + host_line() +
                            "Content-Type: application/octet-stream\r\n"
                            "Content-Length: 2000000000\r\n\r\n");
  EXPECT_EQ(a.rfind("HTTP/1.1 413", 0), 0u) << a.substr(0, 200);
  EXPECT_NE(a.find("more than the limit") == std::string::npos ? a.find("expected at most 1000000") : 0,
            std::string::npos)
      << a;
  const std::string j = raw("POST /api/fit HTTP/1.1\r\n" + host_line() +
                            "Content-Type: application/json\r\n"
                            "Content-Length: 5000000\r\n\r\n{");
  EXPECT_EQ(j.rfind("HTTP/1.1 413", 0), 0u) << j.substr(0, 200);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  // An upload within the limit goes through the socket and opens.
  auto c = client();
  const std::string bytes = read_text(folder_ / "imu.csv");
  const auto u = c.Post("/api/upload?name=imu.csv", bytes, "application/octet-stream");
  ASSERT_TRUE(u);
  ASSERT_EQ(u->status, 200) << u->body;
  const std::string id = OJson::parse(u->body).at("upload");
  const auto o2 = c.Post("/api/open", OJson{{"upload", id}}.dump(), "application/json");
  ASSERT_TRUE(o2);
  EXPECT_EQ(o2->status, 200) << o2->body;
}

TEST_F(ServeServerTest, KeepsServingAHundredConcurrentRequestsAndAClientThatDropsMidRequest) {
  start();
  auto c = client();
  const auto o = c.Post("/api/open", R"({"file": "imu.csv"})", "application/json");
  ASSERT_TRUE(o);
  const std::string d = OJson::parse(o->body).at("dataset");
  // Clients that go away: mid-body, mid-headers, and right after submitting a long job.
  raw("POST /api/fit HTTP/1.1\r\n" + host_line() +
          "Content-Type: application/json\r\nContent-Length: 500\r\n\r\n{\"data",
      false);
  raw("GET /api/fi", false);
  raw("POST /api/select HTTP/1.1\r\n" + host_line() + "Content-Type: application/json\r\nContent-Length: " +
          std::to_string(OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "3*AR1+WN+RW+QN+DR"}}.dump().size()) +
          "\r\n\r\n" + OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "3*AR1+WN+RW+QN+DR"}}.dump(),
      false);
  std::atomic<int> ok{0}, failed{0};
  std::mutex m;
  std::vector<std::string> why;
  std::vector<std::thread> clients;
  for (int k = 0; k < 100; ++k)
    clients.emplace_back([&, k] {
      httplib::Client cl = client();
      httplib::Result r =
          k % 4 == 0   ? cl.Get("/api/files")
          : k % 4 == 1 ? cl.Get("/")
          : k % 4 == 2 ? cl.Post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN+RW"}}.dump(),
                                 "application/json")
                       : cl.Post("/api/fit", "{broken", "application/json");
      // A burst of 25 fits beyond the analyses' queue (16 waiting) is told to retry (429).
      if (r && (r->status == 200 || (k % 4 == 3 && r->status == 400) || (k % 4 == 2 && r->status == 429))) {
        ++ok;
      } else {
        ++failed;
        std::lock_guard lock(m);
        why.push_back(std::to_string(k) + ": " +
                      (r ? std::to_string(r->status) + " " + r->body : httplib::to_string(r.error())));
      }
    });
  for (auto& t : clients) t.join();
  EXPECT_EQ(ok.load(), 100);
  for (const std::string& w : why) ADD_FAILURE() << w;
  // A job submitted after the storm finishes (once the queue has room again).
  const auto submit = [&] {
    return c.Post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN+RW"}}.dump(),
                  "application/json");
  };
  httplib::Result f = submit();
  for (int i = 0; i < 600 && f && f->status == 429; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    f = submit();
  }
  ASSERT_TRUE(f);
  ASSERT_EQ(f->status, 200) << f->body;
  const std::string job = OJson::parse(f->body).at("job");
  for (int i = 0; i < 3000; ++i) {
    const auto s = c.Get("/api/jobs/" + job);
    ASSERT_TRUE(s);
    if (OJson::parse(s->body).at("state") == "done") return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << "the fit after the storm did not finish";
}

}  // namespace
}  // namespace gmwm::test
