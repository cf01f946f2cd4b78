#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/sim_config.h"

namespace gmwm::io {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string g(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string exact(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

struct Figure {
  double value = 0.0;
  int line = 0;
};

}  // namespace

SimConfig read_kalibr_imu_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the Kalibr imu.yaml");
  std::map<std::string, Figure> figures;
  std::string line;
  for (int no = 1; std::getline(in, line); ++no) {
    const std::string body = trim(line.substr(0, line.find('#')));
    if (body.empty() || body == "---") continue;
    const auto colon = body.find(':');
    if (colon == std::string::npos) continue;  // not a key: value line (Kalibr files are flat)
    const std::string key = trim(body.substr(0, colon));
    std::string value = trim(body.substr(colon + 1));
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front())
      value = value.substr(1, value.size() - 2);
    const bool numeric_key = key == "accelerometer_noise_density" || key == "accelerometer_random_walk" ||
                             key == "gyroscope_noise_density" || key == "gyroscope_random_walk" || key == "update_rate";
    if (!numeric_key) continue;
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size() || !std::isfinite(v))
      throw InputError(path + ":" + std::to_string(no) + ": " + key + ": found '" + value + "', expected a number");
    if (v < 0.0 || (key == "update_rate" && v == 0.0))
      throw InputError(path + ":" + std::to_string(no) + ": " + key + ": found " + value + ", expected " +
                       (key == "update_rate" ? "a positive rate in Hz" : "a non-negative noise figure"));
    figures[key] = {v, no};
  }
  for (const char* k : {"accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density",
                        "gyroscope_random_walk"})
    if (!figures.count(k)) throw InputError(path + ": missing " + std::string(k) + " (a Kalibr imu.yaml gives the "
                                            "four noise figures and update_rate)");
  SimConfig c;
  c.source = "Kalibr imu.yaml (" + path + ")";
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
      lines.push_back(std::string(k.white) + " = " + g(N) + " " + k.density_unit + " -> WN sigma2 = (N" + per +
                      ")^2 x f = " + g(sigma2) + " (" + u.name + ")^2 per sample at f = " + g(f) + " Hz");
      spec += "WN(sigma2=" + exact(sigma2) + ")";
    } else {
      lines.push_back(std::string(k.white) + " = 0: no white noise term");
    }
    if (K > 0.0) {
      const double gamma2 = (K * u.per_si) * (K * u.per_si) / f;
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
