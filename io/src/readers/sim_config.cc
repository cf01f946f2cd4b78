// A column's baseline from a simulator configuration (SimConfig): the sensor kind's model,
// or the model of the column's axis when the simulator configures the axes differently.
#include <cctype>

#include "gmwm/engine/error.h"
#include "gmwm/io/sim_config.h"

namespace gmwm::io {

char column_axis(const std::string& column) {
  if (column.empty()) return 0;
  const unsigned char last = static_cast<unsigned char>(column.back());
  const char axis = static_cast<char>(std::tolower(last));
  if (axis != 'x' && axis != 'y' && axis != 'z') return 0;
  if (column.size() == 1) return axis;
  const unsigned char before = static_cast<unsigned char>(column[column.size() - 2]);
  if (!std::isalpha(before)) return axis;                       // gyro_x, acc.Z, gyro2x
  if (std::isupper(last) && std::islower(before)) return axis;  // gyroX
  return 0;
}

std::optional<SimBaseline> baseline_for_column(const SimConfig& config, SensorKind kind, const std::string& column) {
  const std::string k = to_string(kind);
  auto with_notes = [&](std::vector<std::string> lines) {
    lines.insert(lines.end(), config.notes.begin(), config.notes.end());
    return lines;
  };
  const auto kind_lines = config.conversions.find(kind);
  std::vector<std::string> lines =
      kind_lines != config.conversions.end() ? kind_lines->second : std::vector<std::string>{};
  if (const auto it = config.models.find(kind); it != config.models.end())
    return SimBaseline{it->second, with_notes(lines)};
  bool per_axis = false;
  for (const auto& [key, unused] : config.axis_conversions) per_axis = per_axis || key.rfind(k + "_", 0) == 0;
  if (!per_axis) return std::nullopt;
  const char axis = column_axis(column);
  if (!axis)
    throw InputError("column '" + column + "': " + config.source + " configures the " + k +
                     " axes differently, and the name does not end in an axis letter (x, y or z, e.g. " + k +
                     "_x) to choose one");
  const std::string key = k + "_" + axis;
  const auto m = config.axis_models.find(key);
  if (m == config.axis_models.end()) return std::nullopt;
  if (const auto c = config.axis_conversions.find(key); c != config.axis_conversions.end())
    lines.insert(lines.end(), c->second.begin(), c->second.end());
  return SimBaseline{m->second, with_notes(lines)};
}

}  // namespace gmwm::io
