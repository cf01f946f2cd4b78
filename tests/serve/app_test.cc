// The web app's API without sockets (serve/app.h): the folder's rule, the documents equal
// to the CLI's, refusals with their messages, uploads, jobs and their cancellation.

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/engine/error.h"
#include "serve_fixture.h"

namespace gmwm::test {
namespace {

namespace fs = std::filesystem;

std::string error_of(const serve::HttpResponse& r) { return OJson::parse(r.body).value("error", std::string()); }

TEST_F(ServeAppTest, ListsTheFoldersRecordingsAndConfigsButNoLinkThatLeavesIt) {
  write_text(folder_ / "imu.yaml", "accelerometer_noise_density: 1\n");
  fs::create_symlink(dir_ / "secret.csv", folder_ / "link_out.csv");
  fs::create_symlink(folder_ / "imu.csv", folder_ / "link_in.csv");
  const OJson f = body_of(get("/api/files"));
  std::vector<std::string> files;
  for (const auto& e : f.at("files")) files.push_back(e.at("path"));
  EXPECT_EQ(files, (std::vector<std::string>{"imu.csv", "link_in.csv", "sub/imu2.csv"}));
  ASSERT_EQ(f.at("configs").size(), 1u);
  EXPECT_EQ(f.at("configs")[0].at("path"), "imu.yaml");
  EXPECT_GT(f.at("files")[0].at("size").get<std::int64_t>(), 1000);
}

TEST_F(ServeAppTest, RefusesEveryPathThatLeavesTheFolderWith404AndReadsNothing) {
  fs::create_symlink(dir_ / "secret.csv", folder_ / "link_out.csv");
  fs::create_directory_symlink(dir_, folder_ / "dir_out");
  for (const std::string& bad : std::vector<std::string>{
           "../secret.csv", "/etc/passwd", (dir_ / "secret.csv").string(), "sub/../../secret.csv", "link_out.csv",
           "dir_out/secret.csv", "sub", ".", "", "imu.csv/..", "%2e%2e/secret.csv", std::string("imu.csv\0x", 9)}) {
    const serve::HttpResponse r = post("/api/open", OJson{{"file", bad}});
    EXPECT_TRUE(r.status == 404 || r.status == 400) << bad << ": " << r.status << " " << r.body;
    EXPECT_EQ(r.body.find("\"dataset\""), std::string::npos) << bad;
    if (r.status == 404) {
      EXPECT_NE(error_of(r).find("no recording"), std::string::npos) << r.body;
    }
  }
  // A link that stays inside is followed.
  fs::create_symlink(folder_ / "imu.csv", folder_ / "link_in.csv");
  EXPECT_EQ(post("/api/open", OJson{{"file", "link_in.csv"}}).status, 200);
  EXPECT_EQ(post("/api/open", OJson{{"file", "sub/imu2.csv"}}).status, 200);
}

TEST_F(ServeAppTest, OpensARecordingAndListsItsColumnsWithTheirSensorKinds) {
  const OJson o = body_of(post("/api/open", OJson{{"file", "imu.csv"}}));
  EXPECT_EQ(o.at("name"), "imu.csv");
  EXPECT_NEAR(o.at("freq").get<double>(), 100.0, 1e-9) << "estimated from the timestamps";
  EXPECT_EQ(o.at("n"), 16384);
  ASSERT_EQ(o.at("columns").size(), 2u);
  EXPECT_EQ(o.at("columns")[0].at("name"), "gyro_x");
  EXPECT_EQ(o.at("columns")[0].at("kind"), "gyro");
  EXPECT_EQ(o.at("dataset").get<std::string>().size(), 2u + 32u) << "a random 128-bit id";
}

TEST_F(ServeAppTest, OpeningARecordSaysWhatReadingSaidOfItAsTheReportsHeaderDoes) {
  EXPECT_EQ(body_of(post("/api/open", OJson{{"file", "imu.csv"}})).at("notes"), OJson::array());
  // A column whose every other sample copies the one before (an accelerometer at half the
  // gyroscope's rate): the web app says it, in the library's words.
  std::string csv = "time [s],gyro_x,accel_x\n";
  std::uint64_t state = 7;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  double held = 0.0;
  for (int t = 0; t < 8192; ++t) {
    if (t % 2 == 0) held = next();
    csv += std::to_string(t / 100.0) + "," + std::to_string(next()) + "," + std::to_string(held) + "\n";
  }
  write_text(folder_ / "held.csv", csv);
  const OJson o = body_of(post("/api/open", OJson{{"file", "held.csv"}}));
  ASSERT_EQ(o.at("notes").size(), 1u) << o.dump();
  EXPECT_EQ(o.at("notes")[0].get<std::string>().rfind("accel_x: 50% of the samples copy the one before (held", 0), 0u)
      << o.dump();
  // Its fit above the smoothed scales is the command's, "auto" or the level as a number.
  const std::string d = o.at("dataset");
  const OJson cli =
      cli_document({"fit", "held.csv", "--columns", "accel_x", "--model", "WN", "--first-level", "auto"}, folder_);
  const int first = cli.at("columns").at(0).at("first_level");
  ASSERT_GT(first, 1) << cli.dump();
  EXPECT_EQ(run_job("/api/fit", {{"dataset", d}, {"column", "accel_x"}, {"model", "WN"}, {"first_level", "auto"}})
                .at("document"),
            cli);
  EXPECT_EQ(
      run_job("/api/fit", {{"dataset", d}, {"column", "accel_x"}, {"model", "WN"}, {"first_level", first}})
          .at("document"),
      cli_document({"fit", "held.csv", "--columns", "accel_x", "--model", "WN", "--first-level", std::to_string(first)},
                   folder_));
  for (const OJson& bad : {OJson(0), OJson(63), OJson(2.5), OJson(true), OJson("x"), OJson(-1)}) {
    const serve::HttpResponse r =
        post("/api/fit", OJson{{"dataset", d}, {"column", "accel_x"}, {"model", "WN"}, {"first_level", bad}}.dump());
    EXPECT_EQ(r.status, 400) << bad.dump();
    EXPECT_EQ(error_of(r),
              "/api/fit: field 'first_level': found " + bad.dump() + ", expected auto or a whole number from 1 to 62")
        << bad.dump();
  }
}

TEST_F(ServeAppTest, FitsAColumnAndAnswersTheCliDocumentAndTheReportsSection) {
  const std::string d = open_imu();
  const OJson r = run_job("/api/fit", {{"dataset", d}, {"column", "gyro_y"}, {"model", "AR1+WN+RW"}});
  EXPECT_EQ(r.at("document"), cli_document({"fit", "imu.csv", "--columns", "gyro_y", "--model", "AR1+WN+RW"}, folder_));
  EXPECT_NE(r.at("text").get<std::string>().find("gyro_y: AR1+WN+RW"), std::string::npos) << r.at("text");
  const std::string html = r.at("html");
  EXPECT_NE(html.find("<section class=\"column\""), std::string::npos);
  EXPECT_NE(html.find("parameters of AR1+WN+RW"), std::string::npos);
  ASSERT_EQ(r.at("plots").size(), 2u);
  EXPECT_EQ(r.at("plots")[0].at("kind"), "wv");
  EXPECT_EQ(r.at("plots")[1].at("kind"), "adev");
  EXPECT_NE(html.find("id=\"" + r.at("plots")[0].at("id").get<std::string>() + "\""), std::string::npos);
}

TEST_F(ServeAppTest, RobustFitWithUnitsAndOmegaEqualsTheCliWithTheSameFlags) {
  const std::string d = open_imu();
  const OJson r = run_job("/api/fit", {{"dataset", d},
                                       {"column", "gyro_x"},
                                       {"model", "WN+RW"},
                                       {"robust", true},
                                       {"eff", 0.8},
                                       {"units", "gyro=deg/s"},
                                       {"omega", "full"}});
  EXPECT_EQ(r.at("document"), cli_document({"fit", "imu.csv", "--columns", "gyro_x", "--model", "WN+RW", "--robust",
                                            "--eff", "0.8", "--units", "gyro=deg/s", "--omega", "full"},
                                           folder_));
}

TEST_F(ServeAppTest, SelectsAndWvAnswerTheCliDocuments) {
  const std::string d = open_imu();
  const OJson s = run_job("/api/select", {{"dataset", d}, {"column", "gyro_x"}, {"model", "2*AR1+WN+RW+QN"}});
  EXPECT_EQ(s.at("document"),
            cli_document({"select", "imu.csv", "--columns", "gyro_x", "--model", "2*AR1+WN+RW+QN"}, folder_));
  EXPECT_NE(s.at("html").get<std::string>().find("model selection"), std::string::npos);
  const OJson w = run_job("/api/wv", {{"dataset", d}, {"column", "gyro_x"}});
  EXPECT_EQ(w.at("document"), cli_document({"wv", "imu.csv", "--columns", "gyro_x", "--adev"}, folder_));
}

TEST_F(ServeAppTest, SelectsOverListedModelsAsTheCliDoes) {
  // The ';' list was the CLI's alone (issue 45): the same rule now fills every face's request.
  const std::string d = open_imu();
  const OJson s = run_job("/api/select", {{"dataset", d}, {"column", "gyro_x"}, {"models", "WN+RW;AR1+WN;WN"}});
  EXPECT_EQ(s.at("document"),
            cli_document({"select", "imu.csv", "--columns", "gyro_x", "--models", "WN+RW;AR1+WN;WN"}, folder_));
}

TEST_F(ServeAppTest, StepsThroughTheRankingShowingEachRowsOwnFit) {
  const std::string d = open_imu();
  const OJson j = body_of(post("/api/select", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "2*AR1+WN+RW"}}));
  const std::string id = j.at("job");
  const OJson s = wait_job(id);
  const OJson& ranking = s.at("result").at("document").at("columns")[0].at("ranking");
  ASSERT_GE(ranking.size(), 3u);
  for (std::size_t k = 1; k <= ranking.size(); ++k) {
    const OJson r = body_of(get("/api/jobs/" + id + "/ranking/" + std::to_string(k)));
    const OJson& row = ranking[k - 1];
    EXPECT_EQ(r.at("model"), row.at("model"));
    EXPECT_EQ(r.at("rank"), row.at("rank"));
    EXPECT_EQ(r.at("criterion"), row.at("criterion"));
    // The row's own estimates, not the first model's: what the document lists for that row.
    EXPECT_EQ(r.at("parameters"), row.at("parameters")) << row.at("model");
    EXPECT_NE(r.at("html").get<std::string>().find("parameters of " + row.at("model").get<std::string>()),
              std::string::npos);
    EXPECT_EQ(r.at("plots")[0].at("kind"), "wv");
  }
  EXPECT_EQ(get("/api/jobs/" + id + "/ranking/0").status, 404);
  EXPECT_EQ(get("/api/jobs/" + id + "/ranking/" + std::to_string(ranking.size() + 1)).status, 404);
  EXPECT_EQ(get("/api/jobs/" + id + "/ranking/x1").status, 404);
  const OJson fit = body_of(post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}}));
  (void)wait_job(fit.at("job"));
  EXPECT_EQ(get("/api/jobs/" + fit.at("job").get<std::string>() + "/ranking/1").status, 404) << "a fit has no ranking";
}

