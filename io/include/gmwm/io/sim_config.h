#pragma once
// A simulator's IMU noise configuration as a baseline model for the gap diagnosis
// (docs/gap.md, method note 1): the continuous noise figures converted to discrete processes at the
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
//
// Gazebo (io/src/gazebo_sdf.cc): gz-sensors SDF <noise> blocks of an IMU sensor and
// RotorS/PX4 IMU <plugin> parameters; see read_gazebo_sdf below.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/model.h"
#include "gmwm/io/units.h"

namespace gmwm::io {

/// The file formats a simulator's configuration is read from.
enum class SimFormat { kKalibr, kGzSensors, kRotors, kDatasheet };
/// "kalibr", "gz-sdf", "rotors" (the export format names that write each), "datasheet".
const char* to_string(SimFormat f);
/// The inverse of to_string (nullopt for any other name).
std::optional<SimFormat> parse_sim_format(const std::string& name);

/// One numeric figure as the file gives it, in the file's own unit.
struct ConfigField {
  std::string name;  ///< Kalibr key, gz-sensors path ("angular_velocity/x/noise/stddev") or RotorS parameter
  double value = 0.0;
  std::string unit;  ///< e.g. "rad/s/sqrt(Hz)", "s", "Hz"
  /// Where the figure is in SimConfig::text: its 1-based line (the key's or the element's
  /// start tag's; 0 when not known) and the figure as written there (an element's text, a
  /// YAML scalar: "8.73e-3", "0.05 deg/s/sqrt(Hz)"). A corrected file edits it in place.
  int line = 0;
  std::string text;
};

struct SimConfig {
  std::string source;  ///< e.g. "Kalibr imu.yaml (path)"
  SimFormat format = SimFormat::kKalibr;
  /// The file's text as read: a corrected file is this text with the figures it changes
  /// edited in place (everything else as the user wrote it).
  std::string text;
  /// Kalibr: the IMU of a chain the figures came from ("imu1"; empty for a single imu.yaml
  /// or a one-IMU chain), so that a corrected file is read back from the same one.
  std::string imu;
  /// Every numeric figure read, in file order (for what a corrected file changes).
  std::vector<ConfigField> fields;
  std::map<SensorKind, Model> models;                          ///< with values (Model::given_values)
  std::map<SensorKind, std::vector<std::string>> conversions;  ///< one line per figure, with units
  std::vector<std::string> notes;                              ///< e.g. a rate mismatch
  /// Per-axis models, for a simulator that configures the x, y and z axes of a sensor
  /// differently (gz-sensors <x>/<y>/<z> noise blocks), keyed to_string(kind) + "_" + axis
  /// ("gyro_x", "accel_z"). A kind is either in `models` (axes alike) or here (axes
  /// differ), never both; an axis without any term has no entry. Empty for Kalibr.
  std::map<std::string, Model> axis_models;
  /// The conversion lines of each axis ("gyro_x" ...), for every axis of a per-axis kind
  /// (conversions[kind] then holds the kind's own lines, e.g. that its axes differ).
  std::map<std::string, std::vector<std::string>> axis_conversions;
};

/// One column's baseline from a SimConfig: the model and the lines behind it (the kind's
/// conversions, the axis's when per-axis, then the notes).
struct SimBaseline {
  Model model;
  std::vector<std::string> conversions;
};

/// The axis a column name ends in: 'x', 'y' or 'z' when its last character is that letter
/// (either case) and it is the whole name or follows a character that is not a letter
/// ("gyro_x", "w_RS_S_y", "acc.Z", "gyro2x", "x"), or is a capital following a lower-case
/// letter ("gyroX"); 0 otherwise ("gyro", "accx": no axis).
char column_axis(const std::string& column);

/// The baseline of a column of sensor `kind`: the kind's model when its axes are alike,
/// else the model of the column's axis (column_axis). std::nullopt when the config has no
/// term for that kind (or axis). InputError naming the column when the kind's axes differ
/// and the column name ends in no axis letter.
std::optional<SimBaseline> baseline_for_column(const SimConfig& config, SensorKind kind, const std::string& column);

/// Reads a Kalibr imu.yaml (yaml-cpp), or one IMU of a chain (imu0:, imu1:, ... as Kalibr's
/// camchain-imucam and OpenVINS's kalibr_imu_chain.yaml write them; an OpenCV "%YAML:1.0"
/// first line is accepted). `imu` names the chain's IMU ("imu1"); empty: the file is one
/// IMU, or a chain of exactly one. Throws InputError "<path>:<line>[:<column>]: ..." for
/// invalid YAML, a duplicate key, a malformed (hex floats included), negative or
/// unrepresentable figure; "<path>: ..." for a missing figure, an unreadable file, an
/// unknown `imu`, or a chain of several IMUs with none named.
SimConfig read_kalibr_imu_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units,
                               const std::string& imu = {});
/// As read_kalibr_imu_yaml, from the file's text; `name` stands for the path in messages.
SimConfig parse_kalibr_imu_yaml(const std::string& text, const std::string& name, double data_freq,
                                const std::map<SensorKind, Unit>& units, const std::string& imu = {});

