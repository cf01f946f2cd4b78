// The fleet's HTML report (fleet_page.h): the page's data from the study (per group: the
// headline, per axis the strips of N, K, B (Q, R where read) and the band of Allan deviations), its Vega
// specs, the page and its static SVG.

#include "gmwm/report/fleet_page.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <boost/math/distributions/normal.hpp>
#include <spdlog/spdlog.h>

#include "gmwm/engine/physical.h"
#include "gmwm/io/units.h"
#include "gmwm/report/fleet_output.h"
#include "gmwm/report/html_report.h"
#include "gmwm/report/terminal.h"
#include "html_report_detail.h"

namespace gmwm::report {

namespace {

using detail::html_escape;
using detail::num;
using fleet::FleetRow;
using fleet::FleetStudy;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const ChosenFigure& figure_of(const FleetRow& r, int k) { return r.figures[k]; }

// The index of a figure's symbol in kFigureNames (N, K, B, Q, R).
int index_of(char figure) {
  int k = 0;
  while (k + 1 < kFigureCount && kFigureNames[k].symbol != figure) ++k;
  return k;
}

// ---- units -----------------------------------------------------------------------------

// The data unit's size per SI unit; 1 for an undeclared unit (SI, the convention of
// --units) or one that does not parse (the summary's convention, fleet_study.cc).
double per_si(const std::string& unit) {
  if (unit.empty()) return 1.0;
  try {
    return io::parse_any_unit(unit).second.per_si;
  } catch (const std::exception&) {
    return 1.0;
  }
}

// A row's figures and curves x this = the same in the summary's unit: 1 when the row's
// unit is the summary's, else the summary is in SI (fleet_summary's rule).
double to_summary_unit(const FleetRow& r, const std::string& summary_unit) {
  return r.data_unit == summary_unit ? 1.0 : 1.0 / per_si(r.data_unit);
}

// The figure's unit pattern in `unit`: N per sqrt(Hz), K per s per sqrt(Hz), B as is, Q times
// s, R per s.
std::string pattern(char figure, const std::string& unit) {
  const std::string u = unit.empty() ? "U" : unit;
  if (figure == 'Q' || figure == 'R') return render_unit(kFigureNames[index_of(figure)].unit_pattern, u);
  return u + (figure == 'N' ? "/sqrt(Hz)" : figure == 'K' ? "/s/sqrt(Hz)" : "");
}

const char* figure_name(char figure) {
  return figure == 'N' ? "white noise density" : figure == 'K' ? "random walk" : kFigureNames[index_of(figure)].name;
}

// "0.577 deg/sqrt(h)"; "-" when not finite.
std::string with_unit(double v, const std::string& unit, int digits = 3) {
  return std::isfinite(v) ? num(v, digits) + " " + unit : std::string("-");
}

// ---- the strips of N, K and B ------------------------------------------------------------

// The golden ratio's conjugate: unit i sits at the fractional part of i x this on its
// strip's height, so that units close in the manifest do not land close on the strip.
constexpr double kGoldenRatioConjugate = 0.6180339887498949;
// The share of the strip's height the dots use (the rest: room for the labels).
constexpr double kLaneLow = 0.14, kLaneSpan = 0.72;

double lane_of(std::size_t unit_index) {
  const double x = static_cast<double>(unit_index) * kGoldenRatioConjugate;
  return kLaneLow + kLaneSpan * (x - std::floor(x));
}

const fleet::FleetFigureSummary* summary_of(const FleetStudy& s, const std::string& group, const std::string& axis,
                                            char figure) {
  for (const auto& f : s.summary)
    if (f.group == group && f.axis == axis && f.figure == figure) return &f;
  return nullptr;
}

std::string flag_of(const FleetRow& r, char figure) {
  const std::string prefix = std::string(1, figure) + ": ";
  for (const std::string& f : r.flags)
    if (f.rfind(prefix, 0) == 0) return f;
  return {};
}

// The panel's limits from the summary's outlier rule (fleet::OutlierYardstick, the one the
// units were flagged by): each dot's own limits median x reach(se)^(+-1), z = log(x /
// median) / scale(se); the band those of a read-off of the group's typical precision.
void judge(FleetFigurePanel& p, const fleet::OutlierYardstick& rule, double alpha) {
  if (!(std::isfinite(p.median) && std::isfinite(p.spread))) return;
  const double z_half = boost::math::quantile(boost::math::normal(), 1.0 - alpha / 2.0);
  p.unit_spread = std::exp(std::sqrt(rule.between2));
  const double reach = rule.reach(std::sqrt(rule.typical_se2));
  p.band_low = p.median / reach;
  p.band_high = p.median * reach;
  for (FleetDot& d : p.dots) {
    if (d.bound) continue;
    const double se = fleet::log_standard_error(d.low, d.high, z_half);
    const double scale = rule.scale(se), own = rule.reach(se);
    d.limit_low = p.median / own;
    d.limit_high = p.median * own;
    d.z = scale > 0.0 ? std::log(d.value / p.median) / scale : kNaN;
    d.beyond =
        d.flagged && std::isfinite(d.low) && std::isfinite(d.high) && (d.low > d.limit_high || d.high < d.limit_low);
  }
}

FleetFigurePanel figure_panel(const FleetStudy& s, const fleet::FleetFigureSummary& sum,
                              const std::vector<std::size_t>& rows, const std::vector<std::string>& units,
                              double alpha) {
  FleetFigurePanel p;
  p.figure = sum.figure;
  p.data_unit = pattern(sum.figure, sum.unit);
  if (const std::optional<DatasheetValue> d = datasheet_value(sum.figure, 1.0, sum.unit)) {
    p.unit = d->unit;
    p.to_panel = d->value;
  } else {
    p.unit = p.data_unit;
  }
  p.units = sum.units;
  p.can_flag = sum.units >= fleet::kMinUnitsForFlags;
  const bool summarised = sum.units > 0 && std::isfinite(sum.median) && std::isfinite(sum.spread);
  p.median = summarised ? sum.median * p.to_panel : kNaN;
  p.spread = summarised ? sum.spread : kNaN;
  const int k = index_of(sum.figure);
  for (const std::size_t i : rows) {
    const FleetRow& r = s.rows[i];
    if (!r.figures_known) continue;
    const ChosenFigure& f = figure_of(r, k);
    if (!(std::isfinite(f.figure.value) && f.figure.value > 0.0)) continue;
    FleetDot d;
    d.unit = r.unit;
    d.path = r.path;
    const double c = to_summary_unit(r, sum.unit);
    d.value = f.figure.value * c * p.to_panel;
    d.low = f.figure.low > 0.0 ? f.figure.low * c * p.to_panel : kNaN;
    d.high = f.figure.high > 0.0 ? f.figure.high * c * p.to_panel : kNaN;
    d.source = to_string(f.source);
    d.bound = f.figure.status == ReadoffStatus::kBound;
    d.flag = flag_of(r, sum.figure);
    d.flagged = !d.flag.empty();
    d.index = static_cast<int>(std::find(units.begin(), units.end(), r.unit) - units.begin());
    p.dots.push_back(std::move(d));
  }
  judge(p, sum.yardstick, alpha);
  return p;
}

// ---- the Allan deviation curves drawn (the band itself: fleet_band.h) -----------------------

FleetUnitCurve unit_curve(const FleetRow& r, const fleet::FleetCurves& c, double factor) {
  FleetUnitCurve u;
  u.unit = r.unit;
  u.path = r.path;
  u.flags = r.flags;
  const AllanDeviation& a = c.adev;
  for (std::size_t i = 0; i < a.tau.size() && i < a.adev.size(); ++i) {
    if (!(a.adev[i] > 0.0 && std::isfinite(a.adev[i]))) continue;
    u.tau.push_back(a.tau[i]);
    u.adev.push_back(a.adev[i] * factor);
    u.low.push_back(i < a.ci_low.size() && a.ci_low[i] > 0.0 ? a.ci_low[i] * factor : kNaN);
    u.high.push_back(i < a.ci_high.size() && a.ci_high[i] > 0.0 ? a.ci_high[i] * factor : kNaN);
  }
  return u;
}

// ---- a group and its axes ----------------------------------------------------------------

void axis_notes(FleetAxisView& a, double level) {
  const std::string unit = a.unit.empty() ? "U" : a.unit;
  std::string few;  // "N 3 read-offs; K none, 3 only an upper bound"
  for (const FleetFigurePanel& p : a.figures) {
    if (p.can_flag) continue;
    int bounds = 0;
    for (const FleetDot& d : p.dots) bounds += d.bound;
    few += (few.empty() ? "" : "; ") + std::string(1, p.figure) + " " +
           (p.units ? std::to_string(p.units) : std::string("no")) + " read-off(s)" +
           (bounds ? ", " + std::to_string(bounds) + " only an upper bound" : std::string());
  }
  if (!few.empty())
    a.notes.push_back("Not judged: " + few + ". Flags need " + std::to_string(fleet::kMinUnitsForFlags) +
                      " read-offs or more (the median and MAD of fewer are no yardstick); their bands are drawn "
                      "lighter.");
  const FleetAdevBand& b = a.band;
  if (b.units == 0) {
    a.notes.push_back("Allan deviation: no unit of this axis has a curve to draw.");
    return;
  }
  std::string line =
      "Allan deviation band: the " + std::to_string(b.units) + " unit(s) not flagged on " + a.axis +
      ", per tau their median, min-max" +
      (b.percentiles ? " and 5-95% envelopes"
                     : " envelope (the 5-95% envelope needs " + std::to_string(kFleetPercentileUnits) + " units)") +
      ", in " + unit + ".";
  a.notes.push_back(line);
  if (b.interpolated)
    a.notes.push_back(
        "The units' tau grids differ (other rates or lengths): each unit's ADEV is interpolated in log-log onto a "
        "common grid; at each tau the envelopes are over the units whose curve reaches it.");
  if (a.flagged.empty())
    a.notes.push_back("No unit is flagged on " + a.axis + ": the band alone.");
  else
    a.notes.push_back(std::to_string(a.flagged.size()) + " flagged unit(s) drawn over the band, each with its " +
                      num(100.0 * (1.0 - level), 3) + "% interval.");
}

// The level of the figures' intervals (1 - alpha): the curves' (the study's WV alpha); 0.05
// without a curve.
double interval_alpha(const FleetStudy& s) {
  for (const fleet::FleetCurves& c : s.curves)
    if (!c.adev.tau.empty() && c.adev.alpha > 0.0 && c.adev.alpha < 1.0) return c.adev.alpha;
  return 0.05;
}

// Where the row's worst flagged figure (largest |robust z|) was read, in seconds (NaN: unknown).
double worst_flag_tau(const FleetRow& r, const FleetAxisView& a) {
  double worst = -1.0, tau = kNaN;
  for (const FleetFigurePanel& p : a.figures)
    for (const FleetDot& d : p.dots)
      if (d.unit == r.unit && d.flagged && std::abs(d.z) > worst) {
        worst = std::abs(d.z);
        tau = figure_of(r, index_of(p.figure)).figure.tau;
      }
  return tau;
}

FleetAxisView axis_view(const FleetStudy& s, const std::string& group, const std::string& axis,
                        const std::vector<std::size_t>& group_rows, const std::vector<std::string>& units) {
  FleetAxisView a;
  a.axis = axis;
  std::vector<std::size_t> rows;
  for (const std::size_t i : group_rows)
    if (s.rows[i].axis == axis) rows.push_back(i);
  for (const int k : fleet_shown_figures(s)) {
    const char figure = kFigureNames[k].symbol;
    if (const fleet::FleetFigureSummary* sum = summary_of(s, group, axis, figure)) {
      a.figures.push_back(figure_panel(s, *sum, rows, units, interval_alpha(s)));
      a.unit = sum->unit;
    } else {
      a.figures.emplace_back().figure = figure;
    }
  }
  std::vector<fleet::AdevSeries> band;
  double level = 0.05;
  for (const std::size_t i : rows) {
    const FleetRow& r = s.rows[i];
    if (r.status != "ok" || i >= s.curves.size() || s.curves[i].adev.tau.empty()) continue;
    const double factor = to_summary_unit(r, a.unit);
    level = s.curves[i].adev.alpha;
    if (!r.flags.empty()) {
      a.flagged.push_back(unit_curve(r, s.curves[i], factor));
      a.flagged.back().label_tau = worst_flag_tau(r, a);
    } else if (fleet::AdevSeries ser = fleet::positive_series(s.curves[i].adev, factor); !ser.tau.empty())
      band.push_back(std::move(ser));
  }
  a.band = fleet::adev_band(band);
  axis_notes(a, level);
  return a;
}

// A unit's flags in the group ranked: first whether one of them is beyond (its interval
// wholly outside its flag limits), then the worst |robust z|.
std::pair<bool, double> severity(const FleetGroupView& g, const std::string& unit) {
  bool beyond = false;
  double worst = 0.0;
  for (const FleetAxisView& a : g.axes)
    for (const FleetFigurePanel& p : a.figures)
      for (const FleetDot& d : p.dots)
        if (d.unit == unit && d.flagged) {
          beyond = beyond || d.beyond;
          if (std::isfinite(d.z)) worst = std::max(worst, std::abs(d.z));
        }
  return {beyond, worst};
}

// The units flagged in the group, the surest first (ties: manifest order).
std::vector<std::string> flagged_units(const FleetGroupView& g, const std::vector<std::string>& units) {
  std::vector<std::string> out;
  for (const std::string& u : units)
    for (const FleetAxisView& a : g.axes)
      for (const FleetFigurePanel& p : a.figures)
        for (const FleetDot& d : p.dots)
          if (d.unit == u && d.flagged && std::find(out.begin(), out.end(), u) == out.end()) out.push_back(u);
  std::stable_sort(out.begin(), out.end(),
                   [&](const std::string& x, const std::string& y) { return severity(g, x) > severity(g, y); });
  return out;
}

// The most flagged units the headline names one by one; the table lists them all.
constexpr std::size_t kHeadlineUnits = 10;

// "N on gyro_x 0.114 [0.113, 0.116] deg/sqrt(h), 1.86x the median 0.0614 (robust z 9.44;
// flag limits 0.0487-0.0774: interval wholly above them)"
std::string flag_clause(const FleetAxisView& a, const FleetFigurePanel& p, const FleetDot& d) {
  const bool interval = std::isfinite(d.low) && std::isfinite(d.high);
  std::string out = std::string(1, p.figure) + " on " + a.axis + " " + num(d.value, 3) +
                    (interval ? " [" + num(d.low, 3) + ", " + num(d.high, 3) + "]" : std::string()) + " " + p.unit +
                    ", " + num(d.value / p.median, 3) + "x the median " + num(p.median, 3) + " (robust z " +
                    num(d.z, 3) + "; flag limits " + num(d.limit_low, 3) + "-" + num(d.limit_high, 3) + ": ";
  if (!interval) return out + "no interval)";
  if (d.beyond) return out + "interval wholly " + (d.value > p.median ? "above" : "below") + " them)";
  return out + "interval reaching within them)";
}

std::string unit_sentence(const FleetGroupView& g, const std::string& unit) {
  std::string out = unit + ":";
  bool first = true;
  for (const FleetAxisView& a : g.axes)
    for (const FleetFigurePanel& p : a.figures)
      for (const FleetDot& d : p.dots) {
        if (d.unit != unit || !d.flagged) continue;
        out += (first ? " " : "; ") + flag_clause(a, p, d);
        first = false;
      }
  return out + ".";
}

// "K on gyro_x (2), gyro_y (2)": the figures with too few read-offs to flag, "" when none.
std::string not_judged(const FleetGroupView& g) {
  std::string out;
  for (const FigureName& name : kFigureNames) {
    const char f = name.symbol;
    // Axes by their count of read-offs, in order: "0 on gyro_x, gyro_y, 2 on accel_x".
    std::vector<std::pair<int, std::string>> counts;
    std::size_t axes = 0, short_axes = 0;
    for (const FleetAxisView& a : g.axes)
      for (const FleetFigurePanel& p : a.figures) {
        if (p.figure != f) continue;
        ++axes;
        if (p.can_flag) continue;
        ++short_axes;
        auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == p.units; });
        if (it == counts.end())
          counts.emplace_back(p.units, a.axis);
        else
          it->second += ", " + a.axis;
      }
    if (counts.empty()) continue;
    std::string line;
    for (const auto& [n, list] : counts)
      line += (line.empty() ? "" : ", ") + std::to_string(n) + " on " +
              (counts.size() == 1 && short_axes == axes ? std::string("each axis") : list);
    out += (out.empty() ? "" : "; ") + std::string(1, f) + ": " + line;
  }
  return out;
}

