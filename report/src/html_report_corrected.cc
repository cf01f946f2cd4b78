// The HTML report's "what to change" section of `gmwm gap` (docs/gap.md, "The corrected
// configuration"): the same tables the terminal prints, every user string escaped.
#include <cmath>
#include <sstream>
#include <string>

#include "gmwm/engine/physical.h"
#include "html_report_detail.h"

namespace gmwm::report::detail {

namespace {

std::string arrow3(const std::string& a, const std::string& b, const std::string& c) {
  return a + " -> " + b + " -> " + c;
}

// The data unit of the report's column `name` ("U" when not declared or not found).
std::string unit_of(const ReportData& data, const std::string& name) {
  for (const ReportColumn& c : data.columns)
    if (c.name == name) return data_unit(c);
  return "U";
}

}  // namespace

std::string corrected_section(const pipeline::CorrectedConfig& c, const ReportData& data) {
  std::ostringstream os;
  os << "<section class=\"column\" id=\"what-to-change\">\n<h2>what to change (" << html_escape(c.format)
     << ")</h2>\n<p class=\"facts\">The baseline's own format with every figure the diagnosis' final model gives it; "
        "<code>gmwm gap ... --corrected PATH</code> writes the file below.</p>\n";
  if (c.format != "model") {
    os << "<table class=\"changes\">\n<caption>fields, in the format's own units</caption>\n"
       << th_row({"field", "input", "corrected", "unit", "changed"});
    for (const pipeline::ConfigChange& ch : c.changes)
      os << "<tr>" << td(ch.field) << td(std::isfinite(ch.input) ? num(ch.input, 4) : "-", "num")
         << td(std::isfinite(ch.corrected) ? num(ch.corrected, 4) : "-", "num") << td(ch.unit)
         << td(ch.changed ? "yes" : "") << "</tr>\n";
    os << "</table>\n";
  }
  const bool nav = !data.columns.empty() && data.columns.front().freq_known;
  std::vector<std::string> head{"column", "levels outside (input -> file -> full)",
                                "objective (input -> file -> full)"};
  if (nav) head.push_back("integrated error after 60 s (input -> file -> full)");
  os << "<table class=\"gap-left\">\n<caption>the gap left with the input, with the corrected file and with the full "
        "model</caption>\n"
     << th_row(head);
  for (const pipeline::CorrectedColumn& col : c.columns) {
    os << "<tr>" << td(col.name)
       << td(arrow3(std::to_string(col.before.levels_outside), std::to_string(col.with_config.levels_outside),
                    std::to_string(col.with_full.levels_outside)),
             "num")
       << td(arrow3(num(col.before.objective, 3), num(col.with_config.objective, 3), num(col.with_full.objective, 3)),
             "num");
    if (nav)
      os << td(arrow3(num(col.before.navigation_rms, 3), num(col.with_config.navigation_rms, 3),
                      num(col.with_full.navigation_rms, 3)) +
                   " " + render_unit("U*s", unit_of(data, col.name)) + " RMS",
               "num");
    os << "</tr>\n";
  }
  os << "</table>\n";
  bool any = false;
  for (const pipeline::CorrectedColumn& col : c.columns)
    for (const std::string& x : col.warnings) {
      if (!any) os << "<ul class=\"facts\">\n";
      any = true;
      os << "<li class=\"warn\">warning, " << html_escape(col.name) << ": " << html_escape(x) << "</li>\n";
    }
  for (const pipeline::CorrectedColumn& col : c.columns)
    if (!col.why.empty()) {
      if (!any) os << "<ul class=\"facts\">\n";
      any = true;
      os << "<li>kept, " << html_escape(col.name) << ": " << html_escape(col.why) << "</li>\n";
    }
  for (const pipeline::CorrectedColumn& col : c.columns)
    for (const std::string& x : col.not_expressible) {
      if (!any) os << "<ul class=\"facts\">\n";
      any = true;
      os << "<li>cannot express, " << html_escape(col.name) << ": " << html_escape(x) << "</li>\n";
    }
  if (any) os << "</ul>\n";
  os << "<details><summary>the corrected file</summary>\n<pre>" << html_escape(c.content) << "</pre>\n</details>\n"
     << "</section>\n";
  return os.str();
}

}  // namespace gmwm::report::detail
