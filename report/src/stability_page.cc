// The frequency-stability study's HTML report (stability_output.h): per column the chosen
// deviations on log-log axes with their intervals, one plot per unit (the data's; the phase's
// for the time deviations), and the table of every value with its interval and noise; with
// the three-cornered hat, per kind each column's separated deviation with its interval, on a
// plot and in a table.
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "gmwm/engine/number_text.h"
#include "gmwm/report/stability_output.h"
#include "html_report_detail.h"
#include "stability_detail.h"

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

// What a deviation plot draws as its series: the rows' field naming each (a kind, a column),
// the legend's title and the points' tooltip (a Vega expression of the row).
struct Series {
  std::string field, legend, tip;
};

const Series kKindSeries = {
    "kind", "deviation",
    "{'deviation': datum.kind, 'tau [s]': format(datum.tau, '.4~g'), 'value': format(datum.v, '.5~e'), "
    "'interval': format(datum.lo, '.4~e') + ' .. ' + format(datum.hi, '.4~e'), 'edf': datum.edf == null ? '-' : "
    "format(datum.edf, '.4~g'), 'noise': datum.noise}"};

// Log-log, one line per series with its interval as a band from lo to hi (where lo is null, an
// interval reaching 0: from the plot's floor), a point at each value with its tooltip; a row
// whose value is null (none there) breaks its line and band.
Json deviation_spec(const std::string& title, const std::string& y_title, const Json& rows, const Series& s) {
  Json spec = {
      {"$schema", "https://vega.github.io/schema/vega/v5.json"},
      {"width", 760},
      {"height", 360},
      {"padding", 5},
      {"title", {{"text", title}, {"anchor", "start"}, {"fontSize", 13}}},
      {"data",
       {{{"name", "rows"}, {"values", rows}},
        {{"name", "drawn"}, {"source", "rows"}, {"transform", {{{"type", "filter"}, {"expr", "isValid(datum.v)"}}}}}}}};
  spec["scales"] = {{{"name", "x"},
                     {"type", "log"},
                     {"domain", {{"data", "rows"}, {"field", "tau"}}},
                     {"range", "width"},
                     {"nice", true}},
                    {{"name", "y"},
                     {"type", "log"},
                     {"domain",
                      {{"fields",
                        {{{"data", "rows"}, {"field", "lo"}},
                         {{"data", "rows"}, {"field", "v"}},
                         {{"data", "rows"}, {"field", "hi"}}}}}},
                     {"range", "height"},
                     {"nice", true}},
                    {{"name", "color"},
                     {"type", "ordinal"},
                     {"domain", {{"data", "rows"}, {"field", s.field}}},
                     {"range", "category"}}};
  spec["axes"] = {{{"orient", "bottom"}, {"scale", "x"}, {"title", "tau [s]"}, {"grid", true}, {"gridOpacity", 0.35}},
                  {{"orient", "left"},
                   {"scale", "y"},
                   {"title", y_title},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"format", ".2~e"}}};
  spec["legends"] = {{{"stroke", "color"}, {"title", s.legend}, {"orient", "right"}, {"symbolType", "stroke"}}};
  const Json series = {{"facet", {{"name", "series"}, {"data", "rows"}, {"groupby", {s.field}}}}};
  const Json band = {
      {"x", {{"scale", "x"}, {"field", "tau"}}}, {"y", {{"signal", "datum.lo > 0 ? scale('y', datum.lo) : height"}}},
      {"y2", {{"scale", "y"}, {"field", "hi"}}}, {"fill", {{"scale", "color"}, {"field", s.field}}},
      {"fillOpacity", {{"value", 0.15}}},        {"defined", {{"signal", "isValid(datum.v)"}}}};
  const Json line = {{"x", {{"scale", "x"}, {"field", "tau"}}},
                     {"y", {{"scale", "y"}, {"field", "v"}}},
                     {"stroke", {{"scale", "color"}, {"field", s.field}}},
                     {"strokeWidth", {{"value", 2}}},
                     {"defined", {{"signal", "isValid(datum.v)"}}}};
  Json group_marks = Json::array();
  group_marks.push_back({{"type", "area"}, {"from", {{"data", "series"}}}, {"encode", {{"update", band}}}});
  group_marks.push_back({{"type", "line"}, {"from", {{"data", "series"}}}, {"encode", {{"update", line}}}});
  spec["marks"] = Json::array();
  spec["marks"].push_back({{"type", "group"}, {"from", series}, {"marks", std::move(group_marks)}});
  const Json points = {{"x", {{"scale", "x"}, {"field", "tau"}}},
                       {"y", {{"scale", "y"}, {"field", "v"}}},
                       {"fill", {{"scale", "color"}, {"field", s.field}}},
                       {"size", {{"value", 30}}},
                       {"tooltip", {{"signal", s.tip}}}};
  spec["marks"].push_back({{"type", "symbol"}, {"from", {{"data", "drawn"}}}, {"encode", {{"update", points}}}});
  return spec;
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
    t << "<th>" << stability::deviation_name(d.kind) << "<br><small>["
      << html_escape(detail::deviation_unit(d.kind, unit)) << "]</small></th>";
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
                      deviation_spec(c.name + ": deviations", "deviation [" + unit + "]", rows, kKindSeries));
  if (!time_rows.empty())
    body << plots.add(
        id + "-stability-time", "stability-time",
        deviation_spec(c.name + ": time deviations", "deviation [(" + unit + ")*s]", time_rows, kKindSeries));
  body << deviation_table(c, unit) << "</section>\n";
  return body.str();
}