void flag_headline(FleetGroupView& g, const std::vector<std::string>& flagged) {
  std::string per_figure, beyond;
  int n_beyond = 0;
  for (const FigureName& name : kFigureNames) {
    const char f = name.symbol;
    bool shown = false;
    for (const FleetAxisView& a : g.axes)
      for (const FleetFigurePanel& p : a.figures) shown = shown || p.figure == f;
    if (!shown) continue;
    std::vector<std::string> on;
    for (const FleetAxisView& a : g.axes)
      for (const FleetFigurePanel& p : a.figures)
        for (const FleetDot& d : p.dots)
          if (p.figure == f && d.flagged && std::find(on.begin(), on.end(), d.unit) == on.end()) on.push_back(d.unit);
    per_figure += std::string(per_figure.empty() ? "" : ", ") + f + ": " +
                  (on.empty() ? std::string("none") : std::to_string(on.size()));
  }
  for (const std::string& u : flagged)
    if (severity(g, u).first) beyond += (n_beyond++ ? ", " : "") + u;
  std::string line = std::to_string(flagged.size()) + " unit(s) flagged (robust z of a figure's log beyond " +
                     num(fleet::kFleetOutlierZ, 2) + "; units per figure: " + per_figure + "). ";
  if (n_beyond == 0)
    line += "None has an interval wholly outside its flag limits: each flagged figure's interval reaches within them.";
  else
    line += std::to_string(n_beyond) + " with a figure whose interval lies wholly outside its flag limits: " + beyond +
            (static_cast<std::size_t>(n_beyond) < flagged.size()
                 ? "; the other " + std::to_string(flagged.size() - static_cast<std::size_t>(n_beyond)) +
                       " only with intervals reaching within them."
                 : ".");
  g.headline.push_back(line + " The surest first:");
  for (std::size_t i = 0; i < flagged.size() && i < kHeadlineUnits; ++i)
    g.headline.push_back(unit_sentence(g, flagged[i]));
  if (flagged.size() > kHeadlineUnits)
    g.headline.push_back("... and " + std::to_string(flagged.size() - kHeadlineUnits) + " more in the table below.");
}

