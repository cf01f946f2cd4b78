// The navigation study's JSON, terminal summary and HTML report (nav_output.h).
#include "gmwm/report/nav_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "gmwm/engine/error.h"
#include "html_report_detail.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::report {

namespace {

using detail::html_escape;

// The terminal's width (docs: every table fits 100 columns) and the label column's share.
constexpr std::size_t kTerminalWidth = 100;
constexpr std::size_t kLabelWidth = 28;

std::string g(double x, int digits = 4) { return significant(x, digits, NonFinite::kDash); }

std::string scenario_line(const pipeline::NavStudy& s, double imu_rate) {
  const nav::Scenario& c = s.scenario;
  std::string out = std::string(nav::to_string(c.trajectory)) + ", " + g(c.horizon) + " s at " + g(imu_rate) + " Hz, ";
  if (c.fix_rate > 0.0) {
    out += "position fixes at " + g(c.fix_rate) + " Hz (" + g(c.fix_sigma) + " m)";
    for (const nav::Outage& o : c.outages) out += ", outage " + g(o.start) + "-" + g(o.end) + " s";
  } else {
    out += "no position fix (free inertial)";
  }
  if (c.judge_from > 0.0) out += "; NEES judged from " + g(c.judge_from) + " s";
  return out;
}

Json scenario_json(const nav::Scenario& c, double imu_rate) {
  Json outages = Json::array();
  for (const nav::Outage& o : c.outages) outages.push_back({json_number(o.start), json_number(o.end)});
  return {{"trajectory", nav::to_string(c.trajectory)},
          {"imu_rate", json_number(imu_rate)},
          {"horizon", json_number(c.horizon)},
          {"fix_rate", json_number(c.fix_rate)},
          {"fix_sigma", json_number(c.fix_sigma)},
          {"outages", outages},
          {"gravity", json_number(c.gravity)},
          {"initial",
           {{"position", json_number(c.initial_position)},
            {"velocity", json_number(c.initial_velocity)},
            {"attitude", json_number(c.initial_attitude)}}},
          {"output_interval", json_number(c.output_interval)},
          {"judge_from", json_number(c.judge_from)}};
}

Json numbers(const std::vector<double>& v, double scale = 1.0) {
  Json a = Json::array();
  for (double x : v) a.push_back(json_number(x * scale));
  return a;
}

double largest(const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); }

}  // namespace

std::size_t summary_index(const pipeline::NavStudy& study, const nav::FilterErrors& f) {
  if (f.time.empty()) return 0;
  // The last outage ending inside the horizon: its last output time before the fix that
  // ends it (the fix at `end` already pulls the error back).
  double end = -1.0;
  for (const nav::Outage& o : study.scenario.outages)
    if (o.end <= f.time.back() + 1e-9 && o.end > end) end = o.end;
  if (end < 0.0) return f.time.size() - 1;
  std::size_t k = 0;
  while (k + 1 < f.time.size() && f.time[k + 1] < end - 1e-9) ++k;
  return k;
}

