#pragma once
// The fleet study's renderings (fleet/fleet_study.h): its JSON document, its table as CSV
// (one row per unit x axis: the fleet's results table) and the terminal's table.

#include <cstddef>
#include <string>
#include <vector>

#include "gmwm/fleet/fleet_study.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// json_document("fleet"): "manifest", "model_spec", "recordings", "failed", "cached",
/// "cache", "spec", and "rows" (per unit x axis: "unit", "model", "group", "path", "axis",
/// "unit_of_data", "status", "chosen" (with values), "chosen_structure", "gof_p_value", "freq",
/// "n", "N", "K", "B", "Q", "R" each {"value", "low", "high", "source"}, "seconds", "cached", "flags";
/// with a spec "spec" (per figure checked: "figure", "limit", "limit_unit", "limit_key",
/// "limit_where", "value", "low", "high" in the limit's unit, "verdict", "note"),
/// "spec_verdict" and "spec_note"), "summary" (per group, axis and figure: "units", "unit",
/// "median", "spread", "flagged", "out_of_spec") and "outlier_rule".
Json fleet_document(const fleet::FleetStudy& study);

/// The results table: a header, then one line per row of the study (fields as the JSON's,
/// N, K, B, Q, R as value, low, high; numbers in their shortest exact form, empty when
/// unknown). Q and R's columns follow B's (issue 48).
std::string fleet_csv(const fleet::FleetStudy& study);

/// The figures the fleet's tables and page show (indices into kFigureNames): N, K and B
/// always, Q and R where a unit's row or a joint model reads them (not only bounds: a column
/// of upper bounds on every axis would crowd out the rest; the JSON and CSV hold them).
std::vector<int> fleet_shown_figures(const fleet::FleetStudy& study);

/// The most unit x axis rows the terminal lists without --verbose (a fleet of hundreds of
/// units is read in its summary; the table is the CSV's).
inline constexpr std::size_t kFleetTerminalRows = 60;

/// The terminal's text, at most 100 columns: the headline, each group's axes (median and
/// spread of N, K, B in datasheet units, and of Q, R where read: fleet_shown_figures), the
/// units that stand out, the spec's verdicts, the failed recordings; then the per-unit table
/// (the figures, GoF p, chosen model) when
/// `verbose` or at most kFleetTerminalRows rows.
std::string fleet_text(const fleet::FleetStudy& study, bool verbose = false);

}  // namespace gmwm::report