void headline(FleetGroupView& g, const std::vector<std::string>& units) {
  g.headline.push_back(std::to_string(g.units) + " unit(s); " +
                       (g.failed == 0 ? std::string("every recording analysed")
                                      : std::to_string(g.failed) + " recording(s) failed (the reasons below)") +
                       ".");
  bool any_judged = false;
  for (const FleetAxisView& a : g.axes)
    for (const FleetFigurePanel& p : a.figures) any_judged = any_judged || p.can_flag;
  const std::string few = not_judged(g);
  if (!any_judged) {
    g.headline.push_back("No unit can be flagged: flags need " + std::to_string(fleet::kMinUnitsForFlags) +
                         " or more units with a read-off of a figure (the median and MAD of fewer are no "
                         "yardstick); read-offs per figure: " +
                         few + ".");
    return;
  }
  const std::vector<std::string> flagged = flagged_units(g, units);
  if (flagged.empty())
    g.headline.push_back("No unit flagged: every read-off judged lies within its flag limits (robust z within +-" +
                         num(fleet::kFleetOutlierZ, 2) + ").");
  else
    flag_headline(g, flagged);
  if (!few.empty())
    g.headline.push_back("Not judged (fewer than " + std::to_string(fleet::kMinUnitsForFlags) +
                         " read-offs; the others only upper bounds): " + few + ".");
}

FleetGroupView group_view(const FleetStudy& s, const std::string& group) {
  FleetGroupView g;
  g.name = group;
  std::vector<std::size_t> rows;
  std::vector<std::string> units;
  for (std::size_t i = 0; i < s.rows.size(); ++i) {
    const FleetRow& r = s.rows[i];
    if (r.group != group) continue;
    rows.push_back(i);
    if (std::find(units.begin(), units.end(), r.unit) == units.end()) units.push_back(r.unit);
    if (r.axis.empty()) ++g.failed;
    if (r.status != "ok") g.failed_rows.push_back(i);
    if (!r.flags.empty()) g.flagged_rows.push_back(i);
  }
  g.units = static_cast<int>(units.size());
  std::vector<std::string> axes;
  for (const auto& f : s.summary)
    if (f.group == group && std::find(axes.begin(), axes.end(), f.axis) == axes.end()) axes.push_back(f.axis);
  for (const std::string& a : axes) g.axes.push_back(axis_view(s, group, a, rows, units));
  headline(g, units);
  const std::vector<std::string> order = flagged_units(g, units);
  std::stable_sort(g.flagged_rows.begin(), g.flagged_rows.end(), [&](std::size_t x, std::size_t y) {
    const auto rank = [&](std::size_t i) {
      return std::find(order.begin(), order.end(), s.rows[i].unit) - order.begin();
    };
    return rank(x) < rank(y);
  });
  return g;
}

// ---- the Vega specs ------------------------------------------------------------------

// The width a plot is made at before the page fills its container (Plots::add), as the
// other pages' plots.
constexpr int kPlotWidth = 560;
// A strip's height, and the room under it for its axis and above the next one for its title.
constexpr int kStripHeight = 84, kStripGap = 64, kStripTop = 26;
constexpr int kBandHeight = 340;
// Fixed colours (not the page's series palette, so Plots::add leaves them): a unit's dot,
// a flagged unit's, the flag band, the median, the ADEV band's envelopes.
constexpr const char* kDotColour = "#1f77b4";
constexpr const char* kFlagColour = "#d62728";
constexpr const char* kZoneColour = "#dbe9f6";
// The band of a figure with too few units to flag, lighter: drawn, not a verdict.
constexpr double kUnjudgedZoneOpacity = 0.4;
constexpr const char* kMedianColour = "#303030";
constexpr const char* kInnerColour = "#a3a3a3";
constexpr const char* kOuterColour = "#d4d4d4";
constexpr const char* kEdgeColour = "#8c8c8c";
// The series palette (Tableau 10, as html_report's): Plots::add gives each unit's series a
// colour of its own across the page.
constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                  "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
// Intervals reach at most this factor past the dots, median and band before a strip's axis
// cuts them (a bound-like interval over decades would squeeze every dot into a corner).
constexpr double kIntervalRoom = 10.0;
// The same for the flagged units' ADEV intervals past the band and the curves (the last
// averaging times' intervals span decades: they would flatten the curves).
constexpr double kCurveIntervalRoom = 3.0;

// Rounded for the page (the tables and JSON keep every digit): 6 significant digits.
Json short_number(double x) { return std::isfinite(x) ? Json(std::stod(num(x, 6))) : Json(nullptr); }

// The [lo, hi] a log axis shows: `core` padded by 5% of its log span each side, widened to
// hold `extra` within kIntervalRoom of it.
std::array<double, 2> log_domain(const std::vector<double>& core, const std::vector<double>& extra,
                                 double room = kIntervalRoom) {
  double lo = INFINITY, hi = 0.0;
  for (const double v : core)
    if (v > 0.0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > 0.0)) return {0.1, 10.0};
  const double room_lo = lo / room, room_hi = hi * room;
  for (const double v : extra)
    if (v > 0.0 && std::isfinite(v)) lo = std::min(lo, std::max(v, room_lo)), hi = std::max(hi, std::min(v, room_hi));
  double a = std::log10(lo), b = std::log10(hi);
  if (b - a < 0.2) a -= 0.1, b += 0.1;  // one value, or values within 1.6x: a readable strip
  const double pad = 0.05 * (b - a);
  return {std::pow(10.0, a - pad), std::pow(10.0, b + pad)};
}

Json dot_rows(const FleetFigurePanel& p) {
  Json rows = Json::array();
  for (const FleetDot& d : p.dots)
    rows.push_back(
        {{"unit", d.unit},
         {"fig", std::string(1, p.figure)},
         {"lane", short_number(lane_of(static_cast<std::size_t>(d.index)))},
         {"v", short_number(d.value)},
         {"lo", short_number(d.low)},
         {"hi", short_number(d.high)},
         {"u", p.unit},
         {"src", d.bound ? "upper bound only (left out of the median)" : d.source + " read-off"},
         {"z", short_number(d.z)},
         {"lim", p.can_flag && std::isfinite(d.limit_low) ? num(d.limit_low, 3) + " to " + num(d.limit_high, 3)
                                                          : std::string("none (not judged)")},
         {"llo", short_number(d.limit_low)},
         {"lhi", short_number(d.limit_high)},
         // Beyond the band yet not flagged: its own, wider limits are drawn as ticks.
         {"wide", p.can_flag && !d.flagged && !d.bound && std::isfinite(d.limit_low) &&
                      (d.value > p.band_high || d.value < p.band_low)},
         {"flag", d.flag},
         {"rec", d.path},
         {"bound", d.bound}});
  return rows;
}

// A strip's flag band, median and their labels (nothing without a median).
void zone_marks(const FleetFigurePanel& p, const std::string& data, Json& marks) {
  if (std::isfinite(p.band_low)) {
    const std::string zone = "flag band of a read-off of the fleet's typical precision (robust z within +-" +
                             num(fleet::kFleetOutlierZ, 2) + "): " + with_unit(p.band_low, p.unit) + " to " +
                             with_unit(p.band_high, p.unit) +
                             (p.can_flag ? std::string() : " (too few units to flag: not judged)");
    marks.push_back({{"type", "rect"},
                     {"encode",
                      {{"update",
                        {{"x", {{"scale", "x"}, {"value", p.band_low}}},
                         {"x2", {{"scale", "x"}, {"value", p.band_high}}},
                         {"y", {{"value", 0}}},
                         {"y2", {{"value", kStripHeight}}},
                         {"fill", {{"value", kZoneColour}}},
                         {"fillOpacity", {{"value", p.can_flag ? 1.0 : kUnjudgedZoneOpacity}}},
                         {"tooltip", {{"value", zone}}}}}}}});
    marks.push_back({{"type", "rule"},
                     {"encode",
                      {{"update",
                        {{"x", {{"scale", "x"}, {"value", p.median}}},
                         {"y", {{"value", 0}}},
                         {"y2", {{"value", kStripHeight}}},
                         {"stroke", {{"value", kMedianColour}}},
                         {"strokeWidth", {{"value", 2}}},
                         {"tooltip", {{"value", "the group's median: " + with_unit(p.median, p.unit, 4)}}}}}}}});
    marks.push_back({{"type", "text"},
                     {"from", {{"data", data + "_marks"}}},
                     {"encode",
                      {{"update",
                        {{"x", {{"scale", "x"}, {"field", "x"}}},
                         {"dx", {{"value", 3}}},
                         {"y", {{"value", 2}}},
                         {"baseline", {{"value", "top"}}},
                         {"text", {{"field", "t"}}},
                         {"fontSize", {{"value", 10}}},
                         {"fill", {{"value", "#57606a"}}}}}}}});
  }
}