TEST_F(ServeAppTest, RefusesMalformedRequestsWithOneLineNamingTheFieldAndKeepsServing) {
  const std::string d = open_imu();
  struct Case {
    std::string path, body;
    int status;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"/api/fit", "{\"dataset\": ", 400, "not JSON: parse error at line 1, column 13"},
      {"/api/fit", "[1, 2]", 400, "expected a JSON object"},
      {"/api/fit", R"({"dataset": 3})", 400, "field 'dataset': expected a string"},
      {"/api/fit", R"({"dataset": "d-nope", "column": "gyro_x", "model": "WN"})", 404, "unknown dataset 'd-nope'"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_q"}, {"model", "WN"}}.dump(), 400,
       "'gyro_q' is not a column of imu.csv (gyro_x, gyro_y)"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN+ZZ"}}.dump(), 400, "field 'model'"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}}.dump(), 400, "field 'model': missing"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}, {"omega", "nope"}}.dump(), 400,
       "field 'omega': found 'nope'"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}, {"eff", 0.5}}.dump(), 400,
       "\"eff\" 0.5: only meaningful with \"robust\": true"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}, {"robust", true}, {"eff", 1.5}}.dump(),
       400, "strictly between 0 and 1"},
      {"/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}, {"units", "gyro=furlong"}}.dump(), 400,
       "field 'units'"},
      {"/api/select", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}, {"replicates", -3}}.dump(), 400,
       "field 'replicates'"},
      {"/api/select", OJson{{"dataset", d}, {"column", "gyro_x"}, {"models", "WN;;RW"}}.dump(), 400,
       "/api/select: \"models\" \"WN;;RW\": empty model in the list"},
      {"/api/select", OJson{{"dataset", d}, {"column", "gyro_x"}}.dump(), 400,
       "select: give either \"model\" SPEC (every sub-model) or \"models\" \"SPEC1;SPEC2;...\""},
      {"/api/select", OJson{{"dataset", d}, {"column", "gyro_x"}, {"models", "WN;WN+ZZ"}}.dump(), 400, "ZZ"},
      {"/api/nope", "{}", 404, "POST /api/nope: no such endpoint"},
      {"/api/export", R"({"result": {"command": "wv"}, "format": "kalibr"})", 400, "/api/export"},
      {"/api/export", R"({"result": {}, "format": "klibr"})", 400, "found 'klibr', expected one of kalibr"},
  };
  for (const Case& c : cases) {
    const serve::HttpResponse r = post(c.path, c.body);
    EXPECT_EQ(r.status, c.status) << c.body << " -> " << r.body;
    const std::string e = error_of(r);
    EXPECT_NE(e.find(c.says), std::string::npos) << c.body << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << "one line: " << e;
  }
  EXPECT_EQ(request("PATCH", "/api/fit", {}, "{}").status, 405);
  EXPECT_EQ(get("/api/jobs/j-unknown").status, 404);
  EXPECT_EQ(get("/nothing").status, 404);
  // Still serving.
  EXPECT_EQ(get("/api/files").status, 200);
}

