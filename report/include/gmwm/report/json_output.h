#pragma once
// The JSON documents of the `gmwm` commands (docs/cli.md "JSON": the field names are a
// contract). Every document has the common top level
//   {"tool": "gmwm", "version": "...", "command": "...", "columns": [...], "run": {...}}
// where each element of "columns" has "name", "n", "freq" plus the command's fields, and
// "run" holds everything that varies between identical runs (timings, threads, host,
// date), so that two runs compare equal once "run" is removed.
//
// Numbers keep full precision (shortest round-trip form); NaN and infinities are written
// as null. Nothing here writes files: callers build the whole document first, then write
// it with write_file_atomically (no partial output on failure).
//
//   auto doc = gmwm::report::json_document("wv");
//   doc["columns"].push_back(gmwm::report::wv_column_json(column, wv));
//   gmwm::io::write_file_atomically(path, gmwm::report::dump_json(doc));

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/gap/gap.h"
#include "gmwm/gap/gap_check.h"
#include "gmwm/selection/select.h"
#include "gmwm/robust/contamination.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/pipeline/corrected_config.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/wv_study.h"

namespace gmwm::report {

/// JSON objects keep their insertion order ("tool", "version", "command", ... first).
using Json = nlohmann::ordered_json;

/// The project's version ("0.1.0").
std::string version();

/// A number, or null when not finite.
Json json_number(double x);

/// What every element of "columns" starts with.
struct ColumnInfo {
  std::string name;
  std::int64_t n = 0;
  double freq = 0.0;        ///< Hz
  bool freq_known = false;  ///< "freq" is null when false
  std::string unit;         ///< the data's unit ("deg/s") when declared, else empty
};

/// The run-dependent facts, written under "run".
struct RunInfo {
  int threads = 0;                        ///< TBB's allowed parallelism
  std::map<std::string, double> seconds;  ///< named timings, e.g. {"read", 0.12}
  std::vector<std::string> argv;          ///< the command line
};

/// {"tool", "version", "command", "columns": []} (no "run": see add_run_info).
Json json_document(const std::string& command);

/// Adds "run": {"threads", "seconds": {...}, "host", "date" (UTC, ISO 8601), "argv"}.
void add_run_info(Json& doc, const RunInfo& run);

/// What the timestamp column says: {"column", "unit", "unit_source", "samples",
/// "median_step_seconds", "estimated_freq", "gaps", "largest_gap_seconds", "disorder",
/// "given_freq"}.
Json timing_json(const io::TimingReport& timing);
/// A record's timing in the documents: timing_json with the samples the stamps show missing
/// ("missing_samples"), how the gaps were taken ("gap_handling": "windows" or "join") and
/// whether the studies read them as missing ("gaps_read_as_missing").
Json record_timing_json(const io::SignalSet& set);
/// One column's held and interpolated samples (io::find_repeated_samples): the shares, the
/// pattern, where, and the finest scale read without their smoothing, with the one-line
/// summary. The documents' "repeated_samples" (a list over the columns where some were
/// found) and gmwm.read's Recording.repeated_samples.
Json repeated_samples_json(const io::Signal& signal, double freq, bool freq_known);
/// The record's "timing" (record_timing_json, with a timestamp column) and, when reading
/// converted increments or decimated, "conditioning": data, decimation, its filter, the rate
/// before it and the one-line summary (io::conditioning_summary); "repeated_samples" when a
/// column's samples repeat.
void add_record_json(Json& doc, const io::SignalSet& set);

/// {"name", "n", "freq"}.
Json column_json(const ColumnInfo& column);

/// The "levels" list of a WV: {"level", "tau", "tau_seconds", "wv", "ci_low", "ci_high",
/// "coefficients"} per level (tau_seconds null when the rate is unknown), plus "partial"
/// when the WV counts the windows read that miss samples, and "note" when it has one for
/// the level.
Json wv_levels_json(const WaveletVariance& wv, double freq, bool freq_known);

/// A "wv" column: column_json + "estimator", "efficiency", "alpha", "levels".
Json wv_column_json(const ColumnInfo& column, const WaveletVariance& wv);

/// A robust "wv" column: wv_column_json of the robust WV, each level also with
/// "classical_wv", "robust_to_classical", "ci_disjoint", "contaminated" (docs/cli.md) and
/// "rounding_ratio" (what the data's rounding alone makes of the ratio), "tail_share";
/// the column with "quantization": {"detected", "quantum"}.
Json robust_wv_column_json(const ColumnInfo& column, const WaveletVariance& robust,
                           const std::vector<robust::LevelDiagnostic>& diagnostic,
                           const robust::Quantization& quantization);

/// One row of the parameter table of a fit, in display units (SIN's f in Hz, ...).
struct ParameterRow {
  std::string process;  ///< "AR1"
  int component = 0;    ///< 1-based position in the canonical model
  std::string name;     ///< "phi"
  double value = 0.0, se = 0.0, ci_low = 0.0, ci_high = 0.0;
  std::string interval;  ///< to_string(IntervalKind): "two-sided", "one-sided", ... ("" without inference)
};

/// The fit-quality fields: {"rejected" (GoF p < 0.05), "verdict" (rejection_summary, or
/// null), "worst_levels": [{level, tau, tau_seconds, ratio, z}], "degenerate",
/// "degeneracy" (or null)}.
Json fit_quality_json(const FitResult& fit, double freq, bool freq_known);

/// The parameter rows of a fit (canonical order; NaN where inference is unavailable).
std::vector<ParameterRow> parameter_rows(const FitResult& fit);

/// The parameter rows as JSON: [{process, component, name, value, se, ci_low, ci_high, interval}]
/// (empty when the fit has no usable values).
Json parameters_json(const FitResult& fit);

/// A "fit" column: column_json + "model", "model_structure", "parameters", "objective",
/// "gof", "status", "message", "notes", "evaluations", "omega", "implied_wv", "levels".
Json fit_column_json(const ColumnInfo& column, const WaveletVariance& wv, const FitResult& fit, OmegaKind omega);

/// The fit a selection's ranking row stands for, as select_column_json lists it: the
/// first-ranked row's refit with inference (Selection::best_fit), any other row's effective
/// model with its own estimates, objective and goodness of fit (no intervals). One
/// definition, so that no page shows a row's model with another row's fit.
FitResult ranking_row_fit(const selection::Selection& sel, const selection::RankedModel& r);

/// A "select" column (docs/cli.md): column_json + "full_model", "best" (canonical, no values),
/// "best_model" (with values), "penalty", "representation_violations", "ranking" (rank, model,
/// objective, optimism, criterion, optimism_analytic, optimism_bootstrap,
/// optimism_bootstrap_se, rank_analytic, rank_bootstrap, gof_p_value, parameters, and
/// "optimism_note" when the analytic optimism dropped boundary components), "best_fit"
/// (the first-ranked model with inference, as a fit column's fields) and "levels".
Json select_column_json(const ColumnInfo& column, const WaveletVariance& wv, const selection::Selection& sel,
                        selection::Penalty penalty);

/// A "gap" column (docs/cli.md): column_json + "baseline_model", "gap" {detected, p_value,
/// statistic, bands, levels, windows (null: not computed)}, "attribution" {effect, steps,
/// model, parameters, event (STEP/TRANSIENT: sample, time_seconds, size, time_constant
/// [_seconds], level, statistic, threshold; else null), event_test {statistic, threshold}
/// (null without the series), temperature {coupling, ci_low, ci_high, z, threshold,
/// significant} (null without a temperature channel), drift {omega (per sample), ci_low,
/// ci_high, z, threshold, significant} (the end-segment trend test; null without the
/// series), step_drops (G removed by each step; "effect" is the largest), candidates},
/// "shrinkage" {...},
/// "conversions" and "notes". The effect's parameters carry their bootstrap CIs and
/// "physical" quantities (engine/physical.h) in the column's unit ("U" when undeclared);
/// "navigation" {horizon_seconds, rms_without, rms_with, unit}: the noise's integral.
Json gap_column_json(const ColumnInfo& column, const gap::GapResult& gap, const std::vector<std::string>& conversions);

/// The WV study's document (json_document("wv") filled): "input", "timing" and "columns":
/// wv_column_json (robust_wv_column_json for a robust study), with "unit", "allan" and
/// "noise_figures" when the study has the Allan deviation; `units` as fit_document's.
Json wv_document(const io::SignalSet& set, const pipeline::WvStudy& study, const std::vector<std::string>& units);

/// The fit study's document (json_document("fit") filled): "input", "model_spec", "seed",
/// "timing" and "columns": fit_column_json with "unit", "continuous", "kalman" (at
/// `filter_rate`, 0: the data's rate), "allan" and "noise_figures". `units[k]` is column
/// k's declared unit ("" when none; empty vector: none declared).
Json fit_document(const io::SignalSet& set, const pipeline::FitStudy& study, const std::vector<std::string>& units,
                  double filter_rate);

/// The selection study's document (json_document("select") filled): "input", "model_spec"
/// (the models joined by ';'), "mode" ("sub-models" or "listed"), "optimism", "omega",
/// "seed", "timing" and "columns": select_column_json with "unit", "best_continuous",
/// "best_kalman" (at `filter_rate`), "allan" and "noise_figures"; `units` as fit_document's.
Json select_document(const io::SignalSet& set, const pipeline::SelectStudy& study,
                     const std::vector<std::string>& units, double filter_rate);

/// AGMWM (the replicates' own estimates averaged) as a fit of the joint model, and the
/// replicate-t interval as the joint fit's intervals: for parameter_rows (display units).
FitResult agmwm_as_fit(const JointFitResult& r);
FitResult replicate_bootstrap_as_fit(const JointFitResult& r, const ReplicateBootstrap& b);

/// The joint fit's document (json_document("fit") with "joint": true, "estimator"): per
/// axis its replicates (source, n, levels, objective share, own fit), the joint model and
/// parameters, AGMWM, the replicate-t interval and the shared-theta test, and the physical
/// fields of the joint model (add_physical_fields: "unit" from `units[k]` for group k,
/// "continuous", "kalman" at `filter_rate` (0: the data's rate), "noise_figures") (docs/cli.md).
Json joint_fit_document(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                        const pipeline::JointFitStudy& study, const std::vector<std::string>& units = {},
                        double filter_rate = 0.0);

/// The selection over replicates' document (json_document("select") with "joint": true,
/// "optimism" "replicates" or "all"): per axis the chosen, recommended and analytic/bootstrap
/// choices and the ranking with its three WVICs, and the recommended model's joint fit:
/// "best_model" (with values), "best_fit" {status, objective, gof}, and its physical fields
/// ("unit", "best_continuous", "best_kalman", "noise_figures"); `units`, `filter_rate` as
/// joint_fit_document's.
Json joint_select_document(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                           const pipeline::JointSelectStudy& study, const std::vector<std::string>& units = {},
                           double filter_rate = 0.0);

/// The gap diagnosis's self-check document (json_document("gap-check") filled): the
/// settings, the confusion matrix, power per family and strength, each family's
/// detection/location and oracle comparison, and the case list (docs/gap.md).
Json gap_check_document(const gap::GapCheckOptions& options, const gap::GapCheckResult& result);

/// The gap study's document (json_document("gap") filled): "input", "baseline_source",
/// "replicates", "seed", "timing", "temperature_column", "cross_axis" {tested, significant
/// [{a, b, tau, tau_seconds, rho, z}]} and "columns" (gap_column_json). `set` is the set
/// the study ran on.
Json gap_document(const io::SignalSet& set, const pipeline::GapStudy& study);

/// The corrected configuration (io/corrected_config.h) as the gap document's "corrected":
/// {format, content, header [..], changes [{field, input, corrected, unit, changed}],
/// columns [{name, expressible, full, not_expressible [..], verdict (pipeline::to_string of
/// CorrectedVerdict), why, warnings [..], gap_left {input, config, full:
/// {objective, null_mean, levels_outside, p_value, navigation_rms, remaining [bands]}}}]}.
/// Band times in seconds when `freq` > 0.
Json corrected_config_json(const pipeline::CorrectedConfig& c, double freq);

/// The data's Allan deviation and the model's on the same grid: {"points_per_octave"?,
/// "alpha", "tau" [s], "m", "adev", "ci_low", "ci_high", "edf", "model" (null entries
/// when no model), and with missing samples "complete" and "partial" (each point's windows
/// without one, and those read that miss some)}, in the column's unit.
Json allan_json(const AllanDeviation& adev, const std::vector<double>& model_adev);

/// One read-off: {"value", "low", "high", "status", "tau", "region_from", "region_to",
/// "how", "components": [{"component", "share"}]}.
Json readoff_json(const Readoff& r);

/// The figures to use: {"white"/"walk"/"instability"/"quantization"/"ramp" (N, K, B, Q, R):
/// {value, low, high, unit, source ("model"|"data"|"bound"), status, tau, how, note,
/// components, "model": readoff, "data": readoff}} in the column's unit ("U" when
/// undeclared). Q and R were added beside N, K and B (issue 48): a reader of older documents
/// finds no "quantization" or "ramp".
Json noise_figures_json(const ChosenFigures& figures, const std::string& unit);

/// The units of N, K, B, Q and R for a data unit ("deg/s" -> deg/s/sqrt(Hz),
/// deg/s^2/sqrt(Hz), deg/s, deg, deg/s^2); "U" patterns when the unit is empty.
struct FigureUnits {
  std::string white, walk, instability, quantization, ramp;
};
FigureUnits figure_units(const std::string& unit);

/// A fit's parameters as continuous quantities (engine/physical.h) with their intervals
/// mapped from the discrete CIs and unit strings in the column's unit ("U" when it is not
/// declared): [{process, component, name, value, ci_low, ci_high, unit, convention}];
/// empty without a known sampling rate or a usable fit.
Json continuous_json(const FitResult& fit, const ColumnInfo& column);

/// A fit's Kalman-filter terms at `filter_rate` Hz (engine/kalman.h): {filter_rate, terms:
/// [{process, component, role, q, q_unit, transition, discrete, discrete_unit, note}]}.
/// With `figures`, the terms of the model as a whole come first (kalman_terms of
/// noise_figures.h: R from N, the bias random walk from K, a Gauss-Markov state for B),
/// their "process" "N, K, B", then the quantization's measurement noise from a read Q,
/// its "process" "Q"; the per-component terms follow.
Json kalman_json(const FitResult& fit, const ColumnInfo& column, double filter_rate,
                 const ChosenFigures* figures = nullptr);

/// A fitted column's physical fields: "unit" (null when not declared), the continuous
/// parameters and Kalman terms under the given keys, "allan" as given, and "noise_figures"
/// (null without `figures`). What every fitted column of fit/select documents carries, joint
/// ones included, so that export can tell the unit its numbers are in.
void add_physical_fields(Json& col, const FitResult& fit, const ColumnInfo& info, double filter_rate,
                         const ChosenFigures* figures, Json allan, const char* continuous_key, const char* kalman_key);

/// The document as text: pretty-printed (2 spaces), ending with a newline.
std::string dump_json(const Json& doc);

}  // namespace gmwm::report
