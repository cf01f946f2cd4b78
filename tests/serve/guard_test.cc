// The rules every request to the web app passes (serve/src/guard.h, docs/serve.md "Threat
// model"): what a hostile page in the user's browser, a rebound domain or another local
// user can send, and that none of it reads a file or starts a job.

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

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
    std::map<std::string, std::string> h = page_headers(method, path);
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
  const std::string token = app().token();
  EXPECT_EQ(send("GET", "/api/files", {{"host", "localhost:43210"}, {"x-gmwm-token", token}}).status, 200);
  EXPECT_EQ(send("GET", "/api/files", {{"host", "localhost:8080"}, {"x-gmwm-token", token}}).status, 403);
}

TEST_F(ServeGuardTest, ARequestFromAnotherPageIsRefusedByItsOriginOrFetchSite) {
  const std::string open = OJson{{"file", "imu.csv"}}.dump();
  // Another site, another port of localhost (the same site, not the same origin), a sandboxed
  // frame or a file, https on the app's port.
  for (const std::string origin : {"http://evil.example", "http://127.0.0.1:9999", "null", "https://127.0.0.1:8080",
                                   "http://127.0.0.1:8080/x", "http://evil.example:8080"}) {
    for (const std::string& method : {std::string("GET"), std::string("POST")}) {
      const std::string path = method == "GET" ? "/api/files" : "/api/open";
      const serve::HttpResponse r = send(method, path, {{"origin", origin}}, open);
      EXPECT_EQ(r.status, 403) << origin << " " << method << ": " << r.body;
      EXPECT_EQ(r.body.find("imu.csv"), std::string::npos) << r.body;
      EXPECT_NE(error_of(r).find("is refused (only this server's own page"), std::string::npos) << r.body;
    }
  }
  for (const std::string site : {"same-site", "cross-site"}) {
    const serve::HttpResponse r = send("POST", "/api/open", {{"sec-fetch-site", site}, {"origin", ""}}, open);
    EXPECT_EQ(r.status, 403) << site << ": " << r.body;
    EXPECT_NE(error_of(r).find("Sec-Fetch-Site: " + site), std::string::npos) << r.body;
  }
  // The page's own origin, under each of its names.
  EXPECT_EQ(send("POST", "/api/open", {{"origin", "http://localhost:8080"}, {"host", "localhost:8080"}}, open).status,
            200);
  EXPECT_EQ(send("POST", "/api/open", {}, open).status, 200);
}

TEST_F(ServeGuardTest, AFormThatAnyPageCanPostWithoutAskingIsRefusedAndOpensNothing) {
  // What <form enctype=...> sends, and no type at all; the body would be valid JSON.
  const std::string open = OJson{{"file", "imu.csv"}}.dump();
  for (const std::string type : {"text/plain", "text/plain;charset=UTF-8", "application/x-www-form-urlencoded",
                                 "multipart/form-data; boundary=x", "none"}) {
    const serve::HttpResponse r = send("POST", "/api/open", {{"content-type", type == "none" ? "" : type}}, open);
    EXPECT_EQ(r.status, 415) << type << ": " << r.body;
    EXPECT_EQ(r.body.find("dataset"), std::string::npos) << r.body;
    EXPECT_NE(error_of(r).find("expected application/json"), std::string::npos) << r.body;
  }
  EXPECT_EQ(send("POST", "/api/open", {{"content-type", "Application/JSON; charset=utf-8"}}, open).status, 200);
  // An upload sent as a form is refused too, and nothing is kept.
  const serve::HttpResponse u =
      app().handle({"POST", "/api/upload", {{"name", "x.csv"}}, "timestamp,gyro_x\n0,1\n", [&] {
                      auto h = page_headers("POST", "/api/upload");
                      h["content-type"] = "text/plain";
                      return h;
                    }()});
  EXPECT_EQ(u.status, 415) << u.body;
  EXPECT_NE(error_of(u).find("expected application/octet-stream"), std::string::npos) << u.body;
  // A compressed body would expand beyond every limit before it is counted.
  const serve::HttpResponse z = send("POST", "/api/open", {{"content-encoding", "gzip"}}, open);
  EXPECT_EQ(z.status, 415) << z.body;
  EXPECT_EQ(send("POST", "/api/open", {{"transfer-encoding", "gzip, chunked"}}, open).status, 400);
}

