#pragma once
// The gap study of a signal set (docs/gap.md): each column's baseline (a fully given model,
// a simulator's configuration or a fitted family), its WVs, the unit check, the diagnosis
// (gap/gap.h) and the cross-axis correlations. What `gmwm gap` and Python's
// gmwm.gap both run; they differ only in how they write the result.
//
//   gmwm::pipeline::GapStudyOptions o;
//   o.baseline = gmwm::pipeline::ConfigBaseline{gmwm::io::read_kalibr_imu_yaml(path, freq, units), path};
//   const gmwm::pipeline::GapStudy s = gmwm::pipeline::study_gap(set, o);
//   // s.columns[k].result.headline, s.cross_axis ...

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "gmwm/engine/model.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/gap/cross_axis.h"
#include "gmwm/gap/gap.h"
#include "gmwm/pipeline/first_level.h"

namespace gmwm::pipeline {

/// A model with every value given ("WN(sigma2=2.5e-5)+RW(gamma2=1e-12)").
struct ModelBaseline {
  ModelSpec spec;
};
/// A simulator's noise configuration (a Kalibr imu.yaml, an SDF) already read; `path` names
/// it in messages.
struct ConfigBaseline {
  io::SimConfig config;
  std::string path;
};
/// A family fitted on each column first ("AR1+WN+RW"): the study says what it lacks.
struct FitBaseline {
  ModelSpec spec;
};
using GapBaselineSource = std::variant<ModelBaseline, ConfigBaseline, FitBaseline>;

struct GapStudyOptions {
  GapBaselineSource baseline;
  /// Levels and alpha of the WVs (the robust WV uses the same).
  WvOptions wv;
  /// The data's units per sensor kind (io::parse_units); SI where absent.
  std::map<io::SensorKind, io::Unit> units;
  /// True when the units were declared (the JSON then names each column's unit).
  bool units_declared = false;
  /// Every column is this sensor (else each column's name tells it).
  std::optional<io::SensorKind> sensor;
  /// A temperature column: taken out of the set, each signal's coupling to it is tested.
  std::string temperature_column;
  /// Off: diagnose even when a column's finest scales sit at a unit factor from the baseline.
  bool unit_check = true;
  /// The first level compared with the baseline (tau = 2^level samples; first_level.h): the
  /// finer ones are shown, not compared, not fitted. kAutoFirstLevel (the default): each
  /// column's first_fit_level, above the scales its held or interpolated samples smooth (a
  /// diagnosis there names effects of the repetition, not the sensor's), 1 where its samples
  /// do not repeat.
  int first_level = kAutoFirstLevel;
  /// The diagnosis' settings, handed down to every column: reference replicates, seed
  /// (every column's: a column's diagnosis does not depend on the others listed, and
  /// columns with one baseline share its reference), test level (also the cross-axis test's), practical effect
  /// size, the candidate effects, the stepwise limit, the deciding coefficients and the
  /// candidates' fit settings. Its estimator, refit_baseline, context, unit and progress
  /// are the study's to set (per column) and must be left as default-constructed.
  gap::GapOptions gap;
  /// Called with (steps done, steps in all) while the columns are diagnosed.
  std::function<void(double, double)> progress;

  /// Empty when valid, else what is wrong (naming the option).
  std::string Validate() const;
};

/// One column's study.
struct GapColumnStudy {
  std::string name;
  /// The data's unit when declared or given by a simulator's SI figures, else empty.
  std::string unit;
  Model baseline;
  Eigen::VectorXd theta;
  /// How the baseline was obtained (a simulator's figures converted, a bias taken as RW, a fit).
  std::vector<std::string> conversions;
  /// Every level of the column's WVs; the diagnosis took them from result.first_level on.
  WaveletVariance wv, robust_wv;
  gap::GapResult result;
};

struct GapStudy {
  std::vector<GapColumnStudy> columns;
  /// Pairs of columns tested for cross-axis wavelet correlation (significant ones flagged).
  std::vector<gap::CrossAxisPair> cross_axis;
  /// "model", "fit SPEC", or the simulator configuration's source.
  std::string baseline_source;
  std::string temperature_column;
  int replicates = 0;
  std::uint64_t seed = 0;
  /// Wall time of the WVs and of the diagnoses.
  double wv_seconds = 0.0, gap_seconds = 0.0;
};

/// A column's baseline from a simulator configuration as study_gap takes it: the kind's
/// (or the column's axis's) model with its values, a Gauss-Markov bias whose correlation
/// time spans many records of n samples taken as the random walk it is over the record.
struct ColumnBaseline {
  Model model;
  Eigen::VectorXd theta;
  std::vector<std::string> conversions;
};
/// std::nullopt when the configuration has no term for the column's sensor (or axis).
std::optional<ColumnBaseline> config_baseline(const io::SimConfig& config, io::SensorKind kind,
                                              const std::string& column, std::int64_t n);

/// The unit guard every face applies before it compares data with a baseline (gap, the web
/// app's overlay): when the data's WV at the finest scales is near a unit factor times the
/// baseline's ((180/pi)^2 for deg/s read as rad/s, 9.80665^2 for m/s^2 read as g, ...), the
/// data are in another unit than `units` says (SI where the kind is absent): throws
/// InputError "PATH: column 'C': ... give --units KIND=UNIT (or --no-unit-check ...)".
/// Nothing for a column that is neither a gyro nor an accelerometer (`sensor` unset and its
/// name tells neither).
void check_baseline_units(const std::string& path, const std::string& column, const WaveletVariance& wv,
                          const Model& baseline, const Eigen::VectorXd& theta, std::optional<io::SensorKind> sensor,
                          const std::map<io::SensorKind, io::Unit>& units);

/// Runs the study on `set` (the temperature column, when named, is taken out of it).
/// Throws InputError for invalid options, a baseline without values, a simulator file
/// with no figure for a column's sensor, a unit mix-up (unless unit_check is off), a failed
/// fit, or a model with more parameters than the WV has levels.
GapStudy study_gap(io::SignalSet& set, const GapStudyOptions& options);

}  // namespace gmwm::pipeline
