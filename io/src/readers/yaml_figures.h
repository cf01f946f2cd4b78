#pragma once
// YAML helpers shared by the readers of noise-figure files (Kalibr imu.yaml, datasheet
// yaml): parsing with "<path>:<line>:<column>" errors, duplicate keys refused, and the
// plain decimal numbers the CSV reader accepts.
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

namespace gmwm::io::detail {

/// "<path>:<line>" for a node's mark, "<path>" when it has none.
std::string yaml_at(const std::string& path, const YAML::Mark& m);

/// The YAML document of `text`; InputError "<path>:<line>:<column>: not valid YAML: ...".
YAML::Node load_yaml(const std::string& text, const std::string& path);

/// A map's keys, each once: a repeated key is an InputError naming both lines (YAML
/// leaves it to the reader, and yaml-cpp would silently keep the first).
void check_unique_keys(const YAML::Node& map, const std::string& path);

/// The mark of `key`'s own line in `map` (a missing value's mark is the next line).
YAML::Mark key_mark(const YAML::Node& map, const std::string& key);

/// A plain decimal number (an optional leading '+', as YAML 1.2 allows): no hex floats,
/// no ".inf". Sets `out_of_range` for a number beyond a double.
std::optional<double> decimal(std::string text, bool& out_of_range);

}  // namespace gmwm::io::detail
