// The stability study's HTML report (report/stability_output.h) with the three-cornered hat,
// without a browser: its section after the columns, a plot per kind with the three columns
// and their bands, the table of every value [low, high] and the negative variances listed,
// not drawn; a hostile column name escaped in text and in the embedded specs; the web app's
// fragment of the same study the same sections.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gmwm/engine/number_text.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/report/html_report.h"
#include "gmwm/report/stability_output.h"

namespace {

using gmwm::pipeline::StabilityStudy;
using gmwm::pipeline::StabilityStudyOptions;
using gmwm::stability::DeviationKind;

#define REQUIRE_VEGA()                                                                \
  do {                                                                                \
    if (const std::string why = gmwm::report::vega_missing_reason(); !why.empty()) {  \
      const char* req = std::getenv("GMWM_REQUIRE_BROWSER");                          \
      if (req && std::string(req) == "1") FAIL() << "Vega is required (CI): " << why; \
      GTEST_SKIP() << "Vega (Debian libjs-vega) not available: " << why;              \
    }                                                                                 \
  } while (0)

constexpr const char* kHostile = "</script><img src=x onerror=alert(1)>";

// Three sensors at 100 Hz sharing an input (white 0.3 and a random walk) a hundred times their
// own white noises of 1e-3 times `levels`: a level 0 is the common input alone, whose separated
// variance is as often negative as positive.
gmwm::io::SignalSet three_sensors(const std::vector<std::string>& names, const std::vector<double>& levels) {
  gmwm::io::SignalSet set;
  set.path = "three.csv";
  set.freq = 100.0;
  set.freq_known = true;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> y(3);
  double walk = 0.0;
  for (int i = 0; i < 20000; ++i) {
    walk += 3e-4 * g(rng);
    const double common = 0.3 * g(rng) + walk;
    for (std::size_t s = 0; s < 3; ++s) y[s].push_back(common + 1e-3 * levels[s] * g(rng));
  }
  for (std::size_t s = 0; s < 3; ++s) set.signals.push_back({names[s], gmwm::Samples(std::move(y[s])), ""});
  return set;
}

StabilityStudyOptions hat_options() {
  StabilityStudyOptions o;
  o.kinds = {DeviationKind::kOadev, DeviationKind::kMdev, DeviationKind::kTdev};
  o.three_cornered_hat = true;
  return o;
}

// The page's embedded spec list.
nlohmann::json specs_of(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"gmwm-specs\">";
  const auto a = page.find(open);
  const auto b = page.find("</script>", a);
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(page.substr(a + open.size(), b - a - open.size()));
}

std::vector<nlohmann::json> hat_specs(const nlohmann::json& specs) {
  std::vector<nlohmann::json> out;
  for (const nlohmann::json& s : specs)
    if (s.at("kind") == "stability-hat") out.push_back(s);
  return out;
}

int count(const std::string& text, const std::string& part) {
  int n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(StabilityPage, TheHatsSectionFollowsTheColumnsWithAPlotPerKindOfTheThreeColumnsAndTheirBands) {
  REQUIRE_VEGA();
  const gmwm::io::SignalSet set = three_sensors({"a", "b", "c"}, {1.0, 2.0, 3.0});
  const StabilityStudyOptions o = hat_options();
  const StabilityStudy study = gmwm::pipeline::study_stability(set, o);
  const std::string page = gmwm::report::render_stability_html(set, study, o, {"deg/s", "deg/s", "deg/s"});
  const auto hat = page.find("<section class=\"column\" id=\"stability-hat\">\n<h2>three-cornered hat</h2>");
  ASSERT_NE(hat, std::string::npos);
  EXPECT_LT(page.find("id=\"stability-3\""), hat) << "after the columns";
  EXPECT_NE(page.find("three-cornered hat of a, b, c: each column&#39;s own deviation, separated from what the three "
                      "share. The columns, recorded together, give the differences a - b, b - c, c - a"),
            std::string::npos);
  EXPECT_NE(page.find("<p>Bands and [low, high]: the 68.27% score interval of each separated variance from edf, the "
                      "smallest of the three pairs&#39; degrees of freedom"),
            std::string::npos);
  const std::vector<nlohmann::json> specs = hat_specs(specs_of(page));
  ASSERT_EQ(specs.size(), 3u);
  const std::vector<std::string> kinds = {"oadev [deg/s]", "mdev [deg/s]", "tdev [(deg/s)*s]"};
  for (std::size_t d = 0; d < specs.size(); ++d) {
    EXPECT_EQ(specs[d].at("id"), "plot-hat-" + std::to_string(d + 1));
    EXPECT_NE(page.find("data-plot=\"stability-hat\" id=\"plot-hat-" + std::to_string(d + 1) + "\""),
              std::string::npos);
    const nlohmann::json& spec = specs[d].at("spec");
    EXPECT_EQ(spec.at("axes")[1].at("title"), kinds[d]);
    EXPECT_EQ(spec.at("axes")[0].at("title"), "tau [s]");
    EXPECT_EQ(spec.at("legends")[0].at("title"), "column");
    std::set<std::string> sensors;
    int bands = 0;
    for (const nlohmann::json& row : spec.at("data")[0].at("values")) {
      if (row.at("v").is_null()) continue;  // a negative variance
      sensors.insert(row.at("sensor").get<std::string>());
      // Every value drawn has its band around it (lo null: from 0, the plot's floor).
      const double v = row.at("v"), hi = row.at("hi");
      EXPECT_GE(hi, v) << row.dump();
      if (!row.at("lo").is_null()) EXPECT_LE(row.at("lo").get<double>(), v) << row.dump();
      bands += hi > v ? 1 : 0;
    }
    EXPECT_EQ(sensors, (std::set<std::string>{"a", "b", "c"}));
    EXPECT_GE(bands, 3 * 8) << "the bands of each column's first octaves at least";
  }
  // The table: per tau each column's value [low, high], as the document has them.
  const gmwm::stability::ThreeCorneredHat& oadev = study.hat->kinds[0];
  const auto cell = [](double x) { return gmwm::significant(x, 5, gmwm::NonFinite::kDash); };
  EXPECT_NE(page.find("<th>b<br><small>oadev [deg/s]</small></th>"), std::string::npos);
  EXPECT_NE(page.find("<td class=\"num\">" + cell(oadev.sensors[1].value[0]) + "<br><small>[" +
                      cell(oadev.sensors[1].low[0]) + ",&nbsp;" + cell(oadev.sensors[1].high[0]) + "]</small></td>"),
            std::string::npos);
}

TEST(StabilityPage, ANegativeVarianceIsListedInTheTableAndNotDrawn) {
  REQUIRE_VEGA();
  const gmwm::io::SignalSet set = three_sensors({"a", "b", "c"}, {0.0, 2.0, 3.0});
  const StabilityStudyOptions o = hat_options();
  const StabilityStudy study = gmwm::pipeline::study_stability(set, o);
  const std::string page = gmwm::report::render_stability_html(set, study, o, {});
  const gmwm::stability::HatSensor& a = study.hat->kinds[0].sensors[0];
  std::size_t negative = 0, rows = 0, drawn = 0;
  for (const bool b : a.negative) negative += b ? 1 : 0;
  ASSERT_GE(negative, 1u);
  const nlohmann::json oadev = hat_specs(specs_of(page)).at(0);
  for (const nlohmann::json& row : oadev.at("spec").at("data")[0].at("values"))
    if (row.at("sensor") == "a") {
      ++rows;
      drawn += row.at("v").is_null() ? 0 : 1;
    }
  EXPECT_EQ(rows, a.value.size());
  EXPECT_EQ(drawn, a.value.size() - negative) << "the negative ones are not drawn (their rows break the line)";
  for (std::size_t i = 0; i < a.negative.size(); ++i)
    if (a.negative[i])
      EXPECT_NE(page.find("<td class=\"num\">[var " + gmwm::significant(a.variance[i], 5) + "]"), std::string::npos);
  EXPECT_NE(page.find("[var V]: the separated variance V (in the unit squared) is negative: no deviation"),
            std::string::npos);
  // Without a declared unit, the data's is U.
  EXPECT_NE(page.find("<th>a<br><small>tdev [(U)*s]</small></th>"), std::string::npos);
}

TEST(StabilityPage, EscapesAHostileColumnNameInTheHatsTextTablesAndSpecs) {
  REQUIRE_VEGA();
  const gmwm::io::SignalSet set = three_sensors({"a", kHostile, "c"}, {1.0, 2.0, 3.0});
  const StabilityStudyOptions o = hat_options();
  const StabilityStudy study = gmwm::pipeline::study_stability(set, o);
  const std::string page = gmwm::report::render_stability_html(set, study, o, {});
  // Nowhere raw: not in text, not in an attribute, not in a script.
  EXPECT_EQ(page.find(kHostile), std::string::npos);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  const std::string text = "&lt;/script&gt;&lt;img src=x onerror=alert(1)&gt;";
  EXPECT_NE(page.find("three-cornered hat of a, " + text + ", c"), std::string::npos);
  EXPECT_NE(page.find("<th>" + text + "<br><small>oadev [U]</small></th>"), std::string::npos);
  // In the embedded JSON: '<', '>' as \u003c, \u003e; the page's own script elements only (the
  // error catcher, the specs, Vega, the page's script).
  EXPECT_NE(page.find("\\u003c/script\\u003e\\u003cimg src=x onerror=alert(1)\\u003e"), std::string::npos);
  EXPECT_EQ(count(page, "<script"), 4);
  EXPECT_EQ(count(page, "</script>"), 4);
  // And the JSON reads back to the very name, drawn as text by Vega.
  std::set<std::string> sensors;
  const nlohmann::json oadev = hat_specs(specs_of(page)).at(0);
  for (const nlohmann::json& row : oadev.at("spec").at("data")[0].at("values"))
    sensors.insert(row.at("sensor").get<std::string>());
  EXPECT_EQ(sensors, (std::set<std::string>{"a", kHostile, "c"}));
}

TEST(StabilityPage, TheWebAppsFragmentOfTheStudyHasTheReportsSectionsAndPlots) {
  const gmwm::io::SignalSet set = three_sensors({"a", "b", "c"}, {1.0, 2.0, 3.0});
  const StabilityStudyOptions o = hat_options();
  const StabilityStudy study = gmwm::pipeline::study_stability(set, o);
  const gmwm::report::HtmlFragment f = gmwm::report::render_stability_fragment(set, study, o, {});
  EXPECT_EQ(f.html.rfind("<section class=\"column\" id=\"stability-1\">\n<h2>a</h2>\n<p>read as rate", 0), 0u);
  EXPECT_NE(f.html.find("<section class=\"column\" id=\"stability-hat\">"), std::string::npos);
  std::vector<std::string> kinds;
  for (const nlohmann::json& p : f.plots) kinds.push_back(p.at("kind"));
  EXPECT_EQ(kinds, (std::vector<std::string>{"stability", "stability-time", "stability", "stability-time", "stability",
                                             "stability-time", "stability-hat", "stability-hat", "stability-hat"}));
  // One column without the hat: that column's fragment.
  StabilityStudy one = study;
  one.columns.resize(1);
  one.hat.reset();
  const gmwm::report::HtmlFragment column = gmwm::report::render_stability_fragment(set, one, o, {}, 0);
  EXPECT_EQ(gmwm::report::render_stability_fragment(set, one, o, {}).html, column.html);
}

}  // namespace
