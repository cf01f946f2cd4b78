#pragma once
// The HTML report of `gmwm fleet MANIFEST --report PATH` (issue 30, item 2): one
// self-contained page a production engineer reads to decide which units to pull.
//
//   const gmwm::fleet::FleetStudy s = gmwm::fleet::study_fleet(manifest, options);
//   gmwm::io::OutputSet out;
//   out.declare("--report", "fleet.html");
//   out.declare("--report", gmwm::report::report_svg_path("fleet.html"));
//   gmwm::report::stage_fleet_report(out, "fleet.html", s);   // fleet.html and fleet.html.svg
//   out.commit();
//
// What the page holds, per group (the manifest's `group`, by default the sensor model):
//   - a headline: its units, the recordings that failed, the units flagged and on which
//     figure of which axis, each with its value and interval, the group's median, its z and
//     its flag limits (the units whose interval lies wholly outside their limits first);
//   - the flagged units (FleetRow::flags) and the failures (FleetRow::status), as tables;
//   - per axis, the distribution of N, K and B over the units (data-plot="fleet-figures"):
//     one log-scale strip per figure, a dot per unit with its interval as a rule, the
//     group's median and the flag band drawn; a flagged unit red and labelled by its id; a
//     unit with only an upper bound an open triangle (the summary leaves bounds out);
//     hovering a dot shows unit, value, interval, read-off source, z, its own flag limits and
//     the recording. The rule is fleet_summary's (fleet_study.h, kFleetOutlierZ): z =
//     log(x / median) / sqrt(tau^2 + se^2) beyond 3.5, se the unit's own standard error, tau
//     the spread between units net of the read-offs' noise; the band drawn is the limits of
//     a read-off of the fleet's median precision, median x exp(+-3.5 sqrt(tau^2 + median
//     se^2)) (median x spread^(+-3.5), spread = exp(MAD of the logs / 0.6745), whenever the
//     units differ more than their read-offs' noise); a less precise read-off's own limits
//     are wider (its tooltip says them);
//   - per axis, the fleet's band of Allan deviation curves (data-plot="adev"): per averaging
//     time the median, the min-max and (from kFleetPercentileUnits units on) the 5-95%
//     envelopes of the ADEVs of the units not flagged on the axis, and every flagged unit's
//     ADEV with its interval band over it, in its own colour (one colour per unit across the
//     page) and labelled; when the units' tau grids differ (other rates or lengths) each ADEV
//     is interpolated in log-log onto a common grid, and the page says so;
//   - the summary table: per axis and figure the units, the median (in the data's unit and
//     the datasheet's), the spread and the units' own spread, the band, the units flagged
//     and the bounds.
// Figures are drawn in the datasheet's unit where the data's unit is declared (N in
// deg/sqrt(h) or ug/sqrt(Hz), K in deg/h/sqrt(h) or m/s^2/sqrt(h), B in deg/h or mg: as the
// terminal prints them), else in the data unit's pattern (U/sqrt(Hz), U/s/sqrt(Hz), U). A
// group whose units were recorded in different units is drawn in the SI unit its summary
// uses, every unit's figures and curves converted.
//
// DOM contract, Vega and escaping: as html_report.h (the same page frame, script and
// style; tests/cli/html_report_browser_test.cc checks it): plots of kind "fleet-figures"
// and "adev" (an Allan deviation plot: tau [s], "Allan deviation [UNIT]"), every user
// string (unit ids, axes, paths, groups, models, reasons) HTML-escaped in text and
// attributes and embedded as JSON with '<', '>', '&' escaped.
//
// PATH.svg: the static Allan deviation band plot of the first axis with a flagged unit (the
// first axis when none is), drawn as plain SVG as html_report.h's PATH.svg is.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gmwm/fleet/fleet_band.h"
#include "gmwm/fleet/fleet_study.h"
#include "gmwm/report/html_report.h"
#include "gmwm/io/output_set.h"

