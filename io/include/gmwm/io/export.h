#pragma once
// Exports of fitted noise models in the exact form each consumer reads (issue 6, item 3):
// Kalibr imu.yaml, OpenVINS kalibr_imu_chain.yaml, VINS-Mono/Fusion config fields,
// ORB-SLAM3 settings, Basalt calib.json noise fields, a gz-sensors SDF <sensor>/<imu>
// block and RotorS/PX4 IMU <plugin> parameters.
//
// Every figure comes from the engine's continuous ("physical") quantities of the fitted
// components at the data's rate (engine/physical.h): WN -> noise density N = sqrt(sigma2/f),
// RW -> random walk K = sqrt(gamma2 f), AR1/GM -> correlation time T and stationary sigma,
// converted from the data's unit to SI (rad/s, m/s^2) with io/units.h. Each renderer
// (io/src/export_*.cc) documents, next to every field, the consumer's convention and where
// it was read. Components a format cannot express are listed in the file's header as "not
// representable" and returned as warnings (the library never prints).
//
//   gmwm::io::ExportOptions o;            // o.Validate() == "" when usable
//   o.format = gmwm::io::ExportFormat::kKalibr;
//   gmwm::io::ExportResult r = gmwm::io::render_export(columns, o, "fit.json");
//   write_file_atomically(path, r.content);   // + r.sidecar for Basalt (PATH.txt)

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/units.h"

namespace gmwm::io {

enum class ExportFormat { kKalibr, kOpenVins, kVins, kOrbSlam3, kBasalt, kGzSdf, kRotors };
/// "kalibr", "openvins", "vins", "orbslam3", "basalt", "gz-sdf", "rotors".
const char* to_string(ExportFormat f);
std::optional<ExportFormat> parse_export_format(const std::string& name);
/// "kalibr, openvins, vins, orbslam3, basalt, gz-sdf, rotors" (for messages and --help).
std::string export_format_names();
/// The file name a consumer expects ("imu.yaml" for Kalibr, "calib.json" for Basalt, ...),
/// for a download that has no path of its own (gmwm serve).
const char* default_export_filename(ExportFormat f);
/// True for the formats with a field per axis (Basalt 3-vectors, gz-sensors <x>/<y>/<z>).
bool has_per_axis_fields(ExportFormat f);
/// False for the formats without comments (Basalt's JSON): the header goes to a sidecar.
bool allows_comments(ExportFormat f);

/// How the axes of one sensor become the file's figures.
enum class Aggregation {
  kPerAxis,  ///< one figure per axis (only formats with per-axis fields)
  kMean,     ///< arithmetic mean of each figure over the sensor's axes
  kWorst,    ///< largest value of each figure over the sensor's axes
};
const char* to_string(Aggregation a);  ///< "per-axis", "mean", "worst"
std::optional<Aggregation> parse_aggregation(const std::string& name);

/// What an export does for a sensor kind the source has no column of (a gyroscope-only fit
/// exported to a format with accelerometer fields).
enum class MissingSensor {
  /// Refused, naming --partial: a 0 would be read as a perfect sensor, and so would a field
  /// left out by the readers that default it (OpenCV's FileStorage in VINS reads a missing
  /// acc_n as 0; gz-sensors simulates an <imu> without <noise> noise-free).
  kRefuse,
  /// Its fields left out, and the header says so (--partial: one sensor's lines to paste
  /// into a file that has the other's).
  kLeaveOut,
  /// Written as 0, for a caller that writes its own values in their place (gap --corrected
  /// writes the input configuration's).
  kZero,
};

struct ExportOptions {
  ExportFormat format = ExportFormat::kKalibr;
  MissingSensor missing = MissingSensor::kRefuse;
  Aggregation aggregation = Aggregation::kMean;
  /// Multiplies every noise figure written (densities, standard deviations, the bias
  /// driving densities), NOT the variances: a factor x on the figures is x^2 on the
  /// variances. Correlation times are not changed. > 0; 1 writes the fitted values.
  double inflate = 1.0;
  /// The random walks' factor in the WN + RW formats when it differs from `inflate`
  /// (export --consistent-for may inflate K alone: a WN + RW filter lacks the bias's
  /// dynamics, not its white noise). > 0.
  std::optional<double> inflate_walk;
  /// Why the inflation is what it is, for the header (empty: given by the user).
  std::string inflation_reason;
  /// The IMU rate written in update-rate fields (and at which per-sample values are
  /// given: VINS, gz-sensors stddev). Default: the data's rate.
  std::optional<double> rate;
  std::string rostopic = "/imu0";  ///< Kalibr / OpenVINS rostopic

