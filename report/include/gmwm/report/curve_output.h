#pragma once
// What `gmwm fit --curve` (and Python's gmwm.fit_curve) writes: the curve fit study's
// (pipeline/curve_study.h) JSON document and terminal text, in the shape of gmwm fit's.
//
// JSON (docs/cli.md "JSON", docs/curve-fit.md): {"tool", "version", "command": "fit",
//   "input", "model_spec", "seed", "columns": [...], "run"}; each column a fit column
//   (fit_column_json: "model", "parameters", "quality", "objective", "gof" (p_value null:
//   no test on a curve), "status", "message", "notes", "evaluations", "omega", "implied_wv"
//   (the model at every point), "estimator": "curve", "alpha", "levels" (every point as a
//   WV: "tau" 2m samples, "tau_seconds", "wv", "ci_low", "ci_high", "coefficients" 0)),
//   "first_level" 1, the physical fields ("unit", "continuous", "kalman", "allan" (the points
//   fitted, with the model's deviation there), "noise_figures") and "curve": {"source",
//   "value" (adev, avar or wv), "tau" (as given, s), "fitted" (per point), "excluded" (the
//   --exclude-taus text, or null), "weights" (edf, intervals, record, shortest-record),
//   "confidence" (of given intervals, else null), "record_seconds" (given, else null),
//   "rate" ("given" or "curve": its finest tau one sample), "whole_samples"}.
#include <string>
#include <vector>

#include "gmwm/pipeline/curve_study.h"
#include "gmwm/report/json_output.h"
#include "gmwm/report/study_text.h"

namespace gmwm::report {

/// One curve's column of the document. `unit` the data's ("" when not declared); the Kalman
/// terms at `filter_rate` Hz (0: the curve's rate).
Json curve_fit_column_json(const pipeline::CurveFitStudy& study, std::size_t k, const std::string& unit,
                           double filter_rate);

/// The document (without "run": add_run_info). `input` names the curve's file(s); `units[k]`
/// curve k's unit ("" or an empty vector: none declared).
Json curve_fit_document(const std::string& input, const pipeline::CurveFitStudy& study,
                        const std::vector<std::string>& units, double filter_rate);

/// The terminal text: the per-axis summary of `doc`, then with options.verbose each curve's
/// points, weights and rate, its fit (fit_detail's) and its continuous, noise-figure and
/// Kalman tables (else kDetailsHint).
std::string curve_fit_text(const Json& doc, const pipeline::CurveFitStudy& study, const TextOptions& options);

}  // namespace gmwm::report