// A strip's units: each one's interval and dot, the own limits of a unit beyond the band but
// not flagged, the flagged units' labels.
void unit_marks(const std::string& data, Json& marks) {
  const std::string tip =
      "{'unit': datum.unit, 'figure': datum.fig, 'value': format(datum.v, '.4~g') + ' ' + datum.u, 'interval': "
      "isValid(datum.lo) && isValid(datum.hi) ? format(datum.lo, '.3~g') + ' to ' + format(datum.hi, '.3~g') : "
      "'n/a', 'source': datum.src, 'robust z': isValid(datum.z) ? format(datum.z, '.3~g') : 'n/a', 'its flag "
      "limits': datum.lim, 'flag': datum.flag ? datum.flag : 'none', 'recording': datum.rec}";
  marks.push_back(
      {{"type", "rule"},
       {"from", {{"data", data + "_iv"}}},
       {"clip", true},
       {"encode",
        {{"update",
          {{"x", {{"scale", "x"}, {"field", "lo"}}},
           {"x2", {{"scale", "x"}, {"field", "hi"}}},
           {"y", {{"scale", "y"}, {"field", "lane"}}},
           {"stroke", {{"signal", std::string("datum.flag ? '") + kFlagColour + "' : '" + kDotColour + "'"}}},
           {"strokeOpacity", {{"value", 0.55}}},
           {"strokeWidth", {{"value", 1.5}}}}}}}});
  marks.push_back(
      {{"type", "symbol"},
       {"from", {{"data", data}}},
       {"clip", true},
       {"encode",
        {{"update",
          {{"x", {{"scale", "x"}, {"field", "v"}}},
           {"y", {{"scale", "y"}, {"field", "lane"}}},
           {"shape", {{"signal", "datum.bound ? 'triangle-left' : 'circle'"}}},
           {"fill",
            {{"signal",
              std::string("datum.flag ? '") + kFlagColour + "' : datum.bound ? '#ffffff' : '" + kDotColour + "'"}}},
           {"stroke", {{"signal", std::string("datum.flag ? '") + kFlagColour + "' : '" + kDotColour + "'"}}},
           {"strokeWidth", {{"value", 1.2}}},
           {"fillOpacity", {{"value", 0.85}}},
           {"size", {{"signal", "datum.flag ? 130 : 55"}}},
           {"tooltip", {{"signal", tip}}}}},
         {"hover", {{"size", {{"value", 220}}}}}}}});
  for (const char* edge : {"llo", "lhi"})  // a unit beyond the band but within its own, wider limits
    marks.push_back({{"type", "rule"},
                     {"from", {{"data", data + "_wide"}}},
                     {"clip", true},
                     {"encode",
                      {{"update",
                        {{"x", {{"scale", "x"}, {"field", edge}}},
                         {"y", {{"scale", "y"}, {"field", "lane"}, {"offset", -7}}},
                         {"y2", {{"scale", "y"}, {"field", "lane"}, {"offset", 7}}},
                         {"stroke", {{"value", kMedianColour}}},
                         {"strokeWidth", {{"value", 1.5}}},
                         {"tooltip", {{"signal", "'flag limits of ' + datum.unit + ': ' + datum.lim"}}}}}}}});
  marks.push_back({{"type", "text"},
                   {"from", {{"data", data + "_flagged"}}},
                   {"encode",
                    {{"update",
                      {{"x", {{"scale", "x"}, {"field", "v"}}},
                       {"y", {{"scale", "y"}, {"field", "lane"}}},
                       {"dx", {{"value", 8}}},
                       {"dy", {{"value", -7}}},
                       {"text", {{"field", "unit"}}},
                       {"fill", {{"value", kFlagColour}}},
                       {"fontWeight", {{"value", "bold"}}},
                       {"fontSize", {{"value", 11}}}}}}}});
}

// The strip of one figure at height y: its scales, axis, title and marks.
Json strip_group(const FleetFigurePanel& p, int y) {
  std::vector<double> core = {p.median, p.band_low, p.band_high}, extra;
  for (const FleetDot& d : p.dots) {
    core.push_back(d.value);
    extra.insert(extra.end(), {d.low, d.high});
  }
  const auto dom = log_domain(core, extra);
  const std::string data = std::string("dots_") + p.figure;
  std::string title = std::string(1, p.figure) + ", " + figure_name(p.figure) + ": ";
  if (p.units == 0)
    title += "no read-off (upper bounds only)";
  else
    title += std::to_string(p.units) + " read-off(s), median " + with_unit(p.median, p.unit) + ", spread x" +
             num(p.spread, 3) + (p.can_flag ? "" : "; too few units to flag");
  Json marks = Json::array();
  zone_marks(p, data, marks);
  unit_marks(data, marks);
  return {{"type", "group"},
          {"name", std::string("strip_") + p.figure},
          {"title", {{"text", title}, {"anchor", "start"}, {"fontSize", 12}, {"fontWeight", "normal"}, {"offset", 6}}},
          {"encode",
           {{"update",
             {{"x", {{"value", 0}}},
              {"y", {{"value", y}}},
              {"width", {{"signal", "width"}}},
              {"height", {{"value", kStripHeight}}},
              {"stroke", {{"value", "#d0d7de"}}}}}}},
          {"scales",
           {{{"name", "x"},
             {"type", "log"},
             {"domain", {dom[0], dom[1]}},
             {"range", {0, {{"signal", "width"}}}},
             {"zero", false}},
            {{"name", "y"}, {"type", "linear"}, {"domain", {0, 1}}, {"range", {kStripHeight, 0}}}}},
          {"axes",
           {{{"orient", "bottom"},
             {"scale", "x"},
             {"title", std::string(1, p.figure) + " [" + p.unit + "]"},
             {"grid", true},
             {"gridOpacity", 0.3},
             {"labelOverlap", true},
             {"format", ".3~g"}}}},
          {"marks", std::move(marks)}};
}

Json strip_data(const FleetFigurePanel& p) {
  const std::string name = std::string("dots_") + p.figure;
  const std::string z = num(fleet::kFleetOutlierZ, 2);
  Json marks = Json::array();
  if (std::isfinite(p.band_low))
    marks = Json::array({{{"x", short_number(p.band_low)}, {"t", "z -" + z}},
                         {{"x", short_number(p.median)}, {"t", "median"}},
                         {{"x", short_number(p.band_high)}, {"t", "z +" + z}}});
  return Json::array(
      {{{"name", name}, {"values", dot_rows(p)}},
       {{"name", name + "_iv"},
        {"source", name},
        {"transform", {{{"type", "filter"}, {"expr", "isValid(datum.lo) && isValid(datum.hi)"}}}}},
       {{"name", name + "_flagged"}, {"source", name}, {"transform", {{{"type", "filter"}, {"expr", "datum.flag"}}}}},
       {{"name", name + "_wide"}, {"source", name}, {"transform", {{{"type", "filter"}, {"expr", "datum.wide"}}}}},
       {{"name", name + "_marks"}, {"values", std::move(marks)}}});
}

// "N, K and B" (or "N, K, B, Q and R"): the figures the axis shows.
std::string figure_list(const FleetAxisView& a) {
  std::string out;
  for (std::size_t k = 0; k < a.figures.size(); ++k)
    out += (k == 0 ? "" : k + 1 == a.figures.size() ? " and " : ", ") + std::string(1, a.figures[k].figure);
  return out;
}

Json strips_spec(const FleetAxisView& a, const std::string& group) {
  const std::string z = num(fleet::kFleetOutlierZ, 2);
  Json spec = {
      {"$schema", "https://vega.github.io/schema/vega/v5.json"},
      {"width", kPlotWidth},
      {"height", static_cast<int>(a.figures.size()) * (kStripHeight + kStripGap) - kStripGap + kStripTop},
      {"padding", 5},
      {"title",
       {{"text", group + ", " + a.axis + ": " + figure_list(a) + " of each unit"},
        {"subtitle",
         "dot: a unit's figure, rule: its interval; line: the group's median; shaded: the flag band, robust "
         "z within +-" +
             z +
             " for a read-off of the fleet's typical precision (ticks: a less precise unit's own, wider limits); red: "
             "flagged"},
        {"anchor", "start"},
        {"fontSize", 13}}}};
  Json data = Json::array();
  Json marks = Json::array();
  for (std::size_t k = 0; k < a.figures.size(); ++k) {
    for (Json& d : strip_data(a.figures[k])) data.push_back(std::move(d));
    marks.push_back(strip_group(a.figures[k], kStripTop + static_cast<int>(k) * (kStripHeight + kStripGap)));
  }
  spec["data"] = std::move(data);
  const Json kinds = {"a unit's figure", "flagged unit", "upper bound only (not in the median)"};
  spec["scales"] = {
      {{"name", "dotfill"}, {"type", "ordinal"}, {"domain", kinds}, {"range", {kDotColour, kFlagColour, "#ffffff"}}},
      {{"name", "dotshape"}, {"type", "ordinal"}, {"domain", kinds}, {"range", {"circle", "circle", "triangle-left"}}}};
  spec["legends"] = {
      {{"fill", "dotfill"},
       {"shape", "dotshape"},
       {"orient", "top"},
       {"direction", "horizontal"},
       {"labelLimit", 300},
       {"encode",
        {{"symbols", {{"update", {{"stroke", {{"value", kDotColour}}}, {"strokeWidth", {{"value", 1.2}}}}}}}}}}};
  spec["marks"] = std::move(marks);
  return spec;
}

// A group of marks faceted by "series" over `data`, as large as the plot (so that its
// clipped marks see the plot's bounds).
Json facet_group(const std::string& name, const std::string& data, Json marks) {
  return {{"type", "group"},
          {"from", {{"facet", {{"name", name}, {"data", data}, {"groupby", "series"}}}}},
          {"encode", {{"update", {{"width", {{"signal", "width"}}}, {"height", {{"signal", "height"}}}}}}},
          {"marks", std::move(marks)}};
}

