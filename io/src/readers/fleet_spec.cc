// The fleet's spec mask (fleet_spec.h): per sensor model a datasheet map, or one datasheet
// for every model, read by the datasheet reader (datasheet_limits.h).
#include "gmwm/io/fleet_spec.h"

#include "datasheet_limits.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/side_file.h"
#include "yaml_figures.h"

namespace gmwm::io {

const SensorLimits* FleetSpec::limits(const std::string& model, SensorKind kind) const {
  for (const std::string& key : {model, std::string()}) {
    const auto m = by_model.find(key);
    if (m == by_model.end()) continue;
    const auto k = m->second.find(kind);
    return k == m->second.end() ? nullptr : &k->second;
  }
  return nullptr;
}

FleetSpec read_fleet_spec(const std::string& path) {
  return parse_fleet_spec(read_side_file(path, "a spec yaml (datasheet limits per sensor model)", kMaxKalibrYamlBytes),
                          path);
}

FleetSpec parse_fleet_spec(const std::string& text, const std::string& path) {
  const YAML::Node root = detail::load_yaml(text, path);
  if (!root.IsMap() || root.size() == 0)
    throw InputError(path +
                     ": expected a spec yaml: per sensor model (the manifest's `model`) a datasheet map, e.g. "
                     "'ADIS16405: {gyroscope: {angle_random_walk: 2 deg/sqrt(h)}}', or one datasheet for every model");
  detail::check_unique_keys(root, path);
  FleetSpec spec;
  spec.path = path;
  bool datasheet = false;
  for (const auto& kv : root) datasheet = datasheet || is_datasheet_key(kv.first.Scalar());
  if (datasheet) {
    spec.by_model.emplace("", datasheet_limits(root, path));
    return spec;
  }
  for (const auto& kv : root) {
    const std::string model = kv.first.Scalar();
    if (!kv.second.IsMap())
      throw InputError(detail::yaml_at(path, kv.first.Mark()) + ": " + model +
                       ": expected the model's datasheet map (gyroscope: / accelerometer: maps of figures)");
    spec.by_model.emplace(model, datasheet_limits(kv.second, path));
  }
  return spec;
}

}  // namespace gmwm::io
