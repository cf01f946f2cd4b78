#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/sim_config.h"
#include "config_text.h"
#include "yaml_figures.h"

namespace gmwm::io {
namespace {

using detail::check_unique_keys;
using detail::decimal;
using detail::exact;
using detail::g;
using detail::trim;

struct Figure {
  double value = 0.0;
  int line = 0;
  std::string text;  // as written
};

constexpr const char* kNumericKeys[] = {"accelerometer_noise_density", "accelerometer_random_walk",
                                        "gyroscope_noise_density", "gyroscope_random_walk", "update_rate"};

// The unit of a Kalibr figure (Kalibr's own documentation of imu.yaml).
std::string kalibr_unit(const std::string& key) {
  if (key == "accelerometer_noise_density") return "m/s^2/sqrt(Hz)";
  if (key == "accelerometer_random_walk") return "m/s^3/sqrt(Hz)";
  if (key == "gyroscope_noise_density") return "rad/s/sqrt(Hz)";
  if (key == "gyroscope_random_walk") return "rad/s^2/sqrt(Hz)";
  return "Hz";  // update_rate
}

// The file's text with an OpenCV-style first line "%YAML:1.0" (OpenVINS, VINS) blanked:
// YAML proper writes that directive "%YAML 1.0". Line numbers are kept.
std::string read_text(const std::string& path) {
  return read_side_file(path, "a Kalibr imu.yaml", kMaxKalibrYamlBytes);
}

// The map holding the figures: the file itself, or one IMU of a chain (imu0, imu1, ...).
YAML::Node imu_node(const YAML::Node& root, const std::string& path, const std::string& imu) {
  std::vector<std::string> chain;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key.size() > 3 && key.rfind("imu", 0) == 0 && key.find_first_not_of("0123456789", 3) == std::string::npos &&
        kv.second.IsMap())
      chain.push_back(key);
  }
  if (!imu.empty()) {
    if (std::find(chain.begin(), chain.end(), imu) == chain.end())
      throw InputError(path + ": no IMU '" + imu + "' in this file" +
                       (chain.empty() ? std::string(" (a single imu.yaml: give the file alone)") : " (it has " + [&] {
                         std::string l;
                         for (const auto& c : chain) l += (l.empty() ? "" : ", ") + c;
                         return l;
                       }() + ")"));
    return root[imu];
  }
  if (chain.empty()) return root;
  if (chain.size() == 1) return root[chain.front()];
  std::string list;
  for (const auto& c : chain) list += (list.empty() ? "" : ", ") + c;
  throw InputError(path + ": an IMU chain with " + list + ": name the IMU, e.g. --kalibr " + path + ":" +
                   chain.front());
}

// A per-sample variance from a figure must be a normal positive double.
void check_representable(double v, const std::string& path, const Figure& from, const char* key, const char* what) {
  if (v > 0.0 && detail::within_double(v)) return;
  throw InputError(path + ":" + std::to_string(from.line) + ": " + key + ": " + g(from.value) + " gives " + what +
                   " = " + g(v) + " per sample, outside the range of a double (expected a figure near the sensor's)");
}

}  // namespace

SimConfig read_kalibr_imu_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units,
                               const std::string& imu) {
  return parse_kalibr_imu_yaml(read_text(path), path, data_freq, units, imu);
}

