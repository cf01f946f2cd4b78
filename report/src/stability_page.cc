// The frequency-stability study's HTML report (stability_output.h): per column the chosen
// deviations on log-log axes with their intervals, one plot per unit (the data's; the phase's
// for the time deviations), and the table of every value with its interval and noise.
#include <cmath>
#include <map>
#include <sstream>

#include "gmwm/engine/number_text.h"
#include "gmwm/report/stability_output.h"
#include "html_report_detail.h"

namespace gmwm::report {
namespace {

using detail::html_escape;

std::string g(double x, int digits = 5) { return significant(x, digits, NonFinite::kDash); }

// Rows {kind, tau, v, lo, hi, edf, noise} of the kinds in (or out of) the phase's unit;
// positive values only (a log axis).
Json deviation_rows(const pipeline::StabilityColumn& c, bool time_units) {
  Json rows = Json::array();
  for (std::size_t d = 0; d < c.deviations.size(); ++d) {
    const stability::DeviationCurve& curve = c.deviations[d];
    if (stability::in_time_units(curve.kind) != time_units) continue;
    const stability::DeviationIntervals& ci = c.intervals[d];
    for (std::size_t i = 0; i < curve.m.size(); ++i) {
      if (!(curve.value[i] > 0.0) || !std::isfinite(curve.value[i])) continue;
      const bool band = ci.low[i] > 0.0 && std::isfinite(ci.high[i]);
      rows.push_back({{"kind", std::string(stability::deviation_name(curve.kind))},
                      {"tau", curve.tau[i]},
                      {"v", curve.value[i]},
                      {"lo", band ? Json(ci.low[i]) : Json(curve.value[i])},
                      {"hi", band ? Json(ci.high[i]) : Json(curve.value[i])},
                      {"edf", json_number(ci.edf[i])},
                      {"noise", std::string(stability::noise_name(ci.noise[i].alpha))}});
    }
  }
  return rows;
}

Json deviation_spec(const std::string& title, const std::string& y_title, const Json& rows) {
  Json spec = {{"$schema", "https://vega.github.io/schema/vega/v5.json"},
               {"width", 760},
               {"height", 360},
               {"padding", 5},
               {"title", {{"text", title}, {"anchor", "start"}, {"fontSize", 13}}},
               {"data", {{{"name", "rows"}, {"values", rows}}}}};
  spec["scales"] = {
      {{"name", "x"},
       {"type", "log"},
       {"domain", {{"data", "rows"}, {"field", "tau"}}},
       {"range", "width"},
       {"nice", true}},
      {{"name", "y"},
       {"type", "log"},
       {"domain", {{"fields", {{{"data", "rows"}, {"field", "lo"}}, {{"data", "rows"}, {"field", "hi"}}}}}},
       {"range", "height"},
       {"nice", true}},
      {{"name", "color"},
       {"type", "ordinal"},
       {"domain", {{"data", "rows"}, {"field", "kind"}}},
       {"range", "category"}}};
  spec["axes"] = {{{"orient", "bottom"}, {"scale", "x"}, {"title", "tau [s]"}, {"grid", true}, {"gridOpacity", 0.35}},
                  {{"orient", "left"},
                   {"scale", "y"},
                   {"title", y_title},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"format", ".2~e"}}};
  spec["legends"] = {{{"stroke", "color"}, {"title", "deviation"}, {"orient", "right"}, {"symbolType", "stroke"}}};
  const Json series = {{"facet", {{"name", "series"}, {"data", "rows"}, {"groupby", {"kind"}}}}};
  const Json band = {{"x", {{"scale", "x"}, {"field", "tau"}}},
                     {"y", {{"scale", "y"}, {"field", "lo"}}},
                     {"y2", {{"scale", "y"}, {"field", "hi"}}},
                     {"fill", {{"scale", "color"}, {"field", "kind"}}},
                     {"fillOpacity", {{"value", 0.15}}}};
  const Json line = {{"x", {{"scale", "x"}, {"field", "tau"}}},
                     {"y", {{"scale", "y"}, {"field", "v"}}},
                     {"stroke", {{"scale", "color"}, {"field", "kind"}}},
                     {"strokeWidth", {{"value", 2}}}};
  Json group_marks = Json::array();
  group_marks.push_back({{"type", "area"}, {"from", {{"data", "series"}}}, {"encode", {{"update", band}}}});
  group_marks.push_back({{"type", "line"}, {"from", {{"data", "series"}}}, {"encode", {{"update", line}}}});
  spec["marks"] = Json::array();
  spec["marks"].push_back({{"type", "group"}, {"from", series}, {"marks", std::move(group_marks)}});
  const std::string tip =
      "{'deviation': datum.kind, 'tau [s]': format(datum.tau, '.4~g'), 'value': format(datum.v, '.5~e'), "
      "'interval': format(datum.lo, '.4~e') + ' .. ' + format(datum.hi, '.4~e'), 'edf': datum.edf == null ? '-' : "
      "format(datum.edf, '.4~g'), 'noise': datum.noise}";
  const Json points = {{"x", {{"scale", "x"}, {"field", "tau"}}},
                       {"y", {{"scale", "y"}, {"field", "v"}}},
                       {"fill", {{"scale", "color"}, {"field", "kind"}}},
                       {"size", {{"value", 30}}},
                       {"tooltip", {{"signal", tip}}}};
  spec["marks"].push_back({{"type", "symbol"}, {"from", {{"data", "rows"}}}, {"encode", {{"update", points}}}});
  return spec;
}

// The unit of a kind's values: the data's (`unit`), the phase's for the time deviations.
std::string kind_unit(stability::DeviationKind kind, const std::string& unit) {
  return stability::in_time_units(kind) ? "(" + unit + ")*s" : unit;
}

// A table cell: the value, under it its interval [low, high] (where the kind has one) and
// the noise its degrees of freedom assumed, each on its own line (HTML).
std::string deviation_cell(const pipeline::StabilityColumn& c, std::size_t d, std::size_t i) {
  const stability::DeviationIntervals& ci = c.intervals[d];
  std::string cell = html_escape(g(c.deviations[d].value[i]));
  if (std::isfinite(ci.low[i]))
    cell += "<br><small>[" + html_escape(g(ci.low[i])) + ",&nbsp;" + html_escape(g(ci.high[i])) + "]</small>";
  return cell + "<br><small>" + html_escape(stability::noise_name(ci.noise[i].alpha)) + "</small>";
}

// Every value with its interval and noise, one row per averaging time, one column per kind
// (headed by its unit: `unit` the data's).
std::string deviation_table(const pipeline::StabilityColumn& c, const std::string& unit) {
  std::map<double, std::vector<std::string>> rows;
  for (std::size_t d = 0; d < c.deviations.size(); ++d)
    for (std::size_t i = 0; i < c.deviations[d].m.size(); ++i) {
      auto& row = rows[c.deviations[d].tau[i]];
      row.resize(c.deviations.size(), "-");
      row[d] = deviation_cell(c, d, i);
    }
  std::ostringstream t;
  t << "<table><tr><th>tau [s]</th>";
  for (const stability::DeviationCurve& d : c.deviations)
    t << "<th>" << stability::deviation_name(d.kind) << "<br><small>[" << html_escape(kind_unit(d.kind, unit))
      << "]</small></th>";
  t << "</tr>\n";
  for (auto& [tau, cells] : rows) {
    cells.resize(c.deviations.size(), "-");
    t << "<tr><td class=\"num\">" << g(tau, 6) << "</td>";
    for (const std::string& cell : cells) t << "<td class=\"num\">" << cell << "</td>";
    t << "</tr>\n";
  }
  t << "</table>\n";
  return t.str();
}

// How the study read the column: the record's data kind, tau0, the phase points.
std::string study_facts(const io::SignalSet& set, const pipeline::StabilityStudy& study) {
  return "read as " + html_escape(io::data_kind_name(set.data)) + " &middot; tau0 = " + html_escape(g(study.tau0, 6)) +
         " s &middot; " + std::to_string(study.phase_points) + " phase points";
}

// What the bands and [low, high] are: the interval's confidence, its quantiles, its noise.
std::string interval_note(const pipeline::StabilityStudyOptions& options) {
  return "Bands and [low, high]: the " + html_escape(g(100.0 * options.intervals.confidence, 4)) +
         "% chi-square interval (" + html_escape(stability::interval_method_name(options.intervals.method)) +
         " quantiles) from the equivalent degrees of freedom of the " +
         (options.intervals.noise_alpha
              ? "noise given (alpha " + std::to_string(*options.intervals.noise_alpha) + ", " +
                    html_escape(stability::noise_name(*options.intervals.noise_alpha)) + ")"
              : std::string("noise identified at each tau (lag-1 autocorrelation; B1 and R(n) on fewer than 30 "
                            "points)")) +
         " (docs/stability.md).";
}

// Column k's section: its heading, `intro` (HTML), the deviations in the data's unit and
// those in the phase's on a plot each, and the table. The report's and the web app's.
std::string column_section(const pipeline::StabilityColumn& c, std::size_t k, const std::string& unit,
                           const std::string& intro, detail::Plots& plots) {
  const std::string id = "plot-" + std::to_string(k + 1);
  std::ostringstream body;
  body << "<section class=\"column\" id=\"stability-" << k + 1 << "\">\n<h2>" << html_escape(c.name) << "</h2>\n"
       << intro;
  const Json rows = deviation_rows(c, false), time_rows = deviation_rows(c, true);
  if (!rows.empty())
    body << plots.add(id + "-stability", "stability",
                      deviation_spec(c.name + ": deviations", "deviation [" + unit + "]", rows));
  if (!time_rows.empty())
    body << plots.add(id + "-stability-time", "stability-time",
                      deviation_spec(c.name + ": time deviations", "deviation [(" + unit + ")*s]", time_rows));
  body << deviation_table(c, unit) << "</section>\n";
  return body.str();
}

std::string unit_of(const std::vector<std::string>& units, std::size_t k) {
  return k < units.size() && !units[k].empty() ? units[k] : "U";
}

}  // namespace

