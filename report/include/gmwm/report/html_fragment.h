#pragma once
// One column of a report as an HTML fragment with its Vega specs, for a page that shows
// results one at a time (gmwm serve's web app, serve/): the same section, tables and plots
// as the HTML report (html_report.h) renders for that column, so that the app and the report
// never differ in what they show.
//
//   const gmwm::report::ReportData data = gmwm::report::fit_report_data(set, study, "AR1+WN", units, rate);
//   const gmwm::report::HtmlFragment f = gmwm::report::render_column_fragment(data, 0);
//   // f.html: <section class="column">... with <div class="gmwm-plot" data-plot="wv" id="plot-1-wv">
//   // f.plots: [{"id": "plot-1-wv", "kind": "wv", "spec": {...Vega 5...}}, ...]
//
// Every user string in `html` is HTML-escaped (html_report.h's escaping); the specs are
// JSON values, to be embedded with script_safe_json() when written into a page.

#include <cstddef>
#include <string>
#include <string_view>

#include "gmwm/report/html_report.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

struct HtmlFragment {
  std::string html;            ///< the column's <section>, plot containers included
  Json plots = Json::array();  ///< [{"id", "kind", "spec"}], in the order of the containers
};

/// The section of `data.columns[column]` (std::out_of_range beyond the columns). Plot ids
/// are "plot-<column+1>-<kind>" as in the report.
HtmlFragment render_column_fragment(const ReportData& data, std::size_t column);

/// The report's style sheet (CSS text), for a page that embeds fragments.
std::string report_style_sheet();

/// The inlined Vega 5 modules defining the global `vega` (script text, safe inside a
/// <script> element). Throws InputError when Vega cannot be read (vega_missing_reason()).
std::string vega_inline_script();

/// JSON text safe inside a <script> element ('<', '>', '&' escaped as \u003c, \u003e, \u0026).
std::string script_safe_json(const Json& j);

/// Text safe in HTML text and attribute values (& < > " ' escaped), as the report writes it.
std::string html_text(std::string_view s);

}  // namespace gmwm::report
