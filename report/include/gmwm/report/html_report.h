#pragma once
// The self-contained HTML report of `gmwm wv|fit|select|gap --report PATH` (issue 6):
// one file that opens offline, with interactive Vega 5 plots (zoom, pan, hover values)
// and the tables a reader needs beside them.
//
//   gmwm::report::ReportData r;                       // filled by the command
//   r.command = "select"; r.input = set.path;
//   gmwm::report::ReportColumn c; c.name = "gyro_x"; c.freq = 100; c.freq_known = true; c.wvs = {wv};
//   r.columns.push_back(c);
//   r.columns.back().selection = result[0];
//   gmwm::report::write_html_report("report.html", r);  // report.html and report.html.svg
//
// What the page holds, per column: the log-log WV against tau in seconds with its CI band
// (every WV given, e.g. classical and robust overlaid), the model's implied WV and each
// component's WV (dashed) for a fit or a selection's chosen model, the parameter table in
// discrete (per sample) and continuous (physical) units, the selection's ranking with the
// chosen model highlighted, and for a gap diagnosis the window x scale map, the
// before/after curves (data, baseline, final model, reference band) and its tables; once
// per report, the gap's scale x axis map of log2(data WV / baseline WV). For an axis
// fitted over replicates (`--joint`): every replicate's WV with its band overlaid with the
// joint model, each replicate's share of the objective, the shared-theta test, the
// parameters side by side (joint with sandwich and replicate-t intervals, AGMWM, each
// replicate's own estimate) and, for a selection, the CV / analytic / bootstrap WVIC table
// with the equivalent models and the recommended one.
//
// Plotting: Vega 5 from Debian's libjs-vega, inlined into the page, so that it opens with
// no network. Debian 12 ships Vega as its separate UMD modules (vega-util.min.js,
// vega-view.min.js, ...; no single vega.min.js bundle), so the page inlines the modules a
// plain Vega spec needs, each wrapped in a tiny CommonJS loader, and composes the `vega`
// object the way Vega's own index does (its transforms registered with the dataflow). The
// folder is found at configure time (CMake: GMWM_VEGA_DIR) and read when a report is
// rendered; the environment variable GMWM_VEGA_DIR overrides it.
//
// DOM contract (tests/cli/html_report_browser_test.cc relies on it): each plot is a
// <div class="gmwm-plot" data-plot="KIND" id="..."> with KIND one of wv, adev, gap-levels,
// gap-windows, gap-curves; its Vega spec is the entry with that id in the JSON array of
// <script id="gmwm-specs" type="application/json">. Views render with the SVG renderer;
// a rendered plot gets data-rendered="svg". Script errors (window.onerror, rejected
// promises, Vega's own error log) are written into <div id="gmwm-errors">, Vega warnings
// into <div id="gmwm-warnings">; when every view has run, <body> gets
// data-gmwm-status="done" and data-gmwm-rendered="<count>".
//
// Static image: write_html_report also writes PATH.svg, the first column's WV plot. It is
// drawn here as a plain SVG (polylines and polygons on log-log axes with decade ticks),
// not by Vega: running a browser from the command line would make a CLI result depend on
// a browser being installed and on its sandbox. The decision is deliberate: the plot is a
// trivial polyline plot, while every interactive plot stays Vega's. The page also offers
// Vega's own SVG and PNG export of each plot (view.toImageURL) for pasting.
//
// Escaping: every user string (column names, paths, model strings, notes) is HTML-escaped
// in text and attributes; data and specs are embedded as JSON with '<', '>' and '&'
// written as \u003c, \u003e, \u0026, so that no string can close the script element.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/gap/gap.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/selection/select.h"
#include "gmwm/pipeline/corrected_config.h"
#include "gmwm/io/output_set.h"

