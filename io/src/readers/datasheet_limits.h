#pragma once
// The datasheet reader's figures as limits (datasheet_yaml.cc), for the fleet's spec mask
// (fleet_spec.cc): one datasheet map read as `gmwm gap --datasheet` reads it.
#include <map>
#include <string>

#include <yaml-cpp/yaml.h>

#include "gmwm/io/fleet_spec.h"

namespace gmwm::io {

/// True for a key a datasheet map holds at its top (gyroscope, gyro, accelerometer, accel,
/// name, part).
bool is_datasheet_key(const std::string& key);

/// The limits of a datasheet map; InputError as parse_datasheet_yaml.
std::map<SensorKind, SensorLimits> datasheet_limits(const YAML::Node& root, const std::string& path);

}  // namespace gmwm::io