Json nav_document(const pipeline::NavStudy& study) {
  Json doc = json_document("nav");
  doc["scenario"] = scenario_json(study.scenario, study.exact.imu_rate);
  doc["truth"] = {{"source", study.truth.source}, {"models", study.truth.lines}};
  Json filters = Json::array();
  for (std::size_t i = 0; i < study.exact.filters.size(); ++i) {
    const nav::FilterErrors& f = study.exact.filters[i];
    const std::size_t k = summary_index(study, f);
    Json j = {{"label", f.label},
              {"source", study.filters[i].source},
              {"models", study.filters[i].lines},
              {"notes", f.notes},
              {"verdict", nav::to_string(f.verdict)},
              {"nees_inside", json_number(f.nees_inside)},
              {"nees_above", json_number(f.nees_above)},
              {"nees_band", {json_number(f.nees_low), json_number(f.nees_high)}}};
    j["summary"] = {{"time", json_number(f.time[k])},
                    {"position_rms", json_number(f.position_rms[k])},
                    {"position_3sigma", json_number(3.0 * f.position_claimed[k])},
                    {"velocity_rms", json_number(f.velocity_rms[k])},
                    {"velocity_3sigma", json_number(3.0 * f.velocity_claimed[k])},
                    {"attitude_rms", json_number(f.attitude_rms[k])},
                    {"attitude_3sigma", json_number(3.0 * f.attitude_claimed[k])},
                    {"nees", json_number(f.nees[k])},
                    {"largest_position_rms", json_number(largest(f.position_rms))},
                    {"largest_nees", json_number(largest(f.nees))}};
    j["curves"] = {{"time", numbers(f.time)},
                   {"position_rms", numbers(f.position_rms)},
                   {"position_3sigma", numbers(f.position_claimed, 3.0)},
                   {"velocity_rms", numbers(f.velocity_rms)},
                   {"velocity_3sigma", numbers(f.velocity_claimed, 3.0)},
                   {"attitude_rms", numbers(f.attitude_rms)},
                   {"attitude_3sigma", numbers(f.attitude_claimed, 3.0)},
                   {"nees", numbers(f.nees)}};
    if (study.sampled) {
      const nav::FilterErrors& m = study.sampled->filters[i];
      j["monte_carlo"] = {{"position_rms", numbers(m.position_rms)},
                          {"velocity_rms", numbers(m.velocity_rms)},
                          {"attitude_rms", numbers(m.attitude_rms)},
                          {"nees", numbers(m.nees)},
                          {"verdict", nav::to_string(m.verdict)}};
    } else {
      j["monte_carlo"] = nullptr;
    }
    filters.push_back(std::move(j));
  }
  doc["filters"] = std::move(filters);
  doc["monte_carlo"] = study.sampled ? Json{{"runs", study.monte_carlo_runs}, {"seed", study.seed}} : Json(nullptr);
  doc["units"] = {{"position", "m"}, {"velocity", "m/s"}, {"attitude", "rad"}, {"time", "s"}};
  return doc;
}

std::string nav_terminal(const pipeline::NavStudy& study) {
  std::ostringstream os;
  // Labels, paths and notes come from the user or from files: printable, one line each.
  auto line = [&](const std::string& s) { os << printable_line(s).substr(0, kTerminalWidth) << '\n'; };
  line("truth: " + study.truth.source);
  line("scenario: " + scenario_line(study, study.exact.imu_rate));
  if (study.exact.filters.empty()) return os.str();
  const double at = study.exact.filters.front().time[summary_index(study, study.exact.filters.front())];
  char head[160];
  std::snprintf(head, sizeof head, "%-*s %12s %12s %10s %9s  %s", static_cast<int>(kLabelWidth), "filter model",
                ("pos@" + g(at) + "s").c_str(), "its 3-sigma", "max pos", "NEES ok", "verdict");
  line(head);
  std::vector<std::string> long_labels;
  for (const nav::FilterErrors& f : study.exact.filters) {
    const std::size_t k = summary_index(study, f);
    std::string label = printable_line(f.label);
    if (label.size() > kLabelWidth) {
      long_labels.push_back(label);
      label = "[" + std::to_string(long_labels.size()) + "] " + label.substr(0, kLabelWidth - 8) + "...";
    }
    char row[200];
    std::snprintf(row, sizeof row, "%-*s %10s m %10s m %8s m %8s%%  %s", static_cast<int>(kLabelWidth), label.c_str(),
                  g(f.position_rms[k]).c_str(), g(3.0 * f.position_claimed[k]).c_str(),
                  g(largest(f.position_rms)).c_str(), g(100.0 * f.nees_inside, 3).c_str(), nav::to_string(f.verdict));
    line(row);
  }
  for (std::size_t i = 0; i < long_labels.size(); ++i) line("[" + std::to_string(i + 1) + "] " + long_labels[i]);
  line("pos: position error (RMS over 3 axes) where the outage ends; its 3-sigma: what the filter claims.");
  line("NEES ok: share of output times with the expected NEES in the 95% band of a " + std::to_string(nav::kNeesRuns) +
       "-run mean;");
  line("  consistent when >= 95%, else optimistic (claims less error than it makes) or pessimistic.");
  if (study.sampled)
    line("Monte Carlo: " + std::to_string(study.monte_carlo_runs) + " runs (seed " + std::to_string(study.seed) +
         "), in the JSON and the report beside the exact curves.");
  return os.str();
}