namespace gmwm::report {

/// `fit --joint` / `select --joint`: an axis fitted over replicates. The column's `wvs`
/// are the replicates' WVs (in this order, overlaid and labelled by their sources) and its
/// `fit` is the joint model drawn over them (for select: the recommended model's joint fit).
struct ReplicateReport {
  std::vector<std::string> sources;   ///< "FILE:COLUMN" per replicate
  std::vector<std::int64_t> n;        ///< per replicate, its observed samples
  std::vector<std::int64_t> missing;  ///< per replicate, the samples its stamps show missing (0: none)
  std::string estimator;              ///< "classical WV", "robust WV (...)"
  /// The joint fit with each replicate's own fit and AGMWM (per-parameter view).
  std::optional<JointFitResult> joint;
  std::optional<ReplicateTest> test;                       ///< the shared-theta test
  std::optional<ReplicateBootstrap> bootstrap;             ///< replicate-t intervals
  std::optional<selection::ReplicateSelection> selection;  ///< CV / analytic / bootstrap WVIC table
};

/// One analysed column (signal) of a report.
struct ReportColumn {
  std::string name;
  std::int64_t n = 0;
  double freq = 1.0;         ///< Hz
  bool freq_known = false;   ///< tau in seconds when true, else in samples
  std::string unit;          ///< the data unit ("deg/s"); empty: undeclared (shown as "U")
  double filter_rate = 0.0;  ///< Kalman table's filter rate in Hz; 0: the data's rate
  /// The WVs to overlay (e.g. the classical one, then a robust one), each labelled by its
  /// `estimator`. The first one is the one the model was fitted to (if any).
  std::vector<WaveletVariance> wvs;
  /// `fit`: the fitted model (its implied WV, components and parameter table).
  std::optional<FitResult> fit;
  /// `select`: the ranking; its best_fit is the model drawn and tabulated.
  std::optional<selection::Selection> selection;
  /// The Allan deviation with its noise figures (fit, select, wv --adev): a log-log ADEV
  /// plot of the data with its interval band, the model's curve when fitted, and the IEEE
  /// 952 guide lines (-1/2 through N, +1/2 through K, the flat 0.664 B), then the table.
  std::optional<FigureReport> allan;
  /// `gap`: the diagnosis and how the baseline was converted to this column.
  std::optional<gap::GapResult> gap;
  /// `fit --joint`, `select --joint`: the replicates, their test and selection.
  std::optional<ReplicateReport> replicates;
  std::vector<std::string> conversions;
  /// Reference models drawn beside the data's (a datasheet's or a simulator's model, as gmwm
  /// serve overlays them): each one's implied WV at the column's scales in the WV plot and
  /// its Allan deviation in the ADEV plot, one solid curve named `name`.
  struct Reference {
    std::string name;  ///< "datasheet adis16405.yaml: WN+FLICKER+RW"
    Model model;
    Eigen::VectorXd theta;
  };
  std::vector<Reference> references;
};

struct ReportData {
  std::string title;               ///< empty: "gmwm COMMAND: INPUT"
  std::string command;             ///< wv | fit | select | gap
  std::string input;               ///< the input file's path, as given
  std::string model_spec;          ///< the model option as given (may be empty)
  std::vector<std::string> notes;  ///< free lines shown under the header
  std::vector<ReportColumn> columns;
  /// `gap`: the corrected configuration ("what to change"), shown after the overview.
  std::optional<pipeline::CorrectedConfig> corrected;
};

/// Empty when the Vega modules can be read, else why not (one line, naming the folder).
std::string vega_missing_reason();

/// The whole page. Throws InputError when Vega cannot be read (vega_missing_reason).
std::string render_html_report(const ReportData& data);

/// The static SVG of a column's WV plot (estimates with CI bands, model and components).
std::string render_wv_svg(const ReportColumn& column);

/// Renders the page and the first column's SVG, then writes PATH and PATH.svg, both or
/// neither (an OutputSet). Throws InputError for an unwritable path or a missing Vega;
/// nothing is written then.
void write_html_report(const std::string& path, const ReportData& data);

/// As write_html_report(), staged in `outputs` with the run's other files (PATH.svg is
/// declared there as "--report"'s companion, so it too may not be an input).
void stage_html_report(io::OutputSet& outputs, const std::string& path, const ReportData& data);

/// The companion SVG's path for a report at `path`.
std::string report_svg_path(const std::string& path);

}  // namespace gmwm::report