Json xy(const char* x, const char* y) {
  return {{"x", {{"scale", "x"}, {"field", x}}}, {"y", {{"scale", "y"}, {"field", y}}}};
}

// The band's envelopes, their edges and the median with its hover points.
void envelope_marks(bool percentiles, Json& marks) {
  auto envelope = [&](const char* lo, const char* hi, const char* colour) {
    Json enc = xy("tau", lo);
    enc["y2"] = {{"scale", "y"}, {"field", hi}};
    enc["fill"] = {{"value", colour}};
    enc["fillOpacity"] = {{"value", 0.8}};
    marks.push_back({{"type", "area"},
                     {"from", {{"data", "band"}}},
                     {"clip", true},
                     {"sort", {{"field", "datum.tau"}}},
                     {"encode", {{"update", enc}}}});
  };
  auto line = [&](const char* from, const char* field, const char* colour, double width) {
    Json enc = xy("tau", field);
    enc["stroke"] = {{"value", colour}};
    enc["strokeWidth"] = {{"value", width}};
    marks.push_back({{"type", "line"},
                     {"from", {{"data", from}}},
                     {"clip", true},
                     {"sort", {{"field", "datum.tau"}}},
                     {"encode", {{"update", enc}}}});
  };
  envelope("min", "max", kOuterColour);
  if (percentiles) envelope("p05", "p95", kInnerColour);
  line("band", "min", kEdgeColour, 1.0);
  line("band", "max", kEdgeColour, 1.0);
  line("band", "med", kMedianColour, 2.2);
  const std::string tip_band =
      "{'tau [s]': format(datum.tau, '.4~g'), 'median': format(datum.med, '.4~e'), '5-95%': isValid(datum.p05) ? "
      "format(datum.p05, '.3~e') + ' to ' + format(datum.p95, '.3~e') : 'n/a (fewer than " +
      std::to_string(kFleetPercentileUnits) +
      " units)', 'min-max': format(datum.min, '.3~e') + ' to ' + format(datum.max, '.3~e'), 'units': datum.n}";
  Json med = xy("tau", "med");
  med["fill"] = {{"value", kMedianColour}};
  med["size"] = {{"value", 22}};
  med["tooltip"] = {{"signal", tip_band}};
  marks.push_back({{"type", "symbol"},
                   {"from", {{"data", "band"}}},
                   {"clip", true},
                   {"encode", {{"update", med}, {"hover", {{"size", {{"value", 90}}}}}}}});
}

// The flagged units' interval bands, curves with their hover points, and labels.
void flagged_marks(Json& marks) {
  Json ci = xy("tau", "lo");
  ci["y2"] = {{"scale", "y"}, {"field", "hi"}};
  ci["fill"] = {{"scale", "color"}, {"field", "series"}};
  ci["fillOpacity"] = {{"value", 0.12}};
  marks.push_back(facet_group("ci_facet", "unit_bands",
                              {{{"type", "area"},
                                {"from", {{"data", "ci_facet"}}},
                                {"clip", true},
                                {"sort", {{"field", "datum.tau"}}},
                                {"encode", {{"update", ci}}}}}));
  const std::string tip_unit =
      "{'unit': datum.unit, 'tau [s]': format(datum.tau, '.4~g'), 'ADEV': format(datum.v, '.4~e'), 'CI': "
      "isValid(datum.lo) && isValid(datum.hi) ? format(datum.lo, '.3~e') + ' to ' + format(datum.hi, '.3~e') : "
      "'n/a', 'flagged': datum.flags}";
  Json unit_line = xy("tau", "v");
  unit_line["stroke"] = {{"scale", "color"}, {"field", "series"}};
  unit_line["strokeWidth"] = {{"value", 2.5}};
  Json unit_sym = xy("tau", "v");
  unit_sym["fill"] = {{"scale", "color"}, {"field", "series"}};
  unit_sym["size"] = {{"value", 26}};
  unit_sym["tooltip"] = {{"signal", tip_unit}};
  marks.push_back(facet_group("unit_facet", "units",
                              {{{"type", "line"},
                                {"from", {{"data", "unit_facet"}}},
                                {"clip", true},
                                {"sort", {{"field", "datum.tau"}}},
                                {"encode", {{"update", unit_line}}}},
                               {{"type", "symbol"},
                                {"from", {{"data", "unit_facet"}}},
                                {"clip", true},
                                {"encode", {{"update", unit_sym}, {"hover", {{"size", {{"value", 100}}}}}}}}}));
  Json label = xy("tau", "v");
  label["text"] = {{"field", "unit"}};
  label["align"] = {{"signal", "datum.right ? 'right' : 'left'"}};
  label["dx"] = {{"signal", "datum.right ? -6 : 6"}};
  label["dy"] = {{"signal", "-12 - 14 * datum.k"}};
  label["fill"] = {{"scale", "color"}, {"field", "series"}};
  label["fontWeight"] = {{"value", "bold"}};
  label["fontSize"] = {{"value", 12}};
  marks.push_back({{"type", "text"}, {"from", {{"data", "labels"}}}, {"encode", {{"update", label}}}});
}

Json band_marks(bool percentiles) {
  Json marks = Json::array();
  envelope_marks(percentiles, marks);
  flagged_marks(marks);
  return marks;
}

// Where a flagged unit's label goes: the point of its curve nearest (in log) the averaging
// time its worst flagged figure was read at, where the curve shows why it is flagged; its
// last point when that is unknown.
std::size_t label_point(const FleetUnitCurve& c) {
  std::size_t at = c.tau.empty() ? 0 : c.tau.size() - 1;
  if (!(c.label_tau > 0.0)) return at;
  double best = INFINITY;
  for (std::size_t i = 0; i < c.tau.size(); ++i)
    if (const double d = std::abs(std::log(c.tau[i] / c.label_tau)); d < best) best = d, at = i;
  return at;
}

// What a band plot draws: its rows, the flagged units' points and labels, the series and
// their colours, and the values its axes must hold.
struct BandData {
  Json rows = Json::array(), curves = Json::array(), labels = Json::array();
  Json domain = Json::array(), range = Json::array();
  std::vector<double> xs, ys, extra;
};

BandData band_data(const FleetAxisView& a) {
  const FleetAdevBand& b = a.band;
  BandData d;
  for (std::size_t i = 0; i < b.tau.size(); ++i) {
    d.rows.push_back({{"tau", short_number(b.tau[i])},
                      {"min", short_number(b.min[i])},
                      {"p05", short_number(b.p05[i])},
                      {"med", short_number(b.median[i])},
                      {"p95", short_number(b.p95[i])},
                      {"max", short_number(b.max[i])},
                      {"n", b.count[i]}});
    d.xs.push_back(b.tau[i]);
    d.ys.insert(d.ys.end(), {b.min[i], b.max[i]});
  }
  d.domain.push_back("fleet median");
  d.range.push_back(kMedianColour);
  if (b.percentiles) d.domain.push_back("fleet 5-95%"), d.range.push_back(kInnerColour);
  d.domain.push_back("fleet min-max");
  d.range.push_back(kOuterColour);
  for (std::size_t k = 0; k < a.flagged.size(); ++k) {
    const FleetUnitCurve& c = a.flagged[k];
    const std::string series = "unit " + c.unit;
    d.domain.push_back(series);
    d.range.push_back(kPalette[k % kPalette.size()]);
    std::string flags;
    for (const std::string& f : c.flags) flags += (flags.empty() ? "" : "; ") + f;
    for (std::size_t i = 0; i < c.tau.size(); ++i) {
      d.curves.push_back({{"series", series},
                          {"unit", c.unit},
                          {"tau", short_number(c.tau[i])},
                          {"v", short_number(c.adev[i])},
                          {"lo", short_number(c.low[i])},
                          {"hi", short_number(c.high[i])},
                          {"flags", flags}});
      d.xs.push_back(c.tau[i]);
      d.ys.push_back(c.adev[i]);
      d.extra.insert(d.extra.end(), {c.low[i], c.high[i]});
    }
    if (const std::size_t at = label_point(c); at < c.tau.size())
      d.labels.push_back({{"series", series},
                          {"unit", c.unit},
                          {"tau", short_number(c.tau[at])},
                          {"v", short_number(c.adev[at])},
                          {"right", 2 * at > c.tau.size()},
                          {"k", static_cast<int>(k)}});
  }
  return d;
}