TEST_F(ServeAppTest, AJsonBodyBeyondTheLimitIs413) {
  serve::ServeOptions o;
  o.max_json_bytes = 1000;
  app(o);
  const serve::HttpResponse r = post("/api/open", "{\"file\": \"" + std::string(2000, 'a') + "\"}");
  EXPECT_EQ(r.status, 413);
  EXPECT_NE(error_of(r).find("expected at most 1000"), std::string::npos) << r.body;
}

TEST_F(ServeAppTest, AnUploadIsOpenedLikeAFileAndOneBeyondTheLimitIs413AndLeavesNothing) {
  serve::ServeOptions o;
  o.max_upload_bytes = 2'000'000;
  app(o);
  const std::string bytes = read_text(folder_ / "imu.csv");
  ASSERT_LT(bytes.size(), 2'000'000u);
  const OJson u = body_of(request("POST", "/api/upload", {{"name", "../../evil name.csv"}}, bytes));
  EXPECT_EQ(u.at("name"), "evil name.csv") << "only the base name is kept";
  EXPECT_EQ(u.at("size"), bytes.size());
  const OJson opened = body_of(post("/api/open", OJson{{"upload", u.at("upload")}}));
  EXPECT_EQ(opened.at("n"), 16384);
  // Streamed in pieces past the limit: refused, the partial file removed.
  serve::HttpResponse refusal;
  auto up = app().begin_upload("big.csv", -1, refusal);
  ASSERT_TRUE(up);
  const std::string piece(1'000'000, 'x');
  EXPECT_TRUE(app().append_upload(*up, piece.data(), piece.size()));
  EXPECT_TRUE(app().append_upload(*up, piece.data(), piece.size()));
  EXPECT_FALSE(app().append_upload(*up, piece.data(), piece.size()));
  EXPECT_EQ(app().finish_upload(up, true).status, 413);
  // Declared too large: refused before a byte is kept.
  EXPECT_FALSE(app().begin_upload("big.csv", 3'000'000, refusal));
  EXPECT_EQ(refusal.status, 413);
  std::size_t kept = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir_))
    if (e.is_regular_file() && e.path().string().find("gmwm-serve-uploads") != std::string::npos) ++kept;
  EXPECT_EQ(kept, 1u) << "only the finished upload";
}

