// The HTML report's page: header, per-column sections with their plots and tables, the
// embedded specs and the inlined Vega (html_report.h); and its atomic writer.

#include "gmwm/report/html_report.h"
#include "gmwm/report/html_fragment.h"
#include "gmwm/report/study_text.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <system_error>

#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "gmwm/io/output_set.h"
#include "html_report_detail.h"

namespace gmwm::report {

namespace {

using detail::html_escape;
using detail::kErrorCapture;
using detail::Plots;

std::string column_facts(const ReportColumn& c) {
  std::ostringstream os;
  os << "N = " << c.n;
  if (c.freq_known)
    os << ", " << html_escape(detail::num(c.freq, 6)) << " Hz ("
       << html_escape(detail::num(static_cast<double>(c.n) / c.freq, 4)) << " s)";
  else
    os << ", sampling rate unknown (tau in samples)";
  os << ", data unit " << (c.unit.empty() ? "not declared (U)" : html_escape(c.unit));
  if (c.replicates) {
    os << "; " << c.wvs.size() << " replicates (" << html_escape(c.replicates->estimator)
       << "), N and levels per replicate below";
    return os.str();
  }
  for (const auto& w : c.wvs) os << "; " << html_escape(detail::wv_label(w)) << ", " << w.levels() << " levels";
  return os.str();
}

// The goodness-of-fit level of the "rejected" lines: 5%, as everywhere a fit is called
// rejected (rejection_summary's default, engine/fit.h; the JSON's "rejected").
constexpr double kRejectionLevel = 0.05;

// The fit-quality sentences (rejection with the worst scales, degeneracy), highlighted.
std::string quality_lines(const FitResult& f, const ReportColumn& c, bool all_rejected, const std::string& full_model) {
  std::ostringstream os;
  const std::vector<int> none;
  const std::vector<int>& stacked = c.replicates && c.replicates->joint ? c.replicates->joint->levels : none;
  const std::string why = rejection_summary(f, c.freq, c.freq_known, kRejectionLevel, stacked);
  if (all_rejected)
    os << "<p class=\"quality\"><b>every candidate is rejected at 5%</b>: no sub-model of " << html_escape(full_model)
       << " describes these data"
       << (why.empty() ? "" : "; the chosen " + html_escape(f.model.to_string()) + " is " + html_escape(why))
       << "</p>\n";
  else if (!why.empty())
    os << "<p class=\"quality\"><b>" << html_escape(f.model.to_string()) << " is " << html_escape(why) << "</b></p>\n";
  if (const std::string d = degeneracy_summary(f); !d.empty())
    os << "<p class=\"quality\">" << html_escape(d) << "</p>\n";
  return os.str();
}

// Where a robust WV's spike screen replaced samples: a strip over the record with a mark at
// each range (hover: its samples and time), under the summary the terminal prints.
std::string screening_strip(const ReportColumn& c, const WaveletVariance& w) {
  // The ranges are positions on the WV's grid (observed and missing samples together).
  const std::int64_t grid = w.n > 0 ? w.n : c.n;
  const std::string summary = screening_summary(w, grid, c.freq, c.freq_known);
  if (summary.empty()) return {};
  constexpr double kWidth = 1000.0, kHeight = 18.0;
  std::ostringstream os;
  std::string lines = html_escape(summary);
  for (std::size_t p = lines.find('\n'); p != std::string::npos && p + 1 < lines.size(); p = lines.find('\n', p + 5))
    lines.replace(p, 1, "<br>");
  const std::string end =
      c.freq_known ? detail::num(static_cast<double>(grid) / c.freq, 6) + " s" : std::to_string(grid) + " samples";
  os << "<div class=\"screening\"><p class=\"facts\">" << lines << "</p>\n"
     << "<svg class=\"screening-strip\" viewBox=\"0 0 " << kWidth << " " << kHeight
     << "\" preserveAspectRatio=\"none\" width=\"100%\" height=\"" << kHeight
     << "\" role=\"img\" aria-label=\"replaced samples over the record\">"
     << "<rect x=\"0\" y=\"0\" width=\"" << kWidth << "\" height=\"" << kHeight << "\" fill=\"#f6f8fa\"/>";
  const double n = static_cast<double>(std::max<std::int64_t>(grid, 1));
  for (const auto& [a, b] : w.replaced) {
    const double x = kWidth * static_cast<double>(a) / n;
    const double width = std::max(1.0, kWidth * static_cast<double>(b - a + 1) / n);
    const std::string at =
        c.freq_known ? detail::num(static_cast<double>(a) / c.freq, 6) + " s" : "sample " + std::to_string(a);
    os << "<rect x=\"" << detail::num(x, 6) << "\" y=\"0\" width=\"" << detail::num(width, 4) << "\" height=\""
       << kHeight << "\" fill=\"#cf222e\"><title>" << (b - a + 1) << " sample(s) at " << html_escape(at)
       << "</title></rect>";
  }
  os << "</svg><p class=\"facts\" style=\"display:flex;justify-content:space-between;margin:0\"><span>0</span><span>"
     << html_escape(end) << "</span></p></div>\n";
  return os.str();
}

std::string column_section(const ReportColumn& c, std::size_t k, Plots& plots) {
  const std::string idx = std::to_string(k + 1);
  std::ostringstream os;
  os << "<section class=\"column\" id=\"col-" << idx << "\">\n<h2>" << html_escape(c.name)
     << "</h2>\n<p class=\"facts\">" << column_facts(c) << "</p>\n";
  if (!c.wvs.empty()) os << plots.add("plot-" + idx + "-wv", "wv", detail::wv_plot_spec(c));
  for (const WaveletVariance& w : c.wvs) os << screening_strip(c, w);
  if (c.fit) {
    os << "<h3>"
       << (c.replicates ? (c.replicates->selection ? "recommended model, fitted jointly over the replicates"
                                                   : "joint fit over the replicates")
                        : "fit")
       << "</h3>\n<p class=\"facts\">objective " << html_escape(detail::num(c.fit->objective, 6))
       << ", goodness of fit: statistic " << html_escape(detail::num(c.fit->gof.statistic)) << ", df "
       << html_escape(detail::num(c.fit->gof.df)) << ", p-value " << html_escape(detail::num(c.fit->gof.p_value, 4))
       << ", status " << html_escape(gmwm::to_string(c.fit->status))
       << (c.fit->message.empty() ? "" : " (" + html_escape(c.fit->message) + ")") << "</p>\n";
    // Notes before the tables they qualify (the levels fitted, parameters left out).
    for (const auto& n : c.fit->notes) os << "<p class=\"facts\">note: " << html_escape(n) << "</p>\n";
    os << detail::parameter_tables(*c.fit, c, "parameters of " + c.fit->model.to_string());
    os << quality_lines(*c.fit, c, false, "");
  }
  os << detail::replicate_tables(c);
  if (c.allan) {
    os << "<h3>Allan deviation and noise figures</h3>\n"
       << plots.add("plot-" + idx + "-adev", "adev", detail::adev_plot_spec(c)) << detail::noise_figures_table(c);
  }
  if (c.selection) {
    os << "<h3>model selection</h3>\n" << detail::ranking_table(*c.selection);
    if (const FitResult* f = detail::shown_model(c)) {
      os << detail::parameter_tables(*f, c, "chosen model " + f->model.to_string() + " (refitted with inference)");
      os << quality_lines(*f, c, c.selection->all_rejected, c.selection->full_model);
    }
    for (const auto& r : c.selection->ranking)
      if (r.rank == 1)
        for (const auto& line : r.effective.reductions)
          os << "<p class=\"facts\">effective form of " << html_escape(r.reduced_member) << ": " << html_escape(line)
             << "</p>\n";
  }
  if (c.gap) {
    os << "<h3>sim-to-real gap</h3>\n";
    os << plots.add("plot-" + idx + "-gap-curves", "gap-curves", detail::gap_curves_spec(c));
    if (c.gap->windows_checked)
      os << plots.add("plot-" + idx + "-gap-windows", "gap-windows", detail::gap_windows_spec(c));
    else
      os << "<p class=\"facts\">window x scale map: the series is too short for enough windows.</p>\n";
    os << detail::gap_tables(c);
  }
  os << detail::wv_table(c) << "</section>\n";
  return os.str();
}

}  // namespace

std::string vega_missing_reason() {
  try {
    (void)detail::vega_script();
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

std::string render_html_report(const ReportData& data) {
  const std::string vega = detail::vega_script();  // first: fails before any work
  const std::string title = data.title.empty() ? "gmwm " + data.command + ": " + data.input : data.title;
  Plots plots;
  std::ostringstream body;
  body << "<header>\n<h1>" << html_escape(title) << "</h1>\n<p>gmwm " << html_escape(version())
       << " &middot; command <code>" << html_escape(data.command) << "</code> &middot; input <code>"
       << html_escape(data.input) << "</code>";
  // gap's "model" is its baseline: a model with values, "fit SPEC", or the simulator's or datasheet's file.
  if (!data.model_spec.empty())
    body << " &middot; " << (data.command == "gap" ? "baseline" : "model") << " <code>" << html_escape(data.model_spec)
         << "</code>";
  body << "</p>\n<p>" << data.columns.size() << " column(s). WV = Haar wavelet variance nu^2 at tau_j = 2^j samples, "
       << "tau shown in seconds (AVAR at averaging time m = 2 x WV at tau = 2m).</p>\n</header>\n<main>\n"
       << "<div id=\"gmwm-errors\" class=\"errors\" hidden></div>\n"
       << "<div id=\"gmwm-warnings\" class=\"warnings\" hidden></div>\n"
       << kErrorCapture;
  if (data.columns.size() > 1) {
    body << "<nav>columns: ";
    for (std::size_t k = 0; k < data.columns.size(); ++k)
      body << "<a href=\"#col-" << k + 1 << "\">" << html_escape(data.columns[k].name) << "</a>";
    body << "</nav>\n";
  }
  for (const auto& n : data.notes) body << "<p class=\"facts\">" << html_escape(n) << "</p>\n";
  bool any_gap = false;
  for (const auto& c : data.columns) any_gap = any_gap || c.gap.has_value();
  if (any_gap)
    body << "<section class=\"column\" id=\"gap-overview\">\n<h2>gap overview</h2>\n"
         << plots.add("plot-gap-levels", "gap-levels", detail::gap_levels_spec(data)) << "</section>\n";
  if (data.corrected) body << detail::corrected_section(*data.corrected, data);
  for (std::size_t k = 0; k < data.columns.size(); ++k) body << column_section(data.columns[k], k, plots);
  body << "</main>\n<footer>Plots: Vega 5 (Debian libjs-vega), inlined; the file needs no network. Drag to pan, wheel "
          "to zoom, double-click to reset, hover a point for its values; SVG/PNG under each plot saves it.</footer>\n";

  std::string page = detail::html_page(title, body.str(), plots, vega);
  spdlog::debug("HTML report: {} plot(s), {} bytes", plots.specs.size(), page.size());
  return page;
}

HtmlFragment render_column_fragment(const ReportData& data, std::size_t column) {
  const ReportColumn& c = data.columns.at(column);
  Plots plots;
  HtmlFragment f;
  f.html = column_section(c, column, plots);
  for (const Json& entry : plots.specs) f.plots.push_back(entry);
  return f;
}

std::string report_style_sheet() { return detail::page_style(); }

std::string vega_inline_script() { return detail::vega_script(); }

std::string script_safe_json(const Json& j) { return detail::script_json(j); }

std::string html_text(std::string_view s) { return detail::html_escape(s); }

std::string report_svg_path(const std::string& path) { return path + ".svg"; }

void stage_html_report(io::OutputSet& outputs, const std::string& path, const ReportData& data) {
  const std::string html = render_html_report(data);
  outputs.stage(path, html);
  if (!data.columns.empty()) outputs.stage(report_svg_path(path), render_wv_svg(data.columns.front()));
}

void write_html_report(const std::string& path, const ReportData& data) {
  io::OutputSet outputs;
  outputs.declare("--report", path);
  outputs.declare("--report", report_svg_path(path));
  stage_html_report(outputs, path, data);
  outputs.commit();
}

}  // namespace gmwm::report
