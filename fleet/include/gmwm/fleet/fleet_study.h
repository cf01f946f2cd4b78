#pragma once
// The fleet study (what `gmwm fleet MANIFEST` runs): every recording of a manifest analysed
// the same way (the selection over a maximal model with its noise figures, as `gmwm select`),
// one row per unit x axis: N, K, B, Q, R with their intervals, the chosen model and its goodness of
// fit. A recording that cannot be read or analysed is a row with its one-line reason, never
// a stopped run. report::fleet_document / fleet_csv / fleet_text write it.
//
// The study is a pipeline of named stages (fleet_study.cc):
//   plan      each recording's cache key (fleet_cache.h: its content's hash, how it is read,
//             the options) and its record when the cache holds one;
//   run       the other recordings as tasks (fleet_record.h), here one after another or by
//             the caller's runner (a Dask cluster through the Python module), each record
//             stored in the cache as soon as it is done: an interrupted run loses at most the
//             recordings in flight, and a re-run computes only what is missing or changed;
//   assemble  the rows, labelled from the manifest;
//   summarise the distribution of N, K, B, Q, R per group and axis and the units that stand out
//             (fleet_summary.h).
//
//   const io::FleetManifest m = io::read_fleet_manifest("fleet.csv");
//   gmwm::fleet::FleetStudyOptions o;
//   o.model = "2*AR1+WN+RW";
//   o.cache_dir = ".gmwm-cache";
//   const gmwm::fleet::FleetStudy s = gmwm::fleet::study_fleet(m, o);

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/fleet_manifest.h"
#include "gmwm/io/fleet_spec.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/pipeline/first_level.h"
#include "gmwm/selection/select.h"

namespace gmwm::fleet {

/// One recording to analyse: its index in the manifest and the task's text (fleet_task_text:
/// how to read it and the options), what a worker elsewhere needs to run it (run_fleet_task).
struct FleetTask {
  std::size_t index = 0;
  std::string text;
};

/// Runs `tasks` and hands each one's record text (run_fleet_task's) to `done(k, text)`, k
/// the task's position in `tasks`, in any order, from the thread that called the runner.
/// A task that throws is the runner's to turn into a record (failed_record_text); a runner
/// that cannot go on (its cluster is gone) throws, and the records handed over so far stay
/// cached. May throw gmwm::Cancelled.
using FleetRunner = std::function<void(const std::vector<FleetTask>& tasks,
                                       const std::function<void(std::size_t, const std::string&)>& done)>;

/// A baseline every unit's recording is diagnosed against (`gmwm gap`'s diagnosis, docs/gap.md):
/// a simulator's configuration (Kalibr imu.yaml, Gazebo SDF) or a datasheet yaml, as text so
/// that a task carries it to wherever it runs, read at each recording's rate and units.
struct FleetGapBaseline {
  io::SimFormat format = io::SimFormat::kKalibr;  ///< kKalibr, kGzSensors or kDatasheet
  std::string name;                               ///< the file's path, in messages
  std::string text;                               ///< the file's content
  std::string imu;                                ///< a Kalibr chain's IMU ("imu1"), or empty
  /// Reference replicates per column (gap's default 200: the level's band and the global
  /// test's held-out replicates; fewer are faster and coarser).
  int replicates = 200;
};

/// The baseline file at `path` read whole (io::read_side_file) and parsed once at
/// `nominal_freq` Hz, so that a file that is not one is refused before any work (InputError
/// naming its line); `imu` names a Kalibr chain's IMU.
FleetGapBaseline read_gap_baseline(io::SimFormat format, const std::string& path, const std::string& imu,
                                   int replicates, double nominal_freq);

struct FleetStudyOptions {
  /// The maximal model every axis's selection ranks the sub-models of.
  ModelSpec model;
  /// The selection's settings (optimism, Omega, penalty, seed, fits), as `gmwm select`'s.
  /// Its callbacks, estimator, bootstrap draw and the fits' caller-given starts and Omega
  /// must be left empty: a task carries the settings as text to wherever it runs.
  selection::SelectOptions select;
  /// Levels and alpha of the WV.
  WvOptions wv;
  /// The first level each axis's selection fits and its gap diagnosis compares (tau =
  /// 2^level samples; pipeline/first_level.h). kAutoFirstLevel (the default): above the
  /// scales a unit's held or interpolated samples smooth, 1 where its samples do not repeat,
  /// so that no unit stands out from its fleet for its driver's copies.
  int first_level = pipeline::kAutoFirstLevel;
  /// Bytes a recording's samples may take in memory (io::ReadOptions); 0: the default.
  double memory_budget = 0.0;
  /// The datasheet limits each unit is checked against (`--spec FILE`; fleet_spec.h): a
  /// check of the assembled rows, not part of any record or cache key.
  std::optional<io::FleetSpec> spec;
  /// Each recording's gap diagnosis against this baseline (none: no diagnosis). Part of the
  /// tasks and of the cache key.
  std::optional<FleetGapBaseline> gap;
  /// The joint model of each group's axis (fleet_joint.h): off by default (it costs a
  /// selection over the group's units per axis: ~20 s for 495 units of 2^18 samples).
  struct Joint {
    bool enabled = false;
    /// Draws of the shared-theta test's bootstrap for groups of at most
    /// kMaxBootstrapTestUnits units (beyond: its chi-square calibration).
    int test_draws = 100;
  } joint;
  /// The folder of cached records (fleet_cache.h); empty: no cache.
  std::string cache_dir;
  /// Where the recordings that are not cached run; empty: here, one after another (each
  /// selection parallel inside).
  FleetRunner runner;
  /// (recordings done, recordings): after each recording (cached ones at once); may throw
  /// gmwm::Cancelled.
  std::function<void(int, int)> progress;