std::string render_stability_html(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                  const pipeline::StabilityStudyOptions& options,
                                  const std::vector<std::string>& units) {
  const std::string vega = detail::vega_script();
  const std::string title = "gmwm stability: " + set.path;
  detail::Plots plots;
  std::ostringstream body;
  body << "<header>\n<h1>" << html_escape(title) << "</h1>\n<p>gmwm " << html_escape(version())
       << " &middot; command <code>stability</code> &middot; " << study_facts(set, study) << "</p>\n<p>"
       << interval_note(options) << "</p>\n</header>\n<main>\n"
       << "<div id=\"gmwm-errors\" class=\"errors\" hidden></div>\n<div id=\"gmwm-warnings\" class=\"warnings\" "
          "hidden></div>\n"
       << detail::kErrorCapture;
  for (std::size_t k = 0; k < study.columns.size(); ++k)
    body << column_section(study.columns[k], k, unit_of(units, k), "", plots);
  body << "</main>\n<footer>Plots: Vega 5 (Debian libjs-vega), inlined; the file needs no network.</footer>\n";
  return detail::html_page(title, body.str(), plots, vega);
}

HtmlFragment render_stability_fragment(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                       const pipeline::StabilityStudyOptions& options,
                                       const std::vector<std::string>& units, std::size_t column) {
  const pipeline::StabilityColumn& c = study.columns.at(column);
  detail::Plots plots;
  HtmlFragment f;
  f.html = column_section(c, column, unit_of(units, column),
                          "<p>" + study_facts(set, study) + "</p>\n<p>" + interval_note(options) + "</p>\n", plots);
  for (const Json& entry : plots.specs) f.plots.push_back(entry);
  return f;
}

}  // namespace gmwm::report
