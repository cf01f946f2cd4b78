#pragma once
// The corrected simulator configuration of a gap study (docs/gap.md, "The corrected
// configuration"): the diagnosis' final model of every column written back in the
// baseline's own format (Kalibr imu.yaml, gz-sensors <sensor>, RotorS plugin, or a model
// string), with the same figures `export` writes for that model (IEEE 952 read-offs
// checked against the data's Allan deviation), a header saying which fields changed, from
// what to what and why, and what the format cannot express; then the file read back
// exactly as `gap --kalibr/--gazebo` would read it and assessed on the diagnosis' own
// yardstick (the gap left with the expressible config and with the full model).
// A simulator's file is the input's text with the changed figures edited in place: the
// axes and sensors not diagnosed, comments and everything around the IMU stay as written.
//
//   const gmwm::pipeline::CorrectedConfig c = gmwm::pipeline::corrected_config(set, study, options);
//   write_file_atomically(path, c.content);   // c.changes, c.columns[k].expressible ...

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/gap/gap.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/gap_study.h"

namespace gmwm::pipeline {

/// One field of the configuration, in the format's own unit.
struct ConfigChange {
  std::string field;
  double input = std::numeric_limits<double>::quiet_NaN();      ///< NaN: not in the input file
  double corrected = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not in the corrected file
  std::string unit;
  bool changed = false;  ///< beyond kUnchangedRelative of the input (or added / dropped)
};

/// Two figures closer than this (relative) are the same figure: well below any figure's
/// uncertainty (a noise density read off 1e6 samples is known to ~0.1% at best), well
/// above rounding (the export writes the shortest text that reads back exactly).
inline constexpr double kUnchangedRelative = 1e-3;

/// What the corrected file does with the figures that hold a column (docs/gap.md, "The
/// corrected configuration"): a gz-sensors axis, or a sensor's figures in the formats with
/// one figure per sensor (Kalibr, RotorS, a datasheet).
enum class CorrectedVerdict {
  kWritten,    ///< the diagnosis' figures are written
  kUnchanged,  ///< they are the input's (every figure within kUnchangedRelative)
  /// The input's figures are kept: the figure also holds axes of the sensor that --columns
  /// left out of the run (one figure for three axes cannot change one without the others).
  kKeptSubset,
  /// The input's figures are kept: they are not where the input's text says (a flow-style
  /// YAML map, say), so they cannot be edited in place.
  kKeptUnplaced,
};
/// "written", "unchanged", "kept: holds axes not diagnosed", "kept: not found in the input's text".
const char* to_string(CorrectedVerdict v);

/// One column: its baseline as the corrected file gives it, and the gap left.
struct CorrectedColumn {
  std::string name;
  Model expressible;  ///< the corrected file's model for this column (data units, per sample)
  Eigen::VectorXd expressible_theta;
  Model full;  ///< the diagnosis' final model
  Eigen::VectorXd full_theta;
  /// On the diagnosis' yardstick: the input baseline, the corrected file, the full model.
  gap::GapAssessment before, with_config, with_full;
  /// Components of the full model the format holds no field for (e.g. "QN(Q2=...)").
  std::vector<std::string> not_expressible;
  CorrectedVerdict verdict = CorrectedVerdict::kWritten;
  std::string why;  ///< one line: why the input's figures are kept ("" when written)
  /// One line each, said in the header, on the terminal, in the JSON and the report: the
  /// file is worse than its input on this column (kWorseThanInputTolerance), or more
  /// optimistic than the data's model (kOptimisticShare).
  std::vector<std::string> warnings;
};

/// A corrected file is worse than its input on a column when its objective exceeds the
/// input's by more than this share, or more levels lie outside the model's band: the figures
/// are written to 4 significant digits, which moves the objective by far less.
inline constexpr double kWorseThanInputTolerance = 0.01;
/// A corrected file is more optimistic than the data's model when its integrated error
/// after the navigation horizon is below the full model's by more than this share: a
/// filter tuned from it then trusts the IMU that much too far (issue 43: a Kalibr file's
/// 60 s gyro error 0.37 deg against 1.18-1.64 deg for the data's own model).
inline constexpr double kOptimisticShare = 0.2;

/// CorrectedColumn::warnings from its assessments (none for a column whose figures the file
/// keeps as the input's, or that the format cannot express at all).
std::vector<std::string> corrected_column_warnings(const CorrectedColumn& col);

struct CorrectedConfig {
  std::string format;               ///< "kalibr", "gz-sdf", "rotors" or "model"
  std::string content;              ///< the file's text, header included
  std::vector<std::string> header;  ///< the header lines (without comment markers)
  std::vector<ConfigChange> changes;
  std::vector<CorrectedColumn> columns;
};

struct CorrectedConfigOptions {
  std::map<io::SensorKind, io::Unit> units;  ///< the data's units (SI where absent)
  std::optional<io::SensorKind> sensor;      ///< every column is this sensor
  std::string baseline_path;                 ///< the input configuration's path, for the header
  /// The run's columns were chosen among the record's (--columns): a figure that holds a
  /// sensor's three axes changes only when all three were diagnosed.
  bool columns_chosen = false;
};

/// The corrected configuration of `study` (run on `set`, whose series it reads for the
/// Allan deviation). Throws InputError when the study's rate is unknown and the baseline is
/// a simulator's configuration (its figures are densities), or when the export of the
/// final models fails (one line).
CorrectedConfig corrected_config(const io::SignalSet& set, const GapStudy& study, const GapStudyOptions& options,
                                 const CorrectedConfigOptions& o);

}  // namespace gmwm::pipeline