TEST_F(ServeGuardTest, EveryRequestButThePagesStaticFilesNeedsTheLaunchsToken) {
  const std::string open = OJson{{"file", "imu.csv"}}.dump();
  // Another local user, or a script that never saw the start-up line.
  for (const auto& [method, path] : std::vector<std::pair<std::string, std::string>>{{"GET", "/api/files"},
                                                                                     {"POST", "/api/open"},
                                                                                     {"GET", "/api/jobs/j-0"},
                                                                                     {"DELETE", "/api/jobs/j-0"},
                                                                                     {"POST", "/api/upload"},
                                                                                     {"GET", "/api/nothing"}}) {
    for (const auto& wrong :
         std::vector<std::map<std::string, std::string>>{{{"cookie", ""}},
                                                         {{"cookie", "gmwm_serve_8080=" + std::string(32, '0')}},
                                                         {{"cookie", "gmwm_serve_9090=" + app().token()}},
                                                         {{"cookie", "gmwm_serve_8080=" + app().token() + "x"}},
                                                         {{"cookie", ""}, {"x-gmwm-token", app().token().substr(1)}}}) {
      const serve::HttpResponse r = send(method, path, wrong, open);
      EXPECT_EQ(r.status, 401) << method << " " << path << ": " << r.body;
      EXPECT_NE(error_of(r).find("needs its access token"), std::string::npos) << r.body;
    }
  }
  // A script's header, or a bearer token, instead of the cookie.
  EXPECT_EQ(send("GET", "/api/files", {{"cookie", ""}, {"x-gmwm-token", app().token()}}).status, 200);
  EXPECT_EQ(send("GET", "/api/files", {{"cookie", ""}, {"authorization", "Bearer " + app().token()}}).status, 200);
  // The page: without the token it says which address to open; with the start-up address's
  // token it keeps the token in a cookie of this port and leaves the address bar.
  const serve::HttpResponse bare = send("GET", "/", {{"cookie", ""}});
  EXPECT_EQ(bare.status, 401);
  EXPECT_EQ(bare.content_type, "text/html; charset=utf-8");
  EXPECT_NE(bare.body.find("?token="), std::string::npos) << bare.body;
  EXPECT_EQ(bare.body.find(app().token()), std::string::npos) << "the page never shows the token";
  auto h = page_headers();
  h.erase("cookie");
  const serve::HttpResponse in = app().handle({"GET", "/", {{"token", app().token()}}, {}, h});
  EXPECT_EQ(in.status, 303);
  std::map<std::string, std::string> ih(in.headers.begin(), in.headers.end());
  EXPECT_EQ(ih["Location"], "/");
  EXPECT_EQ(ih["Set-Cookie"], "gmwm_serve_8080=" + app().token() + "; Path=/; HttpOnly; SameSite=Strict");
  // One hex digit changed (never the same digit: a drawn token starts with '0' one time in 16).
  std::string near = app().token();
  near[0] = near[0] == '0' ? '1' : '0';
  EXPECT_EQ(app().handle({"GET", "/", {{"token", near}}, {}, h}).status, 401);
  // The page's static files carry nothing of the user's.
  for (const std::string f : {"/app.js", "/app.css", "/favicon.ico"})
    EXPECT_LT(send("GET", f, {{"cookie", ""}}).status, 300) << f;
  // A drawn token: 128 bits as hex, a fresh one each launch.
  EXPECT_EQ(app().token().size(), 32u);
  EXPECT_EQ(app().token().find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_NE(serve::App(app().options()).token(), app().token());
}

TEST_F(ServeGuardTest, AChosenTokenIsUsedAndAWeakOneRefusedByTheOptions) {
  serve::ServeOptions o;
  o.folder = folder_.string();
  o.token = "short";
  EXPECT_NE(o.Validate().find("token: expected at least 16"), std::string::npos) << o.Validate();
  o.token = "sixteen-chars-ok";
  EXPECT_EQ(o.Validate(), "");
  o.token = "sixteen chars no";
  EXPECT_NE(o.Validate(), "");
  o.token = "a-script's-own-token-0123";
  EXPECT_NE(o.Validate(), "");
  o.token = "a_scripts_own_token_0123";
  app(o);
  EXPECT_EQ(app().token(), "a_scripts_own_token_0123");
  EXPECT_EQ(send("GET", "/api/files", {{"cookie", ""}, {"x-gmwm-token", "a_scripts_own_token_0123"}}).status, 200);
}

TEST_F(ServeGuardTest, OnlyRecordingsAndConfigsThatAreNotHiddenAreListedOrOpened) {
  namespace fs = std::filesystem;
  write_text(folder_ / ".env", "API_KEY=sk-live-1234\n");
  fs::create_directories(folder_ / ".git");
  write_text(folder_ / ".git" / "config", "[remote \"origin\"]\n\turl = git@secret.example:x.git\n");
  write_text(folder_ / ".git" / "log.csv", "API_KEY,1\n");
  fs::create_directories(folder_ / ".hidden");
  fs::copy_file(folder_ / "imu.csv", folder_ / ".hidden" / "imu.csv");
  write_text(folder_ / "notes.md", "API_KEY=in-notes\n");
  write_text(folder_ / "id_rsa", "API_KEY=key\n");
  fs::create_symlink(folder_ / ".env", folder_ / "env.csv");  // a recording's name, a hidden file's bytes
  fs::create_symlink(folder_ / "notes.md", folder_ / "notes.yaml");
  const OJson listing = body_of(get("/api/files"));
  EXPECT_EQ(listing.dump().find("env"), std::string::npos) << listing.dump();
  EXPECT_EQ(listing.dump().find("hidden"), std::string::npos) << listing.dump();
  EXPECT_EQ(listing.dump().find("notes"), std::string::npos) << listing.dump();
  EXPECT_EQ(listing.at("folder"), "recordings") << "the folder's own name, not the machine's path";
  for (const std::string name : {".env", ".git/config", ".git/log.csv", ".hidden/imu.csv", "notes.md", "id_rsa",
                                 "env.csv", "./.env", "sub/../.env"}) {
    const serve::HttpResponse r = post("/api/open", OJson{{"file", name}, {"freq", 100}});
    EXPECT_EQ(r.status, 404) << name << ": " << r.body;
    EXPECT_EQ(r.body.find("API_KEY"), std::string::npos) << name << " was read: " << r.body;
    EXPECT_EQ(r.body.find("secret.example"), std::string::npos) << name << " was read: " << r.body;
  }
  const std::string d = open_imu();
  for (const std::string name : {".env", ".git/config", "notes.yaml", "notes.md"}) {
    const serve::HttpResponse r =
        post("/api/overlay", OJson{{"dataset", d}, {"column", "gyro_x"}, {"format", "kalibr"}, {"file", name}});
    EXPECT_EQ(r.status, 404) << name << ": " << r.body;
    EXPECT_EQ(r.body.find("API_KEY"), std::string::npos) << r.body;
  }
}

TEST_F(ServeGuardTest, NoAnswerNamesAPathOfTheMachine) {
  write_text(folder_ / "broken.yaml", "accelerometer_noise_density: [\n");
  write_text(folder_ / "text.csv", "timestamp,gyro_x\n0,abc\n");
  const std::string d = open_imu();
  const std::vector<serve::HttpResponse> answers = {
      post("/api/overlay", OJson{{"dataset", d}, {"column", "gyro_x"}, {"format", "kalibr"}, {"file", "broken.yaml"}}),
      post("/api/open", OJson{{"file", "text.csv"}, {"freq", 100}}),
      post("/api/open", OJson{{"file", "sub/../../recordings/imu.csv/x"}}), get("/api/files")};
  for (const serve::HttpResponse& r : answers) {
    EXPECT_EQ(r.body.find(dir_.string()), std::string::npos) << r.body;
    EXPECT_EQ(r.body.find(std::filesystem::canonical(dir_).string()), std::string::npos) << r.body;
  }
  EXPECT_EQ(answers[0].status, 400) << answers[0].body;
  EXPECT_NE(error_of(answers[0]).find("broken.yaml"), std::string::npos)
      << "named as the page names it: " << answers[0].body;
  EXPECT_EQ(answers[1].status, 400) << answers[1].body;
  EXPECT_NE(error_of(answers[1]).find("text.csv"), std::string::npos) << answers[1].body;
}

TEST_F(ServeGuardTest, EveryAnswerRefusalsIncludedForbidsCachingSniffingFramingAndForeignScripts) {
  for (const serve::HttpResponse& r : {send("GET", "/api/files", {}), send("GET", "/api/files", {{"host", "evil"}}),
                                       send("GET", "/", {}), send("POST", "/api/open", {}, "{")}) {
    std::map<std::string, std::string> h(r.headers.begin(), r.headers.end());
    EXPECT_EQ(h["Cache-Control"], "no-store") << r.status;
    EXPECT_EQ(h["X-Content-Type-Options"], "nosniff") << r.status;
    EXPECT_EQ(h["X-Frame-Options"], "DENY") << r.status;
    EXPECT_EQ(h["Cross-Origin-Resource-Policy"], "same-origin") << r.status;
    EXPECT_EQ(h["Referrer-Policy"], "no-referrer") << r.status;
    const std::string csp = h["Content-Security-Policy"];
    EXPECT_NE(csp.find("frame-ancestors 'none'"), std::string::npos) << csp;
    EXPECT_NE(csp.find("script-src 'self' 'unsafe-eval';"), std::string::npos) << "no inline script: " << csp;
    EXPECT_NE(csp.find("connect-src 'self'"), std::string::npos) << csp;
  }
  // The page holds no inline script the policy would block.
  const std::string page = send("GET", "/", {}).body;
  for (std::size_t p = page.find("<script"); p != std::string::npos; p = page.find("<script", p + 1))
    EXPECT_EQ(page.compare(p, 13, "<script src=\""), 0) << page.substr(p, 80);
}

}  // namespace
}  // namespace gmwm::test
