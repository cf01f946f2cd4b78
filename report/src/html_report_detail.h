#pragma once
// Internals of the HTML report (html_report.h), shared by its files:
//   html_report.cc         the page (sections, layout) and the atomic writer
//   html_report_format.cc  escaping, numbers, the series a plot draws
//   html_report_specs.cc   the Vega 5 specs
//   html_report_tables.cc  the HTML tables (parameters, ranking, gap)
//   html_report_svg.cc     the static SVG of the main plot
//   html_report_vega.cc    the inlined Vega modules, the page's script and style

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "gmwm/report/html_report.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report::detail {

// ---- html_report_format.cc ----

/// The page's plots: each a container and its spec's entry in the page's spec list.
struct Plots {
  Json specs = Json::array();
  /// The container of a plot and its spec's entry. `id` is built from indices only. The
  /// spec is made as wide as the page (a fixed "width" becomes the container's width, the
  /// legend inside it), and its "color" scale's series take the page's colours: a series
  /// name keeps one colour in every plot of the page (series_colours).
  std::string add(const std::string& id, const std::string& kind, Json spec);
  /// Series name -> colour, in the order the page's plots first name them.
  std::map<std::string, std::string> series_colours;
};

/// A script that catches the errors of every later script (Vega's modules included) into
/// <div id="gmwm-errors">.
extern const char* const kErrorCapture;

/// The whole page around `body` (already escaped HTML): head, style, the specs, Vega
/// (`vega`, from vega_script()) and the page's script.
std::string html_page(const std::string& title, const std::string& body, const Plots& plots, const std::string& vega);

/// Text for HTML text and attribute values: & < > " ' escaped.
std::string html_escape(std::string_view s);
/// JSON text safe inside a <script> element: '<', '>', '&' as \u003c, \u003e, \u0026
/// (they can only occur inside JSON strings, so the document's meaning is unchanged).
std::string script_json(const Json& j);
/// %.{digits}g, or "-" when not finite.
std::string num(double x, int digits = 6);

/// A point estimate with its interval at one scale.
struct WvPoint {
  int level = 0;
  double tau = 0.0;  ///< in the plot's unit (seconds when the rate is known)
  double wv = 0.0, lo = 0.0, hi = 0.0;
};
/// One WV estimate series (points with wv > 0 only; lo/hi kept when positive, else NaN).
struct WvSeries {
  std::string name;  ///< "classical WV", "huber WV (eff. 0.6)"
  std::vector<WvPoint> points;
};
/// A model curve at the WV's scales.
struct Curve {
  std::string name;
  bool dashed = false;  ///< components dashed, the whole model solid
  std::vector<double> tau, value;
};

/// Factor from samples to the plot's tau unit (1 / freq, or 1 when the rate is unknown).
double tau_scale(const ReportColumn& c);
/// "s" or "samples".
std::string tau_unit(const ReportColumn& c);
/// The data unit or "U" when undeclared.
std::string data_unit(const ReportColumn& c);
/// Label of a WV: "classical WV" or "<estimator> WV (eff. E)".
std::string wv_label(const WaveletVariance& wv);
WvSeries wv_series(const WaveletVariance& wv, const ReportColumn& c);
/// The model whose WV the column shows: the fit, else the selection's best fit (else its
/// first-ranked model's fit); nullptr when none has a finite theta.
const FitResult* shown_model(const ReportColumn& c);
/// The scales (in samples) the model curve is drawn at: those of the WV with the most
/// levels (the longest replicate for a joint column).
const std::vector<double>& model_tau(const ReportColumn& c);
/// True when the fit holds a usable theta.
bool has_theta(const FitResult& f);
/// The model's WV at the scales `tau_samples` ("<label>") and, when `components`, each
/// component's WV ("<k>: <NAME>", dashed). Non-positive values are left out.
std::vector<Curve> model_curves(const Model& model, const Eigen::VectorXd& theta,
                                const std::vector<double>& tau_samples, double scale, const std::string& label,
                                bool components);

// ---- html_report_specs.cc ----

/// The column's WV plot (estimates, CI bands, model and components).
Json wv_plot_spec(const ReportColumn& c);
/// The column's Allan deviation plot (requires c.allan): data with its band, the model's
/// curve, the N / K / B guide lines.
Json adev_plot_spec(const ReportColumn& c);
/// Scale x axis heat map of log2(ratio) of every column with a gap result.
Json gap_levels_spec(const ReportData& d);
/// Window x scale map of the cells that depart (requires gap->windows_checked).
Json gap_windows_spec(const ReportColumn& c);
/// Before/after: data WV, reference band, baseline WV, final model WV.
Json gap_curves_spec(const ReportColumn& c);

// ---- html_report_tables.cc ----

/// A table cell, its text escaped (cls: an optional class).
std::string td(const std::string& text, const char* cls = nullptr);
/// A header row, each heading escaped.
std::string th_row(const std::vector<std::string>& head);

/// Discrete and continuous parameter tables of a fit (empty when no theta).
std::string parameter_tables(const FitResult& fit, const ReportColumn& c, const std::string& caption);
/// The ranking table, the chosen model's row highlighted.
std::string ranking_table(const selection::Selection& sel);
/// The gap's summary, levels, candidates, shrinkage and notes.
std::string gap_tables(const ReportColumn& c);
/// The noise figures N, K, B with their sources, read-offs and notes.
std::string noise_figures_table(const ReportColumn& c);
/// An axis fitted over replicates: the replicates, the shared-theta test, the parameters
/// side by side and the selection's three-WVIC table (empty without c.replicates).
std::string replicate_tables(const ReportColumn& c);
/// The WV levels of the column's first WV (collapsed <details>).
std::string wv_table(const ReportColumn& c);

// ---- html_report_corrected.cc ----

/// `gap`'s corrected configuration: the fields changed (input, corrected, unit), each
/// column's gap left (input -> file -> full model: levels outside, objective, integrated
/// error), what the format cannot express, and the file's text (collapsed).
std::string corrected_section(const pipeline::CorrectedConfig& c, const ReportData& data);

// ---- html_report_vega.cc ----

/// The folder with the Vega modules (env GMWM_VEGA_DIR, else the configured one).
std::string vega_dir();
/// The inlined modules and the shim defining `vega` (throws InputError when unreadable).
std::string vega_script();
/// The page's own script: renders every spec, records errors, adds the export links.
std::string page_script();
/// The page's style sheet.
std::string page_style();

}  // namespace gmwm::report::detail
