#pragma once
// What `gmwm plan` (and Python's gmwm.plan) writes: the JSON document and the terminal
// table of a record-length plan (pipeline/plan_study.h).
//
// JSON (docs/cli.md, "plan"): {"tool", "version", "command": "plan", "source", "precision",
//   "confidence", "record_seconds", "columns": [{"name", "unit", "model", "resolved":
//   {"samples", "seconds", "by"}, "targets": [{"name", "value", "unit", "reachable",
//   "samples", "seconds", "own_samples", "relative_se", "precision_at_record", "basis"}]}],
//   "run": {...}}.
#include <string>

#include "gmwm/report/json_output.h"
#include "gmwm/pipeline/plan_study.h"

namespace gmwm::report {

/// The document (without "run": add_run_info).
Json plan_document(const pipeline::PlanStudy& study, const RecordPlanOptions& options);

/// One line per column and target: the length needed (samples, and as a duration), the
/// relative standard error there, the precision a given record reaches; lines of at most
/// 100 columns, the basis of each figure below the table.
std::string plan_terminal(const pipeline::PlanStudy& study, const RecordPlanOptions& options);

}  // namespace gmwm::report