SimConfig parse_kalibr_imu_yaml(const std::string& text_in, const std::string& path, double data_freq,
                                const std::map<SensorKind, Unit>& units, const std::string& imu) {
  std::string text = text_in;
  if (text.rfind("%YAML:", 0) == 0) text.erase(0, text.find('\n'));
  const YAML::Node root = detail::load_yaml(text, path);
  if (!root.IsMap())
    throw InputError(path + ": expected a Kalibr imu.yaml (key: value noise figures) or an IMU chain (imu0: ...)");
  check_unique_keys(root, path);
  const YAML::Node node = imu_node(root, path, imu);
  check_unique_keys(node, path);
  std::map<std::string, Figure> figures;
  for (const char* key : kNumericKeys) {
    const YAML::Node v = node[key];
    if (!v) continue;
    const YAML::Mark mark = detail::key_mark(node, key);
    const std::string where = detail::yaml_at(path, mark);
    if (v.IsNull()) throw InputError(where + ": " + key + ": found nothing, expected a number");
    const std::string found = v.IsScalar() ? v.Scalar() : std::string(v.IsMap() ? "a map" : "a list");
    bool out_of_range = false;
    const std::optional<double> x = v.IsScalar() ? decimal(trim(found), out_of_range) : std::nullopt;
    if (out_of_range) throw InputError(where + ": " + key + ": found " + found + ", beyond the range of a double");
    if (!x) throw InputError(where + ": " + key + ": found '" + found + "', expected a number");
    if (*x < 0.0 || (std::string(key) == "update_rate" && *x == 0.0))
      throw InputError(where + ": " + key + ": found " + found + ", expected " +
                       (std::string(key) == "update_rate" ? "a positive rate in Hz" : "a non-negative noise figure"));
    figures[key] = {*x, mark.line + 1, trim(found)};
  }
  for (const char* k :
       {"accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density", "gyroscope_random_walk"})
    if (!figures.count(k))
      throw InputError(path + (imu.empty() ? "" : ":" + imu) + ": missing " + std::string(k) +
                       " (a Kalibr imu.yaml gives the four noise figures and update_rate)");
  SimConfig c;
  c.source = "Kalibr imu.yaml (" + path + (imu.empty() ? "" : ", " + imu) + ")";
  c.format = SimFormat::kKalibr;
  c.text = text_in;
  c.imu = imu;
  for (const char* key : kNumericKeys)
    if (auto it = figures.find(key); it != figures.end())
      c.fields.push_back({key, it->second.value, kalibr_unit(key), it->second.line, it->second.text});
  const double f = data_freq;
  if (auto it = figures.find("update_rate"); it != figures.end() && std::abs(it->second.value - f) > 1e-9 * f)
    c.notes.push_back("update_rate " + g(it->second.value) + " Hz differs from the data's " + g(f) +
                      " Hz: the densities are rate-free and are discretised at the data's rate");
  struct Kind {
    SensorKind kind;
    const char* white;
    const char* walk;
    const char* density_unit;
    const char* walk_unit;
  };
  const Kind kinds[] = {
      {SensorKind::kGyro, "gyroscope_noise_density", "gyroscope_random_walk", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)"},
      {SensorKind::kAccel, "accelerometer_noise_density", "accelerometer_random_walk", "m/s^2/sqrt(Hz)",
       "m/s^3/sqrt(Hz)"}};
  for (const Kind& k : kinds) {
    const auto uit = units.find(k.kind);
    const Unit u = uit != units.end() ? uit->second : si_unit(k.kind);
    const double N = figures[k.white].value, K = figures[k.walk].value;
    auto& lines = c.conversions[k.kind];
    const std::string per = u.per_si == 1.0 ? "" : " x " + g(u.per_si) + " " + u.name + " per " + si_unit(k.kind).name;
    std::string spec;
    if (N > 0.0) {
      const double sigma2 = (N * u.per_si) * (N * u.per_si) * f;
      check_representable(sigma2, path, figures[k.white], k.white, "WN sigma2");
      lines.push_back(std::string(k.white) + " = " + g(N) + " " + k.density_unit + " -> WN sigma2 = (N" + per +
                      ")^2 x f = " + g(sigma2) + " (" + u.name + ")^2 per sample at f = " + g(f) + " Hz");
      spec += "WN(sigma2=" + exact(sigma2) + ")";
    } else {
      lines.push_back(std::string(k.white) + " = 0: no white noise term");
    }
    if (K > 0.0) {
      const double gamma2 = (K * u.per_si) * (K * u.per_si) / f;
      check_representable(gamma2, path, figures[k.walk], k.walk, "RW gamma2");
      lines.push_back(std::string(k.walk) + " = " + g(K) + " " + k.walk_unit + " -> RW gamma2 = (K" + per +
                      ")^2 / f = " + g(gamma2) + " (" + u.name + ")^2 per sample at f = " + g(f) + " Hz");
      spec += std::string(spec.empty() ? "" : "+") + "RW(gamma2=" + exact(gamma2) + ")";
    } else {
      lines.push_back(std::string(k.walk) + " = 0: no random walk term");
    }
    if (!spec.empty()) c.models.emplace(k.kind, parse_model(spec));
  }
  return c;
}

}  // namespace gmwm::io
