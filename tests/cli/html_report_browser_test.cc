// The HTML report (`--report PATH`) opened in headless Chromium with no network (issue 6,
// item 5): the page must render every expected Vega plot as SVG, with its axis titles,
// without any script error or Vega warning, and a screenshot of it is kept under
// <build>/test_artefacts/ (report_select.png, ...). Chromium absent: the tests skip with a
// message, unless GMWM_REQUIRE_BROWSER=1 (CI: .ci/run), in which case they fail.
// GMWM_CHROMIUM names the browser binary when it is not `chromium` on the PATH.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::optional<std::string> find_chromium() {
  if (const char* env = std::getenv("GMWM_CHROMIUM"); env && *env) return std::string(env);
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');)
    for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
      const fs::path p = fs::path(dir) / name;
      if (::access(p.c_str(), X_OK) == 0) return p.string();
    }
  return std::nullopt;
}

#define REQUIRE_BROWSER(exe)                                                                          \
  const std::optional<std::string> exe = find_chromium();                                             \
  do {                                                                                                \
    if (!exe) {                                                                                       \
      const char* req = std::getenv("GMWM_REQUIRE_BROWSER");                                          \
      if (req && std::string(req) == "1")                                                             \
        FAIL() << "headless Chromium not found (GMWM_REQUIRE_BROWSER=1): apt-get install chromium";   \
      GTEST_SKIP() << "headless Chromium not found: apt-get install chromium (or set GMWM_CHROMIUM) " \
                      "to run the browser test";                                                      \
    }                                                                                                 \
  } while (0)

// Artefacts beside the build: <build>/test_artefacts (the gmwm binary's folder).
fs::path artefact_dir() {
  const fs::path d = fs::path(GMWM_CLI_PATH).parent_path() / "test_artefacts";
  fs::create_directories(d);
  return d;
}

// Headless Chromium that cannot reach any network: every host name resolves to nothing
// and every non-loopback connection goes to a closed proxy port.
class Browser {
 public:
  explicit Browser(std::string exe) : exe_(std::move(exe)), profile_(gmwm::test::temp_dir("chromium")) {}
  ~Browser() {
    std::error_code ec;
    fs::remove_all(profile_, ec);
  }
  /// The DOM after the page's scripts ran (virtual time budget 10 s).
  std::string dump_dom(const fs::path& page, const fs::path& log) const {
    const fs::path out = profile_ / "dom.html";
    run({"--dump-dom"}, page, out, log);
    return read_text(out);
  }
  /// A 1400 x 3000 screenshot of the page.
  void screenshot(const fs::path& page, const fs::path& png, const fs::path& log) const {
    run({"--hide-scrollbars", "--window-size=1400,3000", "--screenshot=" + png.string()}, page, profile_ / "stdout.txt",
        log);
  }

