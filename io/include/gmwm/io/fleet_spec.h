#pragma once
// A fleet's spec mask (`gmwm fleet --spec FILE`): the datasheet limits every unit of a sensor
// model is checked against. The figures are a datasheet's, in the datasheet yaml that
// `gmwm gap --datasheet` reads (docs/gap.md, "A datasheet as the baseline"), each read as a
// limit the unit must not exceed:
//
//   ADIS16405:                              # a sensor model, as the manifest's `model` column
//     gyroscope:
//       angle_random_walk: 2.0 deg/sqrt(h)  # N at most
//       in_run_bias_stability: 0.007 deg/s # the Allan deviation's minimum at most
//       rate_random_walk: 10 deg/h/sqrt(h)  # K at most
//     accelerometer:
//       velocity_random_walk: 0.2 m/s/sqrt(h)
//       bias_instability: 0.2 mg            # IEEE 952's B at most
//   BMI088: {gyroscope: {noise_density: 0.014 deg/s/sqrt(Hz)}}
//
// A file that is one datasheet (gyroscope / accelerometer / name at its top) applies to every
// model. Every figure needs its unit (a dimension check refuses deg/h for a density).

#include <map>
#include <optional>
#include <string>

#include "gmwm/io/units.h"

namespace gmwm::io {

/// One limit: in SI (rad, m, s) and as the file writes it, where, and which datasheet key gave it.
struct SpecLimit {
  double si = 0.0;
  double value = 0.0;   ///< as written, in `unit`
  std::string unit;     ///< as written ("deg/sqrt(h)")
  std::string written;  ///< value and unit as text ("2 deg/sqrt(h)")
  std::string where;    ///< "<path>:<line>"
  std::string key;      ///< e.g. "angle_random_walk", "in_run_bias_stability"
};

/// A sensor's limits: N (white noise density), K (random walk), and the bias: IEEE 952's B
/// (bias_instability), or the Allan deviation's minimum (in_run_bias_stability: 0.664 B of
/// the unit's read-off is that minimum).
struct SensorLimits {
  std::optional<SpecLimit> white, walk, instability;
  bool instability_is_minimum = false;
};

struct FleetSpec {
  std::string path;
  /// Per sensor model; the key "" holds a single datasheet's limits, for every model.
  std::map<std::string, std::map<SensorKind, SensorLimits>> by_model;

  /// The limits of `model`'s `kind`, or nullptr when the spec has none.
  const SensorLimits* limits(const std::string& model, SensorKind kind) const;
};

/// Reads a spec file. Throws InputError "<path>:<line>: ..." as the datasheet reader does
/// (an unknown key or figure, a missing or wrong unit, a figure given twice, invalid YAML),
/// and for a model's entry that is not a map.
FleetSpec read_fleet_spec(const std::string& path);
/// The same from the file's text; `path` names it in messages.
FleetSpec parse_fleet_spec(const std::string& text, const std::string& path);

}  // namespace gmwm::io