namespace gmwm::report {

/// The fewest units of a band for its 5-95% envelope (fleet_band.h).
inline constexpr int kFleetPercentileUnits = fleet::kBandPercentileUnits;

/// One unit's figure as its strip draws it (in the panel's unit).
struct FleetDot {
  std::string unit, path;
  int index = 0;  ///< the unit's place in its group: its height on every strip
  double value = 0.0;
  double low = NAN, high = NAN;  ///< NaN when unknown (a bound has no low)
  std::string source;            ///< "model", "data" or "bound" (FigureSource)
  bool bound = false;            ///< only an upper bound: left out of the median and the flags
  bool flagged = false;          ///< flagged on this figure of this axis (its row's flag)
  std::string flag;              ///< the flag's reason ("N: 4.2x the fleet's median (robust z 9.1)")
  /// Its z against the group's median as fleet_summary takes it: log(x / median) /
  /// sqrt(tau^2 + se^2), se its own standard error (NaN for a bound or no spread).
  double z = NAN;
  /// Its own flag limits, median x exp(-+3.5 sqrt(tau^2 + se^2)) (NaN for a bound): a
  /// read-off less precise than the fleet's must lie farther out to be flagged.
  double limit_low = NAN, limit_high = NAN;
  /// Flagged, and its interval lies wholly outside its limits (not only its value): the
  /// surest flags, listed first.
  bool beyond = false;
};

/// One figure of one axis over a group's units.
struct FleetFigurePanel {
  char figure = 'N';
  std::string unit;       ///< the panel's unit ("deg/sqrt(h)", "g/sqrt(Hz)")
  std::string data_unit;  ///< the summary's unit pattern ("deg/s/sqrt(Hz)")
  double to_panel = 1.0;  ///< the summary's value x to_panel = the panel's value
  int units = 0;          ///< read-offs in the summary (bounds left out)
  /// The group's median and spread exp(MAD of the logs / 0.6745) (NaN when no unit has a
  /// read-off); unit_spread = exp(tau), the spread between units net of the read-offs' own
  /// noise (fleet_study.h, kFleetOutlierZ).
  double median = NAN, spread = NAN, unit_spread = NAN;
  /// The flag band of a read-off of the fleet's median precision, median x exp(-+3.5
  /// sqrt(tau^2 + median se^2)): median x spread^(-+3.5) when tau > 0. Panel's unit.
  double band_low = NAN, band_high = NAN;
  bool can_flag = false;  ///< at least fleet::kMinUnitsForFlags read-offs
  std::vector<FleetDot> dots;
};

/// A unit's Allan deviation drawn over the band (in the axis's unit).
struct FleetUnitCurve {
  std::string unit, path;
  std::vector<double> tau, adev, low, high;  ///< low/high NaN where unknown
  std::vector<std::string> flags;            ///< its row's flags
  double label_tau = NAN;                    ///< where its worst flagged figure was read (s): its label's place
};

/// The fleet's band of Allan deviations of one axis, per averaging time.
/// The band of Allan deviations, as fleet/ computed it (fleet_band.h).
using fleet::FleetAdevBand;

struct FleetAxisView {
  std::string axis;
  std::string unit;  ///< the unit of its figures' data pattern and of the ADEVs ("" undeclared: "U")
  /// N, K, B, and Q, R where a unit of the study reads them (fleet_shown_figures), in
  /// kFigureNames' order.
  std::vector<FleetFigurePanel> figures;
  FleetAdevBand band;
  std::vector<FleetUnitCurve> flagged;  ///< the units flagged on this axis, in manifest order
  std::vector<std::string> notes;       ///< what the reader must know to read its plots
};

struct FleetGroupView {
  std::string name;
  int units = 0;                      ///< distinct unit ids
  int failed = 0;                     ///< recordings of the group that failed
  std::vector<std::string> headline;  ///< sentences, every number in them from the study
  std::vector<FleetAxisView> axes;
  std::vector<std::size_t> flagged_rows;  ///< rows (FleetStudy::rows) with a flag
  std::vector<std::size_t> failed_rows;   ///< rows whose recording or axis failed
};

/// What the page shows, computed from the study (tested as data; rendered by render_fleet_page).
struct FleetPageData {
  std::string title;
  std::vector<FleetGroupView> groups;
};

/// The page's data: groups in the order the manifest first names them, axes in the
/// summary's order, units in manifest order.
FleetPageData fleet_page_data(const fleet::FleetStudy& study);

/// The whole page. Throws InputError when Vega cannot be read (vega_missing_reason).
std::string render_fleet_page(const fleet::FleetStudy& study);

/// The static SVG of the first axis with a flagged unit (the first axis when none is): the
/// band, the median and the flagged units' curves. Empty when the study has no axis.
std::string render_fleet_svg(const FleetPageData& data);

/// Stages the page at `path` and, when the study has an axis, its SVG at
/// report_svg_path(path) in `outputs` (declared there as "--report"'s).
void stage_fleet_report(io::OutputSet& outputs, const std::string& path, const fleet::FleetStudy& study);

}  // namespace gmwm::report
