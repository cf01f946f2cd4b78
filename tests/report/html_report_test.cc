// render_html_report / write_html_report without a browser: the page inlines Vega, holds
// one spec per plot container, escapes every user string, stays small, and the static
// SVG and the writer behave (html_report.h). The browser test is
// tests/cli/html_report_browser_test.cc.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/report/html_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::report::ReportColumn;
using gmwm::report::ReportData;

namespace {

// Vega is a listed dependency (tools/setup.sh); absent, the test skips unless the browser
// checks are required (CI), like the browser test.
#define REQUIRE_VEGA()                                                                \
  do {                                                                                \
    if (const std::string why = gmwm::report::vega_missing_reason(); !why.empty()) {  \
      const char* req = std::getenv("GMWM_REQUIRE_BROWSER");                          \
      if (req && std::string(req) == "1") FAIL() << "Vega is required (CI): " << why; \
      GTEST_SKIP() << "Vega (Debian libjs-vega) not available: " << why;              \
    }                                                                                 \
  } while (0)

constexpr const char* kNastyName = "gyro<x>&\"q'</script><script>alert(1)</script>";

gmwm::WaveletVariance synthetic_wv(double scale, int levels = 14) {
  gmwm::WaveletVariance w;
  w.n = std::int64_t{1} << (levels + 1);
  for (int j = 1; j <= levels; ++j) {
    const double tau = std::ldexp(1.0, j);
    const double v = scale * (1.0 / tau + 1e-4 * tau);
    w.tau.push_back(tau);
    w.wv.push_back(v);
    w.ci_low.push_back(0.8 * v);
    w.ci_high.push_back(1.25 * v);
    w.coefficients.push_back(w.n - static_cast<std::int64_t>(tau) + 1);
    w.notes.emplace_back();
  }
  return w;
}

gmwm::FitResult synthetic_fit() {
  gmwm::FitResult f;
  f.model = gmwm::parse_model("AR1+WN", gmwm::ProcessContext{100.0, true});
  f.theta = Eigen::Vector3d(0.99, 1e-4, 1.0);
  f.se = Eigen::Vector3d(0.001, 1e-5, 0.01);
  f.ci_low = Eigen::Vector3d(0.985, 0.8e-4, 0.98);
  f.ci_high = Eigen::Vector3d(0.995, 1.2e-4, 1.02);
  f.status = gmwm::FitStatus::kConverged;
  f.objective = 12.5;
  return f;
}

ReportData six_columns() {
  ReportData d;
  d.command = "fit";
  d.input = "data/<input>&.csv";
  d.model_spec = "AR1+WN";
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", kNastyName};
  for (int k = 0; k < 6; ++k) {
    ReportColumn c;
    c.name = names[k];
    c.n = 1 << 15;
    c.freq = 100.0;
    c.freq_known = true;
    c.unit = k < 3 ? "deg/s" : "";
    c.wvs = {synthetic_wv(1.0 + k)};
    c.fit = synthetic_fit();
    d.columns.push_back(std::move(c));
  }
  return d;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size())) ++n;
  return n;
}

// The embedded specs: the JSON of <script id="gmwm-specs">.
nlohmann::json specs_of(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"gmwm-specs\">";
  const auto b = html.find(open);
  const auto e = html.find("</script>", b);
  EXPECT_NE(b, std::string::npos);
  return nlohmann::json::parse(html.substr(b + open.size(), e - b - open.size()));
}