  std::string Validate() const;
};

/// A figure of a unit's axis against its spec limit.
enum class SpecVerdict {
  kPass,     ///< at or below the limit
  kFail,     ///< above it
  kUnknown,  ///< no read-off, or only an upper bound that lies above the limit
};
const char* to_string(SpecVerdict v);

struct SpecCheck {
  char figure = 'N';    ///< 'N', 'K' or 'B'
  io::SpecLimit limit;  ///< as the spec gives it
  /// The unit's figure in the limit's unit (B as 0.664 B, the Allan minimum, when the limit
  /// is an in-run bias stability), with its interval (NaN when unknown).
  double value = NAN, low = NAN, high = NAN;
  SpecVerdict verdict = SpecVerdict::kUnknown;
  std::string note;  ///< one line: the comparison and what the interval says
};

/// One axis of one unit (or, for a recording that failed, the recording: axis empty).
struct FleetRow {
  std::string unit, model, group, path;
  std::string axis;       ///< the column's name
  std::string data_unit;  ///< the column's unit from the manifest's units ("" when not declared)
  /// "ok", or why the recording or the axis has no result (one line).
  std::string status = "ok";
  std::string chosen;            ///< the chosen model with its values
  std::string chosen_structure;  ///< the chosen model without values ("AR1+WN")
  double gof_p = NAN;            ///< the chosen model's own goodness-of-fit p-value
  double freq = NAN;             ///< Hz
  std::int64_t n = 0;            ///< samples
  /// N, K, B, Q, R as the filter should take them (noise_figures.h), in the data's unit.
  ChosenFigures figures;
  bool figures_known = false;
  /// The recording's wall time (read and select) when it was computed, on each of its rows
  /// (a cached row keeps the time it took then).
  double seconds = 0.0;
  bool cached = false;  ///< the row came from the cache
  /// The gap diagnosis against FleetStudyOptions::gap (empty verdict: none asked): "none"
  /// (no gap), "closed" (the effects named in the headline close it), "remains", or
  /// "not diagnosed" (the headline says why: a unit mix-up, a baseline without this sensor).
  std::string gap_verdict, gap_headline;
  double gap_p = NAN;  ///< the global test's p-value against the baseline
  /// The first level the selection fitted (FleetStudyOptions::first_level; 1 unless the
  /// unit's samples repeat or a level was asked).
  int first_level = 1;
  /// Where this axis stands out from its group's (fleet_summary): "N: 4.2x the fleet's
  /// median (robust z 9.1)", one per figure flagged; empty when it does not.
  std::vector<std::string> flags;
  /// Its figures against the spec of its sensor model and kind (`--spec`; empty without one).
  std::vector<SpecCheck> spec;
  /// Why the spec says nothing of this axis ("no limits for model X's gyroscope"), or empty.
  std::string spec_note;
};

/// What an axis leaves besides its row: the curves the report draws and the group's joint
/// model is fitted to.
struct FleetCurves {
  WaveletVariance wv;         ///< the classical WV the selection ran on
  AllanDeviation adev;        ///< the data's Allan deviation (empty without a rate)
  std::vector<double> model;  ///< the chosen model's Allan deviation on adev's grid (may be empty)
  /// The samples the recording's stamps show missing, on its grid (io::SignalSet::missing,
  /// shared by its axes; empty: none): `wv` read the windows without a gap, and the joint
  /// model's simulated units are read through the same gaps.
  std::vector<MissingRun> missing;
};

/// The most units whose shared-theta test is calibrated by its parametric bootstrap (K x B
/// simulated records: 3.7 s for 12 units of 2^18 samples at B = 100); beyond, by its
/// asymptotic chi-square (Newey and West 1987; its level measured at 0-5% where the
/// bootstrap holds 4-5%, tools/bench/results/2026-11-28-joint-scaling.md), as a 495-unit
/// bootstrap takes 213 s per axis.
inline constexpr int kMaxBootstrapTestUnits = 12;

/// Resamples of the units for the replicate-t intervals (every distinct one up to 5 units).
inline constexpr int kJointIntervalDraws = 200;

struct FleetJointModel {
  std::string group, axis;
  int units = 0;  ///< units taken as replicates (their rows "ok", one rate)
  /// The units that stand out from the group on this axis (their rows' flags), left out:
  /// the joint model is the typical unit's, which a few outliers would pull (it pools the
  /// units' variances, a mean, not a median).
  std::vector<std::string> left_out;
  std::string status = "ok";  ///< "ok", or why the group's axis has no joint model (one line)
  /// The unit of the values and figures: the data unit the units share, else the SI unit
  /// (units recorded in different units are converted to it).
  std::string unit;
  double freq = NAN;
  std::int64_t n = 0;                           ///< the longest unit's samples (the figures' averaging factors)
  std::string recommended;                      ///< the selection's recommended model (without values)
  std::string chosen;                           ///< its smallest CV-WVIC (may be larger than the recommended)
  JointFitResult fit;                           ///< the recommended model fitted jointly (fit.joint)
  std::optional<ReplicateTest> test;            ///< the shared-theta test
  std::optional<ReplicateBootstrap> intervals;  ///< replicate-t intervals
  std::optional<ChosenFigures> figures;         ///< N, K, B, Q, R of the joint model
  double seconds = 0.0;
};

/// The z-score beyond which a unit stands out from its group, on log N, log K, log B (the
/// figures are scale quantities: a unit twice as noisy and one half as noisy are as far from
/// the fleet): z = (log x - median) / sqrt(tau^2 + se^2), tau^2 = (MAD / 0.6745)^2 - median(se^2)
/// the spread between units net of the read-offs' own noise, se the unit's own standard error
/// (from its interval). With equal se it is Iglewicz and Hoaglin's modified z-score (1993, "How
/// to Detect and Handle Outliers": |M| > 3.5, M = 0.6745 (x - median) / MAD); a read-off far
/// less precise than the fleet's (a short record, a bias read at few degrees of freedom) needs
/// a larger departure, the random-effects view of an outlier (DerSimonian and Laird 1986).
inline constexpr double kFleetOutlierZ = 3.5;
/// 0.6745 = the standard normal's 75% quantile: MAD / 0.6745 estimates the standard deviation.
inline constexpr double kMadToSigma = 0.6745;
/// Fewer units in a group than this: no flags (the median and MAD of four values are no yardstick).
inline constexpr int kMinUnitsForFlags = 5;

/// The outlier rule (kFleetOutlierZ) of one figure over a group, the one yardstick the
/// summary flags units by and the fleet page draws (issue 45: the page re-derived it).
struct OutlierYardstick {
  /// tau^2: the spread between units on the log scale, net of the read-offs' own noise.
  double between2 = 0.0;
  /// median(se^2) over the group's read-offs: a read-off of the group's typical precision.
  double typical_se2 = 0.0;
  /// sqrt(tau^2 + se^2): the z-score's scale for a read-off of standard error `se`.
  double scale(double se) const;
  /// How far from the median a read-off of standard error `se` may lie before it stands out:
  /// exp(kFleetOutlierZ scale(se)), a factor (its limits are median / reach, median x reach).
  double reach(double se) const;
};

/// A read-off's standard error on the log scale from its interval [low, high] at level
/// 1 - alpha (`z_half` its normal quantile): log(high / low) / (2 z_half), 0 without one.
double log_standard_error(double low, double high, double z_half);

/// One figure of one axis over a group's units.
struct FleetFigureSummary {
  std::string group, axis;
  char figure = 'N';  ///< 'N', 'K', 'B', 'Q' or 'R' (kFigureNames)
  int units = 0;      ///< units with a read-off (bounds left out)
  /// The unit of `median` (N per sqrt(Hz), K per s per sqrt(Hz), Q times s, R per s): the data unit the group's
  /// rows share, else the SI unit (rows declared in different units are converted to it).
  std::string unit;
  double median = NAN;
  /// The spread as a factor: exp(MAD of the logs / 0.6745), e.g. 1.08 = +-8% one sigma.
  double spread = NAN;
  /// The spread between the units themselves, net of the read-offs' noise: exp(tau)
  /// (kFleetOutlierZ); 1 when the read-offs' noise explains all of `spread`.
  double unit_spread = NAN;
  /// The outlier rule's yardstick the units were judged by (tau^2, median se^2).
  OutlierYardstick yardstick;
  std::vector<std::string> flagged;      ///< the units flagged on it
  std::vector<std::string> out_of_spec;  ///< the units above its spec limit (`--spec`)
};

struct FleetStudy {
  std::string manifest;
  std::string model_spec;
  std::vector<FleetRow> rows;               ///< by recording in manifest order, then by axis
  std::vector<FleetCurves> curves;          ///< per row (empty curves for a failed row)
  std::vector<FleetFigureSummary> summary;  ///< per group, axis and figure (fleet_summary)
  std::vector<FleetJointModel> joint;       ///< per group and axis, with options.joint (fleet_joint.h)
  int recordings = 0, failed = 0;
  int cached = 0;  ///< recordings whose record came from the cache
  std::string cache_dir;
  /// What went wrong with the cache, one line each naming the file: an entry that was there
  /// but did not verify (edited, cut short, swapped, of another format: fleet_cache.h; its
  /// recording was computed again), or the folder that could not be written (the records
  /// from then on not cached). For the caller to say (the CLI warns each).
  std::vector<std::string> cache_problems;
  std::string spec_path;     ///< the spec mask's file (empty: none)
  std::string gap_baseline;  ///< the gap baseline's file (empty: no diagnosis)
  double seconds = 0.0;
};

/// Runs the study on every recording of `manifest` (checked first: fleet_manifest_problems
/// is the caller's to report). Throws InputError only for invalid options and a cache folder
/// that cannot be one (check_fleet_cache_dir); each recording's failure is its row.
FleetStudy study_fleet(const io::FleetManifest& manifest, const FleetStudyOptions& options);

/// Each row's figures against `spec` (the limits of its sensor model and of the kind its
/// unit or column name tells); sets FleetRow::spec and spec_note. Called by study_fleet when
/// a spec is given, before fleet_summary.
void check_spec(std::vector<FleetRow>& rows, const io::FleetSpec& spec);

/// The distribution of N, K, B, Q, R per group and axis over the rows that have them (read-offs,
/// not bounds), and the units beyond kFleetOutlierZ (their rows' `flags` set); `alpha` is the
/// level of the figures' intervals (their standard errors). Called by study_fleet;
/// deterministic (the rows' order does not matter).
std::vector<FleetFigureSummary> fleet_summary(std::vector<FleetRow>& rows, double alpha = 0.05);

}  // namespace gmwm::fleet
