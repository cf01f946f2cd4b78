#pragma once
// Physical units of the input columns, so that a simulator's SI noise figures (rad/s,
// m/s^2) can be compared with data recorded in deg/s or g. Declared per sensor kind with
// --units gyro=deg/s,accel=g; SI by default.
#include <map>
#include <optional>
#include <utility>
#include <vector>
#include <string>

namespace gmwm::io {

enum class SensorKind { kGyro, kAccel };
const char* to_string(SensorKind k);
/// "gyro" or "accel" (as to_string writes them), else nullopt.
std::optional<SensorKind> parse_sensor_kind(const std::string& name);
/// The names parse_sensor_kind takes: gyro, accel (gmwm/engine/choice.h: every face's check
/// and refusal of --sensor).
std::vector<std::string> sensor_kind_names();

/// The sensor kind of a column from its name ("gyro_x", "gyr", "omega", "w_RS_S_x" ->
/// gyro; "accel_x", "acc", "alpha", "a_RS_S_x" -> accel), or InputError naming the column.
SensorKind sensor_kind_of_column(const std::string& column);

/// One unit: its name as written and how many of it make one SI unit (rad/s or m/s^2).
struct Unit {
  std::string name;
  double per_si = 1.0;
};

/// A unit name: rad/s, deg/s, deg/h (gyro); m/s^2 (or m/s2), g, mg (accel); InputError
/// otherwise or when it does not belong to `kind`.
Unit parse_unit(const std::string& name, SensorKind kind);

/// A unit of either kind by its name (rad/s, deg/s, deg/h, m/s^2, g, mg) with its kind;
/// InputError naming the six otherwise (a typo is never taken as a label).
std::pair<SensorKind, Unit> parse_any_unit(const std::string& name);

/// The one units convention of the CLI's --units and Python's `units=`: kind=unit pairs
/// ("gyro=deg/s,accel=g"; a column's kind from its name) or one unit name ("deg/s"), which
/// declares its kind and also labels the columns whose name tells no kind.
struct UnitsSpec {
  std::map<SensorKind, Unit> declared;  ///< the kinds the spec names
  std::optional<Unit> plain;            ///< the one unit of a bare spec ("deg/s")
  bool empty() const { return declared.empty(); }
};

/// Parses a units spec ("" gives an empty one); InputError with the option's message.
UnitsSpec parse_units_spec(const std::string& spec);

/// The unit of a column under `spec`: "" for an empty spec; the declared unit of the kind its
/// name tells (SI where that kind is not declared); a bare spec's unit where the name tells no
/// kind; "" otherwise.
std::string unit_of_column(const UnitsSpec& spec, const std::string& column);

/// "--units gyro=deg/s,accel=g": the units per sensor kind (SI where not given).
std::map<SensorKind, Unit> parse_units(const std::string& spec);

/// The kinds "--units" names and nothing else (no SI default): where a unit must be known,
/// not assumed (export). Throws as parse_units.
std::map<SensorKind, Unit> parse_declared_units(const std::string& spec);

/// The SI unit of a kind ("rad/s", "m/s^2").
Unit si_unit(SensorKind kind);

/// The unit of a column of sensor `kind` (or, without one, the kind its name says): the
/// declared unit of that kind in `units`, SI where none is declared; "" when no kind is known.
std::string unit_of_column(const std::map<SensorKind, Unit>& units, std::optional<SensorKind> kind,
                           const std::string& column);

/// The units a sensor kind may be declared in (rad/s, deg/s, deg/h; m/s^2, g, mg).
std::vector<Unit> units_of(SensorKind kind);

/// A unit mix-up seen in a variance ratio (data / baseline at the finest scales).
struct UnitSuggestion {
  Unit unit;            ///< the unit the data look like they are in
  double factor = 1.0;  ///< (unit.per_si / declared.per_si)^2, the ratio a mix-up gives
};

/// Data in `unit` read as `declared` make the data / baseline variance ratio
/// (unit.per_si / declared.per_si)^2 times the sensor's own departure from its datasheet.
/// Returns the unit whose factor explains `variance_ratio` within kUnitFactorTolerance
/// when the ratio itself is at least kUnitRatioMinimum away from 1; nullopt otherwise.
/// The factors of one kind are at least 96x apart (9.80665^2), so one at most matches.
inline constexpr double kUnitFactorTolerance = 2.0;  // a datasheet within 1.41x of the unit in sd
inline constexpr double kUnitRatioMinimum = 10.0;    // no real noise figure is read 10x off in variance by accident
std::optional<UnitSuggestion> suggest_unit(double variance_ratio, SensorKind kind, const Unit& declared);

}  // namespace gmwm::io
