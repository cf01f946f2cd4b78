// The Basalt export: the IMU noise fields of a calib.json. JSON has no comments, so the
// header (and the conventions below) go to a sidecar text file beside it (PATH.txt).
//
// Basalt (basalt-headers include/basalt/calibration/calibration.hpp, struct Calibration):
// "All noise parameters are continous time": Vec3 gyro_noise_std, accel_noise_std (white
// noise densities, rad/s/sqrt(Hz), m/s^2/sqrt(Hz); dicrete_time_gyro_noise_std() =
// gyro_noise_std * sqrt(imu_update_rate)), Vec3 gyro_bias_std, accel_bias_std (bias random
// walk densities: the VIO weights a bias change over dt by 1 / (bias_std^2 dt),
// keypoint_vio's gyro_bias_weight / dt, so rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz)), and
// imu_update_rate (Hz). The fields live under the cereal root "value0" (basalt
// data/euroc_ds_calib.json); the vectors are per axis x, y, z.
#include <nlohmann/json.hpp>

#include "export_internal.h"
#include "gmwm/engine/error.h"

namespace gmwm::io::export_detail {
namespace {

using Json = nlohmann::ordered_json;

// The three axis values of a figure: per axis, or the aggregate three times.
Json vec3(const ExportResult& r, SensorKind kind, double WrittenNoise::*figure) {
  Json v = Json::array();
  const KindExport* k = find_kind(r, kind);
  for (std::size_t s = 0; s < 3; ++s) {
    const WrittenNoise w = !k ? WrittenNoise{} : k->per_axis ? k->axes[s] : k->combined;
    v.push_back(w.*figure);
  }
  return v;
}

}  // namespace

std::string render_basalt(const ExportOptions& o, const ExportResult& r, std::string& sidecar) {
  Json fields = Json::object();
  fields["imu_update_rate"] = r.rate;
  const bool accel = writes_kind(o, r, SensorKind::kAccel), gyro = writes_kind(o, r, SensorKind::kGyro);
  if (accel) fields["accel_noise_std"] = vec3(r, SensorKind::kAccel, &WrittenNoise::noise_density);
  if (gyro) fields["gyro_noise_std"] = vec3(r, SensorKind::kGyro, &WrittenNoise::noise_density);
  if (accel) fields["accel_bias_std"] = vec3(r, SensorKind::kAccel, &WrittenNoise::random_walk);
  if (gyro) fields["gyro_bias_std"] = vec3(r, SensorKind::kGyro, &WrittenNoise::random_walk);
  Json doc = Json::object();
  doc["value0"] = std::move(fields);

  std::vector<std::string> lines = r.header;
  lines.push_back("");
  for (const char* l :
       {"Basalt calib.json IMU noise fields, to merge into the \"value0\" object of your calib.json (JSON allows no",
        "comments: this text is their sidecar). Basalt's Calibration struct (basalt-headers calibration.hpp) says",
        "\"All noise parameters are continous time\":",
        "  accel_noise_std  [m/s^2/sqrt(Hz)]   accelerometer white noise density N, per axis x, y, z",
        "  gyro_noise_std   [rad/s/sqrt(Hz)]   gyroscope white noise density N, per axis",
        "  accel_bias_std   [m/s^3/sqrt(Hz)]   accelerometer bias random walk density K, per axis",
        "  gyro_bias_std    [rad/s^2/sqrt(Hz)] gyroscope bias random walk density K, per axis",
        "  imu_update_rate  [Hz]               Basalt's discrete white noise is noise_std * sqrt(imu_update_rate);",
        "                                      a bias change over dt is weighted by 1 / (bias_std^2 dt)"})
    lines.push_back(l);
  sidecar.clear();
  // One printable line each, as the comment formats' headers: names from files carry no
  // line break or escape sequence into the text.
  for (const auto& l : lines) sidecar += printable_line(l) + "\n";
  return doc.dump(4) + "\n";
}

}  // namespace gmwm::io::export_detail
