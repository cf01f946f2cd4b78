// The web app's bounds (docs/serve.md, "Limits and safety"): what all uploads may hold, an
// upload cut short, the analyses that may wait, the listing's walk and its age, and the
// requests that once answered 500 for what the client sent.

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "serve_fixture.h"

namespace gmwm::test {
namespace {

namespace fs = std::filesystem;

std::string error_of(const serve::HttpResponse& r) { return OJson::parse(r.body).value("error", std::string()); }

// Files under `dir` whose name holds `part`.
std::size_t files_named(const fs::path& dir, const std::string& part) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    n += e.is_regular_file() && e.path().filename().string().find(part) != std::string::npos;
  return n;
}

class ServeLimitsTest : public ServeAppTest {
 protected:
  serve::HttpResponse upload(const std::string& name, const std::string& bytes) {
    return request("POST", "/api/upload", {{"name", name}}, bytes);
  }
};

TEST_F(ServeLimitsTest, UploadsHoldAtMostTheirTotalTheOldestRemovedToMakeRoom) {
  serve::ServeOptions o;
  o.max_upload_bytes = 1000;
  o.max_upload_total_bytes = 2500;
  app(o);
  const std::string kb(1000, 'x');
  std::vector<std::string> ids;
  for (int k = 0; k < 3; ++k) {
    const OJson u = body_of(upload("u" + std::to_string(k) + ".csv", kb));
    ids.push_back(u.at("upload"));
  }
  // Two of 1000 bytes fit in 2500: the first went to make room for the third.
  EXPECT_EQ(files_named(dir_, "-u0.csv"), 0u);
  EXPECT_EQ(files_named(dir_, "-u1.csv"), 1u);
  EXPECT_EQ(files_named(dir_, "-u2.csv"), 1u);
  const serve::HttpResponse gone = post("/api/open", OJson{{"upload", ids[0]}, {"freq", 100}});
  EXPECT_EQ(gone.status, 404);
  EXPECT_NE(error_of(gone).find("the oldest are removed to make room"), std::string::npos) << gone.body;
  // One beyond the limit is refused and leaves nothing.
  const serve::HttpResponse big = upload("big.csv", std::string(1001, 'y'));
  EXPECT_EQ(big.status, 413) << big.body;
  EXPECT_EQ(files_named(dir_, "big.csv"), 0u);
  // The options keep one upload within the total.
  o.max_upload_total_bytes = 999;
  EXPECT_NE(o.Validate().find("max_upload_total_bytes: found 999, expected at least max_upload_bytes (1000)"),
            std::string::npos)
      << o.Validate();
}

TEST_F(ServeLimitsTest, AnUploadCutShortIsRemovedAndNeverKept) {
  serve::HttpResponse refusal;
  auto u = app().begin_upload("cut.csv", -1, refusal);  // chunked: no length declared
  ASSERT_TRUE(u) << refusal.body;
  const std::string part = read_text(folder_ / "imu.csv").substr(0, 20000);
  ASSERT_TRUE(app().append_upload(*u, part.data(), part.size()));
  EXPECT_EQ(files_named(dir_, "cut.csv"), 1u) << "it streams to its file";
  const serve::HttpResponse r = app().finish_upload(u, false);  // the client went away
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(error_of(r).find("before its last byte"), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find("\"upload\""), std::string::npos) << r.body;
  u.reset();
  EXPECT_EQ(files_named(dir_, "cut.csv"), 0u) << "nothing of it is kept";
}

TEST_F(ServeLimitsTest, AnalysesBeyondTheQueuesLimitAreRefusedWithWhenToRetry) {
  serve::ServeOptions o;
  o.job_workers = 1;
  o.max_queued_jobs = 2;
  app(o);
  const std::string d = open_imu();
  // One long job holds the worker; two wait; the next is refused, and queued again once one
  // is cancelled.
  const OJson slow = {{"dataset", d},
                      {"column", "gyro_x"},
                      {"model", "3*AR1+WN+RW+QN+DR"},
                      {"optimism", "bootstrap"},
                      {"replicates", 10000}};
  std::vector<std::string> jobs = {body_of(post("/api/select", slow)).at("job")};
  for (int i = 0; i < 3000 && body_of(get("/api/jobs/" + jobs[0])).at("state") == "queued"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(body_of(get("/api/jobs/" + jobs[0])).at("state"), "running");
  for (int k = 0; k < 2; ++k) jobs.push_back(body_of(post("/api/select", slow)).at("job"));
  const serve::HttpResponse full = post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}});
  EXPECT_EQ(full.status, 429) << full.body;
  EXPECT_NE(error_of(full).find("2 analyses are already waiting"), std::string::npos) << full.body;
  bool retry = false;
  for (const auto& [k, v] : full.headers) retry = retry || (k == "Retry-After" && std::stoi(v) > 0);
  EXPECT_TRUE(retry) << "a Retry-After header";
  EXPECT_EQ(request("DELETE", "/api/jobs/" + jobs[2]).status, 200);
  EXPECT_EQ(post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}}).status, 200);
  for (const std::string& j : jobs) request("DELETE", "/api/jobs/" + j);
}