std::string unit_of(const std::vector<std::string>& units, std::size_t k) {
  return k < units.size() && !units[k].empty() ? units[k] : "U";
}

const Series kSensorSeries = {
    "sensor", "column",
    "{'column': datum.sensor, 'tau [s]': format(datum.tau, '.4~g'), 'value': format(datum.v, '.5~e'), "
    "'interval': datum.high == null ? 'none' : (datum.low > 0 ? format(datum.low, '.4~e') : '0') + ' .. ' + "
    "format(datum.high, '.4~e'), 'edf': datum.edf == null ? '-' : format(datum.edf, '.4~g')}"};

// One kind's rows {sensor, tau, v, lo, hi, low, high, edf}: each column's separated deviation,
// v null where it has none (a negative variance: not drawn, its line broken there; a log axis
// has no 0 either); lo, hi the band's ends (the value where there is no interval; lo null
// where the interval reaches 0), low, high the interval's.
Json hat_rows(const pipeline::StabilityHat& hat, const stability::ThreeCorneredHat& k) {
  Json rows = Json::array();
  for (std::size_t s = 0; s < stability::kHatSensors; ++s) {
    const stability::HatSensor& h = k.sensors[s];
    for (std::size_t i = 0; i < k.m.size(); ++i) {
      if (!(h.value[i] > 0.0) || !std::isfinite(h.value[i])) {
        rows.push_back(
            {{"sensor", hat.sensors[s]}, {"tau", k.tau[i]}, {"v", nullptr}, {"lo", nullptr}, {"hi", nullptr}});
        continue;
      }
      const bool band = std::isfinite(h.high[i]);
      rows.push_back({{"sensor", hat.sensors[s]},
                      {"tau", k.tau[i]},
                      {"v", h.value[i]},
                      {"lo", !band            ? Json(h.value[i])
                             : h.low[i] > 0.0 ? Json(h.low[i])
                                              : Json(nullptr)},
                      {"hi", band ? h.high[i] : h.value[i]},
                      {"low", json_number(h.low[i])},
                      {"high", json_number(h.high[i])},
                      {"edf", json_number(k.edf[i])}});
    }
  }
  return rows;
}

// One kind's table: each averaging time's separated deviation of each column (or "[var V]")
// with its interval [low, high], and the pairs' smallest edf, which the intervals read.
std::string hat_table(const pipeline::StabilityHat& hat, const stability::ThreeCorneredHat& k,
                      const std::string& unit) {
  std::ostringstream t;
  t << "<table><tr><th>tau [s]</th>";
  for (const std::string& name : hat.sensors)
    t << "<th>" << html_escape(name) << "<br><small>" << stability::deviation_name(k.kind) << " ["
      << html_escape(detail::deviation_unit(k.kind, unit)) << "]</small></th>";
  t << "<th>edf</th></tr>\n";
  for (std::size_t i = 0; i < k.m.size(); ++i) {
    t << "<tr><td class=\"num\">" << g(k.tau[i], 6) << "</td>";
    for (const stability::HatSensor& h : k.sensors) {
      t << "<td class=\"num\">" << html_escape(detail::hat_value_text(h, i));
      if (std::isfinite(h.high[i]))
        t << "<br><small>[" << html_escape(g(h.low[i])) << ",&nbsp;" << html_escape(g(h.high[i])) << "]</small>";
      t << "</td>";
    }
    t << "<td class=\"num\">" << html_escape(g(k.edf[i], 4)) << "</td></tr>\n";
  }
  t << "</table>\n";
  return t.str();
}