namespace {

// A plot of one quantity against time: per filter its RMS (solid), its own 3-sigma
// (dashed) and the Monte Carlo's RMS (points); one colour per filter across the plots.
constexpr std::array<const char*, 10> kColours = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                  "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

Json curve_spec(const std::string& title, const std::string& y_title, const Json& rows, const Json& filters, bool band,
                const std::array<double, 2>& nees_band, double judge_from) {
  Json range = Json::array();
  for (std::size_t i = 0; i < filters.size(); ++i) range.push_back(kColours[i % kColours.size()]);
  Json spec = {{"$schema", "https://vega.github.io/schema/vega/v5.json"},
               {"width", 760},
               {"height", 300},
               {"padding", 5},
               {"title", {{"text", title}, {"anchor", "start"}, {"fontSize", 13}}}};
  spec["data"] = {{{"name", "rows"}, {"values", rows}},
                  {{"name", "lines"},
                   {"source", "rows"},
                   {"transform", {{{"type", "filter"}, {"expr", "datum.kind != 'Monte Carlo'"}}}}},
                  {{"name", "points"},
                   {"source", "rows"},
                   {"transform", {{{"type", "filter"}, {"expr", "datum.kind == 'Monte Carlo'"}}}}}};
  spec["scales"] = {{{"name", "x"},
                     {"type", "linear"},
                     {"domain", {{"data", "rows"}, {"field", "t"}}},
                     {"range", "width"},
                     {"zero", false}},
                    {{"name", "y"},
                     {"type", "log"},
                     {"domain", {{"data", "rows"}, {"field", "v"}}},
                     {"range", "height"},
                     {"nice", true}},
                    {{"name", "color"}, {"type", "ordinal"}, {"domain", filters}, {"range", range}},
                    {{"name", "dash"},
                     {"type", "ordinal"},
                     {"domain", band ? Json{"NEES"} : Json{"RMS", "3-sigma claimed"}},
                     {"range", band ? Json{Json{1, 0}} : Json{Json{1, 0}, Json{6, 4}}}}};
  spec["axes"] = {{{"orient", "bottom"}, {"scale", "x"}, {"title", "time [s]"}, {"grid", true}, {"gridOpacity", 0.35}},
                  {{"orient", "left"},
                   {"scale", "y"},
                   {"title", y_title},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"format", ".2~e"}}};
  spec["legends"] = {{{"stroke", "color"},
                      {"title", "filter model"},
                      {"orient", "right"},
                      {"symbolType", "stroke"},
                      {"labelLimit", 260}},
                     {{"strokeDash", "dash"}, {"title", "curve"}, {"orient", "right"}, {"symbolType", "stroke"}}};
  Json marks = Json::array();
  if (band) {
    Json enc = {{"x", {{"value", 0}}},
                {"x2", {{"signal", "width"}}},
                {"y", {{"scale", "y"}, {"value", nees_band[1]}}},
                {"y2", {{"scale", "y"}, {"value", nees_band[0]}}},
                {"fill", {{"value", "#9a9a9a"}}},
                {"fillOpacity", {{"value", 0.3}}}};
    marks.push_back({{"type", "rect"}, {"encode", {{"update", enc}}}});
  }
  if (judge_from > 0.0) {  // where the NEES starts to be judged: a dotted rule
    Json enc = {{"x", {{"scale", "x"}, {"value", judge_from}}},
                {"y", {{"value", 0}}},
                {"y2", {{"signal", "height"}}},
                {"stroke", {{"value", "#57606a"}}},
                {"strokeDash", {{"value", {2, 3}}}},
                {"tooltip", {{"value", "NEES judged from here"}}}};
    marks.push_back({{"type", "rule"}, {"encode", {{"update", enc}}}});
  }
  const std::string tip =
      "{'filter': datum.filter, 'curve': datum.kind, 't [s]': format(datum.t, '.4~g'), 'value': format(datum.v, "
      "'.4~e')}";
  Json line = {{"x", {{"scale", "x"}, {"field", "t"}}},
               {"y", {{"scale", "y"}, {"field", "v"}}},
               {"stroke", {{"scale", "color"}, {"field", "filter"}}},
               {"strokeDash", {{"scale", "dash"}, {"field", "kind"}}},
               {"strokeWidth", {{"value", 2}}}};
  marks.push_back({{"type", "group"},
                   {"from", {{"facet", {{"name", "series"}, {"data", "lines"}, {"groupby", {"filter", "kind"}}}}}},
                   {"marks",
                    {{{"type", "line"},
                      {"from", {{"data", "series"}}},
                      {"sort", {{"field", "datum.t"}}},
                      {"encode", {{"update", line}}}}}}});
  Json hover = {{"x", {{"scale", "x"}, {"field", "t"}}},
                {"y", {{"scale", "y"}, {"field", "v"}}},
                {"fill", {{"scale", "color"}, {"field", "filter"}}},
                {"fillOpacity", {{"value", 0}}},
                {"size", {{"value", 40}}},
                {"tooltip", {{"signal", tip}}}};  // invisible: the curve's hover targets
  marks.push_back({{"type", "symbol"}, {"from", {{"data", "lines"}}}, {"encode", {{"update", hover}}}});
  Json mc = {{"x", {{"scale", "x"}, {"field", "t"}}},
             {"y", {{"scale", "y"}, {"field", "v"}}},
             {"stroke", {{"scale", "color"}, {"field", "filter"}}},
             {"shape", {{"value", "circle"}}},
             {"size", {{"value", 24}}},
             {"tooltip", {{"signal", tip}}}};
  marks.push_back({{"type", "symbol"}, {"from", {{"data", "points"}}}, {"encode", {{"update", mc}}}});
  spec["marks"] = std::move(marks);
  return spec;
}

