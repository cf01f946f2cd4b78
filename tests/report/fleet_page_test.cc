// The fleet's HTML report (report/fleet_page.h) as data and as a page, without a browser:
// each figure's strip against the group's median and its robust-z band, the band of Allan
// deviations over the unflagged units (interpolated when the tau grids differ), the flagged
// units over it, the headline's numbers, failures, units recorded in different units, and
// the escaping of a hostile unit id and axis name. The browser test is
// tests/cli/html_report_browser_test.cc (FleetReportInBrowser).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/output_set.h"
#include "gmwm/report/fleet_output.h"
#include "gmwm/report/fleet_page.h"
#include "gmwm/report/html_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::fleet::FleetCurves;
using gmwm::fleet::FleetRow;
using gmwm::fleet::FleetStudy;
using gmwm::report::fleet_page_data;
using gmwm::report::FleetAxisView;
using gmwm::report::FleetFigurePanel;
using gmwm::report::FleetPageData;

namespace {

#define REQUIRE_VEGA()                                                                \
  do {                                                                                \
    if (const std::string why = gmwm::report::vega_missing_reason(); !why.empty()) {  \
      const char* req = std::getenv("GMWM_REQUIRE_BROWSER");                          \
      if (req && std::string(req) == "1") FAIL() << "Vega is required (CI): " << why; \
      GTEST_SKIP() << "Vega (Debian libjs-vega) not available: " << why;              \
    }                                                                                 \
  } while (0)

constexpr const char* kHostileUnit = "</script><img src=x onerror=alert(1)>";
constexpr const char* kHostileAxis = "gyro\"x'<b>&";
// The standard normal's 97.5% quantile: the 95% intervals' half-width in standard errors.
constexpr double kZ975 = 1.959963984540054;

gmwm::Readoff readoff(double value, double tau, gmwm::ReadoffStatus status = gmwm::ReadoffStatus::kRead) {
  gmwm::Readoff r;
  r.value = value;
  r.status = status;
  r.tau = tau;
  if (status != gmwm::ReadoffStatus::kBound) {
    r.low = 0.99 * value;
    r.high = 1.01 * value;
  } else {
    r.high = value;
  }
  return r;
}

// A unit's axis: N and B read off (intervals +-1%), K an upper bound (as most gyros' K).
FleetRow row(const std::string& unit, const std::string& axis, double n, double b,
             const std::string& data_unit = "deg/s") {
  FleetRow r;
  r.unit = unit;
  r.model = "IMU-X";
  r.group = "line-A";
  r.path = unit + ".csv";
  r.axis = axis;
  r.data_unit = data_unit;
  r.chosen = "WN(sigma2=1e-4)";
  r.chosen_structure = "AR1+WN";
  r.gof_p = 0.5;
  r.freq = 100.0;
  r.n = 65536;
  r.figures_known = true;
  r.figures.white.figure = readoff(n, 1.0);
  r.figures.white.source = gmwm::FigureSource::kModel;
  r.figures.walk.figure = readoff(1e-4, 300.0, gmwm::ReadoffStatus::kBound);
  r.figures.walk.source = gmwm::FigureSource::kBound;
  r.figures.instability.figure = readoff(b, 20.0);
  r.figures.instability.source = gmwm::FigureSource::kData;
  return r;
}

// A white-noise ADEV c / sqrt(tau) at m = 1, 2, 4, ... samples of `freq` Hz, +-5% interval.
FleetCurves white_curve(double c, double freq = 100.0, int points = 12) {
  FleetCurves fc;
  gmwm::AllanDeviation& a = fc.adev;
  a.freq = freq;
  a.alpha = 0.05;
  for (int i = 0; i < points; ++i) {
    const std::int64_t m = std::int64_t{1} << i;
    const double tau = static_cast<double>(m) / freq;
    a.m.push_back(m);
    a.tau.push_back(tau);
    a.adev.push_back(c / std::sqrt(tau));
    a.ci_low.push_back(0.95 * c / std::sqrt(tau));
    a.ci_high.push_back(1.05 * c / std::sqrt(tau));
    a.edf.push_back(100.0);
  }
  return fc;
}

// A study of `units` units (one axis each) whose N spreads by a few percent; unit `outlier`
// (1-based; 0: none) has `factor` times the fleet's N. Summary and flags by fleet_summary.
FleetStudy fleet_of(int units, int outlier = 0, double factor = 2.0, const std::string& axis = "gyro_x",
                    const std::string& outlier_name = "") {
  FleetStudy s;
  s.manifest = "fleet.csv";
  s.model_spec = "AR1+WN+RW";
  for (int k = 1; k <= units; ++k) {
    const double wobble = 1.0 + 0.03 * std::sin(1.7 * k);  // within +-3%
    const double n = 1e-3 * wobble * (k == outlier ? factor : 1.0);
    const std::string name = k == outlier && !outlier_name.empty() ? outlier_name : "U" + std::to_string(k);
    s.rows.push_back(row(name, axis, n, 2e-3 * (1.0 + 0.02 * std::cos(2.3 * k))));
    s.curves.push_back(white_curve(n));
  }
  s.recordings = units;
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  return s;
}

const FleetFigurePanel& panel(const FleetPageData& d, char figure, std::size_t axis = 0) {
  return d.groups.at(0).axes.at(axis).figures.at(figure == 'N' ? 0 : figure == 'K' ? 1 : 2);
}

bool contains(const std::vector<std::string>& lines, const std::string& part) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : std::sqrt(v[n / 2 - 1] * v[n / 2]);  // of the logs: geometric
}

