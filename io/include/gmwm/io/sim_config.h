#pragma once
// A simulator's IMU noise configuration as a baseline model for the gap diagnosis
// (GAP.md s.1): the continuous noise figures converted to discrete processes at the
// data's sampling rate and in the data's units, every conversion written out.
//
// Kalibr imu.yaml (flat "key: value  # comment" lines; other keys are ignored):
//   accelerometer_noise_density  N_a  m/s^2/sqrt(Hz)  -> WN sigma2 = (N_a u)^2 f
//   accelerometer_random_walk    K_a  m/s^3/sqrt(Hz)  -> RW gamma2 = (K_a u)^2 / f
//   gyroscope_noise_density      N_g  rad/s/sqrt(Hz)  -> WN sigma2 = (N_g u)^2 f
//   gyroscope_random_walk        K_g  rad/s^2/sqrt(Hz) -> RW gamma2 = (K_g u)^2 / f
//   update_rate                  Hz (Kalibr's own discretisation rate; the densities are
//                                rate-free, so the data's rate f is used)
// with u the data unit per SI unit (--units). A zero figure leaves its term out.
#include <map>
#include <string>
#include <vector>

#include "gmwm/engine/model.h"
#include "gmwm/io/units.h"

namespace gmwm::io {

struct SimConfig {
  std::string source;                                       ///< e.g. "Kalibr imu.yaml (path)"
  std::map<SensorKind, Model> models;                       ///< with values (Model::given_values)
  std::map<SensorKind, std::vector<std::string>> conversions;  ///< one line per figure, with units
  std::vector<std::string> notes;                           ///< e.g. a rate mismatch
};

/// Reads a Kalibr imu.yaml. Throws InputError "<path>:<line>: ..." for a malformed or
/// negative figure, and "<path>: ..." for a missing one or an unreadable file.
SimConfig read_kalibr_imu_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units);

}  // namespace gmwm::io
