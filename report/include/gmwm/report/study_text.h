#pragma once
// Every study's rendering for people, shared by the CLI and Python: the terminal text of
// each command (its per-axis summary first, the detail tables behind `verbose`) and its CSV
// tables. Every table fits kTerminalWidth columns (terminal.h); the numbers are the JSON
// document's (the summary is read from it, the tables from the same study results).
//
//   const report::Json doc = report::fit_document(set, study, units, filter);
//   std::cout << report::fit_text(doc, set, study, {units, filter, verbose});

#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/gap/cross_axis.h"
#include "gmwm/gap/gap.h"
#include "gmwm/gap/gap_check.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/corrected_config.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/wv_study.h"
#include "gmwm/report/json_output.h"
#include "gmwm/report/terminal.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/selection/select.h"

namespace gmwm::report {

/// The last line of a summary-only text (fit, select): where the details are.
inline constexpr const char* kDetailsHint =
    "(--verbose: the ranking, parameters, read-offs and Kalman terms; --json, --report: everything)\n";

/// How a fit or select text is drawn: each column's unit ("" when not declared), the Kalman
/// table's filter rate (Hz; 0: none) and whether the detail tables follow the summary.
struct TextOptions {
  std::vector<std::string> units;
  double filter_rate = 0.0;
  bool verbose = false;
};

// ---- the detail tables (fit, select and their joint forms) ----

/// Where a robust WV's spike screen replaced samples, in a few lines: how many in how many
/// ranges and their share of the record, when (the first and last, the count in each tenth of
/// the record, the longest range), and that the JSON lists every range ("" when nothing was
/// replaced). Times in seconds when the rate is known, else in samples. `n` is the WV's grid
/// (wv.n: observed and missing samples together, where the ranges are placed). The terminal
/// (wv, fit, select) and the HTML report's strip say the same.
std::string screening_summary(const WaveletVariance& wv, std::int64_t n, double freq, bool freq_known);

/// The parameters in continuous units with their intervals ("" when none has a unit).
std::string continuous_table(const FitResult& fit, const ColumnInfo& column);
/// The Kalman filter terms at `filter_rate` Hz ("" when the rate is unknown or the fit unusable).
std::string kalman_table(const FitResult& fit, const ColumnInfo& column, double filter_rate,
                         const ChosenFigures* figures = nullptr);
/// N, K, B (IEEE 952 read-offs): the value to use with its source, interval and where it was
/// read, the model's and the data's read-offs side by side, and below the table the
/// components behind each and a note where the model misses the data.
std::string noise_figures_table(const ChosenFigures& figures, const std::string& unit);

/// One column's fit: its header, model with values, parameter table, objective, GoF,
/// status, notes and fit-quality verdicts.
std::string fit_detail(const ColumnInfo& column, const WaveletVariance& wv, const FitResult& fit, OmegaKind omega);
/// One column's selection: the ranking (with the candidates that fell onto each model),
/// the best model, its reductions and fit-quality verdicts.
std::string select_detail(const ColumnInfo& column, const selection::Selection& selection);

/// `gmwm fit`'s text: the timing summary, the per-axis summary of `doc`, then with
/// `verbose` each column's fit_detail and its continuous, noise-figure and Kalman tables
/// (else kDetailsHint).
std::string fit_text(const Json& doc, const io::SignalSet& set, const pipeline::FitStudy& study,
                     const TextOptions& options);
/// `gmwm select`'s text, as fit_text with select_detail.
std::string select_text(const Json& doc, const io::SignalSet& set, const pipeline::SelectStudy& study,
                        const TextOptions& options);

// ---- replicates (fit --joint, select --joint) ----

/// "classical WV" or "robust WV (Gaussian efficiency E)".
std::string replicate_estimator_text(const std::optional<robust::RobustWvOptions>& robust);

/// `gmwm fit --joint`'s text: the per-axis summary, then per axis its replicates, the
/// joint parameters beside AGMWM, the replicate-t interval and each replicate's own fit,
/// the shared-theta test, and the joint model's physical tables.
std::string joint_fit_text(const Json& doc, const io::SignalSet& set,
                           const std::vector<pipeline::ReplicateGroup>& groups, const pipeline::JointFitStudy& study,
                           const std::string& estimator, const TextOptions& options);
/// `gmwm select --joint`'s text: the per-axis summary, then per axis the ranking by
/// cross-validated WVIC with the analytic (and bootstrap) WVIC of the joint fit, the chosen
/// and recommended models, and the recommended model's joint fit with its physical tables.
std::string joint_select_text(const Json& doc, const io::SignalSet& set,
                              const std::vector<pipeline::ReplicateGroup>& groups,
                              const pipeline::JointSelectStudy& study, const std::string& estimator,
                              const TextOptions& options);

// ---- wv ----

/// `gmwm wv`'s table per column (robust: beside the classical WV, with the contamination flags).
std::string wv_text(const io::SignalSet& set, const pipeline::WvStudy& study);
/// The --csv table: one row per column and level (numbers in their shortest exact form).
std::string wv_csv(const io::SignalSet& set, const pipeline::WvStudy& study);
/// `gmwm wv --adev`'s Allan deviation table and noise figures per column (`units` per column).
std::string adev_text(const io::SignalSet& set, const pipeline::WvStudy& study, const std::vector<std::string>& units);
/// The --adev-csv table: one row per column and averaging factor.
std::string adev_csv(const io::SignalSet& set, const pipeline::WvStudy& study);

// ---- gap, gap-check ----

/// The last line of gap's summary-only text: where the details are.
inline constexpr const char* kGapDetailsHint =
    "(--verbose: per column the levels against the reference band, the candidate effects, the shrinkage and "
    "the effect's parameters; --json, --report: everything)\n";

/// `gmwm gap`'s text: the summary first (each column's headline and how its baseline was
/// converted, the cross-axis lines and, when given, what to change in the configuration); with `verbose` then per column its
/// baseline, levels against the reference band, the candidate effects, the shrinkage and
/// the effect's parameters (else kGapDetailsHint).
std::string gap_text(const io::SignalSet& set, const pipeline::GapStudy& study,
                     const std::optional<pipeline::CorrectedConfig>& corrected, bool verbose);
/// `gmwm gap-check`'s text: the confusion matrix, the per-family power against the oracle's.
std::string gap_check_text(const gap::GapCheckResult& result);

}  // namespace gmwm::report
