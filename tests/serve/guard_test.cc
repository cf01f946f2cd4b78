// The rules every request to the web app passes (serve/src/guard.h, docs/serve.md "Threat
// model"): what a hostile page in the user's browser, a rebound domain or another local
// user can send, and that none of it reads a file or starts a job.

#include <map>
#include <string>

#include <gtest/gtest.h>

#include "serve_fixture.h"

namespace gmwm::test {
namespace {

std::string error_of(const serve::HttpResponse& r) { return OJson::parse(r.body).value("error", std::string()); }

class ServeGuardTest : public ServeAppTest {
 protected:
  // A request as the page sends it, with `changes` to its headers (an empty value removes one).
  serve::HttpResponse send(const std::string& method, const std::string& path,
                           const std::map<std::string, std::string>& changes, const std::string& body = {}) {
    std::map<std::string, std::string> h = page_headers();
    for (const auto& [k, v] : changes) {
      if (v.empty())
        h.erase(k);
      else
        h[k] = v;
    }
    return app().handle({method, path, {}, body, h});
  }
};

TEST_F(ServeGuardTest, ARequestWhoseHostIsNotThisServerIsRefusedWhateverItAsks) {
  // A page whose domain was made to resolve to 127.0.0.1 (DNS rebinding) sends its own name.
  for (const std::string host : {"evil.example", "evil.example:8080", "127.0.0.1:9999", "localhost.evil.example:8080",
                                 "127.0.0.1:8080.evil.example", "127.0.0.1:8080, evil.example", "[::1", "::1:8080",
                                 "127.0.0.1:", "127.0.0.1:+8080"}) {
    for (const auto& [method, path] :
         std::map<std::string, std::string>{{"GET", "/api/files"}, {"POST", "/api/open"}}) {
      const serve::HttpResponse r = send(method, path, {{"host", host}}, OJson{{"file", "imu.csv"}}.dump());
      EXPECT_EQ(r.status, 403) << host << " " << method << " " << path << ": " << r.body;
      EXPECT_EQ(r.body.find("imu.csv"), std::string::npos) << "nothing of the folder: " << r.body;
      EXPECT_NE(error_of(r).find("is not this server"), std::string::npos) << r.body;
    }
  }
  // No Host at all (HTTP/1.0, a raw socket) is no browser's request to this server either.
  EXPECT_EQ(send("GET", "/api/files", {{"host", ""}}).status, 403);
  // The page itself is refused too: a rebound page cannot load it.
  EXPECT_EQ(send("GET", "/", {{"host", "evil.example:8080"}}).status, 403);
}

TEST_F(ServeGuardTest, TheLoopbackNamesWithThePortAndTheAllowedHostsAreThisServer) {
  serve::ServeOptions o;
  o.allowed_hosts = {"workstation.lab"};
  app(o);
  for (const std::string host :
       {"127.0.0.1:8080", "localhost:8080", "LocalHost:8080", "[::1]:8080", "workstation.lab:8080"})
    EXPECT_EQ(send("GET", "/api/files", {{"host", host}}).status, 200) << host;
  EXPECT_EQ(send("GET", "/api/files", {{"host", "workstation.lab:8081"}}).status, 403) << "another port";
  // Once the server has bound another port, that port is the one named.
  app().set_port(43210);
  EXPECT_EQ(send("GET", "/api/files", {{"host", "localhost:43210"}}).status, 200);
  EXPECT_EQ(send("GET", "/api/files", {{"host", "localhost:8080"}}).status, 403);
}

TEST_F(ServeGuardTest, EveryAnswerRefusalsIncludedForbidsCachingAndSniffing) {
  for (const serve::HttpResponse& r : {send("GET", "/api/files", {}), send("GET", "/api/files", {{"host", "evil"}}),
                                       send("GET", "/", {}), send("POST", "/api/open", {}, "{")}) {
    std::map<std::string, std::string> h(r.headers.begin(), r.headers.end());
    EXPECT_EQ(h["Cache-Control"], "no-store") << r.status;
    EXPECT_EQ(h["X-Content-Type-Options"], "nosniff") << r.status;
  }
}

}  // namespace
}  // namespace gmwm::test