// The band of one axis: its envelopes and median, each flagged unit's ADEV with its
// interval band over it, labelled.
Json band_spec(const FleetAxisView& a, const std::string& group) {
  const FleetAdevBand& b = a.band;
  const std::string unit = a.unit.empty() ? "U" : a.unit;
  BandData d = band_data(a);
  const auto xd = log_domain(d.xs, {}), yd = log_domain(d.ys, d.extra, kCurveIntervalRoom);
  std::string title = group + ", " + a.axis + ": Allan deviation of the " + std::to_string(b.units) +
                      " unflagged unit(s) per tau (median, min-max" + (b.percentiles ? ", 5-95%" : "") + ")";
  title += a.flagged.empty() ? "; no unit flagged on " + a.axis
                             : " and the " + std::to_string(a.flagged.size()) + " flagged unit(s) with their CI";
  Json spec = {{"$schema", "https://vega.github.io/schema/vega/v5.json"},
               {"width", kPlotWidth},
               {"height", kBandHeight},
               {"padding", 5},
               {"title", {{"text", title}, {"anchor", "start"}, {"fontSize", 13}}}};
  if (b.interpolated)
    spec["title"]["subtitle"] = "the units' tau grids differ: each ADEV interpolated in log-log onto a common grid";
  spec["data"] = {{{"name", "band"}, {"values", std::move(d.rows)}},
                  {{"name", "units"}, {"values", std::move(d.curves)}},
                  {{"name", "unit_bands"},
                   {"source", "units"},
                   {"transform", {{{"type", "filter"}, {"expr", "isValid(datum.lo) && isValid(datum.hi)"}}}}},
                  {{"name", "labels"}, {"values", std::move(d.labels)}}};
  spec["scales"] = {
      {{"name", "x"}, {"type", "log"}, {"domain", {xd[0], xd[1]}}, {"range", "width"}, {"zero", false}},
      {{"name", "y"}, {"type", "log"}, {"domain", {yd[0], yd[1]}}, {"range", "height"}, {"zero", false}},
      {{"name", "color"}, {"type", "ordinal"}, {"domain", std::move(d.domain)}, {"range", std::move(d.range)}}};
  spec["axes"] = {{{"orient", "bottom"},
                   {"scale", "x"},
                   {"title", "tau [s]"},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"labelOverlap", true}},
                  {{"orient", "left"},
                   {"scale", "y"},
                   {"title", "Allan deviation [" + unit + "]"},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"format", ".1e"},
                   {"labelOverlap", true}}};
  spec["legends"] = {{{"stroke", "color"},
                      {"title", "series"},
                      {"orient", "right"},
                      {"symbolType", "stroke"},
                      {"symbolStrokeWidth", 4},
                      {"labelLimit", 260}}};
  spec["marks"] = band_marks(b.percentiles);
  return spec;
}

// ---- the page ------------------------------------------------------------------------

// A plot's container with its own hint (Plots::add words the hint for the other pages' kinds).
std::string plot_html(detail::Plots& plots, const std::string& id, const std::string& kind, Json spec,
                      const std::string& hint) {
  std::string html = plots.add(id, kind, std::move(spec));
  const std::string from = "<div class=\"hint\">", to = "<span class=\"export\">";
  const auto a = html.find(from), b = html.find(to);
  if (a != std::string::npos && b != std::string::npos && b > a)
    html.replace(a + from.size(), b - a - from.size(), html_escape(hint));
  return html;
}

std::string td(const std::string& text, const char* cls = nullptr) {
  return std::string("<td") + (cls ? std::string(" class=\"") + cls + "\"" : std::string()) + ">" + html_escape(text) +
         "</td>";
}

std::string head_row(const std::vector<std::string>& head) {
  std::string out = "<tr>";
  for (const std::string& h : head) out += "<th>" + html_escape(h) + "</th>";
  return out + "</tr>\n";
}

// A row's figure in the panel's unit of its axis ("< " before a bound) as a cell, bold when
// flagged; "-" when none.
std::string figure_cell(const FleetRow& r, const FleetAxisView* a, std::size_t k) {
  if (!a || !r.figures_known || k >= a->figures.size()) return td("-", "num");
  const FleetFigurePanel& p = a->figures[k];
  for (const FleetDot& d : p.dots) {
    if (d.unit != r.unit) continue;
    const std::string text =
        (d.bound ? "< " : "") + with_unit(d.value, p.unit) +
        (std::isfinite(d.low) && std::isfinite(d.high) ? " [" + num(d.low, 3) + ", " + num(d.high, 3) + "]"
                                                       : std::string());
    return d.flagged ? "<td class=\"num\"><b>" + html_escape(text) + "</b></td>" : td(text, "num");
  }
  return td("-", "num");
}

// "N: wholly above; B: reaching within": where each flagged figure's interval lies against its
// own flag limits.
std::string against_band(const FleetRow& r, const FleetAxisView* a) {
  std::string out;
  if (!a) return out;
  for (const FleetFigurePanel& p : a->figures)
    for (const FleetDot& d : p.dots)
      if (d.unit == r.unit && d.flagged)
        out += (out.empty() ? "" : "; ") + std::string(1, p.figure) + ": " +
               (!(std::isfinite(d.low) && std::isfinite(d.high)) ? "no interval"
                : d.beyond ? std::string("wholly ") + (d.value > p.median ? "above" : "below")
                           : std::string("reaching within them"));
  return out;
}

const FleetAxisView* axis_of(const FleetGroupView& g, const std::string& axis) {
  for (const FleetAxisView& a : g.axes)
    if (a.axis == axis) return &a;
  return nullptr;
}

// The figures each axis of the group shows (the study's: fleet_shown_figures).
std::size_t shown_count(const FleetGroupView& g) { return g.axes.empty() ? 0 : g.axes.front().figures.size(); }

std::vector<std::string> flagged_head(const FleetGroupView& g) {
  std::vector<std::string> head = {"unit", "axis", "why flagged", "interval against its flag limits"};
  if (!g.axes.empty())
    for (const FleetFigurePanel& p : g.axes.front().figures) head.emplace_back(1, p.figure);
  head.insert(head.end(), {"chosen model", "GoF p", "recording"});
  return head;
}

std::string flagged_table(const FleetStudy& s, const FleetGroupView& g) {
  if (g.flagged_rows.empty()) return {};
  std::ostringstream os;
  os << "<h3>flagged units</h3>\n<table class=\"fleet-flagged\">\n<caption>each unit x axis with a figure beyond "
        "robust z "
     << num(fleet::kFleetOutlierZ, 2)
     << ", the surest unit first (a figure whose interval lies wholly outside its flag limits, then the largest robust "
        "z); "
        "figures with their intervals, in the strips' units</caption>\n"
     << head_row(flagged_head(g));
  for (const std::size_t i : g.flagged_rows) {
    const FleetRow& r = s.rows[i];
    std::string why;
    for (const std::string& f : r.flags) why += (why.empty() ? "" : "; ") + f;
    const FleetAxisView* a = axis_of(g, r.axis);
    os << "<tr class=\"outside\" data-unit=\"" << html_escape(r.unit) << "\" data-axis=\"" << html_escape(r.axis)
       << "\">" << td(r.unit) << td(r.axis) << td(why) << td(against_band(r, a));
    for (std::size_t k = 0; k < shown_count(g); ++k) os << figure_cell(r, a, k);
    os << td(r.chosen_structure) << td(num(r.gof_p, 3), "num") << td(r.path) << "</tr>\n";
  }
  return os.str() + "</table>\n";
}

std::string failure_table(const FleetStudy& s, const FleetGroupView& g) {
  if (g.failed_rows.empty()) return {};
  std::ostringstream os;
  os << "<h3>failures</h3>\n<table class=\"fleet-failures\">\n<caption>recordings (or axes) with no result: not "
        "in the plots or the summary</caption>\n"
     << head_row({"unit", "axis", "reason", "recording"});
  for (const std::size_t i : g.failed_rows) {
    const FleetRow& r = s.rows[i];
    os << "<tr data-unit=\"" << html_escape(r.unit) << "\">" << td(r.unit)
       << td(r.axis.empty() ? "(the recording)" : r.axis) << td(r.status, "note") << td(r.path) << "</tr>\n";
  }
  return os.str() + "</table>\n";
}

// The median in the strip's unit and, when that is a datasheet's, in the data's.
std::string median_text(const FleetFigurePanel& p) {
  if (!std::isfinite(p.median)) return "-";
  std::string t = with_unit(p.median, p.unit, 4);
  if (p.unit != p.data_unit) t += " (" + with_unit(p.median / p.to_panel, p.data_unit, 4) + ")";
  return t;
}

std::string summary_table(const FleetStudy& s, const FleetGroupView& g) {
  std::ostringstream os;
  const bool spec = !s.spec_path.empty();
  os << "<h3>summary</h3>\n<table class=\"fleet-summary\">\n<caption>per axis and figure: the median of the "
        "units' read-offs (upper bounds left out); their spread exp(MAD of the logs / 0.6745) as a factor and the "
        "units' own spread, net of the read-offs' noise; the flag band, beyond which a read-off of the fleet's "
        "typical precision is flagged (robust z beyond "
     << num(fleet::kFleetOutlierZ, 2) << "; groups of " << fleet::kMinUnitsForFlags << " units or more)</caption>\n";
  std::vector<std::string> head = {"axis",      "figure",  "read-offs",   "median", "spread", "units' own spread",
                                   "flag band", "flagged", "upper bounds"};
  if (spec) head.push_back("above spec");
  os << head_row(head);
  for (const FleetAxisView& a : g.axes)
    for (const FleetFigurePanel& p : a.figures) {
      std::string flagged, bounds;
      int n_bounds = 0;
      for (const FleetDot& d : p.dots) {
        if (d.flagged) flagged += (flagged.empty() ? "" : ", ") + d.unit;
        n_bounds += d.bound;
      }
      bounds = std::to_string(n_bounds);
      const std::string band = std::isfinite(p.band_low) && p.can_flag
                                   ? num(p.band_low, 3) + " to " + with_unit(p.band_high, p.unit)
                                   : std::string(p.units ? "- (too few units to flag)" : "-");
      os << "<tr>" << td(a.axis) << td(std::string(1, p.figure) + " " + figure_name(p.figure))
         << td(std::to_string(p.units), "num") << td(median_text(p), "num")
         << td(std::isfinite(p.spread) ? "x" + num(p.spread, 4) : "-", "num")
         << td(std::isfinite(p.unit_spread) ? "x" + num(p.unit_spread, 4) : "-", "num") << td(band, "num")
         << td(flagged.empty() ? "none" : flagged) << td(bounds, "num");
      if (spec) {
        std::string above;
        if (const fleet::FleetFigureSummary* sum = summary_of(s, g.name, a.axis, p.figure))
          for (const std::string& u : sum->out_of_spec) above += (above.empty() ? "" : ", ") + u;
        os << td(above.empty() ? "none" : above);
      }
      os << "</tr>\n";
    }
  return os.str() + "</table>\n";
}