constexpr std::size_t kMonteCarloPoints = 60;

// Rows {filter, kind, t, v} of one quantity (positive values only: a log axis).
Json quantity_rows(const pipeline::NavStudy& s, const std::vector<double> nav::FilterErrors::*rms,
                   const std::vector<double> nav::FilterErrors::*claimed, double scale) {
  Json rows = Json::array();
  auto add = [&](const std::string& filter, const char* kind, const std::vector<double>& t,
                 const std::vector<double>& v, double k) {
    for (std::size_t i = 0; i < t.size() && i < v.size(); ++i)
      if (v[i] * k > 0.0 && std::isfinite(v[i]))
        rows.push_back({{"filter", filter}, {"kind", kind}, {"t", t[i]}, {"v", v[i] * k * scale}});
  };
  for (std::size_t i = 0; i < s.exact.filters.size(); ++i) {
    const nav::FilterErrors& f = s.exact.filters[i];
    if (claimed) {
      add(f.label, "RMS", f.time, f.*rms, 1.0);
      add(f.label, "3-sigma claimed", f.time, f.*claimed, 3.0);
    } else {
      add(f.label, "NEES", f.time, f.*rms, 1.0);
    }
    if (s.sampled) {
      // About kMonteCarloPoints points per curve: every output time would hide the curves.
      const nav::FilterErrors& m = s.sampled->filters[i];
      const std::size_t every = std::max<std::size_t>(1, m.time.size() / kMonteCarloPoints);
      std::vector<double> t, v;
      for (std::size_t k = 0; k < m.time.size(); k += every) {
        t.push_back(m.time[k]);
        v.push_back((m.*rms)[k]);
      }
      add(f.label, "Monte Carlo", t, v, 1.0);
    }
  }
  return rows;
}

}  // namespace

