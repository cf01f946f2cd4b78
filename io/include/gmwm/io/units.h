#pragma once
// Physical units of the input columns, so that a simulator's SI noise figures (rad/s,
// m/s^2) can be compared with data recorded in deg/s or g. Declared per sensor kind with
// --units gyro=deg/s,accel=g; SI by default.
#include <map>
#include <string>

namespace gmwm::io {

enum class SensorKind { kGyro, kAccel };
const char* to_string(SensorKind k);

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

/// "--units gyro=deg/s,accel=g": the units per sensor kind (SI where not given).
std::map<SensorKind, Unit> parse_units(const std::string& spec);

/// The SI unit of a kind ("rad/s", "m/s^2").
Unit si_unit(SensorKind kind);

}  // namespace gmwm::io
