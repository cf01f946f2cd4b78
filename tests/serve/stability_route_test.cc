// The web app's frequency-stability deviations (issue 48, item 6; docs/serve.md): POST
// /api/stability fills the request `gmwm stability` fills, runs the same study and answers
// the command's document with the report's section for the column; its bad fields are 400s
// naming them; the guard refuses a hostile request to it as to every route.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/io/option_wording.h"
#include "serve_fixture.h"

namespace gmwm::test {
namespace {

std::string error_of(const serve::HttpResponse& r) { return OJson::parse(r.body).value("error", std::string()); }

// The text between the first `from` and the `to` after it (empty when absent).
std::string between(const std::string& s, const std::string& from, const std::string& to) {
  const auto a = s.find(from);
  if (a == std::string::npos) return {};
  const auto b = s.find(to, a);
  return b == std::string::npos ? std::string() : s.substr(a, b + to.size() - a);
}

TEST_F(ServeAppTest, StabilityAnswersTheCommandsDocumentAndTheReportsSectionForTheColumn) {
  const std::string d = open_imu();
  const OJson r = run_job(
      "/api/stability",
      {{"dataset", d}, {"column", "gyro_y"}, {"kind", "oadev,mdev,tdev"}, {"taus", "decade"}, {"units", "gyro=deg/s"}});
  const std::vector<std::string> args = {"stability",       "imu.csv", "--columns", "gyro_y",  "--kind",
                                         "oadev,mdev,tdev", "--taus",  "decade",    "--units", "gyro=deg/s"};
  EXPECT_EQ(r.at("document"), cli_document(args, folder_));
  EXPECT_NE(r.at("text").get<std::string>().find("gyro_y: stability deviations, tau0 = 0.01 s"), std::string::npos)
      << r.at("text");
  const std::string html = r.at("html");
  EXPECT_EQ(html.rfind("<section class=\"column\" id=\"stability-1\">\n<h2>gyro_y</h2>", 0), 0u) << html;
  EXPECT_NE(html.find("68.27% chi-square interval (stable32 quantiles)"), std::string::npos) << html;
  ASSERT_EQ(r.at("plots").size(), 2u);
  EXPECT_EQ(r.at("plots")[0].at("kind"), "stability");
  EXPECT_EQ(r.at("plots")[1].at("kind"), "stability-time");
  for (const OJson& p : r.at("plots"))
    EXPECT_NE(html.find("id=\"" + p.at("id").get<std::string>() + "\""), std::string::npos) << p.at("id");
  EXPECT_NE(r.at("plots")[1].at("spec").dump().find("deviation [(deg/s)*s]"), std::string::npos);
  // The same code renders the report: its table is the command's --report table to the byte.
  std::vector<std::string> report = args;
  report.insert(report.end(), {"--report", "stability.html", "--quiet"});
  const CliRun cli = run_gmwm(report, folder_);
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const std::string table = between(html, "<table>", "</table>");
  ASSERT_FALSE(table.empty()) << html;
  EXPECT_NE(table.find("<th>tdev<br><small>[(deg/s)*s]</small></th>"), std::string::npos) << table;
  EXPECT_EQ(between(read_text(folder_ / "stability.html"), "<table>", "</table>"), table);
}

TEST_F(ServeAppTest, StabilityTakesEveryOptionOfTheCommandAndAColumnReadAsPhase) {
  const std::string d = open_imu();
  // Nothing but the column: the command's defaults (oadev at the octaves, Stable32's one sigma).
  EXPECT_EQ(run_job("/api/stability", {{"dataset", d}, {"column", "gyro_x"}}).at("document"),
            cli_document({"stability", "imu.csv", "--columns", "gyro_x"}, folder_));
  const OJson listed = run_job("/api/stability", {{"dataset", d},
                                                  {"column", "gyro_x"},
                                                  {"kind", {"adev", "hdev", "theo1", "mtie"}},
                                                  {"taus", {0.3, 1.5, 15.0}},
                                                  {"confidence", 0.95},
                                                  {"intervals", "exact"},
                                                  {"noise_alpha", -1}});
  EXPECT_EQ(listed.at("document"),
            cli_document({"stability", "imu.csv", "--columns", "gyro_x", "--kind", "adev,hdev,theo1,mtie", "--taus",
                          "0.3,1.5,15", "--confidence", "0.95", "--intervals", "exact", "--noise-alpha", "-1"},
                         folder_));
  EXPECT_NE(listed.at("html").get<std::string>().find("noise given (alpha -1, flicker FM)"), std::string::npos);
  const OJson phase =
      run_job("/api/stability",
              {{"dataset", d}, {"column", "gyro_y"}, {"kind", "oadev,tierms"}, {"taus", "1,2,4"}, {"data", "phase"}});
  EXPECT_EQ(phase.at("document"), cli_document({"stability", "imu.csv", "--columns", "gyro_y", "--kind", "oadev,tierms",
                                                "--taus", "1,2,4", "--data", "phase"},
                                               folder_));
  EXPECT_NE(phase.at("html").get<std::string>().find("read as phase"), std::string::npos);
  // A recording opened as phase is read so by every study; "data": "phase" again would
  // difference it twice.
  const std::string p = body_of(post("/api/open", OJson{{"file", "imu.csv"}, {"data", "phase"}})).at("dataset");
  EXPECT_EQ(
      run_job("/api/stability", {{"dataset", p}, {"column", "gyro_y"}, {"kind", "oadev,tierms"}, {"taus", "1,2,4"}})
          .at("document"),
      phase.at("document"));
  const serve::HttpResponse twice =
      post("/api/stability", OJson{{"dataset", p}, {"column", "gyro_y"}, {"data", "phase"}});
  EXPECT_EQ(twice.status, 400);
  EXPECT_EQ(error_of(twice),
            "/api/stability: field 'data': the recording was opened as phase (/api/open's \"data\"); open it as rate "
            "to read a column as phase here");
}

TEST_F(ServeAppTest, StabilityListsTheLibrarysKindsAndDefaultsForThePage) {
  const OJson c = body_of(get("/api/stability"));
  std::vector<std::string> kinds, chosen;
  for (const OJson& k : c.at("kinds")) {
    kinds.push_back(k.at("name"));
    if (k.at("default").get<bool>()) chosen.push_back(k.at("name"));
    EXPECT_FALSE(k.at("title").get<std::string>().empty()) << k.dump();
  }
  EXPECT_EQ(kinds, (std::vector<std::string>{"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev",
                                             "ttotdev", "htotdev", "theo1", "mtie", "tierms"}));
  EXPECT_EQ(chosen, std::vector<std::string>{"oadev"}) << "the command's default";
  EXPECT_EQ(c.at("taus"), OJson({"octave", "decade", "all"}));
  EXPECT_EQ(c.at("default_taus"), "octave");
  EXPECT_EQ(c.at("intervals"), OJson({"stable32", "exact"}));
  EXPECT_DOUBLE_EQ(c.at("confidence").get<double>(), 0.68268949213708590);
  ASSERT_EQ(c.at("noises").size(), 7u);
  EXPECT_EQ(c.at("noises")[2], OJson({{"alpha", 0}, {"name", "white FM"}}));
}

TEST_F(ServeAppTest, StabilityRefusesEveryBadFieldWithOneLineNamingItBeforeAnyJob) {
  const std::string d = open_imu();
  const auto body = [&d](const char* field, const OJson& value) {
    return OJson{{"dataset", d}, {"column", "gyro_x"}, {field, value}}.dump();
  };
  struct Case {
    std::string body, says;
  };
  const std::string kinds =
      "expected adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev, htotdev, theo1, "
      "mtie or tierms";
  const std::vector<Case> cases = {
      {body("kind", "allan"), "/api/stability: field 'kind': found 'allan', "},
      {body("kind", OJson::array()), "/api/stability: field 'kind': expected at least one deviation"},
      {body("kind", "oadev,mdev,oadev"), "/api/stability: field 'kind': oadev given twice"},
      {body("kind", "oadev,,mdev"), "/api/stability: field 'kind': found an empty entry"},
      {body("kind", 3), "/api/stability: field 'kind': expected a list of strings"},
      {body("taus", "weekly"), "/api/stability: field 'taus': found 'weekly', expected all, octave, decade or"},
      {body("taus", OJson::array()), "/api/stability: field 'taus': expected all, octave, decade or"},
      {body("taus", OJson({1, "x"})), "/api/stability: field 'taus': found \"x\", expected"},
      {body("taus", OJson({10, 1})),
       "/api/stability: field 'taus': expected increasing averaging times, found 1 s after 10 s"},
      {body("taus", "-1"), "/api/stability: field 'taus': found -1, expected positive averaging times in seconds"},
      {body("taus", 10), "/api/stability: field 'taus': expected all, octave, decade or"},
      {body("confidence", 1.5), "/api/stability: field 'confidence': found 1.5, expected a number between 0 and 1"},
      {body("confidence", "high"), "/api/stability: field 'confidence': expected a number"},
      {body("intervals", "approx"), "/api/stability: field 'intervals': found 'approx', expected stable32 or exact"},
      {body("noise_alpha", 3),
       "/api/stability: field 'noise_alpha': found 3, expected an integer from -4 (random-run FM) to 2 (white PM)"},
      {body("noise_alpha", 0.5), "/api/stability: field 'noise_alpha': found 0.5, expected an integer from -4"},
      {body("noise_alpha", 18446744073709551615ULL), "/api/stability: field 'noise_alpha': found 18446744073709551615"},
      {body("data", "angle"), "/api/stability: field 'data': found 'angle', expected rate"},
      {body("units", "gyro=furlong"), "/api/stability: field 'units'"},
      {OJson{{"dataset", d}}.dump(), "/api/stability: field 'column': missing"},
      {OJson{{"dataset", d}, {"column", "gyro_q"}}.dump(), "'gyro_q' is not a column of imu.csv (gyro_x, gyro_y)"},
  };
  for (const Case& c : cases) {
    const serve::HttpResponse r = post("/api/stability", c.body);
    EXPECT_EQ(r.status, 400) << c.body << " -> " << r.body;
    const std::string e = error_of(r);
    EXPECT_EQ(e.rfind(c.says, 0) == 0 || e.find(c.says) != std::string::npos, true) << c.body << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << "one line: " << e;
    EXPECT_EQ(e.find("--"), std::string::npos) << "no option of the command line: " << e;
  }
  EXPECT_EQ(post("/api/stability", OJson{{"dataset", "d-nope"}, {"column", "gyro_x"}}).status, 404);
  // The library's words, as the command says them.
  const CliRun cli = run_gmwm({"stability", "imu.csv", "--kind", "allan"}, folder_);
  EXPECT_EQ(cli.exit_code, 2);
  EXPECT_NE(cli.err.find("--kind: found 'allan', " + kinds), std::string::npos) << cli.err;
  EXPECT_EQ(error_of(post("/api/stability", body("kind", "allan"))),
            "/api/stability: field 'kind': found 'allan', " + kinds);
  EXPECT_EQ(body_of(get("/api/status")).at("jobs"), 0) << "no refused request started a job";
}

TEST_F(ServeAppTest, StabilitysRefusalsOfTheDataAreTheJobsErrorInThePagesWords) {
  const std::string d = open_imu();
  const OJson j = body_of(post("/api/stability", OJson{{"dataset", d}, {"column", "gyro_x"}, {"taus", "0.015"}}));
  const OJson s = wait_job(j.at("job"));
  EXPECT_EQ(s.at("state"), "failed");
  EXPECT_EQ(s.at("error"), "\"taus\": 0.015 s is not a whole number of sampling periods of 0.01 s");
  const OJson far = wait_job(
      body_of(post("/api/stability", OJson{{"dataset", d}, {"column", "gyro_x"}, {"kind", "mdev"}, {"taus", {1e4}}}))
          .at("job"));
  EXPECT_EQ(far.at("state"), "failed");
  EXPECT_NE(far.at("error").get<std::string>().find("\"taus\": 10000 s is 1000000 periods, beyond mdev's largest"),
            std::string::npos)
      << far.dump();
  // Progress by averaging factor (a cancel is heard after each), the last the total: every
  // kind's octave factors and its intervals, 43 steps for OADEV, MDEV and HDEV here.
  const OJson ok =
      wait_job(body_of(post("/api/stability", OJson{{"dataset", d}, {"column", "gyro_x"}, {"kind", "oadev,mdev,hdev"}}))
                   .at("job"));
  EXPECT_EQ(ok.at("state"), "done");
  EXPECT_EQ(ok.at("progress"), OJson({43, 43}));
}

TEST_F(ServeAppTest, StabilityEscapesEveryNameItShows) {
  const std::string name = "gyro_<img src=x onerror=alert(1)>";
  std::string csv = "time [s]," + name + "\n";
  std::uint64_t state = 11;
  for (int t = 0; t < 4096; ++t) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    csv +=
        std::to_string(t / 100.0) + "," + std::to_string(static_cast<double>(state >> 11) / 9007199254740992.0) + "\n";
  }
  write_text(folder_ / "names.csv", csv);
  const OJson o = body_of(post("/api/open", OJson{{"file", "names.csv"}}));
  ASSERT_EQ(o.at("columns")[0].at("name"), name);
  const OJson r = run_job("/api/stability", {{"dataset", o.at("dataset")}, {"column", name}});
  const std::string html = r.at("html");
  EXPECT_EQ(html.find("<img"), std::string::npos) << html;
  EXPECT_NE(html.find("<h2>gyro_&lt;img src=x onerror=alert(1)&gt;</h2>"), std::string::npos) << html;
  // In the specs the name is data (Vega draws it as text); the page embeds none of them as HTML.
  EXPECT_EQ(r.at("plots")[0].at("spec").at("title").at("text"), name + ": deviations");
}

// Three sensors a, b, c at 100 Hz sharing an input a hundred times their own white noises
// (1, 2 and 4 times 1e-3), for the three-cornered hat.
std::string three_sensors_csv() {
  std::string csv = "time [s],a,b,c\n";
  std::uint64_t state = 48;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  double walk = 0.0;
  for (int t = 0; t < 4096; ++t) {
    walk += 1e-3 * uniform();
    const double common = 0.3 * uniform() + walk;
    csv += std::to_string(t / 100.0);
    for (const double level : {1e-3, 2e-3, 4e-3}) {
      char value[32];
      std::snprintf(value, sizeof value, ",%.17g", common + level * uniform());
      csv += value;
    }
    csv += "\n";
  }
  return csv;
}

TEST_F(ServeAppTest, AHatRequestReadsItsThreeColumnsAndAnswersTheCommandsDocumentWithTheHatsSection) {
  write_text(folder_ / "three.csv", three_sensors_csv());
  const std::string d = body_of(post("/api/open", OJson{{"file", "three.csv"}})).at("dataset");
  const OJson r = run_job(
      "/api/stability",
      {{"dataset", d}, {"columns", {"c", "a", "b"}}, {"hat", true}, {"kind", "oadev,tdev"}, {"units", "gyro=deg/s"}});
  const OJson cli = cli_document(
      {"stability", "three.csv", "--columns", "c,a,b", "--hat", "--kind", "oadev,tdev", "--units", "gyro=deg/s"},
      folder_);
  EXPECT_EQ(r.at("document"), cli);
  ASSERT_TRUE(r.at("document").contains("hat"));
  EXPECT_EQ(r.at("document").at("hat").at("sensors"), OJson({"c", "a", "b"}));
  // The report's sections: each column's, then the hat's with a plot per kind.
  const std::string html = r.at("html");
  EXPECT_EQ(html.rfind("<section class=\"column\" id=\"stability-1\">\n<h2>c</h2>", 0), 0u) << html;
  const auto hat = html.find("<section class=\"column\" id=\"stability-hat\">");
  ASSERT_NE(hat, std::string::npos) << html;
  EXPECT_LT(html.find("id=\"stability-3\""), hat);
  EXPECT_NE(html.find("three-cornered hat of c, a, b: each column&#39;s own deviation"), std::string::npos);
  std::vector<std::string> hats;
  for (const OJson& p : r.at("plots")) {
    EXPECT_NE(html.find("id=\"" + p.at("id").get<std::string>() + "\""), std::string::npos) << p.at("id");
    if (p.at("kind") == "stability-hat") hats.push_back(p.at("id"));
  }
  EXPECT_EQ(hats, (std::vector<std::string>{"plot-hat-1", "plot-hat-2"}));
  EXPECT_NE(r.at("text").get<std::string>().find("three-cornered hat of c, a, b"), std::string::npos);
  // The same code renders the report: its hat section is the command's --report's to the byte.
  const CliRun page = run_gmwm({"stability", "three.csv", "--columns", "c,a,b", "--hat", "--kind", "oadev,tdev",
                                "--units", "gyro=deg/s", "--report", "hat.html", "--quiet"},
                               folder_);
  ASSERT_EQ(page.exit_code, 0) << page.err;
  const std::string from = "<section class=\"column\" id=\"stability-hat\">";
  EXPECT_EQ(between(read_text(folder_ / "hat.html"), from, "</section>"), between(html, from, "</section>"));
}

TEST_F(ServeAppTest, AHatRequestOfOtherThanThreeColumnsIsRefusedBeforeAnyJobInTheCommandsWordsNamingItsFields) {
  write_text(folder_ / "three.csv", three_sensors_csv());
  const std::string three = body_of(post("/api/open", OJson{{"file", "three.csv"}})).at("dataset");
  const std::string imu = open_imu();
  struct Case {
    OJson body;
    std::vector<std::string> cli;  // the command's arguments of the same request
  };
  const std::vector<Case> cases = {
      {{{"dataset", three}, {"columns", {"a", "b"}}, {"hat", true}}, {"three.csv", "--columns", "a,b"}},
      {{{"dataset", three}, {"column", "a"}, {"hat", true}}, {"three.csv", "--columns", "a"}},
      {{{"dataset", imu}, {"column", "gyro_x"}, {"hat", true}}, {"imu.csv", "--columns", "gyro_x"}},
  };
  for (const Case& c : cases) {
    const serve::HttpResponse r = post("/api/stability", c.body);
    EXPECT_EQ(r.status, 400) << c.body.dump() << " -> " << r.body;
    const std::string web = error_of(r);
    EXPECT_EQ(web.find('\n'), std::string::npos) << "one line: " << web;
    EXPECT_EQ(web.find("--"), std::string::npos) << "no option of the command line: " << web;
    EXPECT_NE(web.find("\"hat\": true: the three-cornered hat reads three columns recorded together (\"columns\" "
                       "A,B,C), found "),
              std::string::npos)
        << web;
    // The command's refusal of the same request, in the page's words (io::option_wording).
    std::vector<std::string> args = {"stability"};
    args.insert(args.end(), c.cli.begin(), c.cli.end());
    args.push_back("--hat");
    const CliRun cli = run_gmwm(args, folder_);
    EXPECT_EQ(cli.exit_code, 2) << cli.err;
    const std::string line =
        cli.err.substr(cli.err.find(c.cli[0]), cli.err.find_last_not_of('\n') + 1 - cli.err.find(c.cli[0]));
    EXPECT_EQ(web, "/api/stability: " + io::option_wording(line, io::Face::kWeb)) << cli.err;
  }
  const auto refused = [&](const OJson& body, const std::string& says) {
    const serve::HttpResponse r = post("/api/stability", body);
    EXPECT_EQ(r.status, 400) << r.body;
    EXPECT_EQ(error_of(r), says);
  };
  refused({{"dataset", three}, {"columns", {"a", "b", "a"}}, {"hat", true}},
          "/api/stability: field 'columns': found column 'a' twice, expected each column once");
  refused({{"dataset", three}, {"columns", {"a", "b", "q"}}, {"hat", true}},
          "/api/stability: field 'columns': 'q' is not a column of three.csv (a, b, c)");
  refused({{"dataset", three}, {"column", "a"}, {"columns", {"a", "b", "c"}}, {"hat", true}},
          "/api/stability: field 'columns': give \"column\" (one) or \"columns\", not both");
  refused({{"dataset", three}, {"columns", {"a", "b", "c"}}, {"hat", true}, {"kind", "oadev,mtie"}},
          "/api/stability: \"hat\": true: mtie is a maximum, not a variance: the three-cornered hat separates every "
          "kind but mtie");
  EXPECT_EQ(body_of(get("/api/status")).at("jobs"), 0) << "no refused request started a job";
}

// The guard's rules (serve/src/guard.h) hold for the new route as for every other: a rebound
// host, another page's origin or fetch site, a form's body type, no token; none starts a job.
TEST_F(ServeAppTest, TheGuardRefusesAHostileStabilityRequestAsItRefusesEveryOther) {
  const std::string d = open_imu();
  const std::string ok = OJson{{"dataset", d}, {"column", "gyro_x"}}.dump();
  const auto send = [&](const std::string& method, const std::map<std::string, std::string>& changes) {
    std::map<std::string, std::string> h = page_headers(method, "/api/stability");
    for (const auto& [k, v] : changes) {
      if (v.empty())
        h.erase(k);
      else
        h[k] = v;
    }
    return app().handle({method, "/api/stability", {}, method == "POST" ? ok : std::string(), h});
  };
  const std::vector<std::pair<std::map<std::string, std::string>, int>> hostile = {
      {{{"host", "evil.example:8080"}}, 403},
      {{{"origin", "http://evil.example"}}, 403},
      {{{"origin", "http://127.0.0.1:9999"}}, 403},
      {{{"origin", ""}, {"sec-fetch-site", "cross-site"}}, 403},
      {{{"origin", ""}, {"sec-fetch-site", "same-site"}}, 403},
      {{{"content-type", "text/plain"}}, 415},
      {{{"content-type", "application/x-www-form-urlencoded"}}, 415},
      {{{"content-encoding", "gzip"}}, 415},
      {{{"cookie", ""}}, 401},
      {{{"cookie", "gmwm_serve_8080=" + std::string(32, '0')}}, 401},
  };
  for (const auto& [changes, status] : hostile) {
    const serve::HttpResponse r = send("POST", changes);
    EXPECT_EQ(r.status, status) << OJson(changes).dump() << ": " << r.body;
    EXPECT_EQ(r.body.find("\"job\""), std::string::npos) << r.body;
  }
  for (const auto& [changes, status] : hostile) {
    if (changes.count("content-type") || changes.count("content-encoding")) continue;
    EXPECT_EQ(send("GET", changes).status, status) << "GET " << OJson(changes).dump();
  }
  EXPECT_EQ(body_of(get("/api/status")).at("jobs"), 0) << "no hostile request started a job";
  // The page's own request, for contrast.
  EXPECT_EQ(send("POST", {}).status, 200);
  EXPECT_EQ(send("GET", {}).status, 200);
}

}  // namespace
}  // namespace gmwm::test
