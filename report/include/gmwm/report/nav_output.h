#pragma once
// What `gmwm nav` (and Python's gmwm.nav) writes: the JSON document, the terminal summary
// and the HTML report of a navigation study (pipeline/nav_study.h). The CLI and Python
// share these: the numbers in each are the same.
//
// JSON (docs/cli.md, "nav"): {"tool", "version", "command": "nav", "columns": [],
//   "scenario": {...}, "truth": {"source", "models"}, "filters": [{"label", "source",
//   "models", "notes", "verdict", "nees_inside", "nees_band", "summary": {...},
//   "curves": {"time", "position_rms", "position_3sigma", ...}, "monte_carlo": {...}}],
//   "monte_carlo": {"runs", "seed"} | null, "run": {...}}.
#include <string>

#include "gmwm/report/json_output.h"
#include "gmwm/io/output_set.h"
#include "gmwm/pipeline/nav_study.h"

namespace gmwm::report {

/// The output time a summary reads the errors at: the last before the end of the last
/// outage inside the horizon (the worst of a fix-aided run), else the horizon's.
std::size_t summary_index(const pipeline::NavStudy& study, const nav::FilterErrors& f);

/// The document (without "run": add_run_info).
Json nav_document(const pipeline::NavStudy& study);

/// The terminal summary: the scenario, then one line per filter model (position error and
/// the filter's own 3-sigma at the summary time, NEES inside its band, verdict); every
/// line at most 100 columns (long labels numbered, their text below).
std::string nav_terminal(const pipeline::NavStudy& study);

/// The self-contained HTML report: position, velocity and attitude errors against time
/// (RMS solid, the filter's own 3-sigma dashed, Monte Carlo as points), the NEES with its
/// band, the models and the verdicts. Throws InputError when Vega cannot be read.
std::string render_nav_html(const pipeline::NavStudy& study);

}  // namespace gmwm::report