// A figure the curves only bound is drawn as a bound: white noise alone, its Allan deviation
// still falling at its last point, bounds B (and K), and the guides' legend says "<" as the
// tables do, never "B = " for a value no curve showed.
TEST(HtmlReport, TheAllanGuidesOfFiguresTheCurvesOnlyBoundAreLabelledAsBounds) {
  REQUIRE_VEGA();
  std::vector<double> x(1 << 14);
  std::uint64_t state = 88172645463325252ULL;  // xorshift64: a fixed, portable sequence
  for (double& v : x) {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    v = static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;  // uniform white noise
  }
  ReportData d = six_columns();
  d.columns.resize(1);
  d.columns[0].allan = gmwm::data_figure_report(x, 100.0);
  const gmwm::ChosenFigures& chosen = d.columns[0].allan->chosen;
  ASSERT_EQ(chosen.instability.source, gmwm::FigureSource::kBound) << chosen.instability.note;
  // The legend's names, in the embedded specs (where the page writes '<' as \u003c).
  const std::string names = specs_of(gmwm::report::render_html_report(d)).dump();
  EXPECT_NE(names.find("0.664 B, B < "), std::string::npos);
  EXPECT_EQ(names.find("0.664 B, B = "), std::string::npos);
  EXPECT_NE(names.find("\"N = "), std::string::npos) << "the white noise is read, not bounded";
  // White noise shows no -1 or +1 slope: Q and R are bounds, their guides say so, and the
  // figures table has their rows with their units.
  ASSERT_EQ(chosen.quantization.source, gmwm::FigureSource::kBound) << chosen.quantization.note;
  ASSERT_EQ(chosen.ramp.source, gmwm::FigureSource::kBound) << chosen.ramp.note;
  EXPECT_NE(names.find("Q < "), std::string::npos);
  EXPECT_NE(names.find("R < "), std::string::npos);
  EXPECT_EQ(names.find("Q = "), std::string::npos);
  const std::string html = gmwm::report::render_html_report(d);
  EXPECT_NE(html.find("<td>Q quantization</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>R rate ramp</td>"), std::string::npos);
}