std::string render_nav_html(const pipeline::NavStudy& study) {
  const std::string vega = detail::vega_script();
  const std::string title = "gmwm nav: " + study.truth.source;
  detail::Plots plots;
  Json labels = Json::array();
  for (const auto& f : study.exact.filters) labels.push_back(f.label);
  std::ostringstream body;
  body
      << "<header>\n<h1>" << html_escape(title) << "</h1>\n<p>gmwm " << html_escape(version())
      << " &middot; command <code>nav</code> &middot; " << html_escape(scenario_line(study, study.exact.imu_rate))
      << "</p>\n<p>Errors of an INS aided by position fixes on a flat, non-rotating Earth when the IMU's errors follow "
         "the truth model and the filter assumes each filter model: exact covariance analysis of the mismatched filter"
      << (study.sampled ? " (points: " + std::to_string(study.monte_carlo_runs) + " Monte-Carlo runs)" : std::string())
      << ". RMS = root of the trace over the three axes; 3-sigma = the filter's own claim.</p>\n</header>\n<main>\n"
      << "<div id=\"gmwm-errors\" class=\"errors\" hidden></div>\n<div id=\"gmwm-warnings\" class=\"warnings\" "
         "hidden></div>\n"
      << detail::kErrorCapture;
  body << "<section class=\"column\" id=\"nav-summary\">\n<h2>verdicts</h2>\n<table><tr><th>filter "
          "model</th><th>position RMS at "
       << html_escape(g(study.exact.filters.front().time[summary_index(study, study.exact.filters.front())]))
       << " s [m]</th><th>its 3-sigma [m]</th><th>largest position RMS [m]</th><th>NEES in "
          "band</th><th>verdict</th></tr>\n";
  for (const nav::FilterErrors& f : study.exact.filters) {
    const std::size_t k = summary_index(study, f);
    body << "<tr><td>" << html_escape(f.label) << "</td><td class=\"num\">" << g(f.position_rms[k])
         << "</td><td class=\"num\">" << g(3.0 * f.position_claimed[k]) << "</td><td class=\"num\">"
         << g(largest(f.position_rms)) << "</td><td class=\"num\">" << g(100.0 * f.nees_inside, 3) << "%</td><td>"
         << nav::to_string(f.verdict) << "</td></tr>\n";
  }
  body << "</table>\n</section>\n<section class=\"column\" id=\"nav-curves\">\n<h2>errors against time</h2>\n";
  const std::array<double, 2> band = {study.exact.filters.front().nees_low, study.exact.filters.front().nees_high};
  body << plots.add(
      "plot-nav-position", "nav-position",
      curve_spec("position error", "position error [m]",
                 quantity_rows(study, &nav::FilterErrors::position_rms, &nav::FilterErrors::position_claimed, 1.0),
                 labels, false, band, study.scenario.judge_from));
  body << plots.add(
      "plot-nav-velocity", "nav-velocity",
      curve_spec("velocity error", "velocity error [m/s]",
                 quantity_rows(study, &nav::FilterErrors::velocity_rms, &nav::FilterErrors::velocity_claimed, 1.0),
                 labels, false, band, study.scenario.judge_from));
  constexpr double kDegreesPerRadian = 57.29577951308232;
  body << plots.add("plot-nav-attitude", "nav-attitude",
                    curve_spec("attitude error", "attitude error [deg]",
                               quantity_rows(study, &nav::FilterErrors::attitude_rms,
                                             &nav::FilterErrors::attitude_claimed, kDegreesPerRadian),
                               labels, false, band, study.scenario.judge_from));
  body << plots.add(
      "plot-nav-nees", "nav-nees",
      curve_spec("NEES (9 states; grey: the 95% band of a mean over " + std::to_string(nav::kNeesRuns) + " runs)",
                 "expected NEES", quantity_rows(study, &nav::FilterErrors::nees, nullptr, 1.0), labels, true, band,
                 study.scenario.judge_from));
  body << "</section>\n<section class=\"column\" id=\"nav-models\">\n<h2>models</h2>\n<h3>truth: "
       << html_escape(study.truth.source) << "</h3>\n<ul>";
  for (const auto& l : study.truth.lines) body << "<li><code>" << html_escape(l) << "</code></li>";
  body << "</ul>\n";
  for (std::size_t i = 0; i < study.filters.size(); ++i) {
    body << "<h3>" << html_escape(study.exact.filters[i].label) << ": " << html_escape(study.filters[i].source)
         << "</h3>\n<ul>";
    for (const auto& l : study.filters[i].lines) body << "<li><code>" << html_escape(l) << "</code></li>";
    for (const auto& n : study.exact.filters[i].notes) body << "<li>" << html_escape(n) << "</li>";
    body << "</ul>\n";
  }
  body << "</section>\n</main>\n<footer>Plots: Vega 5 (Debian libjs-vega), inlined; the file needs no "
          "network.</footer>\n";
  return detail::html_page(title, body.str(), plots, vega);
}

}  // namespace gmwm::report