  /// "" when usable, else one line naming the option (--inflate, --rate, --aggregate).
  std::string Validate() const;
};

/// A noise figure as the exporter takes it, in the data's unit (noise_figures.h).
struct ExportFigure {
  double value = 0.0;
  std::string source;  ///< "model", "data" or "bound" (FigureSource)
  std::string note;    ///< where it comes from, one line
};

/// N, K and B to write (from choose_noise_figures, or the model alone).
struct ExportFigures {
  ExportFigure white, walk, instability;
};

/// The export's view of chosen figures.
ExportFigures export_figures(const ChosenFigures& figures);

/// One fitted column, as the exporter takes it (from a fit/select result or a fresh fit).
struct ExportColumn {
  std::string name;
  SensorKind kind = SensorKind::kGyro;
  double freq = 0.0;      ///< the data's sampling rate, Hz (> 0)
  std::int64_t n = 0;     ///< samples in the record (0 when unknown)
  Model model;            ///< canonical, with the fitted values in theta
  Eigen::VectorXd theta;  ///< natural (discrete, per-sample) parameters
  Unit unit;              ///< the data's unit (per_si of it per SI unit)
  /// N, K, B in the data's unit, as the fit/select result chose them against the data's
  /// Allan deviation; when absent they are read off the model's own Allan deviation.
  std::optional<ExportFigures> figures;
};

/// A first-order Gauss-Markov term (AR1 with phi > 0, or GM) in continuous form, SI.
struct GaussMarkovNoise {
  double correlation_time = 0.0;  ///< T, s
  double sigma = 0.0;             ///< stationary standard deviation, SI unit
  /// The driving density sigma_b = sigma sqrt(2 / T) (SI unit/s/sqrt(Hz)) of
  /// db/dt = -b/T + sigma_b w(t): the convention of gz-sensors' dynamic_bias_stddev and
  /// RotorS' *RandomWalk (stationary variance sigma_b^2 T / 2).
  double drive = 0.0;
  std::string text;  ///< the component with its values, for the header
};

/// The continuous noise figures of one column, SI units, before inflation.
struct AxisNoise {
  std::string column;
  SensorKind kind = SensorKind::kGyro;
  char axis = 0;                ///< column_axis(column): 'x', 'y', 'z' or 0
  double freq = 0.0;            ///< the data's rate, Hz
  double record_seconds = 0.0;  ///< n / freq (0 when unknown)
  std::string model;            ///< the fitted model with its values (discrete, data unit)
  Unit unit;                    ///< the data's unit
  /// White noise density N, SI/sqrt(Hz): the IEEE 952 read-off of the model as a whole
  /// (a fast AR1 adds to it), or of the data where the model misses them.
  double white = 0.0;
  /// Random walk K, SI/s/sqrt(Hz): its read-off, or an upper bound where no +1/2 slope shows.
  double walk = 0.0;
  double instability = 0.0;                    ///< bias instability B, SI (for the header)
  ExportFigures figures;                       ///< the three with their sources and notes (data unit)
  std::vector<GaussMarkovNoise> gauss_markov;  ///< slow terms (T >= 1 s), by increasing correlation time
  std::vector<std::string> absorbed;           ///< fast terms counted in N (T < 1 s), as text
  std::vector<std::string> others;             ///< the remaining components (QN, DR, SIN, ...) as text
};

/// The figures of one column: N and K from its noise figures (ExportColumn::figures, else
/// the model's own Allan deviation), Gauss-Markov biases from its slow AR1/GM components,
/// divided by unit.per_si. Throws InvalidArgument (check.h) for a non-positive rate or a
/// theta that does not match the model.
AxisNoise axis_noise(const ExportColumn& column);

/// What a file holds for one axis (or the aggregate of a sensor's axes): SI, inflated.
struct WrittenNoise {
  double noise_density = 0.0;  ///< N x inflate, SI/sqrt(Hz)
  double random_walk = 0.0;    ///< K x inflate, SI/s/sqrt(Hz)
  /// Simulators (gz-sdf, rotors): the one Gauss-Markov bias they model, with its driving
  /// density (x inflate) and correlation time; from the AR1/GM with the longest correlation
  /// time, else from the random walk (see bias_from_random_walk).
  double bias_drive = 0.0;
  double bias_correlation_time = 0.0;
  bool bias_from_random_walk = false;  ///< a random walk approximated by a long-T bias
};

/// The written figures of one sensor kind.
struct KindExport {
  SensorKind kind = SensorKind::kGyro;
  std::vector<std::string> columns;  ///< the columns of this kind (empty: none in the source)
  bool per_axis = false;
  std::array<WrittenNoise, 3> axes{};  ///< x, y, z (per-axis only)
  WrittenNoise combined;               ///< mean/worst over the columns (also for per-axis)
};

struct ExportResult {
  std::string content;                 ///< the file's text
  std::optional<std::string> sidecar;  ///< text for PATH.txt (formats without comments)
  double rate = 0.0;                   ///< update rate written, Hz
  std::vector<AxisNoise> columns;      ///< per column, before inflation
  std::vector<KindExport> kinds;       ///< gyro, then accel
  std::vector<std::string> header;     ///< the header lines (as written, without markers)
  std::vector<std::string> warnings;   ///< one line each (not representable, missing kind, ...)
};

/// Renders `columns` in options.format. `source` says where the models come from (one
/// line, e.g. "gmwm fit result fit.json (data imu.csv)"). Throws InputError (one line) for
/// options that do not validate, per-axis aggregation without exactly one column for each
/// of the x, y and z axes of a present sensor, columns whose rates differ without
/// options.rate, or no column at all.
ExportResult render_export(const std::vector<ExportColumn>& columns, const ExportOptions& options,
                           const std::string& source);

/// How to read a fit/select result (read_result_columns).
struct ResultReadOptions {
  std::vector<std::string> columns;  ///< keep only these names, in this order (empty: all)
  std::optional<double> rate;        ///< the data's rate for columns whose "freq" is null
  std::optional<SensorKind> sensor;  ///< every column is this sensor (else told by its name)
  /// Declared units (--units): the unit of a column whose "unit" field is null or absent.
  /// A column without either is refused (never taken as SI), and so is a declared unit
  /// contradicting the column's own.
  std::optional<std::map<SensorKind, Unit>> units;
  /// Read the models as they are, in the data's unit, whatever it is (a record-length plan
  /// needs no unit): the column's "unit" is kept as its name only (per_si 1, "" when
  /// absent), and a name that tells no sensor kind is read as a gyroscope's.
  bool unit_free = false;
};

struct ResultColumns {
  std::string command;  ///< "fit" or "select"
  std::string input;    ///< the document's "input" (the data file), "" if absent
  std::vector<ExportColumn> columns;
  std::vector<std::string> statuses;  ///< per column: "converged", "not_converged", ...
};

/// The fitted columns of a `gmwm fit --json` or `gmwm select --json` document: per column
/// "name", "n", "freq" and the model with its values ("model" for fit, "best_model" for
/// select), parsed with the model syntax at the column's rate. Throws InputError naming the
/// path (with line:column for a JSON syntax error, or the column) for anything else: not a
/// gmwm fit/select document, a column without a fitted model (its fit failed), an unknown
/// name in options.columns, a null "freq" without options.rate, a name that tells no sensor
/// kind without options.sensor, a column whose unit is not known (ResultReadOptions::units).
/// The file is read as a side file (side_file.h: at most kMaxSideFileBytes; a device, folder
/// or socket refused; a FIFO's writer waited for 5 s).
ResultColumns read_result_columns(const std::string& path, const ResultReadOptions& options);
/// The same from the document's text, already read from `path` (a pipe can be read only
/// once: `gmwm fit --json - | gmwm export /dev/stdin ...`); `path` names it in messages.
ResultColumns read_result_columns(const std::string& path, const std::string& text, const ResultReadOptions& options);

}  // namespace gmwm::io
