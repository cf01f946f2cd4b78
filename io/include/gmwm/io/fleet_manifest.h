#pragma once
// A fleet's manifest (`gmwm fleet MANIFEST`): one row per recording of a unit, CSV or YAML.
//
//   path,unit,model,topic,columns,units,rate,group
//   imu1.csv.gz,SN0001,ADIS16405,,,"gyro=deg/s,accel=g",100,line-A
//
//   recordings:                          # YAML: a list of maps with the same keys
//     - {path: imu1.csv.gz, unit: SN0001, model: ADIS16405, units: "gyro=deg/s,accel=g"}
//
// path, unit (the unit's id, unique) and model (the sensor model, e.g. ADIS16405) are
// required; topic, columns (as --columns), units (as --units), rate (Hz, as --freq) and
// group (default: the model) are optional. A relative path is the manifest's folder's.

#include <optional>
#include <string>
#include <vector>

namespace gmwm::io {

struct FleetRecording {
  int row = 0;                 ///< the manifest's line (CSV) or the list item's line (YAML), 1-based
  std::string path;            ///< resolved against the manifest's folder
  std::string unit;            ///< the unit's id
  std::string model;           ///< the sensor model
  std::string topic;           ///< a log's topic (as --topic), or empty
  std::string columns;         ///< as --columns, or empty (every signal column)
  std::string units;           ///< as --units, or empty
  std::optional<double> rate;  ///< Hz, as --freq
  std::string group;           ///< the group it is summarised in (the model when not given)
};

struct FleetManifest {
  std::string path;
  std::vector<FleetRecording> recordings;
};

/// The largest manifest read (a fleet of ~10^5 recordings' rows).
inline constexpr std::size_t kMaxManifestBytes = std::size_t{16} << 20;

/// The longest field of a row, bytes: Linux's PATH_MAX (4096, <linux/limits.h>), the longest
/// path a row can name; a unit id, sensor model, topic, column list, units spec, rate or group
/// is far shorter. A longer field is refused with the manifest (one line naming its row and
/// field) before anything reads it: every name reaches the table, the JSON and the terminal.
inline constexpr std::size_t kMaxManifestFieldBytes = 4096;

/// A row's `columns` as io::ReadOptions::columns takes them: split at commas, each trimmed.
std::vector<std::string> manifest_columns(const std::string& columns);

/// Reads a manifest (YAML when it ends in .yaml or .yml, else CSV), UTF-8 text (a
/// byte-order mark skipped). Throws InputError naming "MANIFEST:LINE" for what makes the
/// file unreadable as a whole: UTF-16 or a NUL byte, no header or an
/// unknown field in it, a malformed row, a field longer than kMaxManifestFieldBytes, an
/// empty manifest.
FleetManifest read_fleet_manifest(const std::string& path);

/// Every recording's problems checked before any work, one line each naming
/// "MANIFEST:ROW": a required field empty, a unit id given twice, a rate that is not one, a
/// bad units spec, and what reading would refuse (a missing file, an unknown column: the
/// file's header is read, io::check_signals). Empty when every row is fine.
std::vector<std::string> fleet_manifest_problems(const FleetManifest& manifest);

}  // namespace gmwm::io