/// Reads a datasheet's noise figures (docs/gap.md, "A datasheet as the baseline"): a YAML
/// map per sensor (`gyroscope:` / `gyro:`, `accelerometer:` / `accel:`; an optional
/// `name:`), each figure "<number> <unit>" in the datasheet's own unit, converted to SI and
/// then to discrete terms at the data's rate f and unit (u per SI unit):
///   noise_density | angle_random_walk | velocity_random_walk  N  (deg/s/sqrt(Hz), deg/sqrt(h),
///       ug/sqrt(Hz), m/s/sqrt(h), ...)                     -> WN sigma2 = (N u)^2 f
///   bias_instability B (IEEE 952: the flicker floor of the Allan deviation is 0.664 B)
///                                                          -> FLICKER(B2 = (B u)^2), or with
///       bias_correlation_time T an AR1 (phi = exp(-1/(f T))) whose Allan deviation peaks at 0.664 B
///   in_run_bias_stability S (the Allan deviation's minimum, as ADI, TDK or Bosch print it)
///                                                          -> the same term, sized so that the
///       whole curve (white noise + bias + random walk) has its minimum at S
///   rate_random_walk | acceleration_random_walk | random_walk  K (deg/h/sqrt(h),
///       rad/s^2/sqrt(Hz), m/s^2/sqrt(h), ...)               -> RW gamma2 = (K u)^2 / f
/// Every figure needs its unit (a dimension check refuses deg/h for a density). Throws
/// InputError "<path>:<line>: ..." for invalid YAML, an unknown key or figure, a figure
/// given twice (noise_density and angle_random_walk), a missing or wrong unit, a negative
/// figure, a correlation time without a bias figure; "<path>: ..." for an unreadable file.
SimConfig read_datasheet_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units);
/// As read_datasheet_yaml, from the file's text; `name` stands for the path in messages.
SimConfig parse_datasheet_yaml(const std::string& text, const std::string& name, double data_freq,
                               const std::map<SensorKind, Unit>& units);

/// One sensor's figures for a corrected datasheet, SI (rad, m, s): what the datasheet yaml
/// can hold of a model.
struct DatasheetFigures {
  double white = 0.0;             ///< N, SI/sqrt(Hz)
  double walk = 0.0;              ///< K, SI/s/sqrt(Hz)
  double instability = 0.0;       ///< IEEE 952's B, SI
  double correlation_time = 0.0;  ///< a Gauss-Markov bias's T, s (0: none)
};

/// A datasheet yaml with `input`'s figures (same keys, each in the unit the input wrote it:
/// "what the datasheet should say") holding `figures` for the sensors it has; a sensor not
/// in `figures` keeps the input's lines. A figure the model has and the input lacked is
/// added in a common unit (deg/h, mg, deg/h/sqrt(h), m/s^2/sqrt(h)); a bias correlation
/// time is written when figures.correlation_time > 0 and the input gave one. An in-run bias
/// stability is the minimum of the Allan deviation of N + the bias of B + K at `freq` Hz:
/// read back, it gives that bias again. Reads back with parse_datasheet_yaml.
std::string write_datasheet_yaml(const SimConfig& input, const std::map<SensorKind, DatasheetFigures>& figures,
                                 double freq);

/// The minimum of a model's Allan deviation (the model's unit) over averaging times of one
/// sample to 1e5 s (at most 2^30 samples) at `freq` Hz: what a datasheet's in-run bias
/// stability reads.
double allan_deviation_minimum(const Model& model, const Eigen::VectorXd& theta, double freq);

/// Reads the IMU noise of a Gazebo model or world (any XML file: SDF, URDF <gazebo>
/// extensions), at the data's rate f and in the data's units (u per SI unit):
///
/// gz-sensors: the <noise type="gaussian|gaussian_quantized|none"> blocks under an
/// <imu>'s <angular_velocity> (rad/s) and <linear_acceleration> (m/s^2) <x>, <y>, <z>:
///   stddev s (per sample, NOT a density)         -> WN sigma2 = (s u)^2
///   precision p (the output rounded to p)        -> WN + (p u)^2 / 12 (once the noise spans
///                                                   a few LSBs; not QN). gz-sensors ignores
///                                                   p within 1e-6 of zero, so does this.
///   dynamic_bias_stddev sigma_b (a DRIVING density, rad/s^2/sqrt(Hz) or m/s^3/sqrt(Hz)) with
///   dynamic_bias_correlation_time T (s)          -> AR1 phi = exp(-1/(f T)), innovation
///                                                   variance (sigma_b u)^2 (T/2)(1 - exp(-2/(f T)));
///                                                   stationary variance (sigma_b u)^2 T/2
///   mean, bias_mean, bias_stddev                 -> constant offsets: no term (a line says so)
/// When the three axes of a sensor are alike: one model per kind (`models`), else one per
/// axis (`axis_models`).
///
/// RotorS / PX4 sitl_gazebo IMU plugin: the children of a <plugin> element
///   gyroscopeNoiseDensity N (rad/s/sqrt(Hz))     -> WN sigma2 = (N u)^2 f
///   gyroscopeRandomWalk K (rad/s^2/sqrt(Hz)) with gyroscopeBiasCorrelationTime T (s)
///                                                -> AR1 as the dynamic bias above (K drives it)
///   gyroscopeTurnOnBiasSigma                     -> constant: no term (a line says so)
///   accelerometer* likewise (m/s^2/sqrt(Hz), m/s^3/sqrt(Hz)).
///
/// With several IMU noise sources in the file, the first (document order) is used and a
/// note names the others. Zero figures leave their term out; a kind without any term is
/// not in the maps. Throws InputError "<path>: ..." (unreadable file, nothing found) or
/// "<path>:<line>: ..." (XML syntax; a negative or non-numeric figure, naming the element;
/// a bias density without a positive correlation time).
SimConfig read_gazebo_sdf(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units);
/// As read_gazebo_sdf, from the file's text; `name` stands for the path in messages.
SimConfig parse_gazebo_sdf(const std::string& text, const std::string& name, double data_freq,
                           const std::map<SensorKind, Unit>& units);

}  // namespace gmwm::io
