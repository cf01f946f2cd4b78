#pragma once
// The serve tests' set-up: a folder with simulated recordings (written by the gmwm program,
// as a user's would be), an App over it, and helpers to send requests and wait for jobs.

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "gmwm/serve/app.h"
#include "test_support.h"

namespace gmwm::test {

using OJson = nlohmann::ordered_json;

/// The truth of the simulated recordings: a bias-like AR1, white noise and a random walk,
/// as a MEMS gyro's WV looks (each term dominates a stretch of scales).
inline constexpr const char* kServeTruth = "AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=1e-4)+RW(gamma2=1e-10)";

class ServeAppTest : public ::testing::Test {
 public:  // the tests' helpers call post() and body_of() too
  void SetUp() override {
    dir_ = temp_dir("serve_app");
    folder_ = dir_ / "recordings";
    std::filesystem::create_directories(folder_ / "sub");
    const auto r = run_gmwm({"simulate", "--model", kServeTruth, "--n", "16384", "--freq", "100", "--signals", "2",
                             "--names", "gyro_x,gyro_y", "--output", "recordings/imu.csv", "--quiet"},
                            dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::filesystem::copy_file(folder_ / "imu.csv", folder_ / "sub" / "imu2.csv");
    write_text(dir_ / "secret.csv", "timestamp,gyro_x\n0,1\n0.01,2\n");
  }
  void TearDown() override {
    app_.reset();
    std::filesystem::remove_all(dir_);
  }

  serve::App& app(serve::ServeOptions o = {}) {
    if (!app_) {
      o.folder = folder_.string();
      o.upload_root = dir_.string();
      app_ = std::make_unique<serve::App>(o);
    }
    return *app_;
  }

  /// The headers the page's own requests carry: a Host naming the app, the page's Origin, the
  /// cookie with the access token, and for a POST its body's type (JSON, or an upload's bytes).
  std::map<std::string, std::string> page_headers(const std::string& method = "GET", const std::string& path = "/") {
    std::map<std::string, std::string> h = {
        {"host", "127.0.0.1:8080"}, {"cookie", "gmwm_serve_8080=" + app().token()}, {"sec-fetch-site", "same-origin"}};
    if (method == "POST") {
      h["origin"] = "http://127.0.0.1:8080";
      h["content-type"] = path == "/api/upload" ? "application/octet-stream" : "application/json";
    }
    return h;
  }
  /// A request as the page sends it.
  serve::HttpResponse request(const std::string& method, const std::string& path,
                              const std::map<std::string, std::string>& query = {}, const std::string& body = {}) {
    return app().handle({method, path, query, body, page_headers(method, path)});
  }
  serve::HttpResponse get(const std::string& path) { return request("GET", path); }
  serve::HttpResponse post(const std::string& path, const std::string& body) { return request("POST", path, {}, body); }
  serve::HttpResponse post(const std::string& path, const OJson& body) { return post(path, body.dump()); }

  /// The body of an answer expected to be `status`.
  static OJson body_of(const serve::HttpResponse& r, int status = 200) {
    EXPECT_EQ(r.status, status) << r.body;
    return OJson::parse(r.body);
  }

  /// Opens recordings/imu.csv; its dataset id.
  std::string open_imu(const std::string& file = "imu.csv") {
    const OJson o = body_of(post("/api/open", OJson{{"file", file}}));
    return o.at("dataset").get<std::string>();
  }

  /// Polls a job until it ends (at most `limit`); its last status.
  OJson wait_job(const std::string& job, std::chrono::seconds limit = std::chrono::seconds(120)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    for (;;) {
      const OJson s = body_of(get("/api/jobs/" + job));
      const std::string state = s.at("state");
      if (state != "queued" && state != "running") return s;
      if (std::chrono::steady_clock::now() > end) {
        ADD_FAILURE() << "job " << job << " still " << state << " after " << limit.count() << " s";
        return s;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  /// Submits `endpoint` with `body` and waits for the job's result (failing the test
  /// unless it ends "done").
  OJson run_job(const std::string& endpoint, const OJson& body) {
    const OJson j = body_of(post(endpoint, body));
    const OJson s = wait_job(j.at("job"));
    EXPECT_EQ(s.at("state"), "done") << s.dump();
    return s.value("result", OJson::object());
  }

  std::filesystem::path dir_, folder_;
  std::unique_ptr<serve::App> app_;
};

/// The CLI's JSON document of `args` run in `dir` (the "run" object removed).
inline OJson cli_document(const std::vector<std::string>& args, const std::filesystem::path& dir) {
  std::vector<std::string> a = args;
  a.insert(a.end(), {"--json", "-", "--quiet"});
  const CliRun r = run_gmwm(a, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  OJson doc = OJson::parse(r.out);
  doc.erase("run");
  return doc;
}

}  // namespace gmwm::test