TEST(HtmlReport, InlinesVegaAndHoldsOneSpecPerPlotContainer) {
  REQUIRE_VEGA();
  const std::string html = gmwm::report::render_html_report(six_columns());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // Vega itself is in the page (no external script, no CDN).
  EXPECT_NE(html.find("/* vega-view (Debian libjs-vega) */"), std::string::npos);
  EXPECT_NE(html.find("/* vega-parser (Debian libjs-vega) */"), std::string::npos);
  EXPECT_NE(html.find("var vega = (function (m)"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("sourceMappingURL"), std::string::npos);
  EXPECT_EQ(html.find("cdn.jsdelivr"), std::string::npos);
  // One spec per plot, ids matching, six WV plots.
  const nlohmann::json specs = specs_of(html);
  ASSERT_EQ(specs.size(), 6u);
  EXPECT_EQ(count(html, "class=\"gmwm-plot\""), 6);
  for (const auto& s : specs) {
    EXPECT_EQ(s.at("kind"), "wv");
    EXPECT_NE(html.find("id=\"" + s.at("id").get<std::string>() + "\""), std::string::npos);
    EXPECT_EQ(s.at("spec").at("axes")[0].at("title"), "tau [s]");
    EXPECT_EQ(s.at("spec").at("$schema"), "https://vega.github.io/schema/vega/v5.json");
  }
  // The model's implied WV and its two components are drawn (curves data).
  const auto& curves = specs[0].at("spec").at("data")[2].at("values");
  std::set<std::string> series;
  for (const auto& row : curves) series.insert(row.at("series").get<std::string>());
  EXPECT_EQ(series, (std::set<std::string>{"model AR1+WN", "1: AR1", "2: WN"}));
  EXPECT_EQ(specs[0].at("spec").at("axes")[1].at("title"), "wavelet variance nu^2 [(deg/s)^2]");
  EXPECT_EQ(specs[3].at("spec").at("axes")[1].at("title"), "wavelet variance nu^2 [(U)^2]");
}

TEST(HtmlReport, EscapesColumnNamesAndPathsInTextAttributesAndScripts) {
  REQUIRE_VEGA();
  const std::string html = gmwm::report::render_html_report(six_columns());
  // The raw string never appears; its HTML-escaped form heads its section.
  EXPECT_EQ(html.find(kNastyName), std::string::npos);
  EXPECT_EQ(html.find("<script>alert(1)"), std::string::npos);
  EXPECT_NE(html.find("<h2>gyro&lt;x&gt;&amp;&quot;q&#39;&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;</h2>"),
            std::string::npos);
  EXPECT_NE(html.find("data/&lt;input&gt;&amp;.csv"), std::string::npos);
  // Exactly the page's own four script elements are closed (error capture, specs, Vega,
  // page): no user string can close one early.
  EXPECT_EQ(count(html, "</script>"), 4);
  // In the specs, the name survives JSON-escaped and reads back intact.
  const nlohmann::json specs = specs_of(html);
  EXPECT_NE(specs[5].at("spec").at("title").at("text").get<std::string>().find(kNastyName), std::string::npos);
}

TEST(HtmlReport, ShowsWhatToChangeWithEveryFieldColumnAndTheFileEscaped) {
  REQUIRE_VEGA();
  ReportData d = six_columns();
  gmwm::pipeline::CorrectedConfig c;
  c.format = "datasheet";
  c.content = "gyroscope:\n  noise_density: 0.0404 deg/s/sqrt(Hz)  # </pre><script>alert(1)</script>\n";
  c.changes.push_back({"gyroscope/noise_density", 0.05, 0.0404, "deg/s/sqrt(Hz)", true});
  c.changes.push_back({"gyroscope/rate_random_walk", NAN, 65.5, "deg/h/sqrt(h)", true});
  gmwm::pipeline::CorrectedColumn col;
  col.name = kNastyName;
  col.before.levels_outside = 14;
  col.with_config.levels_outside = 6;
  col.with_full.levels_outside = 2;
  col.before.objective = 9.81e5;
  col.with_config.objective = 1.24e5;
  col.with_full.objective = 20.0;
  col.not_expressible.push_back("SIN(A2=1,f=16) <b>");
  c.columns.push_back(col);
  d.corrected = c;
  const std::string html = gmwm::report::render_html_report(d);
  const std::size_t at = html.find("<section class=\"column\" id=\"what-to-change\">");
  ASSERT_NE(at, std::string::npos);
  const std::string section = html.substr(at, html.find("</section>", at) - at);
  EXPECT_NE(section.find("<h2>what to change (datasheet)</h2>"), std::string::npos);
  EXPECT_NE(section.find("<td>gyroscope/noise_density</td><td class=\"num\">0.05</td><td class=\"num\">0.0404</td>"
                         "<td>deg/s/sqrt(Hz)</td><td>yes</td>"),
            std::string::npos)
      << section;
  EXPECT_NE(section.find("<td class=\"num\">-</td><td class=\"num\">65.5</td>"), std::string::npos);  // added field
  EXPECT_NE(section.find("14 -&gt; 6 -&gt; 2"), std::string::npos) << section;
  EXPECT_NE(section.find("SIN(A2=1,f=16) &lt;b&gt;"), std::string::npos);
  EXPECT_NE(section.find("&lt;/pre&gt;&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_EQ(section.find(kNastyName), std::string::npos);  // the column name only escaped
  EXPECT_EQ(count(html, "</script>"), 4);
}

TEST(HtmlReport, StaysUnderFiveMegabytesForSixColumns) {
  REQUIRE_VEGA();
  const std::string html = gmwm::report::render_html_report(six_columns());
  EXPECT_LT(html.size(), 5u * 1024u * 1024u);
  EXPECT_GT(html.size(), 300u * 1024u);  // Vega's modules are in it
}

TEST(HtmlReport, ShowsParametersInDiscreteAndContinuousUnits) {
  REQUIRE_VEGA();
  const std::string html = gmwm::report::render_html_report(six_columns());
  EXPECT_EQ(count(html, "<table class=\"discrete\">"), 6);
  EXPECT_EQ(count(html, "<table class=\"continuous\">"), 6);
  // WN sigma2 = 1 at 100 Hz: noise density sqrt(1 / 100) = 0.1 deg/s/sqrt(Hz).
  EXPECT_NE(html.find("<td class=\"num\">0.1</td><td class=\"num\">"), std::string::npos);
  EXPECT_NE(html.find("<td>deg/s/sqrt(Hz)</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>correlation time</td>"), std::string::npos);
  // The Kalman-filter table, at the data's rate: WN sigma2 = 1 per sample is R = 1 (deg/s)^2.
  EXPECT_EQ(count(html, "<table class=\"kalman\">"), 6);
  EXPECT_NE(html.find("<td>measurement noise R</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num\">1 (deg/s)^2</td>"), std::string::npos);
}

TEST(HtmlReport, HighlightsTheChosenModelOfASelection) {
  REQUIRE_VEGA();
  ReportData d = six_columns();
  d.command = "select";
  d.columns.resize(1);
  ReportColumn& c = d.columns[0];
  gmwm::selection::Selection sel;
  sel.full_model = "AR1+WN+RW";
  sel.models = 2;
  sel.best_fit = *c.fit;
  c.fit.reset();
  for (int r = 1; r <= 2; ++r) {
    gmwm::selection::RankedModel m;
    m.rank = r;
    m.model = r == 1 ? "AR1+WN" : "AR1+WN+RW";
    m.parameters = r == 1 ? 3 : 4;
    m.criterion = 10.0 * r;
    sel.ranking.push_back(m);
  }
  c.selection = sel;
  const std::string html = gmwm::report::render_html_report(d);
  EXPECT_EQ(count(html, "<tr class=\"chosen\">"), 1);
  EXPECT_NE(html.find("AR1+WN <span class=\"badge\">chosen</span>"), std::string::npos);
  EXPECT_NE(html.find("chosen model AR1+WN"), std::string::npos);
}

TEST(HtmlReport, DrawsTheGapMapsAndCurvesOfEveryDiagnosedColumn) {
  REQUIRE_VEGA();
  ReportData d = six_columns();
  d.command = "gap";
  d.columns.resize(2);
  for (auto& c : d.columns) {
    c.fit.reset();
    gmwm::gap::GapResult g;
    g.baseline = gmwm::parse_model("WN", gmwm::ProcessContext{100.0, true});
    g.baseline_theta = Eigen::VectorXd::Constant(1, 1.0);
    for (std::size_t j = 0; j < c.wvs[0].tau.size(); ++j) {
      gmwm::gap::GapLevel l;
      l.tau = c.wvs[0].tau[j];
      l.ratio = 1.0 + 0.1 * static_cast<double>(j);
      l.z = 0.5 * static_cast<double>(j);
      l.ref_low = 0.5 / l.tau;
      l.ref_high = 2.0 / l.tau;
      l.outside = j > 10;
      g.levels.push_back(l);
    }
    g.windows_checked = true;
    g.window_length = 4096;
    g.windows.push_back({0, 4095, 64.0, 3.0, 5.0});
    c.gap = g;
  }
  const std::string html = gmwm::report::render_html_report(d);
  const nlohmann::json specs = specs_of(html);
  std::map<std::string, int> kinds;
  for (const auto& s : specs) ++kinds[s.at("kind").get<std::string>()];
  EXPECT_EQ(kinds["wv"], 2);
  EXPECT_EQ(kinds["gap-levels"], 1);
  EXPECT_EQ(kinds["gap-windows"], 2);
  EXPECT_EQ(kinds["gap-curves"], 2);
  EXPECT_EQ(count(html, "class=\"gmwm-plot\""), 7);
  // The scale x axis map holds every level of both columns.
  for (const auto& s : specs) {
    if (s.at("kind") == "gap-levels") {
      EXPECT_EQ(s.at("spec").at("data")[0].at("values").size(), 28u);
    }
  }
}

TEST(HtmlReport, OverlaysTheReplicatesWithTheJointModelAndTabulatesTheTestAndTheThreeWvics) {
  REQUIRE_VEGA();
  // Three replicates of different lengths; the longest is the last, so the model curve must
  // reach its coarsest scale.
  const auto wvs = gmwm::test::simulated_replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", {12, 13, 15}, 77);
  const gmwm::Model model = gmwm::parse_model("WN+RW");
  gmwm::ReplicateTestOptions to;
  to.bootstrap = 19;
  gmwm::selection::ReplicateSelectOptions so;
  so.select.optimism = gmwm::selection::OptimismMethod::kBoth;
  so.select.bootstrap_replicates = 10;
  gmwm::report::ReplicateReport rep;
  rep.sources = {"a/r1.csv:gx", "b/r2.csv:gx", kNastyName};
  rep.n = {1 << 12, 1 << 13, 1 << 15};
  rep.estimator = "classical WV";
  rep.joint = gmwm::fit_gmwm_joint(wvs, model);
  rep.test = gmwm::replicate_test(wvs, *rep.joint, to);
  rep.bootstrap = gmwm::replicate_bootstrap(wvs, *rep.joint);
  rep.selection = gmwm::selection::select_by_replicates(wvs, gmwm::parse_model("AR1+WN+RW"), so);
  ReportData d;
  d.command = "select";
  d.input = "a/r1.csv";
  ReportColumn c;
  c.name = "gx";
  c.n = 1 << 12;
  c.wvs = wvs;
  c.fit = rep.joint->joint;
  c.replicates = rep;
  d.columns.push_back(c);
  const std::string html = gmwm::report::render_html_report(d);
  // The legend names each replicate by its file; the table by its full source, escaped.
  const nlohmann::json specs = specs_of(html);
  ASSERT_EQ(specs.size(), 1u);
  std::set<std::string> series;
  double longest = 0.0;
  for (const auto& data : specs[0].at("spec").at("data"))
    if (data.contains("values"))
      for (const auto& row : data.at("values"))
        if (row.contains("series")) {
          series.insert(row.at("series").get<std::string>());
          if (row.at("series") == "joint model WN+RW") longest = std::max(longest, row.at("tau").get<double>());
        }
  EXPECT_TRUE(series.count("replicate 1: r1.csv"));
  EXPECT_TRUE(series.count("replicate 2: r2.csv"));
  EXPECT_TRUE(series.count("joint model WN+RW"));
  EXPECT_EQ(longest, wvs.back().tau.back());  // tau in samples (rate unknown)
  EXPECT_GT(longest, wvs.front().tau.back());
  EXPECT_NE(html.find("a/r1.csv:gx"), std::string::npos);
  EXPECT_EQ(html.find("<script>alert(1)"), std::string::npos);
  // The test, the side-by-side parameters and the three-WVIC table.
  EXPECT_NE(html.find("shared theta? heterogeneity H = "), std::string::npos);
  EXPECT_NE(html.find("replicate-t interval (95%)"), std::string::npos);
  EXPECT_NE(html.find("replicate 3 alone"), std::string::npos);
  EXPECT_NE(html.find("AGMWM"), std::string::npos);
  EXPECT_NE(html.find("bootstrap WVIC (s.e.)"), std::string::npos);
  EXPECT_NE(html.find("<span class=\"badge\">recommended</span>"), std::string::npos);
  EXPECT_EQ(count(html, "<tr class=\"chosen\">"), 1);
  EXPECT_NE(html.find("recommended model, fitted jointly over the replicates"), std::string::npos);
}

TEST(HtmlReport, StaticSvgDrawsTheFirstColumnsWvModelAndComponents) {
  ReportData d = six_columns();
  const std::string svg = gmwm::report::render_wv_svg(d.columns[5]);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_EQ(svg.find(kNastyName), std::string::npos);
  EXPECT_NE(svg.find("gyro&lt;x&gt;&amp;"), std::string::npos);
  EXPECT_EQ(count(svg, "<polygon"), 1);                                         // the CI band
  EXPECT_EQ(count(svg, "<polyline"), 4);                                        // WV, model, 2 components
  EXPECT_EQ(count(svg, "stroke-width=\"1.5\" stroke-dasharray=\"6,4\"/>"), 2);  // the components' lines
  EXPECT_NE(svg.find(">tau [s]</text>"), std::string::npos);
}

TEST(HtmlReport, WritesThePageAndItsSvgAtomically) {
  REQUIRE_VEGA();
  const fs::path dir = gmwm::test::temp_dir("html_report");
  const fs::path path = dir / "report.html";
  gmwm::report::write_html_report(path.string(), six_columns());
  EXPECT_TRUE(fs::exists(path));
  EXPECT_TRUE(fs::exists(dir / "report.html.svg"));
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 2);  // no temporary left behind
  EXPECT_THROW(gmwm::report::write_html_report((dir / "missing" / "r.html").string(), six_columns()), gmwm::InputError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
  fs::remove_all(dir);
}

}  // namespace
