// The YAML exports: Kalibr imu.yaml, OpenVINS kalibr_imu_chain.yaml, the VINS-Mono/Fusion
// IMU noise fields and the ORB-SLAM3 IMU settings. Each field's comment gives its unit and
// convention; the conventions and where they were read are in the comment blocks below.
// Numbers are written with export_detail::real (always a '.', a signed exponent), which PyYAML
// (Kalibr) and OpenCV's FileStorage (OpenVINS, VINS, ORB-SLAM3) both read as reals.
#include <cmath>

#include "export_internal.h"

namespace gmwm::io::export_detail {
namespace {

// One "key: value  # comment" line at `indent`.
std::string field(const std::string& indent, const std::string& key, const std::string& value,
                  const std::string& comment = "") {
  return indent + key + ": " + value + (comment.empty() ? "" : "  # " + comment) + "\n";
}

std::string header(const ExportResult& r, const std::vector<std::string>& conventions) {
  std::vector<std::string> lines = r.header;
  lines.push_back("");
  lines.insert(lines.end(), conventions.begin(), conventions.end());
  return yaml_comments(lines);
}

}  // namespace

// Kalibr: https://github.com/ethz-asl/kalibr/wiki/IMU-Noise-Model ("The parameters
// gyroscope_noise_density and accelerometer_noise_density ... specify exactly these noise
// strengths sigma_g and sigma_a for the continuous-time model"; sigma_gd = sigma_g /
// sqrt(dt); sigma_bgd = sigma_bg sqrt(dt)); field list and units from Kalibr's
// imu_adis16448.yaml (update_rate 200.0, rostopic /imu0). Read back by
// io::read_kalibr_imu_yaml (sim_config.h).
std::string render_kalibr(const ExportOptions& o, const ExportResult& r) {
  const WrittenNoise g = combined_or_zero(r, SensorKind::kGyro);
  const WrittenNoise a = combined_or_zero(r, SensorKind::kAccel);
  std::string out = header(
      r, {"Kalibr imu.yaml (https://github.com/ethz-asl/kalibr/wiki/IMU-Noise-Model): continuous-time densities,",
          "one value per sensor for its three axes. Kalibr discretises them at update_rate: white noise",
          "sigma_d = N sqrt(update_rate), bias random walk sigma_bd = K / sqrt(update_rate)."});
  if (writes_kind(o, r, SensorKind::kAccel)) {
    out += field("", "accelerometer_noise_density", real(a.noise_density),
                 "[m/s^2/sqrt(Hz)] accelerometer white noise density N (continuous time)");
    out += field("", "accelerometer_random_walk", real(a.random_walk),
                 "[m/s^3/sqrt(Hz)] accelerometer bias random walk density K (continuous time)");
  }
  if (writes_kind(o, r, SensorKind::kGyro)) {
    out += field("", "gyroscope_noise_density", real(g.noise_density),
                 "[rad/s/sqrt(Hz)] gyroscope white noise density N (continuous time)");
    out += field("", "gyroscope_random_walk", real(g.random_walk),
                 "[rad/s^2/sqrt(Hz)] gyroscope bias random walk density K (continuous time)");
  }
  out += field("", "rostopic", o.rostopic, "the IMU topic in the bag");
  out += field("", "update_rate", real(r.rate), "[Hz] the IMU rate Kalibr discretises the densities at");
  return out;
}

// OpenVINS: config/euroc_mav/kalibr_imu_chain.yaml of rpng/open_vins (%YAML:1.0, imu0 with
// T_i_b, the four Kalibr densities, rostopic, time_offset, update_rate, model "kalibr");
// VioManagerOptions::print_and_load_noise reads imu0's densities into NoiseManager
// ("Continuous-time IMU noise": sigma_w [rad/s/sqrt(Hz)], sigma_wb [rad/s^2/sqrt(Hz)],
// sigma_a [m/s^2/sqrt(Hz)], sigma_ab [m/s^3/sqrt(Hz)]), discretised in its propagator
// (https://docs.openvins.com/propagation.html). The same convention as Kalibr.
std::string render_openvins(const ExportOptions& o, const ExportResult& r) {
  const WrittenNoise g = combined_or_zero(r, SensorKind::kGyro);
  const WrittenNoise a = combined_or_zero(r, SensorKind::kAccel);
  std::string out = "%YAML:1.0 # OpenCV FileStorage needs the directive on the first line\n";
  out +=
      header(r, {"OpenVINS kalibr_imu_chain.yaml (rpng/open_vins config/*/kalibr_imu_chain.yaml): the imu0 densities",
                 "are continuous time (ov_msckf NoiseManager: sigma_w, sigma_wb, sigma_a, sigma_ab), the same",
                 "convention as Kalibr; OpenVINS discretises them at the IMU's own sample times",
                 "(https://docs.openvins.com/propagation.html). T_i_b is the identity and time_offset 0:",
                 "replace them with your calibration."});
  out += "imu0:\n";
  out += "  T_i_b:\n";
  for (int i = 0; i < 4; ++i) {
    out += "    - [";
    for (int j = 0; j < 4; ++j) out += std::string(j ? ", " : "") + (i == j ? "1.0" : "0.0");
    out += "]\n";
  }
  if (writes_kind(o, r, SensorKind::kAccel)) {
    out +=
        field("  ", "accelerometer_noise_density", real(a.noise_density), "[ m / s^2 / sqrt(Hz) ] accel white noise");
    out += field("  ", "accelerometer_random_walk", real(a.random_walk), "[ m / s^3 / sqrt(Hz) ] accel bias diffusion");
  }
  if (writes_kind(o, r, SensorKind::kGyro)) {
    out += field("  ", "gyroscope_noise_density", real(g.noise_density), "[ rad / s / sqrt(Hz) ] gyro white noise");
    out += field("  ", "gyroscope_random_walk", real(g.random_walk), "[ rad / s^2 / sqrt(Hz) ] gyro bias diffusion");
  }
  out += field("  ", "model", "\"kalibr\"", "IMU intrinsic model: kalibr, calibrated or rpng");
  out += field("  ", "rostopic", o.rostopic);
  out += field("  ", "time_offset", "0.0", "[s] camera-IMU time offset: from your calibration");
  out += field("  ", "update_rate", real(r.rate), "[Hz]");
  return out;
}

// VINS-Mono / VINS-Fusion: config/euroc/euroc_config.yaml of HKUST-Aerial-Robotics/VINS-Mono
// ("acc_n: accelerometer measurement noise standard deviation", "acc_w: accelerometer bias
// random work noise standard deviation"). The docs give no unit; the units follow from the
// estimator, vins_estimator/src/factor/integration_base.h: the noise vector holds each IMU
// measurement's own noise (acc_0, gyr_0, acc_1, gyr_1: variances ACC_N^2, GYR_N^2) and the
// bias noises (ACC_W^2, GYR_W^2), and midPointIntegration adds V noise V' per step dt with
// V = dt for the bias blocks: a bias step of standard deviation GYR_W dt. So gyr_n is the
// per-sample standard deviation of a measurement, N sqrt(R) at the IMU rate R (Kalibr's
// sigma_gd), and gyr_w the standard deviation of the bias rate per sample: a random walk
// of density K steps by K sqrt(dt) = gyr_w dt, gyr_w = K sqrt(R). Likewise acc_n, acc_w.
std::string render_vins(const ExportOptions& o, const ExportResult& r) {
  const WrittenNoise g = combined_or_zero(r, SensorKind::kGyro);
  const WrittenNoise a = combined_or_zero(r, SensorKind::kAccel);
  const double s = std::sqrt(r.rate);
  std::string out = "%YAML:1.0 # OpenCV FileStorage; paste the four fields into your VINS config\n";
  out += header(
      r,
      {"VINS-Mono/VINS-Fusion IMU noise (config/euroc/euroc_config.yaml: \"measurement noise standard deviation\",",
       "\"bias random work noise standard deviation\"): discrete values at the IMU rate R = " + num(r.rate) +
           " Hz, from the",
       "pre-integration (vins_estimator/src/factor/integration_base.h, midPointIntegration): each measurement's",
       "noise has standard deviation acc_n / gyr_n, and a bias steps by acc_w dt / gyr_w dt per sample dt = 1/R.",
       "So acc_n = N_a sqrt(R), gyr_n = N_g sqrt(R) (Kalibr's per-sample sigma_d) and acc_w = K_a sqrt(R),",
       "gyr_w = K_g sqrt(R) (a random walk of density K steps by K sqrt(dt) = gyr_w dt). VINS's own example",
       "values are inflated well beyond an Allan analysis (its authors tune them); --inflate does that explicitly."});
  const bool acc = writes_kind(o, r, SensorKind::kAccel), gyr = writes_kind(o, r, SensorKind::kGyro);
  if (acc)
    out +=
        field("", "acc_n", real(a.noise_density * s),
              "[m/s^2] accelerometer measurement noise standard deviation, N_a sqrt(R) (N_a = " + num(a.noise_density) +
                  " m/s^2/sqrt(Hz))");
  if (gyr)
    out += field("", "gyr_n", real(g.noise_density * s),
                 "[rad/s] gyroscope measurement noise standard deviation, N_g sqrt(R) (N_g = " + num(g.noise_density) +
                     " rad/s/sqrt(Hz))");
  if (acc)
    out += field("", "acc_w", real(a.random_walk * s),
                 "[m/s^3] accelerometer bias random walk noise standard deviation, K_a sqrt(R) (K_a = " +
                     num(a.random_walk) + " m/s^3/sqrt(Hz))");
  if (gyr)
    out += field("", "gyr_w", real(g.random_walk * s),
                 "[rad/s^2] gyroscope bias random walk noise standard deviation, K_g sqrt(R) (K_g = " +
                     num(g.random_walk) + " rad/s^2/sqrt(Hz))");
  return out;
}

// ORB-SLAM3: Examples/*/EuRoC.yaml of UZ-SLAMLab/ORB_SLAM3 (IMU.NoiseGyro, IMU.NoiseAcc,
// IMU.GyroWalk, IMU.AccWalk, IMU.Frequency); Tracking::ParseIMUParamFile prints them as
// rad/s/sqrt(Hz), rad/s^2/sqrt(Hz), m/s^2/sqrt(Hz), m/s^3/sqrt(Hz) and discretises them
// itself: IMU::Calib(Tbc, Ng*sf, Na*sf, Ngw/sf, Naw/sf) with sf = sqrt(IMU.Frequency).
// Continuous densities, then, as Kalibr's. Settings::readParameter<float> aborts on a value
// FileStorage reads as an integer, hence export_detail::real.
std::string render_orbslam3(const ExportOptions& o, const ExportResult& r) {
  const WrittenNoise g = combined_or_zero(r, SensorKind::kGyro);
  const WrittenNoise a = combined_or_zero(r, SensorKind::kAccel);
  std::string out = "%YAML:1.0 # OpenCV FileStorage; paste the IMU fields into your ORB-SLAM3 settings\n";
  out += header(r, {"ORB-SLAM3 IMU settings: continuous-time densities (Tracking::ParseIMUParamFile prints their",
                    "units and discretises them itself: IMU::Calib(Tbc, Ng*sf, Na*sf, Ngw/sf, Naw/sf),",
                    "sf = sqrt(IMU.Frequency)), the same convention as Kalibr."});
  const bool acc = writes_kind(o, r, SensorKind::kAccel), gyr = writes_kind(o, r, SensorKind::kGyro);
  if (gyr) out += field("", "IMU.NoiseGyro", real(g.noise_density), "[rad/s/sqrt(Hz)] gyroscope white noise density");
  if (acc)
    out += field("", "IMU.NoiseAcc", real(a.noise_density), "[m/s^2/sqrt(Hz)] accelerometer white noise density");
  if (gyr)
    out += field("", "IMU.GyroWalk", real(g.random_walk), "[rad/s^2/sqrt(Hz)] gyroscope bias random walk density");
  if (acc)
    out += field("", "IMU.AccWalk", real(a.random_walk), "[m/s^3/sqrt(Hz)] accelerometer bias random walk density");
  out += field("", "IMU.Frequency", real(r.rate), "[Hz]");
  return out;
}

}  // namespace gmwm::io::export_detail
