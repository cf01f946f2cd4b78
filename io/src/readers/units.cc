#include "gmwm/io/units.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "gmwm/engine/error.h"
#include "gmwm/engine/choice.h"

namespace gmwm::io {
namespace {

// Standard gravity (CGPM 1901, exact): 1 g = 9.80665 m/s^2.
constexpr double kStandardGravity = 9.80665;
constexpr double kDegreesPerRadian = 57.295779513082320877;  // 180 / pi
constexpr double kSecondsPerHour = 3600.0;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool contains(const std::string& s, const char* what) { return s.find(what) != std::string::npos; }

}  // namespace

const char* to_string(SensorKind k) { return k == SensorKind::kGyro ? "gyro" : "accel"; }

namespace {
constexpr SensorKind kSensorKinds[] = {SensorKind::kGyro, SensorKind::kAccel};
}  // namespace

std::optional<SensorKind> parse_sensor_kind(const std::string& name) { return parse_among(name, kSensorKinds); }

std::vector<std::string> sensor_kind_names() { return names_among(kSensorKinds); }

SensorKind sensor_kind_of_column(const std::string& column) {
  const std::string c = lower(column);
  if (contains(c, "gyr") || contains(c, "omega") || c.rfind("w_", 0) == 0) return SensorKind::kGyro;
  if (contains(c, "acc") || contains(c, "alpha") || c.rfind("a_", 0) == 0) return SensorKind::kAccel;
  throw InputError("column '" + column +
                   "': cannot tell whether it is a gyroscope or an accelerometer from its name; "
                   "give --sensor gyro or --sensor accel");
}

Unit si_unit(SensorKind kind) { return kind == SensorKind::kGyro ? Unit{"rad/s", 1.0} : Unit{"m/s^2", 1.0}; }

Unit parse_unit(const std::string& name, SensorKind kind) {
  const std::string n = lower(name);
  if (kind == SensorKind::kGyro) {
    if (n == "rad/s") return {"rad/s", 1.0};
    if (n == "deg/s") return {"deg/s", kDegreesPerRadian};
    if (n == "deg/h") return {"deg/h", kDegreesPerRadian * kSecondsPerHour};
    throw InputError("unit '" + name + "' for gyro: expected rad/s, deg/s or deg/h");
  }
  if (n == "m/s^2" || n == "m/s2") return {"m/s^2", 1.0};
  if (n == "g") return {"g", 1.0 / kStandardGravity};
  if (n == "mg") return {"mg", 1000.0 / kStandardGravity};
  throw InputError("unit '" + name + "' for accel: expected m/s^2, g or mg");
}

std::map<SensorKind, Unit> parse_units(const std::string& spec) {
  std::map<SensorKind, Unit> out = {{SensorKind::kGyro, si_unit(SensorKind::kGyro)},
                                    {SensorKind::kAccel, si_unit(SensorKind::kAccel)}};
  for (const auto& [kind, unit] : parse_declared_units(spec)) out[kind] = unit;
  return out;
}

std::pair<SensorKind, Unit> parse_any_unit(const std::string& name) {
  for (const SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel})
    for (const Unit& u : units_of(kind))
      if (lower(name) == lower(u.name) || (kind == SensorKind::kAccel && lower(name) == "m/s2")) return {kind, u};
  throw InputError("unit '" + name + "': expected rad/s, deg/s, deg/h (gyro) or m/s^2, g, mg (accel)");
}

UnitsSpec parse_units_spec(const std::string& spec) {
  UnitsSpec out;
  if (spec.empty()) return out;
  if (spec.find('=') == std::string::npos && spec.find(',') == std::string::npos) {
    // One unit name: its kind declared, and the label of the columns whose name tells no kind.
    try {
      auto [kind, unit] = parse_any_unit(spec);
      out.declared[kind] = unit;
      out.plain = unit;
      return out;
    } catch (const InputError&) {
      throw InputError("--units '" + spec +
                       "': expected one unit (rad/s, deg/s, deg/h, m/s^2, g, mg) or kind=unit "
                       "pairs such as gyro=deg/s,accel=g");
    }
  }
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError("--units '" + spec + "': expected kind=unit pairs such as gyro=deg/s,accel=g, found '" + item +
                       "'");
    const std::string key = lower(item.substr(0, eq));
    SensorKind kind;
    if (key == "gyro")
      kind = SensorKind::kGyro;
    else if (key == "accel")
      kind = SensorKind::kAccel;
    else
      throw InputError("--units '" + spec + "': unknown sensor kind '" + item.substr(0, eq) +
                       "' (expected gyro or accel)");
    if (out.declared.count(kind))
      throw InputError("--units '" + spec + "': " + to_string(kind) + " given twice (give each kind one unit)");
    try {
      out.declared[kind] = parse_unit(item.substr(eq + 1), kind);
    } catch (const InputError& e) {
      throw InputError("--units '" + spec + "': " + e.what());
    }
    start = comma + 1;
  }
  return out;
}

std::map<SensorKind, Unit> parse_declared_units(const std::string& spec) { return parse_units_spec(spec).declared; }

std::string unit_of_column(const UnitsSpec& spec, const std::string& column) {
  if (spec.empty()) return {};
  std::optional<SensorKind> kind;
  try {
    kind = sensor_kind_of_column(column);
  } catch (const InputError&) {
    return spec.plain ? spec.plain->name : std::string();
  }
  return spec.declared.count(*kind) ? spec.declared.at(*kind).name : si_unit(*kind).name;
}

std::vector<Unit> units_of(SensorKind kind) {
  if (kind == SensorKind::kGyro)
    return {parse_unit("rad/s", kind), parse_unit("deg/s", kind), parse_unit("deg/h", kind)};
  return {parse_unit("m/s^2", kind), parse_unit("g", kind), parse_unit("mg", kind)};
}

std::optional<UnitSuggestion> suggest_unit(double variance_ratio, SensorKind kind, const Unit& declared) {
  if (!(variance_ratio > 0.0) || !std::isfinite(variance_ratio)) return std::nullopt;
  if (std::abs(std::log(variance_ratio)) < std::log(kUnitRatioMinimum)) return std::nullopt;
  for (const Unit& u : units_of(kind)) {
    if (u.name == declared.name) continue;
    const double f = (u.per_si / declared.per_si) * (u.per_si / declared.per_si);
    if (std::abs(std::log(variance_ratio / f)) <= std::log(kUnitFactorTolerance)) return UnitSuggestion{u, f};
  }
  return std::nullopt;
}

std::string unit_of_column(const std::map<SensorKind, Unit>& units, std::optional<SensorKind> kind,
                           const std::string& column) {
  if (!kind) try {
      kind = sensor_kind_of_column(column);
    } catch (const InputError&) {
      return {};
    }
  return units.count(*kind) ? units.at(*kind).name : si_unit(*kind).name;
}

}  // namespace gmwm::io
