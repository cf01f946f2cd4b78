#pragma once
// What `gmwm stability` (and Python's gmwm.stability) writes: the JSON document and the
// terminal tables of the frequency-stability study (pipeline/stability_study.h).
//
// JSON (docs/cli.md, "stability"): {"tool", "version", "command": "stability", "input",
//   "data", "kinds", "taus", "tau0", "phase_points", the record's "timing", "columns":
//   [{"name", "n", "freq", "unit", "deviations": {"<kind>": {"m", "tau", "value", "n",
//   "unit"}}}], "run": {...}}. "n" of a deviation is the number of squares averaged at each
//   factor (Stable32's "#"); "unit" the data's (TDEV: the data's times seconds), null when
//   not declared.
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// The document (without "run": add_run_info). `units` per column ("" when not declared).
Json stability_document(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                        const pipeline::StabilityStudyOptions& options, const std::vector<std::string>& units);

/// Per column, a table of the averaging times (s) and each kind's deviation there ("-" where
/// a kind has no factor), its unit below it.
std::string stability_text(const pipeline::StabilityStudy& study, const std::vector<std::string>& units);

}  // namespace gmwm::report