// The group's joint model per axis (`--joint`): its units as replicates, the typical unit's
// figures (N, K, B, and Q, R where shown), and whether the units share one theta.
std::string joint_table(const FleetStudy& s, const FleetGroupView& g) {
  std::ostringstream os;
  bool any = false;
  for (const fleet::FleetJointModel& m : s.joint) any = any || m.group == g.name;
  if (!any) return {};
  os << "<h3>joint model</h3>\n<table class=\"fleet-joint\">\n<caption>per axis, the units as replicates of one "
        "sensor: the selection over them recommends a model, fitted jointly (the units that stand out left out); "
        "its figures are the group's typical unit's, with replicate-t intervals from the units resampled; the "
        "shared-theta test says whether the units differ beyond their own noise (bootstrap up to 12 units, "
        "chi-square beyond)</caption>\n";
  const std::vector<int> shown = fleet_shown_figures(s);
  std::vector<std::string> head = {"axis", "units", "left out", "model"};
  for (const int k : shown) head.emplace_back(1, kFigureNames[k].symbol);
  head.emplace_back("shared theta?");
  os << head_row(head);
  for (const fleet::FleetJointModel& m : s.joint) {
    if (m.group != g.name) continue;
    std::string left;
    for (const std::string& u : m.left_out) left += (left.empty() ? "" : ", ") + u;
    os << "<tr>" << td(m.axis) << td(std::to_string(m.units), "num") << td(left.empty() ? "none" : left);
    if (m.status != "ok") {
      os << "<td colspan=\"" << shown.size() + 2 << "\">" << html_escape(m.status) << "</td></tr>\n";
      continue;
    }
    os << td(m.fit.joint.model.to_string(m.fit.joint.theta));
    for (const int k : shown) {
      if (!m.figures) {
        os << td("-");
        continue;
      }
      const Readoff& f = (*m.figures)[k].figure;
      const std::string unit = pattern(kFigureNames[k].symbol, m.unit);
      std::string text = (f.status == ReadoffStatus::kBound ? "< " : "") + with_unit(f.value, unit);
      if (std::isfinite(f.low) && std::isfinite(f.high)) text += " [" + num(f.low, 3) + ", " + num(f.high, 3) + "]";
      os << td(text, "num");
    }
    std::string shared = "-";
    if (m.test)
      shared = std::string(m.test->rejects() ? "no" : "yes") + " (H = " + num(m.test->heterogeneity, 4) + ", p " +
               num(m.test->heterogeneity_p, 2) + ", " + to_string(m.test->calibration) + ")";
    os << td(shared) << "</tr>\n";
  }
  return os.str() + "</table>\n";
}

std::string axis_section(const FleetAxisView& a, const std::string& group, const std::string& id,
                         detail::Plots& plots) {
  std::ostringstream os;
  os << "<h3 id=\"" << id << "\">" << html_escape(a.axis) << " <span class=\"facts\">(data in "
     << html_escape(a.unit.empty() ? "U, undeclared" : a.unit) << ")</span></h3>\n";
  os << plot_html(plots, id + "-figures", "fleet-figures", strips_spec(a, group),
                  "hover a dot for the unit, its value, interval, read-off source, robust z and recording");
  os << plot_html(plots, id + "-adev", "adev", band_spec(a, group),
                  "hover the median for the band at that tau, a flagged unit's point for its value and interval");
  for (const std::string& n : a.notes) os << "<p class=\"facts\">" << html_escape(n) << "</p>\n";
  return os.str();
}

std::string group_section(const FleetStudy& s, const FleetGroupView& g, std::size_t k, detail::Plots& plots) {
  const std::string id = "group-" + std::to_string(k + 1);
  std::ostringstream os;
  os << "<section class=\"column\" id=\"" << id << "\" data-group=\"" << html_escape(g.name) << "\">\n<h2>group "
     << html_escape(g.name) << "</h2>\n<ul class=\"headline\">\n";
  for (std::size_t i = 0; i < g.headline.size(); ++i)
    os << "<li" << (i == 1 && !g.flagged_rows.empty() ? " class=\"quality\"" : "") << ">" << html_escape(g.headline[i])
       << "</li>\n";
  os << "</ul>\n";
  if (g.axes.size() > 1) {
    os << "<nav>axes: ";
    for (std::size_t a = 0; a < g.axes.size(); ++a)
      os << "<a href=\"#" << id << "-axis-" << a + 1 << "\">" << html_escape(g.axes[a].axis) << "</a>";
    os << "</nav>\n";
  }
  os << flagged_table(s, g) << failure_table(s, g);
  for (std::size_t a = 0; a < g.axes.size(); ++a)
    os << axis_section(g.axes[a], g.name, id + "-axis-" + std::to_string(a + 1), plots);
  if (!g.axes.empty()) os << summary_table(s, g) << joint_table(s, g);
  os << "</section>\n";
  return os.str();
}

std::string page_header(const FleetStudy& s, const FleetPageData& d) {
  std::ostringstream os;
  os << "<header>\n<h1>" << html_escape(d.title) << "</h1>\n<p>gmwm " << html_escape(version())
     << " &middot; command <code>fleet</code> &middot; manifest <code>" << html_escape(s.manifest)
     << "</code> &middot; model <code>" << html_escape(s.model_spec) << "</code></p>\n<p>" << s.recordings
     << " recording(s), " << s.failed << " failed, " << d.groups.size()
     << " group(s). Each unit x axis selected over the model; N white noise density, K random walk, B bias "
        "instability, Q quantization and R rate ramp (IEEE 952; Q and R drawn where a unit reads them, their upper "
        "bounds alone in the JSON and CSV). A unit is flagged when the log of a figure lies more than "
     << num(fleet::kFleetOutlierZ, 2)
     << " standard deviations from its group's median, the deviation of the units between them (robust: MAD) "
        "and of its own read-off (its interval) together: robust z = log(x / median) / sqrt(tau^2 + se^2), "
        "Iglewicz and Hoaglin's modified z when the read-offs are equally precise; groups of "
     << fleet::kMinUnitsForFlags << " units or more.</p>\n</header>\n";
  return os.str();
}

std::string overview(const FleetPageData& d) {
  std::ostringstream os;
  os << "<nav>groups: ";
  for (std::size_t k = 0; k < d.groups.size(); ++k)
    os << "<a href=\"#group-" << k + 1 << "\">" << html_escape(d.groups[k].name) << "</a>";
  os << "</nav>\n<table class=\"fleet-groups\">\n"
     << head_row({"group", "units", "failed recordings", "flagged units"});
  for (const FleetGroupView& g : d.groups) {
    std::vector<std::string> units;
    for (const FleetAxisView& a : g.axes)
      for (const FleetUnitCurve& c : a.flagged)
        if (std::find(units.begin(), units.end(), c.unit) == units.end()) units.push_back(c.unit);
    std::string list;
    for (const std::string& u : units) list += (list.empty() ? "" : ", ") + u;
    os << "<tr>" << td(g.name) << td(std::to_string(g.units), "num") << td(std::to_string(g.failed), "num")
       << td(units.empty() ? "none" : std::to_string(units.size()) + ": " + list) << "</tr>\n";
  }
  return os.str() + "</table>\n";
}

std::string page_body(const FleetStudy& s, const FleetPageData& d, detail::Plots& plots) {
  std::ostringstream body;
  body << page_header(s, d) << "<main>\n<div id=\"gmwm-errors\" class=\"errors\" hidden></div>\n"
       << "<div id=\"gmwm-warnings\" class=\"warnings\" hidden></div>\n"
       << detail::kErrorCapture;
  if (d.groups.size() > 1) body << overview(d);
  if (d.groups.empty()) body << "<p class=\"facts\">The manifest has no recording.</p>\n";
  for (std::size_t k = 0; k < d.groups.size(); ++k) body << group_section(s, d.groups[k], k, plots);
  body << "</main>\n<footer>Plots: Vega 5 (Debian libjs-vega), inlined; the file needs no network. Hover a dot or "
          "a point for its values; SVG/PNG under each plot saves it. Numbers in full: gmwm fleet --csv / "
          "--json.</footer>\n";
  return body.str();
}

// ---- the static SVG ----------------------------------------------------------------------

constexpr double kSvgWidth = 860, kSvgHeight = 480;
constexpr double kSvgLeft = 86, kSvgRight = 230, kSvgTop = 40, kSvgBottom = 56;

struct SvgAxis {
  double lo = -1, hi = 1;  // log10 of the domain
  double a = 0, b = 1;     // pixels
  double px(double v) const { return a + (std::log10(v) - lo) / (hi - lo) * (b - a); }
};

std::string f2(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}

SvgAxis svg_axis(const std::array<double, 2>& domain, double a, double b) {
  return {std::log10(domain[0]), std::log10(domain[1]), a, b};
}