// A selection that runs for minutes: the bootstrap optimism refits every candidate of a
// 63-candidate maximal model on 200 simulated series. The submitted job's answer.
OJson submit_slow_selection(ServeAppTest& t, const std::string& dataset) {
  return t.body_of(t.post("/api/select", OJson{{"dataset", dataset},
                                               {"column", "gyro_x"},
                                               {"model", "3*AR1+WN+RW+QN+DR"},
                                               {"optimism", "bootstrap"},
                                               {"replicates", 200}}));
}

TEST_F(ServeAppTest, CancellingASlowSelectionEndsItCancelledWithinASecond) {
  const std::string d = open_imu();
  const OJson j = submit_slow_selection(*this, d);
  const std::string id = j.at("job");
  // Wait until it runs and has reported progress.
  for (int i = 0; i < 500; ++i) {
    const OJson s = body_of(get("/api/jobs/" + id));
    if (s.at("state") == "running" && s.at("progress")[0].get<double>() > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(request("DELETE", "/api/jobs/" + id).status, 200);
  const OJson s = wait_job(id, std::chrono::seconds(30));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(s.at("state"), "cancelled") << s.dump();
  EXPECT_LT(seconds, 1.0) << "a candidate's bootstrap is the unit of work between checks";
  // The app still works.
  EXPECT_EQ(run_job("/api/fit", {{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}}).count("document"), 1u);
}

TEST_F(ServeAppTest, TwoTabsFittingAtOnceEachGetTheirOwnResult) {
  const std::string a = open_imu("imu.csv"), b = open_imu("sub/imu2.csv");
  EXPECT_NE(a, b) << "each open is its own dataset";
  std::vector<OJson> results(8);
  std::vector<std::thread> tabs;
  for (int k = 0; k < 8; ++k)
    tabs.emplace_back([&, k] {
      const std::string model = k % 2 ? "WN+RW" : "AR1+WN";
      results[static_cast<std::size_t>(k)] =
          run_job("/api/fit", {{"dataset", k < 4 ? a : b}, {"column", "gyro_x"}, {"model", model}});
    });
  for (auto& t : tabs) t.join();
  const OJson wn_rw = cli_document({"fit", "imu.csv", "--columns", "gyro_x", "--model", "WN+RW"}, folder_);
  const OJson ar1_wn = cli_document({"fit", "imu.csv", "--columns", "gyro_x", "--model", "AR1+WN"}, folder_);
  for (int k = 0; k < 8; ++k) {
    OJson doc = results[static_cast<std::size_t>(k)].at("document");
    EXPECT_EQ(doc.at("input"), k < 4 ? "imu.csv" : "sub/imu2.csv");
    doc["input"] = "imu.csv";  // the same samples under another name
    EXPECT_EQ(doc, k % 2 ? wn_rw : ar1_wn) << "tab " << k;
  }
}

TEST_F(ServeAppTest, AJobNobodyPollsIsCancelledAndForgotten) {
  serve::ServeOptions o;
  o.job_idle_seconds = 0.3;
  app(o);
  const std::string d = open_imu();
  const OJson j = submit_slow_selection(*this, d);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  // The first request after the idle time cancels it; once it has ended it is forgotten.
  (void)get("/api/files");
  (void)post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  (void)post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN"}});
  EXPECT_EQ(get("/api/jobs/" + j.at("job").get<std::string>()).status, 404);
}

TEST_F(ServeAppTest, DatasetsBeyondTheLimitDropTheLeastRecentlyUsed) {
  serve::ServeOptions o;
  o.max_datasets = 2;
  app(o);
  const std::string a = open_imu(), b = open_imu(), c = open_imu();
  EXPECT_EQ(post("/api/fit", OJson{{"dataset", a}, {"column", "gyro_x"}, {"model", "WN"}}).status, 404);
  EXPECT_EQ(post("/api/fit", OJson{{"dataset", b}, {"column", "gyro_x"}, {"model", "WN"}}).status, 200);
  EXPECT_EQ(post("/api/fit", OJson{{"dataset", c}, {"column", "gyro_x"}, {"model", "WN"}}).status, 200);
}

TEST_F(ServeAppTest, OverlaysADatasheetsModelAndDrawsItIntoTheFitsPlot) {
  write_text(folder_ / "sheet.yaml",
             "gyroscope:\n  noise_density: 0.1 deg/s/sqrt(Hz)\n  rate_random_walk: 10 deg/h/sqrt(h)\n");
  const std::string d = open_imu();
  const OJson o = body_of(post("/api/overlay", OJson{{"dataset", d},
                                                     {"column", "gyro_x"},
                                                     {"format", "datasheet"},
                                                     {"file", "sheet.yaml"},
                                                     {"units", "gyro=deg/s"}}));
  EXPECT_EQ(o.at("model").get<std::string>().rfind("WN(sigma2=", 0), 0u) << o.dump();
  // WN sigma2 = N^2 f = 0.1^2 * 100 = 1 (deg/s)^2 per sample; its WV at tau = 2 samples is sigma2 / 2.
  ASSERT_FALSE(o.at("wv").empty());
  EXPECT_NEAR(o.at("tau")[0].get<double>(), 0.02, 1e-15);
  EXPECT_GT(o.at("wv")[0].get<double>(), 0.5);
  const OJson r = run_job("/api/fit", {{"dataset", d},
                                       {"column", "gyro_x"},
                                       {"model", "WN+RW"},
                                       {"overlay", {{"format", "datasheet"}, {"file", "sheet.yaml"}}}});
  const std::string spec = r.at("plots")[0].at("spec").dump();
  EXPECT_NE(spec.find("datasheet: WN+RW"), std::string::npos) << "the overlay is a curve of the WV plot";
  EXPECT_NE(r.at("plots")[1].at("spec").dump().find("datasheet: WN+RW"), std::string::npos)
      << "and of the Allan deviation plot";
  // The document is the fit's alone.
  EXPECT_EQ(r.at("document"), cli_document({"fit", "imu.csv", "--columns", "gyro_x", "--model", "WN+RW"}, folder_));
  EXPECT_EQ(post("/api/overlay", OJson{{"dataset", d}, {"column", "gyro_x"}, {"format", "datasheet"}, {"file", "../x"}})
                .status,
            404);
  const serve::HttpResponse bad = post(
      "/api/overlay", OJson{{"dataset", d}, {"column", "gyro_x"}, {"format", "kalibr"}, {"text", "gyroscope: [1"}});
  EXPECT_EQ(bad.status, 400) << bad.body;
}

TEST_F(ServeAppTest, AnOverlayWhoseUnitsDoNotFitTheDataIsRefusedAsGapRefusesIt) {
  // A Kalibr file whose gyroscope figures are the data's in rad/s divided by 180/pi: drawn
  // against the data as given (rad/s), its curve would sit (180/pi)^2 = 3283 x too low.
  const std::string yaml =
      "gyroscope_noise_density: 1.745e-5\ngyroscope_random_walk: 1.745e-8\naccelerometer_noise_density: 1e-3\n"
      "accelerometer_random_walk: 1e-4\nupdate_rate: 100.0\n";
  write_text(folder_ / "k.yaml", yaml);
  const std::string d = open_imu();
  const CliRun gap = run_gmwm({"gap", "imu.csv", "--columns", "gyro_x", "--kalibr", "k.yaml"}, folder_);
  ASSERT_EQ(gap.exit_code, 2) << gap.err;
  ASSERT_NE(gap.err.find("give --units gyro=deg/s"), std::string::npos) << gap.err;
  const OJson overlay = {{"dataset", d}, {"column", "gyro_x"}, {"format", "kalibr"}, {"file", "k.yaml"}};
  for (const OJson& body :
       {overlay, OJson{{"dataset", d}, {"column", "gyro_x"}, {"format", "kalibr"}, {"text", yaml}}}) {
    const serve::HttpResponse r = post("/api/overlay", body);
    EXPECT_EQ(r.status, 400) << r.body;
    EXPECT_NE(r.body.find("the data look like deg/s, not rad/s; give \\\"units\\\" gyro=deg/s"), std::string::npos)
        << r.body;
  }
  // Drawn into a fit's plot: the same refusal before a job is queued.
  const serve::HttpResponse fit =
      post("/api/fit", OJson{{"dataset", d}, {"column", "gyro_x"}, {"model", "WN+RW"}, {"overlay", overlay}});
  EXPECT_EQ(fit.status, 400) << fit.body;
  // With the units that fit, or the check turned off as gap's --no-unit-check, it is drawn.
  OJson with_units = overlay;
  with_units["units"] = "gyro=deg/s";
  EXPECT_EQ(post("/api/overlay", with_units).status, 200);
  OJson unchecked = overlay;
  unchecked["unit_check"] = false;
  EXPECT_EQ(post("/api/overlay", unchecked).status, 200);
}

TEST_F(ServeAppTest, ExportsTheFileTheCliWritesFromTheSameResult) {
  const std::string d = open_imu();
  const OJson fit = run_job("/api/fit", {{"dataset", d}, {"column", "gyro_x"}, {"model", "WN+RW"}});
  write_text(folder_ / "fit.json", fit.at("document").dump());
  // A gyroscope's model alone: refused as the CLI refuses it (a 0 for the accelerometer
  // would read as a perfect one), unless the gyroscope's fields alone are asked for.
  const serve::HttpResponse refused =
      post("/api/export", OJson{{"result", fit.at("document")}, {"format", "kalibr"}, {"units", "gyro=deg/s"}});
  EXPECT_EQ(refused.status, 400) << refused.body;
  EXPECT_NE(refused.body.find("no accelerometer column"), std::string::npos) << refused.body;
  EXPECT_NE(refused.body.find("give \\\"partial\\\": true"), std::string::npos) << refused.body;
  const CliRun cli_refused =
      run_gmwm({"export", "fit.json", "--format", "kalibr", "--output", "out", "--units", "gyro=deg/s"}, folder_);
  EXPECT_EQ(cli_refused.exit_code, 2) << cli_refused.err;
  EXPECT_FALSE(std::filesystem::exists(folder_ / "out"));
  for (const std::string format : {"kalibr", "openvins", "basalt", "gz-sdf"}) {  // NOLINT(performance-for-range-copy)
    const OJson e = body_of(
        post("/api/export",
             OJson{{"result", fit.at("document")}, {"format", format}, {"units", "gyro=deg/s"}, {"partial", true}}));
    EXPECT_EQ(e.at("content").get<std::string>().find("accelerometer_noise"), std::string::npos) << "none invented";
    const CliRun r = run_gmwm(
        {"export", "fit.json", "--format", format, "--output", "out", "--units", "gyro=deg/s", "--partial", "--quiet"},
        folder_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string cli = read_text(folder_ / "out");
    std::string page = e.at("content");
    // The header names the source: the CLI's file, the page's result.
    const auto body_after_header = [](const std::string& s) {
      std::string out;
      for (const std::string& line : lines_of(s))
        if (line.find("Source:") == std::string::npos && line.find("\"source\"") == std::string::npos)
          out += line + "\n";
      return out;
    };
    EXPECT_EQ(body_after_header(page), body_after_header(cli)) << format;
    EXPECT_FALSE(e.at("filename").get<std::string>().empty());
  }
}

TEST_F(ServeAppTest, ServesThePageWithItsStyleAndVegaInlinedOrSaysWhyNot) {
  const serve::HttpResponse r = get("/");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
  EXPECT_EQ(r.body.find("<!--GMWM_VEGA-->"), std::string::npos);
  EXPECT_EQ(r.body.find("<!--GMWM_REPORT_STYLE-->"), std::string::npos);
  const bool vega = r.body.find("<script src=\"/vega.js\" defer></script>") != std::string::npos;
  EXPECT_TRUE(vega || r.body.find("<meta name=\"gmwm-vega-missing\" content=\"") != std::string::npos);
  if (vega) {
    EXPECT_NE(get("/vega.js").body.find("var vega ="), std::string::npos);
  }
  EXPECT_EQ(get("/app.js").content_type, "text/javascript; charset=utf-8");
}

TEST(ServeOptions, RefuseEveryFieldOutOfRangeNamingIt) {
  const auto why = [](auto set) {
    serve::ServeOptions o;
    set(o);
    return o.Validate();
  };
  EXPECT_EQ(why([](serve::ServeOptions&) {}), "");
  EXPECT_NE(why([](serve::ServeOptions& o) { o.port = 70000; }).find("port"), std::string::npos);
  EXPECT_NE(why([](serve::ServeOptions& o) { o.max_upload_bytes = 0; }).find("max_upload_bytes"), std::string::npos);
  EXPECT_NE(why([](serve::ServeOptions& o) { o.job_workers = 0; }).find("job_workers"), std::string::npos);
  EXPECT_NE(why([](serve::ServeOptions& o) { o.host = ""; }).find("host"), std::string::npos);
  serve::ServeOptions o;
  o.folder = "/nonexistent/folder";
  EXPECT_THROW(serve::App{o}, InputError);
}

}  // namespace
}  // namespace gmwm::test