 private:
  void run(const std::vector<std::string>& extra, const fs::path& page, const fs::path& out,
           const fs::path& log) const {
    std::vector<std::string> args = {"--headless",
                                     "--no-sandbox",
                                     "--disable-gpu",
                                     "--disable-extensions",
                                     "--no-first-run",
                                     "--no-default-browser-check",
                                     "--disable-background-networking",
                                     "--disable-component-update",
                                     "--disable-sync",
                                     "--user-data-dir=" + profile_.string(),
                                     "--proxy-server=127.0.0.1:9",
                                     "--proxy-bypass-list=<-loopback>",
                                     "--host-resolver-rules=MAP * ~NOTFOUND",
                                     "--virtual-time-budget=10000"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::string cmd = "timeout 180 " + quote(exe_);
    for (const auto& a : args) cmd += " " + quote(a);
    cmd += " " + quote("file://" + fs::absolute(page).string()) + " < /dev/null > " + quote(out.string()) + " 2>> " +
           quote(log.string());
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "chromium failed (status " << status << "), see " << log << ": " << cmd;
  }
  std::string exe_;
  fs::path profile_;
};

int count_matches(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

// The content of <div id="ID" ...>...</div> (no nested divs expected when empty).
std::string box_text(const std::string& dom, const std::string& id) {
  std::smatch m;
  const std::regex re("<div id=\"" + id + "\"[^>]*>([\\s\\S]*?)</div>\\s*<(div|script)");
  if (!std::regex_search(dom, m, re)) return "(box " + id + " not found)";
  return m[1].str();
}

// Every plot of the expected kinds rendered as an SVG by Vega, with its axis titles, and
// no error or warning recorded by the page.
void expect_rendered(const std::string& dom, const std::map<std::string, int>& kinds) {
  int total = 0;
  for (const auto& [kind, n] : kinds) {
    total += n;
    EXPECT_EQ(count_matches(dom, "data-plot=\"" + kind + "\""), n) << kind;
    EXPECT_EQ(count_matches(dom, "data-plot=\"" + kind + "\" id=\"[^\"]*\" data-rendered=\"svg\""), n)
        << kind << ": not every plot was rendered";
  }
  EXPECT_EQ(count_matches(dom, "class=\"gmwm-plot\""), total);
  EXPECT_NE(dom.find("data-gmwm-status=\"done\""), std::string::npos) << "the page's script did not finish";
  EXPECT_NE(dom.find("data-gmwm-rendered=\"" + std::to_string(total) + "\""), std::string::npos);
  // Each view's own <svg class="marks">, with marks in it.
  EXPECT_EQ(count_matches(dom, "<svg [^>]*class=\"marks\""), total);
  const int wv_like =
      (kinds.count("wv") ? kinds.at("wv") : 0) + (kinds.count("gap-curves") ? kinds.at("gap-curves") : 0);
  const int adev = kinds.count("adev") ? kinds.at("adev") : 0;
  const int loglog = wv_like + adev;
  EXPECT_EQ(count_matches(dom, "aria-label=\"Y-axis titled 'wavelet variance nu\\^2"), wv_like);
  EXPECT_EQ(count_matches(dom, "aria-label=\"Y-axis titled 'Allan deviation \\["), adev);
  EXPECT_GE(count_matches(dom, "aria-label=\"X-axis titled 'tau \\[s\\]'"), loglog);
  EXPECT_GE(count_matches(dom, "class=\"mark-line role-mark"), 2 * loglog);
  EXPECT_GE(count_matches(dom, "class=\"mark-area role-mark"), loglog);
  EXPECT_GE(count_matches(dom, "class=\"mark-symbol role-mark"), loglog);
  EXPECT_EQ(box_text(dom, "gmwm-errors"), "") << "script errors in the page";
  EXPECT_EQ(box_text(dom, "gmwm-warnings"), "") << "Vega warnings in the page";
}

// A PNG of the expected size that is not a blank page (a blank 1400 x 3000 page is ~20 kB).
void expect_screenshot(const fs::path& png) {
  ASSERT_TRUE(fs::exists(png)) << png;
  const std::string data = read_text(png);
  ASSERT_GE(data.size(), 24u);
  EXPECT_EQ(data.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(data[at + i]);
    return v;
  };
  EXPECT_EQ(data.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(16), 1400u);
  EXPECT_EQ(be32(20), 3000u);
  EXPECT_GT(data.size(), 100u * 1024u) << png << " looks blank";
}

std::string example() { return std::string(GMWM_SOURCE_DIR) + "/data/example_imu6.csv.gz"; }

// Builds a report through the CLI in the artefact folder, opens it, checks its plots and
// keeps a screenshot NAME.png.
void check_report(const std::string& exe, const std::string& name, std::vector<std::string> args,
                  const std::map<std::string, int>& kinds) {
  const fs::path dir = artefact_dir();
  const fs::path page = dir / (name + ".html");
  const fs::path log = dir / (name + ".chromium.log");
  fs::remove(log);
  args.insert(args.end(), {"--report", page.string(), "--quiet"});
  const auto r = run_gmwm(args, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(page));
  EXPECT_TRUE(fs::exists(dir / (name + ".html.svg")));
  EXPECT_LT(fs::file_size(page), 5u * 1024u * 1024u);
  const Browser browser(exe);
  const std::string dom = browser.dump_dom(page, log);
  ASSERT_FALSE(dom.empty()) << "empty DOM dump, see " << log;
  expect_rendered(dom, kinds);
  const fs::path png = dir / (name + ".png");
  fs::remove(png);
  browser.screenshot(page, png, log);
  expect_screenshot(png);
}

TEST(HtmlReportInBrowser, SelectReportOnSixAxesRendersEveryPlotOfflineWithoutScriptErrors) {
  REQUIRE_BROWSER(exe);
  check_report(*exe, "report_select", {"select", example(), "--model", "AR1+WN+RW"}, {{"wv", 6}, {"adev", 6}});
  // The ranking of every axis, its chosen model highlighted.
  const std::string html = read_text(artefact_dir() / "report_select.html");
  EXPECT_EQ(count_matches(html, "<tr class=\"chosen\">"), 6);
  for (const char* axis : {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"})
    EXPECT_NE(html.find(std::string("<h2>") + axis + "</h2>"), std::string::npos) << axis;
}

TEST(HtmlReportInBrowser, GapReportRendersTheScaleAxisMapWindowMapsAndBeforeAfterCurves) {
  REQUIRE_BROWSER(exe);
  check_report(*exe, "report_gap",
               {"gap", example(), "--columns", "gyro_x,accel_x", "--kalibr",
                std::string(GMWM_SOURCE_DIR) + "/data/adis16405_imu.yaml", "--replicates", "40"},
               {{"wv", 2}, {"gap-levels", 1}, {"gap-windows", 2}, {"gap-curves", 2}});
}

TEST(HtmlReportInBrowser, RobustWvAndFitReportsRenderTheirPlots) {
  REQUIRE_BROWSER(exe);
  check_report(*exe, "report_wv", {"wv", example(), "--columns", "gyro_x,accel_y", "--robust"}, {{"wv", 2}});
  check_report(*exe, "report_fit", {"fit", example(), "--columns", "gyro_z", "--model", "AR1+WN+RW"},
               {{"wv", 1}, {"adev", 1}});
}

// fit --joint: the replicates' WVs overlaid with the joint model (here the example's three
// gyro axes stand in for three recordings of one axis).
TEST(HtmlReportInBrowser, JointFitReportOverlaysTheReplicatesWithTheJointModel) {
  REQUIRE_BROWSER(exe);
  check_report(*exe, "report_joint",
               {"fit", example(), "--columns", "gyro_x", "--joint", example() + ":gyro_y", example() + ":gyro_z",
                "--model", "AR1+WN+RW", "--replicates", "19"},
               {{"wv", 1}});
  const std::string html = read_text(artefact_dir() / "report_joint.html");
  EXPECT_NE(html.find("replicate-t interval"), std::string::npos);
  EXPECT_NE(html.find("shared theta?"), std::string::npos);
}

// wv --adev: the Allan deviation plot with its band and the N / K / B guides, and the
// noise-figure table under it.
TEST(HtmlReportInBrowser, AllanDeviationPlotRendersWithItsGuideLines) {
  REQUIRE_BROWSER(exe);
  check_report(*exe, "report_adev",
               {"wv", example(), "--columns", "gyro_x,accel_x", "--adev", "--units", "gyro=rad/s,accel=m/s^2"},
               {{"wv", 2}, {"adev", 2}});
  const std::string html = read_text(artefact_dir() / "report_adev.html");
  EXPECT_EQ(count_matches(html, "<table class=\"figures\">"), 2);
  EXPECT_NE(html.find("N white noise"), std::string::npos);
  EXPECT_NE(html.find("(-1/2 slope)"), std::string::npos) << "the N guide is drawn";
  EXPECT_NE(html.find("rad/s/sqrt(Hz)"), std::string::npos);
}

// A wheel event over the plot zooms about the pointer (both log10 domains shrink) and
// hovering a point shows its values (Vega's tooltip: the view's title attribute).
TEST(HtmlReportInBrowser, WvPlotZoomsOnTheWheelAndShowsValuesOnHover) {
  REQUIRE_BROWSER(exe);
  const fs::path dir = gmwm::test::temp_dir("report_probe");
  const auto r = run_gmwm(
      {"select", example(), "--columns", "gyro_x", "--model", "AR1+WN+RW", "--report", "r.html", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string html = read_text(dir / "r.html");
  const std::string probe = R"JS(<script>
setTimeout(function () {
  var v = window.gmwmViews['plot-1-wv'];
  var span = function () { return [v.signal('xl')[1] - v.signal('xl')[0], v.signal('yl')[1] - v.signal('yl')[0]]; };
  var before = span();
  var svg = document.querySelector('#plot-1-wv svg');
  var box = svg.getBoundingClientRect();
  svg.dispatchEvent(new WheelEvent('wheel', {clientX: box.left + 300, clientY: box.top + 200, deltaY: -300,
                                             bubbles: true, cancelable: true}));
  setTimeout(function () {
    var after = span();
    // Vega's SVG renderer finds the item from the event's target: the point's own path.
    var point = document.querySelector('#plot-1-wv .mark-symbol.role-mark path');
    var sym = point.getBoundingClientRect();
    point.dispatchEvent(new MouseEvent('mousemove', {clientX: sym.left + sym.width / 2, clientY: sym.top + sym.height / 2,
                                                     bubbles: true}));
    setTimeout(function () {
      document.body.setAttribute('data-zoomed', String(after[0] < before[0] && after[1] < before[1]));
      document.body.setAttribute('data-tooltip', document.querySelector('#plot-1-wv .view').getAttribute('title') || '');
    }, 300);
  }, 300);
}, 1500);
</script>
</body>)JS";
  const auto at = html.rfind("</body>");
  ASSERT_NE(at, std::string::npos);
  html.replace(at, 7, probe);
  gmwm::test::write_text(dir / "probe.html", html);
  const std::string dom = Browser(*exe).dump_dom(dir / "probe.html", dir / "chromium.log");
  EXPECT_NE(dom.find("data-zoomed=\"true\""), std::string::npos) << "the wheel did not zoom";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex("data-tooltip=\"([^\"]*)\""))) << "no tooltip probe";
  EXPECT_NE(m[1].str().find("series: classical WV"), std::string::npos) << m[1];
  EXPECT_NE(m[1].str().find("tau [s]: "), std::string::npos) << m[1];
  EXPECT_NE(m[1].str().find("WV: "), std::string::npos) << m[1];
  EXPECT_EQ(box_text(dom, "gmwm-errors"), "");
  fs::remove_all(dir);
}

TEST(HtmlReportInBrowser, SelectReportOnTheSixAxisAdisRecordingStaysUnderFiveMegabytes) {
  GMWM_REQUIRE_SHARED_DATA();
  REQUIRE_BROWSER(exe);
  check_report(
      *exe, "report_select_adis",
      {"select", gmwm::test::shared_data_file("adis_16405_imu1.csv.gz"), "--freq", "100", "--model", "AR1+WN+RW"},
      {{"wv", 6}, {"adev", 6}});
}

// gmwm fleet --report: eight simulated units of two axes (SN5 with 4x the white-noise
// variance: twice the fleet's N) and a recording that cannot be read. Per axis the strips of
// N, K, B and the Allan deviation band render; SN5 is flagged, labelled and drawn over the
// band; the failure is listed with its reason.
TEST(HtmlReportInBrowser, FleetReportRendersEachAxisStripsAndBandWithTheFlaggedUnitAndTheFailure) {
  REQUIRE_BROWSER(exe);
  const fs::path dir = artefact_dir() / "fleet_units";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string manifest = "path,unit,model,units,rate\n";
  for (int k = 1; k <= 8; ++k) {
    const std::string spec = k == 5 ? "WN(sigma2=4e-4)+RW(gamma2=1e-10)" : "WN(sigma2=1e-4)+RW(gamma2=1e-10)";
    const auto r = run_gmwm(
        {"simulate", "--model", spec, "--n", "16384", "--freq", "100", "--signals", "2", "--names", "gyro_x,gyro_y",
         "--seed", std::to_string(20 + k), "--output", "u" + std::to_string(k) + ".csv", "--quiet"},
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    manifest += "u" + std::to_string(k) + ".csv,SN" + std::to_string(k) + ",IMU-X,gyro=deg/s,100\n";
  }
  // SN9's recording: its header reads, a row far into it does not.
  std::string text = read_text(dir / "u1.csv");
  text.insert(text.find('\n', text.size() / 2) + 1, "0.5,abc\n");
  gmwm::test::write_text(dir / "u9.csv", text);
  manifest += "u9.csv,SN9,IMU-X,gyro=deg/s,100\n";
  gmwm::test::write_text(dir / "fleet.csv", manifest);
  check_report(*exe, "report_fleet", {"fleet", (dir / "fleet.csv").string(), "--model", "WN+RW", "--no-cache"},
               {{"fleet-figures", 2}, {"adev", 2}});
  const std::string html = read_text(artefact_dir() / "report_fleet.html");
  EXPECT_NE(html.find("<h2>group IMU-X</h2>"), std::string::npos);
  EXPECT_NE(html.find("9 unit(s); 1 recording(s) failed"), std::string::npos);
  EXPECT_EQ(count_matches(html, "<tr class=\"outside\" data-unit=\"SN5\""), 2) << "SN5 flagged on both axes";
  EXPECT_EQ(count_matches(html, "<tr class=\"outside\""), 2) << "no other unit flagged";
  EXPECT_NE(html.find("<li>SN5: N on gyro_x "), std::string::npos);
  EXPECT_NE(html.find("<td>SN9</td><td>(the recording)</td><td class=\"note\">"), std::string::npos);
  const std::string dom = Browser(*exe).dump_dom(artefact_dir() / "report_fleet.html", artefact_dir() / "fleet.log");
  // The flagged unit labelled on its strips and over the bands (Vega's SVG text).
  EXPECT_GE(count_matches(dom, "<text[^>]*>SN5</text>"), 4) << "SN5's labels: N on each axis and each band";
  EXPECT_GE(count_matches(dom, "aria-label=\"X-axis titled 'N \\[deg/sqrt\\(h\\)\\]'"), 2);
  // Hovering a unit's dot shows its unit, value, interval, read-off source, z and recording.
  std::string probe = html;
  const auto at = probe.rfind("</body>");
  ASSERT_NE(at, std::string::npos);
  probe.replace(at, 7, R"JS(<script>
setTimeout(function () {
  var dot = document.querySelector('#group-1-axis-1-figures .mark-symbol.role-mark path');
  var box = dot.getBoundingClientRect();
  dot.dispatchEvent(new MouseEvent('mousemove', {clientX: box.left + box.width / 2, clientY: box.top + box.height / 2,
                                                 bubbles: true}));
  setTimeout(function () {
    document.body.setAttribute('data-tooltip',
                               document.querySelector('#group-1-axis-1-figures .view').getAttribute('title') || '');
  }, 300);
}, 1500);
</script>
</body>)JS");
  gmwm::test::write_text(artefact_dir() / "report_fleet_probe.html", probe);
  const std::string hovered =
      Browser(*exe).dump_dom(artefact_dir() / "report_fleet_probe.html", artefact_dir() / "fleet.log");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(hovered, m, std::regex("data-tooltip=\"([^\"]*)\""))) << "no tooltip probe";
  for (const char* key : {"unit: SN", "value: ", " deg/sqrt(h)", "interval: ", "source: ", " read-off",
                          "robust z: ", "its flag limits: ", "recording: "})
    EXPECT_NE(m[1].str().find(key), std::string::npos) << key << " in " << m[1];
  fs::remove(artefact_dir() / "report_fleet_probe.html");
  fs::remove_all(dir);
}

// The three ADIS16405 units as a fleet: six axes, each with its strips and band; three
// units are too few to flag, and the page says so.
TEST(HtmlReportInBrowser, FleetReportOfTheThreeAdisUnitsRendersEveryAxis) {
  GMWM_REQUIRE_SHARED_DATA();
  REQUIRE_BROWSER(exe);
  const fs::path dir = artefact_dir();
  std::string manifest = "path,unit,model,units,rate\n";
  for (int k = 1; k <= 3; ++k)
    manifest += gmwm::test::shared_data_file("adis_16405_imu" + std::to_string(k) + ".csv.gz") + ",IMU" +
                std::to_string(k) + ",ADIS16405,\"gyro=deg/s,accel=g\",100\n";
  gmwm::test::write_text(dir / "fleet_adis.csv", manifest);
  check_report(*exe, "report_fleet_adis",
               {"fleet", (dir / "fleet_adis.csv").string(), "--model", "AR1+WN+RW", "--no-cache"},
               {{"fleet-figures", 6}, {"adev", 6}});
  const std::string html = read_text(dir / "report_fleet_adis.html");
  EXPECT_NE(html.find("No unit can be flagged: flags need 5 or more units"), std::string::npos);
  EXPECT_EQ(count_matches(html, "<tr class=\"outside\""), 0);
}

}  // namespace

// gmwm nav: the position, velocity, attitude and NEES plots with the Monte Carlo's points.
TEST(HtmlReportInBrowser, NavReportRendersItsFourCurvePlotsWithoutScriptErrors) {
  REQUIRE_BROWSER(exe);
  const fs::path dir = artefact_dir();
  const fs::path page = dir / "report_nav.html";
  const fs::path log = dir / "report_nav.chromium.log";
  fs::remove(log);
  const auto r =
      run_gmwm({"nav",
                "--truth",
                "gyro=AR1(phi=0.9999,sigma2=1e-12)+WN(sigma2=1e-8);accel=AR1(phi=0.9999,sigma2=1e-8)+WN(sigma2=1e-5)",
                "--filter",
                "truth",
                "--filter",
                "wnrw",
                "--label",
                "the truth",
                "--rate",
                "100",
                "--horizon",
                "300",
                "--outage",
                "120:180",
                "--monte-carlo",
                "20",
                "--report",
                page.string(),
                "--quiet"},
               dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Browser browser(*exe);
  const std::string dom = browser.dump_dom(page, log);
  ASSERT_FALSE(dom.empty()) << "empty DOM dump, see " << log;
  expect_rendered(dom, {{"nav-position", 1}, {"nav-velocity", 1}, {"nav-attitude", 1}, {"nav-nees", 1}});
  EXPECT_NE(dom.find("aria-label=\"X-axis titled 'time [s]'"), std::string::npos);
  EXPECT_NE(dom.find("the truth"), std::string::npos);
  const fs::path png = dir / "report_nav.png";
  fs::remove(png);
  browser.screenshot(page, png, log);
  expect_screenshot(png);
}
