#pragma once
// A simulator's configuration file edited in place (docs/gap.md, "The corrected
// configuration"): the figures a corrected file changes are replaced where the input
// wrote them (io::ConfigField::line and ::text), a figure the input lacked is added after
// a line of its group, one it no longer holds is removed; every other character stays as
// the user wrote it (other axes, other sensors, comments, the model around the sensor).
//
//   std::vector<ConfigEdit> edits{{ConfigEdit::kSet, &field, "0.0071"}};
//   const std::optional<std::string> text = apply_config_edits(config.text, ConfigSyntax::kXml, edits);
#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/sim_config.h"

namespace gmwm::pipeline::detail {

/// How a figure is written: a YAML "key: value" line (Kalibr, datasheet) or an XML
/// element "<name>value</name>" (gz-sensors, RotorS).
enum class ConfigSyntax { kYaml, kXml };

struct ConfigEdit {
  enum Op { kSet, kInsert, kRemove };
  Op op = kSet;
  /// kSet, kRemove: the input's figure. kInsert: a figure of the same group, after whose
  /// line the new one goes (with that line's indentation).
  const io::ConfigField* at = nullptr;
  std::string key;    ///< kInsert: the element's name or the YAML key
  std::string value;  ///< kSet, kInsert: the figure as to write it
};

/// The key or element name a field is written under: the part after the last '/'
/// ("angular_velocity/x/noise/stddev" -> "stddev", "gyroscope/noise_density" ->
/// "noise_density", "gyroscope_noise_density" as it is).
std::string config_key(const std::string& field_name);

/// `text` with `edits` applied (line numbers are the input's; edits on one line are
/// applied together). std::nullopt when a figure is not where its field says (a key or an
/// element not on its line, a flow-style YAML map, an element sharing its line with
/// another one that would be removed): the caller keeps the input's figures then.
std::optional<std::string> apply_config_edits(const std::string& text, ConfigSyntax syntax,
                                              const std::vector<ConfigEdit>& edits);

}  // namespace gmwm::pipeline::detail
