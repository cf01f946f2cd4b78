// The web app's hostile corpus (issue 42): crafted requests sent raw to a real server, each
// what a hostile page, a rebound domain, another local user or a broken client can send. Each
// must be refused with its status and, where the app answers, one line naming what was
// expected; none may read a file, open a dataset, start a job or keep an upload; and the
// server must keep answering the page afterwards.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/serve/server.h"
#include "serve_fixture.h"
// Last: <resolv.h>, which it includes, defines a macro `_res` that breaks Eigen's headers.
#include <httplib.h>

namespace gmwm::test {
namespace {

struct HostileRequest {
  std::string name;
  /// The raw request; {HOST} is "127.0.0.1:PORT", {PORT} the port, {TOKEN} the access token,
  /// {COOKIE} the page's cookie line (the browser sends it with every request to the host).
  std::string raw;
  std::set<int> statuses;     ///< any of these
  std::string mentions = {};  ///< in the answer, when not empty
};

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

std::string json_body(const std::string& body) {
  return "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

const std::string kOpen = R"({"file": "imu.csv", "freq": 100})";

std::vector<HostileRequest> corpus() {
  const std::string own = "Host: {HOST}\r\nX-Gmwm-Token: {TOKEN}\r\n";
  const std::string page = "Host: {HOST}\r\n{COOKIE}";
  std::vector<HostileRequest> c = {
      // A rebound domain, or no HTTP/1.1 request at all.
      {"rebound host",
       "GET /api/files HTTP/1.1\r\nHost: evil.example:{PORT}\r\n{COOKIE}\r\n",
       {403},
       "is not this server"},
      {"rebound host posting", "POST /api/open HTTP/1.1\r\nHost: evil.example\r\n{COOKIE}" + json_body(kOpen), {403}},
      {"no host", "GET /api/files HTTP/1.0\r\nX-Gmwm-Token: {TOKEN}\r\n\r\n", {403}},
      {"two hosts", "GET /api/files HTTP/1.1\r\n" + own + "Host: evil.example\r\n\r\n", {403}},
      {"another port", "GET /api/files HTTP/1.1\r\nHost: 127.0.0.1:1\r\nX-Gmwm-Token: {TOKEN}\r\n\r\n", {403}},
      {"absolute URI of another host",
       "GET http://evil.example/api/files HTTP/1.1\r\nHost: evil.example\r\nX-Gmwm-Token: {TOKEN}\r\n\r\n",
       {403, 404, 400}},
      // Another page in the user's browser (the cookie goes along).
      {"foreign origin",
       "POST /api/open HTTP/1.1\r\n" + page + "Origin: http://evil.example\r\n" + json_body(kOpen),
       {403},
       "only this server's own page"},
      {"null origin", "POST /api/open HTTP/1.1\r\n" + page + "Origin: null\r\n" + json_body(kOpen), {403}},
      {"another localhost port",
       "POST /api/open HTTP/1.1\r\n" + page + "Origin: http://127.0.0.1:1\r\n" + json_body(kOpen),
       {403}},
      {"cross-site fetch", "GET /api/files HTTP/1.1\r\n" + page + "Sec-Fetch-Site: cross-site\r\n\r\n", {403}},
      {"same-site fetch", "GET /api/files HTTP/1.1\r\n" + page + "Sec-Fetch-Site: same-site\r\n\r\n", {403}},
      {"preflight", "OPTIONS /api/upload HTTP/1.1\r\n" + page + "Origin: http://evil.example\r\n\r\n", {403, 405}},
      {"text/plain form",
       "POST /api/open HTTP/1.1\r\n" + page +
           "Content-Type: text/plain\r\nContent-Length: " + std::to_string(kOpen.size()) + "\r\n\r\n" + kOpen,
       {415},
       "expected application/json"},
      {"url-encoded form",
       "POST /api/fit HTTP/1.1\r\n" + page +
           "Content-Type: application/x-www-form-urlencoded\r\nContent-Length: 9\r\n\r\nmodel=WN&",
       {415}},
      {"multipart form",
       "POST /api/open HTTP/1.1\r\n" + page + "Content-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
           std::to_string(kOpen.size()) + "\r\n\r\n" + kOpen,
       {415}},
      {"no content type",
       "POST /api/open HTTP/1.1\r\n" + page + "Content-Length: " + std::to_string(kOpen.size()) + "\r\n\r\n" + kOpen,
       {415}},
      {"upload as a form",
       "POST /api/upload?name=planted.csv HTTP/1.1\r\n" + page +
           "Content-Type: text/plain\r\nContent-Length: 4\r\n\r\n0,1\n",
       {415}},
      // Another user of the machine, or a script without the token.
      {"no token", "GET /api/files HTTP/1.1\r\nHost: {HOST}\r\n\r\n", {401}, "needs its access token"},
      {"wrong token",
       "GET /api/files HTTP/1.1\r\nHost: {HOST}\r\nX-Gmwm-Token: 00000000000000000000000000000000\r\n\r\n",
       {401}},
      {"token in the API's query", "GET /api/files?token={TOKEN} HTTP/1.1\r\nHost: {HOST}\r\n\r\n", {401}},
      {"another port's cookie",
       "GET /api/files HTTP/1.1\r\nHost: {HOST}\r\nCookie: gmwm_serve_1={TOKEN}\r\n\r\n",
       {401}},
      {"the page without the token", "GET / HTTP/1.1\r\nHost: {HOST}\r\n\r\n", {401}, "?token="},
      {"upload without the token",
       "POST /api/upload?name=planted.csv HTTP/1.1\r\nHost: {HOST}\r\nContent-Type: application/octet-stream\r\n"
       "Content-Length: 4\r\n\r\n0,1\n",
       {401}},
      // Bodies framed to pass a limit, or to be read as another request.
      {"compressed body", "POST /api/open HTTP/1.1\r\n" + own + "Content-Encoding: gzip\r\n" + json_body(kOpen), {415}},
      {"odd transfer encoding",
       "POST /api/open HTTP/1.1\r\n" + own +
           "Content-Type: application/json\r\nTransfer-Encoding: gzip, chunked\r\n\r\n0\r\n\r\n",
       {400}},
      {"length and chunks (smuggling)",
       "POST /api/open HTTP/1.1\r\n" + own +
           "Content-Type: application/json\r\nContent-Length: 5\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\nGET "
           "/api/files HTTP/1.1\r\n\r\n",
       {400}},
      {"negative length",
       "POST /api/open HTTP/1.1\r\n" + own + "Content-Type: application/json\r\nContent-Length: -1\r\n\r\n{}",
       {400}},
      {"length in exponent",
       "POST /api/open HTTP/1.1\r\n" + own + "Content-Type: application/json\r\nContent-Length: 1e3\r\n\r\n{}",
       {400}},
      {"a put", "PUT /api/open HTTP/1.1\r\n" + own + json_body(kOpen), {405}},
      {"a patch", "PATCH /api/open HTTP/1.1\r\n" + own + json_body(kOpen), {405}},
      {"a get with a body", "GET /api/files HTTP/1.1\r\n" + own + "Content-Length: 4\r\n\r\nabcd", {400}},
      {"a delete with a chunked body",
       "DELETE /api/jobs/j-0 HTTP/1.1\r\n" + own + "Transfer-Encoding: chunked\r\n\r\n4\r\nabcd\r\n0\r\n\r\n",
       {400}},
      {"unknown method", "BREW /api/files HTTP/1.1\r\n" + own + "\r\n", {400, 405}},
      // What the app reads, and what it answers about it.
      {"a hidden file",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(R"({"file": ".env", "freq": 100})"),
       {404},
       "no recording"},
      {"a git config",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(R"({"file": ".git/config", "freq": 100})"),
       {404}},
      {"a file outside",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(R"({"file": "../secret.csv", "freq": 100})"),
       {404}},
      {"an encoded traversal",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(R"({"file": "%2e%2e/secret.csv"})"),
       {404}},
      {"a hidden overlay",
       "POST /api/overlay HTTP/1.1\r\n" + own +
           json_body(R"({"dataset": "d", "column": "gyro_x", "format": "kalibr", "file": ".git/config"})"),
       {404}},
      {"a number beyond a double",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(R"({"file": "imu.csv", "freq": 1e999})"),
       {400},
       "beyond what a double can hold"},
      {"deeply nested JSON",
       "POST /api/open HTTP/1.1\r\n" + own + json_body(std::string(100'000, '[') + std::string(100'000, ']')),
       {400}},
      {"not an object", "POST /api/open HTTP/1.1\r\n" + own + json_body("[]"), {400}, "expected a JSON object"},
      {"a job id that climbs", "GET /api/jobs/../../etc/passwd HTTP/1.1\r\n" + own + "\r\n", {404, 400}},
      {"a ranking row beyond any",
       "GET /api/jobs/j-0/ranking/99999999999999999999999 HTTP/1.1\r\n" + own + "\r\n",
       {404}},
      {"a NUL in the path", "GET /api/jobs/%00 HTTP/1.1\r\n" + own + "\r\n", {404, 400}},
      {"a header line of 64 kB",
       "GET /api/files HTTP/1.1\r\n" + own + "X-Pad: " + std::string(65'536, 'a') + "\r\n\r\n",
       {400, 431, 413}},
      {"an upload name with a NUL",
       "POST /api/upload?name=a%00.csv HTTP/1.1\r\n" + own +
           "Content-Type: application/octet-stream\r\nContent-Length: 4\r\n\r\n0,1\n",
       {400}},
  };
  return c;
}

class ServeHostileRequests : public ServeAppTest, public ::testing::WithParamInterface<HostileRequest> {
 protected:
  void SetUp() override {
    ServeAppTest::SetUp();
    write_text(folder_ / ".env", "API_KEY=sk-live-1234\n");
    std::filesystem::create_directories(folder_ / ".git");
    write_text(folder_ / ".git" / "config", "[remote]\nurl = git@secret.example:x.git\n");
    serve::ServeOptions o;
    o.folder = folder_.string();
    o.upload_root = dir_.string();
    o.port = 0;
    server_ = std::make_unique<serve::Server>(o);
    port_ = server_->bind();
    thread_ = std::thread([this] { server_->run(); });
    for (int i = 0; i < 500 && !server_->running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
    server_.reset();
    ServeAppTest::TearDown();
  }
  // Sends `bytes` on a fresh connection; the first answer (until its Content-Length is read, or
  // the server closes). The connection is not half-closed: cpp-httplib takes a half-closed
  // client for gone and writes nothing, and no browser half-closes.
  std::string send(const std::string& bytes) const {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    timeval tv{10, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::string answer;
    char buf[4096];
    for (ssize_t k; (k = ::recv(fd, buf, sizeof buf, 0)) > 0;) {
      answer.append(buf, static_cast<std::size_t>(k));
      const auto head = answer.find("\r\n\r\n");
      if (head == std::string::npos) continue;
      const auto cl = answer.find("Content-Length: ");
      if (cl == std::string::npos || cl > head) break;
      if (answer.size() >= head + 4 + std::stoul(answer.substr(cl + 16))) break;
    }
    ::close(fd);
    return answer;
  }
  OJson status() {
    httplib::Client c("127.0.0.1", port_);
    c.set_default_headers({{"X-Gmwm-Token", server_->app().token()}});
    const auto r = c.Get("/api/status");
    EXPECT_TRUE(r && r->status == 200);
    return r ? OJson::parse(r->body) : OJson();
  }
  std::unique_ptr<serve::Server> server_;
  std::thread thread_;
  int port_ = 0;
};

TEST_P(ServeHostileRequests, IsRefusedReadsNothingStartsNothingAndTheServerGoesOn) {
  const HostileRequest& h = GetParam();
  const OJson before = status();
  std::string raw = replaced(h.raw, "{HOST}", "127.0.0.1:" + std::to_string(port_));
  raw = replaced(raw, "{PORT}", std::to_string(port_));
  raw = replaced(raw, "{TOKEN}", server_->app().token());
  raw =
      replaced(raw, "{COOKIE}", "Cookie: gmwm_serve_" + std::to_string(port_) + "=" + server_->app().token() + "\r\n");
  const std::string answer = send(raw);
  ASSERT_GE(answer.size(), 12u) << "no answer";
  const int code = std::stoi(answer.substr(9, 3));
  EXPECT_TRUE(h.statuses.count(code)) << "answered " << answer.substr(0, 400);
  if (!h.mentions.empty()) EXPECT_NE(answer.find(h.mentions), std::string::npos) << answer.substr(0, 600);
  for (const std::string secret : {"API_KEY", "secret.example", "\"imu.csv\"", "\"dataset\"", "\"job\"", "\"upload\""})
    EXPECT_EQ(answer.find(secret), std::string::npos) << secret << " in " << answer.substr(0, 600);
  EXPECT_EQ(answer.find(dir_.string()), std::string::npos) << "a path of the machine: " << answer.substr(0, 600);
  // A refusal the app gives is one JSON line (or the token page).
  const auto body_at = answer.find("\r\n\r\n");
  if (answer.find("application/json") != std::string::npos && body_at != std::string::npos) {
    const OJson e = OJson::parse(answer.substr(body_at + 4));
    EXPECT_EQ(e.at("error").get<std::string>().find('\n'), std::string::npos);
  }
  EXPECT_EQ(status(), before) << "the app holds something it did not before";
  // The page's own requests are still answered.
  httplib::Client c("127.0.0.1", port_);
  c.set_default_headers({{"X-Gmwm-Token", server_->app().token()}});
  const auto files = c.Get("/api/files");
  ASSERT_TRUE(files);
  EXPECT_EQ(files->status, 200);
}

INSTANTIATE_TEST_SUITE_P(Corpus, ServeHostileRequests, ::testing::ValuesIn(corpus()), [](const auto& info) {
  std::string name;
  bool up = true;
  for (const char ch : info.param.name) {
    if (std::isalnum(static_cast<unsigned char>(ch))) {
      name += up ? static_cast<char>(std::toupper(static_cast<unsigned char>(ch))) : ch;
      up = false;
    } else {
      up = true;
    }
  }
  return name;
});

}  // namespace
}  // namespace gmwm::test