TEST_F(ServeLimitsTest, TheListingWalksABoundedNumberOfEntriesAndIsSharedWhileFresh) {
  serve::ServeOptions o;
  o.max_walked_entries = 50;
  o.listing_seconds = 0.3;
  app(o);
  fs::create_directories(folder_ / "a_many");
  for (int k = 0; k < 200; ++k) write_text(folder_ / "a_many" / ("note" + std::to_string(k) + ".log"), "");
  const OJson first = body_of(get("/api/files"));
  EXPECT_TRUE(first.at("truncated").get<bool>()) << "50 entries walked of 200+";
  // Breadth first: the recordings beside the big folder are listed before its contents are
  // walked (depth first, the walk's bound was reached inside it and imu.csv was missing).
  ASSERT_FALSE(first.at("files").empty()) << first.dump();
  EXPECT_EQ(first.at("files")[0].at("path"), "imu.csv") << first.dump();
  // While fresh, the same listing is answered (nothing walked again).
  write_text(folder_ / "new.csv", "timestamp,gyro_x\n0,1\n");
  EXPECT_EQ(body_of(get("/api/files")), first);
  std::this_thread::sleep_for(std::chrono::milliseconds(350));
  // Once older than listing_seconds, walked again (still bounded).
  const OJson later = body_of(get("/api/files"));
  EXPECT_TRUE(later.at("truncated").get<bool>());
}

TEST_F(ServeLimitsTest, ANumberBeyondDoubleAndAnUploadNameOfThousandsOfBytesAreTheClientsErrorsNot500) {
  const serve::HttpResponse huge = post("/api/open", std::string(R"({"file": "imu.csv", "freq": 1e999})"));
  EXPECT_EQ(huge.status, 400) << huge.body;
  EXPECT_NE(error_of(huge).find("/api/open"), std::string::npos) << huge.body;
  EXPECT_EQ(post("/api/open", std::string(R"({"file": "imu.csv", "freq": -1e999})")).status, 400);
  EXPECT_EQ(post("/api/fit", std::string(R"({"dataset": "d", "levels": 1e400})")).status, 400);
  const std::string name = std::string(5000, 'n') + ".csv";
  const OJson u = body_of(upload(name, read_text(folder_ / "imu.csv")));
  const std::string kept = u.at("name");
  EXPECT_LE(kept.size(), 200u);
  EXPECT_TRUE(kept.ends_with("nnn.csv")) << kept;
  EXPECT_EQ(post("/api/open", OJson{{"upload", u.at("upload")}}).status, 200) << "the ending still tells the format";
  // A name of control characters and a multi-byte character cut at the limit.
  std::string utf8;
  for (int k = 0; k < 150; ++k) utf8 += "\xc3\xa9";  // 300 bytes of 'é'
  const OJson v = body_of(upload("a\nb\x01" + utf8 + ".csv", "timestamp,gyro_x\n0,1\n"));
  const std::string n = v.at("name");
  EXPECT_EQ(n.find('\n'), std::string::npos) << n;
  EXPECT_NE(static_cast<unsigned char>(n.front()) & 0xC0, 0x80) << "not cut inside a character";
}

}  // namespace
}  // namespace gmwm::test