// "x,y x,y ..." of (tau, value) pairs with positive values.
std::string svg_points(const SvgAxis& x, const SvgAxis& y, const std::vector<double>& tau, const std::vector<double>& v,
                       bool reverse = false) {
  std::vector<std::string> pts;
  for (std::size_t i = 0; i < tau.size() && i < v.size(); ++i)
    if (v[i] > 0.0 && std::isfinite(v[i])) pts.push_back(f2(x.px(tau[i])) + "," + f2(y.px(v[i])));
  if (reverse) std::reverse(pts.begin(), pts.end());
  std::string out;
  for (const std::string& p : pts) out += p + " ";
  return out;
}

std::string svg_frame(const SvgAxis& x, const SvgAxis& y, const std::string& title, const std::string& unit) {
  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kSvgWidth << "\" height=\"" << kSvgHeight
     << "\" viewBox=\"0 0 " << kSvgWidth << " " << kSvgHeight
     << "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"#ffffff\"/>\n<text x=\"12\" y=\"22\" font-size=\"13\" font-weight=\"bold\">"
     << html_escape(title) << "</text>\n<g stroke=\"#e3e3e3\">\n";
  const double x0 = kSvgLeft, x1 = kSvgWidth - kSvgRight, y0 = kSvgTop, y1 = kSvgHeight - kSvgBottom;
  std::string labels;
  for (int e = static_cast<int>(std::ceil(x.lo)); e <= static_cast<int>(std::floor(x.hi)); ++e) {
    const double px = x.px(std::pow(10.0, e));
    os << "<line x1=\"" << f2(px) << "\" y1=\"" << y0 << "\" x2=\"" << f2(px) << "\" y2=\"" << y1 << "\"/>\n";
    labels += "<text x=\"" + f2(px) + "\" y=\"" + f2(y1 + 16) + "\" text-anchor=\"middle\">1e" + std::to_string(e) +
              "</text>\n";
  }
  for (int e = static_cast<int>(std::ceil(y.lo)); e <= static_cast<int>(std::floor(y.hi)); ++e) {
    const double py = y.px(std::pow(10.0, e));
    os << "<line x1=\"" << x0 << "\" y1=\"" << f2(py) << "\" x2=\"" << x1 << "\" y2=\"" << f2(py) << "\"/>\n";
    labels += "<text x=\"" + f2(x0 - 6) + "\" y=\"" + f2(py + 4) + "\" text-anchor=\"end\">1e" + std::to_string(e) +
              "</text>\n";
  }
  os << "</g>\n<g fill=\"#333333\">\n"
     << labels << "<text x=\"" << f2((x0 + x1) / 2) << "\" y=\"" << kSvgHeight - 14
     << "\" text-anchor=\"middle\">tau [s]</text>\n<text transform=\"translate(20," << f2((y0 + y1) / 2)
     << ") rotate(-90)\" text-anchor=\"middle\">Allan deviation [" << html_escape(unit) << "]</text>\n</g>\n"
     << "<rect x=\"" << x0 << "\" y=\"" << y0 << "\" width=\"" << x1 - x0 << "\" height=\"" << y1 - y0
     << "\" fill=\"none\" stroke=\"#888888\"/>\n<clipPath id=\"plot\"><rect x=\"" << x0 << "\" y=\"" << y0
     << "\" width=\"" << x1 - x0 << "\" height=\"" << y1 - y0 << "\"/></clipPath>\n";
  return os.str();
}

// Each flagged unit's colour on the page: Plots::add's rule replayed over the page's band
// plots in their order (a unit keeps one colour across the page).
std::map<std::string, std::string> unit_colours(const FleetPageData& d) {
  detail::Plots plots;
  for (const FleetGroupView& g : d.groups)
    for (const FleetAxisView& a : g.axes) {
      Json domain = Json::array(), range = Json::array();
      for (std::size_t k = 0; k < a.flagged.size(); ++k) {
        domain.push_back("unit " + a.flagged[k].unit);
        range.push_back(kPalette[k % kPalette.size()]);
      }
      plots.add("c", "adev",
                {{"scales", {{{"name", "color"}, {"type", "ordinal"}, {"domain", domain}, {"range", range}}}}});
    }
  return plots.series_colours;
}

}  // namespace

FleetPageData fleet_page_data(const FleetStudy& study) {
  FleetPageData d;
  d.title = "gmwm fleet: " + study.manifest;
  std::vector<std::string> groups;
  for (const FleetRow& r : study.rows)
    if (std::find(groups.begin(), groups.end(), r.group) == groups.end()) groups.push_back(r.group);
  for (const std::string& g : groups) d.groups.push_back(group_view(study, g));
  return d;
}

namespace {

std::string render_page(const FleetStudy& study, const FleetPageData& d) {
  const std::string vega = detail::vega_script();  // first: fails before any work
  detail::Plots plots;
  const std::string body = page_body(study, d, plots);
  std::string page = detail::html_page(d.title, body, plots, vega);
  spdlog::debug("fleet report: {} plot(s), {} bytes", plots.specs.size(), page.size());
  return page;
}

}  // namespace

std::string render_fleet_page(const FleetStudy& study) { return render_page(study, fleet_page_data(study)); }

std::string render_fleet_svg(const FleetPageData& d) {
  const FleetGroupView* group = nullptr;
  const FleetAxisView* axis = nullptr;
  for (const FleetGroupView& g : d.groups)
    for (const FleetAxisView& a : g.axes)
      if (!axis || (!a.flagged.empty() && axis->flagged.empty())) group = &g, axis = &a;
  if (!axis) return {};
  const FleetAdevBand& b = axis->band;
  std::vector<double> xs = b.tau, ys = b.min, extra;
  ys.insert(ys.end(), b.max.begin(), b.max.end());
  for (const FleetUnitCurve& c : axis->flagged) {
    xs.insert(xs.end(), c.tau.begin(), c.tau.end());
    ys.insert(ys.end(), c.adev.begin(), c.adev.end());
    extra.insert(extra.end(), c.low.begin(), c.low.end());
    extra.insert(extra.end(), c.high.begin(), c.high.end());
  }
  const SvgAxis x = svg_axis(log_domain(xs, {}), kSvgLeft, kSvgWidth - kSvgRight);
  const SvgAxis y = svg_axis(log_domain(ys, extra, kCurveIntervalRoom), kSvgHeight - kSvgBottom, kSvgTop);
  const std::string title = group->name + ", " + axis->axis + ": Allan deviation band of " + std::to_string(b.units) +
                            " unflagged unit(s) and " + std::to_string(axis->flagged.size()) + " flagged";
  std::ostringstream os;
  os << svg_frame(x, y, title, axis->unit.empty() ? "U" : axis->unit) << "<g clip-path=\"url(#plot)\">\n";
  os << "<polygon points=\"" << svg_points(x, y, b.tau, b.max) << svg_points(x, y, b.tau, b.min, true) << "\" fill=\""
     << kOuterColour << "\" stroke=\"" << kEdgeColour << "\"/>\n";
  if (b.percentiles)
    os << "<polygon points=\"" << svg_points(x, y, b.tau, b.p95) << svg_points(x, y, b.tau, b.p05, true) << "\" fill=\""
       << kInnerColour << "\" stroke=\"none\"/>\n";
  os << "<polyline points=\"" << svg_points(x, y, b.tau, b.median) << "\" fill=\"none\" stroke=\"" << kMedianColour
     << "\" stroke-width=\"2.2\"/>\n";
  const std::map<std::string, std::string> colours = unit_colours(d);
  std::vector<std::pair<std::string, std::string>> legend = {{"fleet median", kMedianColour}};
  if (b.percentiles) legend.emplace_back("fleet 5-95%", kInnerColour);
  legend.emplace_back("fleet min-max", kOuterColour);
  for (const FleetUnitCurve& c : axis->flagged) {
    const auto it = colours.find("unit " + c.unit);
    const std::string col = it == colours.end() ? kFlagColour : it->second;
    legend.emplace_back("unit " + c.unit, col);
    os << "<polygon points=\"" << svg_points(x, y, c.tau, c.high) << svg_points(x, y, c.tau, c.low, true)
       << "\" fill=\"" << col << "\" fill-opacity=\"0.18\" stroke=\"none\"/>\n<polyline points=\""
       << svg_points(x, y, c.tau, c.adev) << "\" fill=\"none\" stroke=\"" << col << "\" stroke-width=\"2.5\"/>\n";
  }
  os << "</g>\n";
  double ly = kSvgTop + 8;
  for (const auto& [name, col] : legend) {
    const double lx = kSvgWidth - kSvgRight + 16;
    os << "<line x1=\"" << lx << "\" y1=\"" << f2(ly) << "\" x2=\"" << lx + 24 << "\" y2=\"" << f2(ly) << "\" stroke=\""
       << col << "\" stroke-width=\"4\"/>\n<text x=\"" << lx + 30 << "\" y=\"" << f2(ly + 4) << "\">"
       << html_escape(name) << "</text>\n";
    ly += 18;
  }
  os << "</svg>\n";
  return os.str();
}

void stage_fleet_report(io::OutputSet& outputs, const std::string& path, const FleetStudy& study) {
  const FleetPageData d = fleet_page_data(study);
  outputs.stage(path, render_page(study, d));
  if (const std::string svg = render_fleet_svg(d); !svg.empty()) outputs.stage(report_svg_path(path), svg);
}

}  // namespace gmwm::report
