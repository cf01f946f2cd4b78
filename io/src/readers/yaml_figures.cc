#include "yaml_figures.h"

#include <charconv>
#include <cmath>
#include <map>
#include <system_error>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {

std::string yaml_at(const std::string& path, const YAML::Mark& m) {
  return m.is_null() ? path : path + ":" + std::to_string(m.line + 1);
}

YAML::Node load_yaml(const std::string& text, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError((e.mark.is_null()
                          ? path
                          : path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1)) +
                     ": not valid YAML: " + e.msg);
  }
}

void check_unique_keys(const YAML::Node& map, const std::string& path) {
  std::map<std::string, YAML::Mark> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    const auto [it, fresh] = seen.emplace(key, kv.first.Mark());
    if (!fresh)
      throw InputError(yaml_at(path, kv.first.Mark()) + ": duplicate key '" + key + "' (first at line " +
                       std::to_string(it->second.line + 1) + ")");
  }
}

YAML::Mark key_mark(const YAML::Node& map, const std::string& key) {
  for (const auto& kv : map)
    if (kv.first.Scalar() == key) return kv.first.Mark();
  return map[key].Mark();
}

std::optional<double> decimal(std::string text, bool& out_of_range) {
  out_of_range = false;
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range && ptr == end) out_of_range = true;
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace gmwm::io::detail
