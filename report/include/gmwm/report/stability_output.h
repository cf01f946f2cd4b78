#pragma once
// What `gmwm stability` (and Python's gmwm.stability) writes: the JSON document and the
// terminal tables of the frequency-stability study (pipeline/stability_study.h).
//
// JSON (docs/cli.md, "stability"): {"tool", "version", "command": "stability", "input",
//   "data", "kinds", "taus", "confidence", "interval_method", "noise_alpha", "tau0",
//   "phase_points", the record's "timing", "columns": [{"name", "n", "freq", "unit",
//   "deviations": {"<kind>": {"m", "tau", "value", "ci_low", "ci_high", "edf", "alpha",
//   "noise", "noise_id", "n", "unit"}}}], "run": {...}}. "n" of a deviation is the number of
//   squares averaged at each factor (Stable32's "#"); "alpha" the noise exponent used for the
//   degrees of freedom ("noise" its name, "noise_id" how it was found: acf, b1, b1+rn,
//   default, fixed); "ci_low"/"ci_high"/"edf" null where the kind has no rule; "unit" the
//   data's (TDEV: the data's times seconds), null when not declared. With --hat, "hat":
//   {"sensors": [A, B, C], "pairs": [{"name": "A - B", "deviations": {"<kind>": as a
//   column's}}, B - C, C - A], "deviations": {"<kind>": {"m", "tau", "edf" (the pairs'
//   smallest, which the intervals read), "unit", "sensors": [{"name", "value" (null where the
//   separated variance is negative), "variance" (kept as computed, negative or not),
//   "negative", "ci_low", "ci_high" (the score interval: null where none fits)}]}}}
//   (stability/three_cornered_hat.h).
#include <cstddef>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/report/html_fragment.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// The document (without "run": add_run_info). `units` per column ("" when not declared).
Json stability_document(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                        const pipeline::StabilityStudyOptions& options, const std::vector<std::string>& units);

/// The self-contained HTML report (`gmwm stability --report`): per column the deviations on
/// log-log axes with their interval bands (the time deviations on their own plot: another
/// unit) and the table of every value [low, high] with its noise; with the hat (--hat), its
/// section after the columns: what it is, and per kind each column's separated deviation with
/// its interval band on log-log axes (a negative variance not drawn) and the table of every
/// value [low, high] ("[var V]" where the variance is negative) with the pairs' edf. Throws
/// InputError when Vega cannot be read (vega_missing_reason()). DOM: plots of kind
/// "stability" and "stability-time" (html_report.h's contract), the hat's "stability-hat"
/// (ids "plot-hat-<kind+1>", in <section id="stability-hat">).
std::string render_stability_html(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                  const pipeline::StabilityStudyOptions& options,
                                  const std::vector<std::string>& units);

/// Column `column`'s section of that report (std::out_of_range beyond the columns) with its
/// Vega specs, for the web app (gmwm serve): the same heading, plots and table, rendered by
/// the same code, with what the report's header says (how the column was read, what the
/// intervals are) under the heading. Plot ids "plot-<column+1>-stability[-time]".
HtmlFragment render_stability_fragment(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                       const pipeline::StabilityStudyOptions& options,
                                       const std::vector<std::string>& units, std::size_t column);

/// Every column's section of that report and, with the hat, the hat's, with their Vega specs:
/// the whole study for the web app (a hat's three columns), rendered by the same code, with
/// what the report's header says under the first column's heading (so that for one column
/// without the hat it is that column's fragment above).
HtmlFragment render_stability_fragment(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                                       const pipeline::StabilityStudyOptions& options,
                                       const std::vector<std::string>& units);

/// Per column, a table of the averaging times (s) and each kind's deviation there ("-" where
/// a kind has no factor), its unit below it.
std::string stability_text(const pipeline::StabilityStudy& study, const std::vector<std::string>& units);

}  // namespace gmwm::report