int count(const std::string& text, const std::string& part) {
  int n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// The page's embedded spec list.
nlohmann::json specs_of(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"gmwm-specs\">";
  const auto a = page.find(open);
  const auto b = page.find("</script>", a);
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(page.substr(a + open.size(), b - a - open.size()));
}

TEST(FleetPage, DrawsEachFigureAgainstTheGroupsMedianAndItsRobustZBand) {
  const FleetStudy s = fleet_of(8, 5);
  const FleetPageData d = fleet_page_data(s);
  ASSERT_EQ(d.groups.size(), 1u);
  const FleetFigurePanel& n = panel(d, 'N');
  const gmwm::fleet::FleetFigureSummary& sum = s.summary.at(0);
  ASSERT_EQ(sum.figure, 'N');
  // deg/s/sqrt(Hz) drawn in deg/sqrt(h): x sqrt(3600 s/h) = 60.
  EXPECT_EQ(n.unit, "deg/sqrt(h)");
  EXPECT_EQ(n.data_unit, "deg/s/sqrt(Hz)");
  EXPECT_NEAR(n.to_panel, 60.0, 1e-12);
  EXPECT_EQ(n.units, 8);
  EXPECT_TRUE(n.can_flag);
  EXPECT_NEAR(n.median, sum.median * 60.0, 1e-12 * n.median);
  EXPECT_DOUBLE_EQ(n.spread, sum.spread);
  EXPECT_NEAR(n.unit_spread, sum.unit_spread, 1e-12);
  // The units differ more than their read-offs' noise (tau > 0): the band of a read-off of the
  // fleet's median precision is median x spread^(+-3.5).
  ASSERT_GT(sum.unit_spread, 1.0);
  EXPECT_NEAR(n.band_low, n.median / std::pow(sum.spread, 3.5), 1e-9 * n.median);
  EXPECT_NEAR(n.band_high, n.median * std::pow(sum.spread, 3.5), 1e-9 * n.median);
  const double tau2 = std::pow(std::log(sum.unit_spread), 2);
  ASSERT_EQ(n.dots.size(), 8u);
  for (const auto& dot : n.dots) {
    const FleetRow& r = s.rows.at(static_cast<std::size_t>(dot.index));
    EXPECT_EQ(dot.unit, r.unit);
    EXPECT_NEAR(dot.value, r.figures.white.figure.value * 60.0, 1e-12 * dot.value);
    EXPECT_NEAR(dot.low, r.figures.white.figure.low * 60.0, 1e-12 * dot.value);
    EXPECT_EQ(dot.source, "model");
    // The summary's z: log(x / median) / sqrt(tau^2 + se^2), se from the 95% interval.
    const double se = std::log(dot.high / dot.low) / (2.0 * kZ975);
    const double scale = std::sqrt(tau2 + se * se);
    EXPECT_NEAR(dot.z, std::log(dot.value / n.median) / scale, 1e-9);
    EXPECT_NEAR(dot.limit_high, n.median * std::exp(3.5 * scale), 1e-9 * n.median);
    EXPECT_NEAR(dot.limit_low, n.median / std::exp(3.5 * scale), 1e-9 * n.median);
    EXPECT_EQ(dot.flagged, dot.unit == "U5") << dot.unit;
    EXPECT_EQ(dot.flagged, std::abs(dot.z) > 3.5) << dot.unit;
  }
  const auto& u5 = n.dots.at(4);
  EXPECT_TRUE(u5.beyond);  // its interval (+-1%) lies wholly above its limits
  EXPECT_EQ(u5.flag.rfind("N: 2", 0), 0u) << u5.flag;
  // K: every unit only an upper bound, drawn as such, no median.
  const FleetFigurePanel& k = panel(d, 'K');
  EXPECT_EQ(k.units, 0);
  EXPECT_TRUE(std::isnan(k.median));
  EXPECT_EQ(k.dots.size(), 8u);
  EXPECT_TRUE(std::all_of(k.dots.begin(), k.dots.end(), [](const auto& x) { return x.bound && !x.flagged; }));
  EXPECT_EQ(k.unit, "deg/h/sqrt(h)");
  EXPECT_EQ(panel(d, 'B').unit, "deg/h");
}

TEST(FleetPage, HeadlineNamesTheFlaggedUnitItsFigureAndTheNumbersBehindIt) {
  const FleetStudy s = fleet_of(8, 5);
  const FleetPageData d = fleet_page_data(s);
  const auto& g = d.groups.at(0);
  EXPECT_EQ(g.name, "line-A");
  EXPECT_EQ(g.units, 8);
  EXPECT_EQ(g.failed, 0);
  const std::string h = joined(g.headline);
  EXPECT_NE(h.find("8 unit(s); every recording analysed."), std::string::npos) << h;
  EXPECT_NE(h.find("1 unit(s) flagged"), std::string::npos) << h;
  EXPECT_NE(h.find("units per figure: N: 1, K: none, B: none"), std::string::npos) << h;
  EXPECT_NE(h.find("1 with a figure whose interval lies wholly outside its flag limits: U5."), std::string::npos) << h;
  // The sentence of U5 with its value, interval, ratio, median, z and band, as the strip shows them.
  const FleetFigurePanel& n = panel(d, 'N');
  const auto& u5 = n.dots.at(4);
  char expected[256];
  std::snprintf(expected, sizeof expected, "U5: N on gyro_x %.3g [%.3g, %.3g] deg/sqrt(h), %.3gx the median %.3g",
                u5.value, u5.low, u5.high, u5.value / n.median, n.median);
  EXPECT_TRUE(contains(g.headline, expected)) << expected << "\n" << h;
  char z[64];
  std::snprintf(z, sizeof z, "(robust z %.3g; flag limits %.3g-%.3g: interval wholly above them)", u5.z, u5.limit_low,
                u5.limit_high);
  EXPECT_TRUE(contains(g.headline, z)) << z << "\n" << h;
  EXPECT_TRUE(contains(g.headline,
                       "Not judged (fewer than 5 read-offs; the others only upper bounds): K: 0 on each "
                       "axis."))
      << h;
  ASSERT_EQ(g.flagged_rows.size(), 1u);
  EXPECT_EQ(s.rows.at(g.flagged_rows[0]).unit, "U5");
}

TEST(FleetPage, TheBandIsOverTheUnflaggedUnitsAndTheFlaggedOnesAreDrawnOverIt) {
  const FleetStudy s = fleet_of(8, 5);
  const FleetPageData d = fleet_page_data(s);
  const FleetAxisView& a = d.groups.at(0).axes.at(0);
  EXPECT_EQ(a.unit, "deg/s");
  EXPECT_EQ(a.band.units, 7);
  EXPECT_FALSE(a.band.interpolated);
  EXPECT_FALSE(a.band.percentiles);  // 7 < 20 units
  const std::vector<double>& tau = s.curves[0].adev.tau;
  ASSERT_EQ(a.band.tau, tau);
  for (std::size_t i = 0; i < tau.size(); ++i) {
    std::vector<double> v;
    for (std::size_t u = 0; u < s.rows.size(); ++u)
      if (s.rows[u].unit != "U5") v.push_back(s.curves[u].adev.adev[i]);
    EXPECT_DOUBLE_EQ(a.band.min[i], *std::min_element(v.begin(), v.end()));
    EXPECT_DOUBLE_EQ(a.band.max[i], *std::max_element(v.begin(), v.end()));
    EXPECT_NEAR(a.band.median[i], median_of(v), 1e-12 * a.band.median[i]);
    EXPECT_TRUE(std::isnan(a.band.p05[i]));
    EXPECT_EQ(a.band.count[i], 7);
  }
  ASSERT_EQ(a.flagged.size(), 1u);
  const auto& c = a.flagged[0];
  EXPECT_EQ(c.unit, "U5");
  EXPECT_EQ(c.adev, s.curves[4].adev.adev);
  EXPECT_EQ(c.low, s.curves[4].adev.ci_low);
  EXPECT_EQ(c.high, s.curves[4].adev.ci_high);
  EXPECT_DOUBLE_EQ(c.label_tau, 1.0);  // where its N was read
  EXPECT_TRUE(contains(a.notes, "the 7 unit(s) not flagged on gyro_x")) << joined(a.notes);
  EXPECT_TRUE(contains(a.notes, "the 5-95% envelope needs 20 units")) << joined(a.notes);
  EXPECT_TRUE(contains(a.notes, "1 flagged unit(s) drawn over the band, each with its 95% interval."))
      << joined(a.notes);
}

TEST(FleetPage, ABandOfTwentyUnitsOrMoreHoldsTheFiveToNinetyFivePercentEnvelope) {
  const FleetStudy s = fleet_of(25, 3);
  const FleetPageData d = fleet_page_data(s);
  const FleetAxisView& a = d.groups.at(0).axes.at(0);
  ASSERT_EQ(a.band.units, 24);
  EXPECT_TRUE(a.band.percentiles);
  for (std::size_t i = 0; i < a.band.tau.size(); ++i) {
    std::vector<double> logs;
    for (std::size_t u = 0; u < s.rows.size(); ++u)
      if (s.rows[u].unit != "U3") logs.push_back(std::log(s.curves[u].adev.adev[i]));
    std::sort(logs.begin(), logs.end());
    // Type 7: h = (n - 1) p = 23 x 0.05 = 1.15 -> between the 2nd and 3rd; 23 x 0.95 = 21.85.
    const double p05 = std::exp(logs[1] + 0.15 * (logs[2] - logs[1]));
    const double p95 = std::exp(logs[21] + 0.85 * (logs[22] - logs[21]));
    EXPECT_NEAR(a.band.p05[i], p05, 1e-12 * p05);
    EXPECT_NEAR(a.band.p95[i], p95, 1e-12 * p95);
    EXPECT_LT(a.band.min[i], a.band.p05[i]);
    EXPECT_GT(a.band.max[i], a.band.p95[i]);
  }
}

TEST(FleetPage, UnitsOnDifferentTauGridsAreInterpolatedInLogLogOntoACommonGrid) {
  // Six units of white noise c_k / sqrt(tau): three at 100 Hz, three at 200 Hz (tau from 5 ms).
  FleetStudy s;
  s.manifest = "fleet.csv";
  std::vector<double> c;
  for (int k = 1; k <= 6; ++k) {
    c.push_back(1e-3 * (1.0 + 0.05 * k));
    s.rows.push_back(row("U" + std::to_string(k), "gyro_x", c.back(), 2e-3));
    s.curves.push_back(white_curve(c.back(), k <= 3 ? 100.0 : 200.0));
  }
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  const FleetPageData d = fleet_page_data(s);
  const FleetAxisView& a = d.groups.at(0).axes.at(0);
  ASSERT_TRUE(a.band.interpolated);
  EXPECT_EQ(a.band.units, 6);
  EXPECT_DOUBLE_EQ(a.band.tau.front(), 0.005);
  EXPECT_NEAR(a.band.tau.back(), 2048.0 / 100.0, 1e-9);
  for (std::size_t i = 0; i < a.band.tau.size(); ++i) {
    const double t = a.band.tau[i];
    std::vector<double> in;  // the units whose grid reaches t
    for (int k = 0; k < 6; ++k) {
      const double lo = k < 3 ? 0.01 : 0.005, hi = k < 3 ? 20.48 : 10.24;
      if (t >= lo * (1 - 1e-9) && t <= hi * (1 + 1e-9)) in.push_back(c[static_cast<std::size_t>(k)] / std::sqrt(t));
    }
    ASSERT_EQ(a.band.count[i], static_cast<int>(in.size())) << "tau " << t;
    // A power law is a line in log-log: the interpolation is exact.
    EXPECT_NEAR(a.band.median[i], median_of(in), 1e-9 * a.band.median[i]) << "tau " << t;
    EXPECT_NEAR(a.band.min[i], *std::min_element(in.begin(), in.end()), 1e-9 * a.band.min[i]);
    EXPECT_NEAR(a.band.max[i], *std::max_element(in.begin(), in.end()), 1e-9 * a.band.max[i]);
  }
  EXPECT_EQ(a.band.count.front(), 3);  // only the 200 Hz units reach 5 ms
  EXPECT_TRUE(contains(a.notes, "each unit's ADEV is interpolated in log-log onto a common grid")) << joined(a.notes);
}

TEST(FleetPage, SaysNoUnitIsFlaggedAndDrawsTheBandAlone) {
  const FleetStudy s = fleet_of(8);
  const FleetPageData d = fleet_page_data(s);
  const auto& g = d.groups.at(0);
  EXPECT_TRUE(contains(g.headline, "No unit flagged: every read-off judged lies within its flag limits"))
      << joined(g.headline);
  EXPECT_TRUE(g.flagged_rows.empty());
  const FleetAxisView& a = g.axes.at(0);
  EXPECT_TRUE(a.flagged.empty());
  EXPECT_EQ(a.band.units, 8);
  EXPECT_TRUE(contains(a.notes, "No unit is flagged on gyro_x: the band alone.")) << joined(a.notes);
}

TEST(FleetPage, AnImpreciseReadOffIsJudgedAgainstItsOwnWiderLimits) {
  // Unit 3's N lies 1.3x the median, beyond the band, but its read-off is known to +-40% only.
  FleetStudy s = fleet_of(8);
  gmwm::Readoff& n3 = s.rows[2].figures.white.figure;
  n3.value *= 1.3;
  n3.low = n3.value / 1.4;
  n3.high = n3.value * 1.4;
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  ASSERT_TRUE(s.summary.at(0).flagged.empty());
  const FleetPageData d = fleet_page_data(s);
  const auto& dot = panel(d, 'N').dots.at(2);
  EXPECT_GT(dot.value, panel(d, 'N').band_high);
  EXPECT_FALSE(dot.flagged);
  EXPECT_LT(std::abs(dot.z), 3.5);
  EXPECT_GT(dot.limit_high, dot.value);
  EXPECT_GT(dot.limit_high, panel(d, 'N').band_high);
}

TEST(FleetPage, AGroupOfFewerThanFiveUnitsIsDrawnButNotJudged) {
  const FleetStudy s = fleet_of(3, 2, 3.0);
  const FleetPageData d = fleet_page_data(s);
  const auto& g = d.groups.at(0);
  EXPECT_TRUE(contains(g.headline, "No unit can be flagged: flags need 5 or more units")) << joined(g.headline);
  EXPECT_TRUE(contains(g.headline, "read-offs per figure: N: 3 on each axis; K: 0 on each axis; B: 3 on each axis."))
      << joined(g.headline);
  EXPECT_FALSE(panel(d, 'N').can_flag);
  EXPECT_TRUE(std::isfinite(panel(d, 'N').median));
  EXPECT_TRUE(g.axes.at(0).flagged.empty());
  EXPECT_TRUE(contains(g.axes.at(0).notes,
                       "Not judged: N 3 read-off(s); K no read-off(s), 3 only an upper bound; B 3 "
                       "read-off(s). Flags need 5 read-offs or more"))
      << joined(g.axes.at(0).notes);
}

TEST(FleetPage, FailuresAreCountedAndListedWithTheirReasons) {
  REQUIRE_VEGA();
  FleetStudy s = fleet_of(6);
  FleetRow failed;
  failed.unit = "U7";
  failed.group = "line-A";
  failed.path = "missing<7>.csv";
  failed.status = "cannot read missing<7>.csv: no such file";
  s.rows.push_back(failed);
  s.curves.emplace_back();
  ++s.recordings;
  ++s.failed;
  const FleetPageData d = fleet_page_data(s);
  const auto& g = d.groups.at(0);
  EXPECT_EQ(g.units, 7);
  EXPECT_EQ(g.failed, 1);
  ASSERT_EQ(g.failed_rows.size(), 1u);
  EXPECT_EQ(g.failed_rows[0], 6u);
  EXPECT_TRUE(contains(g.headline, "7 unit(s); 1 recording(s) failed (the reasons below).")) << joined(g.headline);
  const std::string page = gmwm::report::render_fleet_page(s);
  EXPECT_NE(page.find("<table class=\"fleet-failures\">"), std::string::npos);
  EXPECT_NE(page.find("<td class=\"note\">cannot read missing&lt;7&gt;.csv: no such file</td>"), std::string::npos);
  EXPECT_NE(page.find("<td>(the recording)</td>"), std::string::npos);
}

TEST(FleetPage, UnitsRecordedInDifferentUnitsAreDrawnInTheSummarysSiUnit) {
  FleetStudy s;
  s.manifest = "fleet.csv";
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (int k = 1; k <= 6; ++k) {
    // Unit 6 recorded in rad/s, the others in deg/s: all the same gyro.
    const double n_deg = 0.06 * (1.0 + 0.01 * k), b_deg = 0.002;
    const bool rad = k == 6;
    s.rows.push_back(row("U" + std::to_string(k), "gyro_x", rad ? n_deg * kDeg : n_deg, rad ? b_deg * kDeg : b_deg,
                         rad ? "rad/s" : "deg/s"));
    s.curves.push_back(white_curve(rad ? n_deg * kDeg : n_deg));
  }
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  ASSERT_EQ(s.summary.at(0).unit, "rad/s");
  const FleetPageData d = fleet_page_data(s);
  const FleetFigurePanel& n = panel(d, 'N');
  EXPECT_EQ(n.data_unit, "rad/s/sqrt(Hz)");
  EXPECT_EQ(n.unit, "deg/sqrt(h)");
  for (int k = 1; k <= 6; ++k)  // every unit's N in deg/sqrt(h): deg/s/sqrt(Hz) x 60
    EXPECT_NEAR(n.dots.at(static_cast<std::size_t>(k - 1)).value, 60.0 * 0.06 * (1.0 + 0.01 * k), 1e-9) << k;
  const FleetAxisView& a = d.groups.at(0).axes.at(0);
  EXPECT_EQ(a.unit, "rad/s");
  for (std::size_t i = 0; i < a.band.tau.size(); ++i)  // the band in rad/s
    EXPECT_NEAR(a.band.min[i], 0.06 * 1.01 * kDeg / std::sqrt(a.band.tau[i]), 1e-12);
}

TEST(FleetPage, OneFlaggedUnitKeepsOneColourAcrossThePage) {
  REQUIRE_VEGA();
  FleetStudy s = fleet_of(8, 5);
  FleetStudy y = fleet_of(8, 5, 2.0, "gyro_y");
  s.rows.insert(s.rows.end(), y.rows.begin(), y.rows.end());
  s.curves.insert(s.curves.end(), y.curves.begin(), y.curves.end());
  for (FleetRow& r : s.rows) r.flags.clear();
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  const nlohmann::json specs = specs_of(gmwm::report::render_fleet_page(s));
  ASSERT_TRUE(specs.is_array());
  std::vector<std::string> colours;
  for (const auto& e : specs) {
    if (e.at("kind") != "adev") continue;
    for (const auto& scale : e.at("spec").at("scales"))
      if (scale.at("name") == "color") {
        const auto& dom = scale.at("domain");
        for (std::size_t i = 0; i < dom.size(); ++i)
          if (dom[i] == "unit U5") colours.push_back(scale.at("range").at(i));
      }
  }
  ASSERT_EQ(colours.size(), 2u);
  EXPECT_EQ(colours[0], colours[1]);
  EXPECT_EQ(specs.size(), 4u);  // per axis: the strips and the band
}

TEST(FleetPage, EscapesAHostileUnitIdAndAxisNameInTextAttributesAndJson) {
  REQUIRE_VEGA();
  const FleetStudy s = fleet_of(8, 5, 2.0, kHostileAxis, kHostileUnit);
  const std::string page = gmwm::report::render_fleet_page(s);
  // Nowhere raw: not in text, not in an attribute, not in a script.
  EXPECT_EQ(page.find(kHostileUnit), std::string::npos);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  EXPECT_EQ(page.find(kHostileAxis), std::string::npos);
  EXPECT_EQ(page.find("<b>&"), std::string::npos);
  // In text (the headline, the tables, the section titles), HTML-escaped.
  const std::string unit_text = "&lt;/script&gt;&lt;img src=x onerror=alert(1)&gt;";
  const std::string axis_text = "gyro&quot;x&#39;&lt;b&gt;&amp;";
  EXPECT_NE(page.find("<li>" + unit_text + ": N on " + axis_text + " "), std::string::npos);
  EXPECT_NE(page.find("<td>" + unit_text + "</td><td>" + axis_text + "</td>"), std::string::npos);
  EXPECT_NE(page.find("\">" + axis_text + " <span class=\"facts\">"), std::string::npos);
  // In attributes.
  EXPECT_NE(page.find("data-unit=\"" + unit_text + "\" data-axis=\"" + axis_text + "\""), std::string::npos);
  // In the embedded JSON: '<', '>', '&' as \u003c, \u003e, \u0026; the quotes JSON-escaped.
  EXPECT_NE(page.find("\\u003c/script\\u003e\\u003cimg src=x onerror=alert(1)\\u003e"), std::string::npos);
  EXPECT_NE(page.find("gyro\\\"x'\\u003cb\\u003e\\u0026"), std::string::npos);
  // The script elements are the page's own: the error catcher, the specs, Vega, the page's script.
  EXPECT_EQ(count(page, "<script"), 4);
  EXPECT_EQ(count(page, "</script>"), 4);
  // And the JSON reads back to the very strings.
  const nlohmann::json specs = specs_of(page);
  ASSERT_TRUE(specs.is_array());
  const std::string dump = specs.dump();
  EXPECT_NE(dump.find(nlohmann::json(kHostileUnit).dump()), std::string::npos);
  EXPECT_NE(dump.find(nlohmann::json(std::string("unit ") + kHostileUnit).dump()), std::string::npos);
  // The static SVG escapes them too.
  const std::string svg = gmwm::report::render_fleet_svg(fleet_page_data(s));
  EXPECT_EQ(svg.find(kHostileUnit), std::string::npos);
  EXPECT_NE(svg.find("unit " + unit_text), std::string::npos);
  EXPECT_NE(svg.find(axis_text), std::string::npos);
}

TEST(FleetPage, WritesThePageAndItsSvgAllOrNothingThroughTheOutputSet) {
  REQUIRE_VEGA();
  const fs::path dir = gmwm::test::temp_dir("fleet_page");
  const FleetStudy s = fleet_of(8, 5);
  {
    gmwm::io::OutputSet out;
    const std::string path = (dir / "fleet.html").string();
    out.declare("--report", path);
    out.declare("--report", gmwm::report::report_svg_path(path));
    gmwm::report::stage_fleet_report(out, path, s);
    out.commit();
  }
  std::ifstream html(dir / "fleet.html"), svg(dir / "fleet.html.svg");
  std::stringstream h, v;
  h << html.rdbuf();
  v << svg.rdbuf();
  EXPECT_EQ(h.str().rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(count(h.str(), "class=\"gmwm-plot\" data-plot=\"fleet-figures\""), 1);
  EXPECT_EQ(count(h.str(), "class=\"gmwm-plot\" data-plot=\"adev\""), 1);
  EXPECT_EQ(v.str().rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_NE(v.str().find(">unit U5</text>"), std::string::npos);
  EXPECT_NE(v.str().find(">fleet median</text>"), std::string::npos);
  {  // never committed: nothing written
    gmwm::io::OutputSet out;
    const std::string path = (dir / "other.html").string();
    out.declare("--report", path);
    gmwm::report::stage_fleet_report(out, path, s);
  }
  EXPECT_FALSE(fs::exists(dir / "other.html"));
  EXPECT_FALSE(fs::exists(dir / "other.html.svg"));
  fs::remove_all(dir);
}

TEST(FleetPage, AStudyWithoutRecordingsIsAPageThatSaysSo) {
  REQUIRE_VEGA();
  FleetStudy s;
  s.manifest = "empty.csv";
  EXPECT_TRUE(fleet_page_data(s).groups.empty());
  EXPECT_NE(gmwm::report::render_fleet_page(s).find("The manifest has no recording."), std::string::npos);
  EXPECT_EQ(gmwm::report::render_fleet_svg(fleet_page_data(s)), "");
}

TEST(FleetPage, QAndRAreDrawnAndTabulatedWhereAUnitReadsThemAndAlwaysWrittenInTheCsvAndJson) {
  // Every unit's Q and R only bounded (as on the ADIS recordings): N, K, B alone on the page
  // and in the terminal's tables; the CSV and JSON carry Q and R all the same.
  FleetStudy s = fleet_of(6);
  EXPECT_EQ(gmwm::report::fleet_shown_figures(s), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(fleet_page_data(s).groups.at(0).axes.at(0).figures.size(), 3u);
  EXPECT_EQ(gmwm::report::fleet_text(s).find("R rate ramp"), std::string::npos);
  const std::string csv = gmwm::report::fleet_csv(s);
  EXPECT_NE(csv.find(",B_high,Q,Q_low,Q_high,R,R_low,R_high,seconds,"), std::string::npos) << csv.substr(0, 300);
  const nlohmann::json doc = gmwm::report::fleet_document(s);
  EXPECT_TRUE(doc.at("rows").at(0).contains("Q"));
  EXPECT_TRUE(doc.at("rows").at(0).contains("R"));
  // A ramp read on every unit (R = 1e-6 deg/s^2, +-1%): its strip, summary and column appear.
  for (FleetRow& r : s.rows) {
    r.figures.ramp.figure = readoff(1e-6, 500.0);
    r.figures.ramp.source = gmwm::FigureSource::kData;
  }
  s.summary = gmwm::fleet::fleet_summary(s.rows);
  EXPECT_EQ(gmwm::report::fleet_shown_figures(s), (std::vector<int>{0, 1, 2, 4}));
  const FleetPageData d = fleet_page_data(s);
  ASSERT_EQ(d.groups.at(0).axes.at(0).figures.size(), 4u);
  const FleetFigurePanel& r = d.groups.at(0).axes.at(0).figures.at(3);
  EXPECT_EQ(r.figure, 'R');
  EXPECT_EQ(r.units, 6);
  EXPECT_EQ(r.unit, "deg/h^2");  // datasheet units: 1e-6 deg/s^2 = 12.96 deg/h^2
  EXPECT_NEAR(r.median, 12.96, 12.96 * 0.05);
  const std::string text = gmwm::report::fleet_text(s);
  EXPECT_NE(text.find("deg/h^2"), std::string::npos) << text;
}

TEST(FleetPage, ListsEachAxissJointModelWithTheUnitsLeftOutAndWhyAnAxisHasNone) {
  REQUIRE_VEGA();
  FleetStudy s = fleet_of(8, 5, 2.0, "gyro_x", kHostileUnit);
  gmwm::fleet::FleetJointModel m;
  m.group = s.rows.front().group;
  m.axis = "gyro_x";
  m.units = 7;
  m.left_out = {kHostileUnit};
  m.unit = "rad/s";
  m.fit.joint.model = gmwm::parse_model("WN");
  m.fit.joint.theta = Eigen::VectorXd::Constant(1, 1e-4);
  gmwm::ChosenFigures f;
  f.white.figure = readoff(1e-3, 1.0);
  f.white.figure.low = 0.98e-3;
  f.white.figure.high = 1.02e-3;
  m.figures = f;
  gmwm::ReplicateTest t;
  t.heterogeneity = 120.0;
  t.heterogeneity_p = 0.001;
  t.calibration = gmwm::ReplicateCalibration::kChiSquare;
  m.test = t;
  s.joint.push_back(m);
  gmwm::fleet::FleetJointModel none;
  none.group = m.group;
  none.axis = "gyro_y";
  none.status = "a joint model needs 2 units or more with a result, found 1";
  s.joint.push_back(none);
  const std::string page = gmwm::report::render_fleet_page(s);
  EXPECT_NE(page.find("<h3>joint model</h3>"), std::string::npos);
  EXPECT_NE(page.find("<td>&lt;/script&gt;&lt;img src=x onerror=alert(1)&gt;</td>"), std::string::npos);
  EXPECT_EQ(page.find(kHostileUnit), std::string::npos);
  EXPECT_NE(page.find("1 rad/s/sqrt(Hz)"), std::string::npos) << "N in the data's unit pattern";
  EXPECT_NE(page.find("no (H = 120, p 0.001, chi-square)"), std::string::npos);
  EXPECT_NE(page.find("a joint model needs 2 units or more with a result, found 1"), std::string::npos);
  // Without --joint the table is absent.
  EXPECT_EQ(gmwm::report::render_fleet_page(fleet_of(8)).find("<h3>joint model</h3>"), std::string::npos);
}

}  // namespace