// What the hat is and how its intervals are formed (stability/three_cornered_hat.h;
// docs/stability.md, "Three-cornered hat").
std::string hat_intro(const pipeline::StabilityHat& hat, double confidence) {
  std::string pairs;
  for (const pipeline::StabilityColumn& p : hat.pairs) pairs += (pairs.empty() ? "" : ", ") + html_escape(p.name);
  return "<p>" + html_escape(detail::hat_heading(hat)) + ". The columns, recorded together, give the differences " +
         pairs +
         ", free of whatever input they share; with independent noises a difference's variance is the sum of its two "
         "columns' at every tau, so each column's own is half its two pairs' less the third's (s_A^2 = (s_AB^2 + "
         "s_CA^2 - s_BC^2) / 2; Gray and Allan 1974, NIST SP 1065). A separated variance is unbiased, not always "
         "positive: a negative one is kept as computed and has no deviation (not drawn).</p>\n<p>Bands and [low, "
         "high]: " +
         html_escape(detail::hat_interval_words(confidence)) +
         " (E. B. Wilson 1927: the normal test inverted with the variance at the value tested, for Gaussian noises of "
         "one spectral shape); none where no variance &gt;= 0 fits or where edf &lt; 4 z^2, z the normal quantile of "
         "(1 + confidence) / 2 (docs/stability.md, &quot;Three-cornered hat&quot;). Where an interval reaches 0, its "
         "band reaches the plot's floor. The pairs' deviations are in the JSON (hat.pairs).</p>\n";
}

// The hat's section: what it is, then per kind a plot of the three columns' separated
// deviations with their bands and the table. The report's and the web app's.
std::string hat_section(const pipeline::StabilityHat& hat, const std::vector<std::string>& units,
                        detail::Plots& plots) {
  const std::string known = detail::hat_unit(units), unit = known.empty() ? "U" : known;
  std::ostringstream body;
  body << "<section class=\"column\" id=\"stability-hat\">\n<h2>three-cornered hat</h2>\n"
       << hat_intro(hat, hat.kinds.front().confidence);
  for (std::size_t d = 0; d < hat.kinds.size(); ++d) {
    const stability::ThreeCorneredHat& k = hat.kinds[d];
    const std::string kind(stability::deviation_name(k.kind));
    const Json rows = hat_rows(hat, k);
    if (std::any_of(rows.begin(), rows.end(), [](const Json& r) { return !r["v"].is_null(); }))
      body << plots.add("plot-hat-" + std::to_string(d + 1), "stability-hat",
                        deviation_spec("three-cornered hat: " + kind,
                                       kind + " [" + detail::deviation_unit(k.kind, unit) + "]", rows, kSensorSeries));
    body << hat_table(hat, k, unit);
  }
  if (detail::hat_has_negative(hat))
    body << "<p class=\"facts\">" << html_escape(detail::hat_negative_note()) << "</p>\n";
  body << "</section>\n";
  return body.str();
}

// Every column's section (the first with `intro` under its heading) and the hat's: the
// report's body and the web app's answer.
std::string study_sections(const pipeline::StabilityStudy& study, const std::vector<std::string>& units,
                           const std::string& intro, detail::Plots& plots) {
  std::string body;
  for (std::size_t k = 0; k < study.columns.size(); ++k)
    body += column_section(study.columns[k], k, unit_of(units, k), k == 0 ? intro : std::string(), plots);
  if (study.hat) body += hat_section(*study.hat, units, plots);
  return body;
}

// The study's facts and the intervals' rule, the web app's sections' intro (the report's header says them).
std::string fragment_intro(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                           const pipeline::StabilityStudyOptions& options) {
  return "<p>" + study_facts(set, study) + "</p>\n<p>" + interval_note(options) + "</p>\n";
}

HtmlFragment fragment_of(const std::string& html, const detail::Plots& plots) {
  HtmlFragment f;
  f.html = html;
  for (const Json& entry : plots.specs) f.plots.push_back(entry);
  return f;
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
       << detail::kErrorCapture << study_sections(study, units, "", plots)
       << "</main>\n<footer>Plots: Vega 5 (Debian libjs-vega), inlined; the file needs no network.</footer>\n";
  return detail::html_page(title, body.str(), plots, vega);
}

HtmlFragment render_stability_fragment(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                       const pipeline::StabilityStudyOptions& options,
                                       const std::vector<std::string>& units, std::size_t column) {
  const pipeline::StabilityColumn& c = study.columns.at(column);
  detail::Plots plots;
  const std::string html =
      column_section(c, column, unit_of(units, column), fragment_intro(set, study, options), plots);
  return fragment_of(html, plots);
}

HtmlFragment render_stability_fragment(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                       const pipeline::StabilityStudyOptions& options,
                                       const std::vector<std::string>& units) {
  detail::Plots plots;
  const std::string html = study_sections(study, units, fragment_intro(set, study, options), plots);
  return fragment_of(html, plots);
}

}  // namespace gmwm::report
