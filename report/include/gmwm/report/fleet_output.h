#pragma once
// The fleet study's renderings (fleet/fleet_study.h): its JSON document, its table as CSV
// (one row per unit x axis: the fleet's results table) and the terminal's table.

#include <string>

#include "gmwm/fleet/fleet_study.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// json_document("fleet"): "manifest", "model_spec", "recordings", "failed", and "rows"
/// (per unit x axis: "unit", "model", "group", "path", "axis", "unit_of_data", "status",
/// "chosen" (with values), "chosen_structure", "gof_p_value", "freq", "n", "N", "K", "B" each {"value", "low", "high",
/// "source"}, "seconds", "flags"), "summary" (per group, axis and figure: "units", "median",
/// "spread", "flagged") and "outlier_rule".
Json fleet_document(const fleet::FleetStudy& study);

/// The results table: a header, then one line per row of the study (fields as the JSON's,
/// N, K, B as value, low, high; numbers in their shortest exact form, empty when unknown).
std::string fleet_csv(const fleet::FleetStudy& study);

/// The terminal's table: unit, axis, chosen model, N, K, B in the data's unit and the GoF
/// p-value; a failed recording's row says why.
std::string fleet_text(const fleet::FleetStudy& study);

}  // namespace gmwm::report
