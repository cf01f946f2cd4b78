// Exports (io/export.h): every format's fields against numbers computed by hand from that
// format's own documentation, the aggregation, the inflation, the components a format
// cannot express, bad options, reading a fit/select result, and the Kalibr round trip (fit
// WN+RW, export, import with io::read_kalibr_imu_yaml, simulate, refit).
//
// The reference sensor is the EuRoC ADIS16448 of Kalibr's imu_adis16448.yaml at 200 Hz:
//   gyro  N = 1.6968e-04 rad/s/sqrt(Hz) -> WN sigma2 = N^2 f = 2.87913024e-08 x 200 = 5.75826048e-06 (rad/s)^2
//         K = 1.9393e-05 rad/s^2/sqrt(Hz) -> RW gamma2 = K^2 / f = 3.76088449e-10 / 200 = 1.880442245e-12
//   accel N = 2.0e-03 m/s^2/sqrt(Hz)     -> WN sigma2 = 4e-06 x 200 = 8e-04 (m/s^2)^2
//         K = 3.0e-03 m/s^3/sqrt(Hz)     -> RW gamma2 = 9e-06 / 200 = 4.5e-08
// so an export must give back N and K (the engine's N = sqrt(sigma2 / f), K = sqrt(gamma2 f)).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/io/export.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "test_support.h"

namespace gmwm::io {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kGyroEuroc = "WN(sigma2=5.75826048e-06)+RW(gamma2=1.880442245e-12)";
constexpr const char* kAccelEuroc = "WN(sigma2=8e-04)+RW(gamma2=4.5e-08)";

ExportColumn column(const std::string& name, const std::string& spec, double freq = 200.0, std::int64_t n = 65536,
                    std::optional<Unit> unit = std::nullopt) {
  ExportColumn c;
  c.name = name;
  c.kind = sensor_kind_of_column(name);
  c.freq = freq;
  c.n = n;
  c.unit = unit ? *unit : si_unit(c.kind);
  c.model = parse_model(spec, ProcessContext{freq, true});
  c.theta = c.model.given_values();
  c.model = c.model.canonical(&c.theta);
  return c;
}

std::vector<ExportColumn> euroc_six_axes() {
  std::vector<ExportColumn> v;
  for (const char* a : {"x", "y", "z"}) v.push_back(column(std::string("gyro_") + a, kGyroEuroc));
  for (const char* a : {"x", "y", "z"}) v.push_back(column(std::string("accel_") + a, kAccelEuroc));
  return v;
}

// The options of format f; a source with one sensor writes that sensor's fields alone
// (--partial: the refusal without it has its own test).
ExportOptions options(ExportFormat f) {
  ExportOptions o;
  o.format = f;
  o.missing = MissingSensor::kLeaveOut;
  return o;
}

// The raw value of "key: value  # comment" (the first such line, any indentation).
// A YAML export parsed by a real YAML parser (yaml-cpp), after OpenCV's "%YAML:1.0" first
// line (a FileStorage directive yaml-cpp does not know; OpenCV itself skips it): the
// scalar under `key`, searched through nested maps (a chain's imu0), as written.
std::optional<std::string> find_scalar(const YAML::Node& node, const std::string& key) {
  if (!node.IsMap()) return std::nullopt;
  for (const auto& kv : node) {
    if (kv.first.as<std::string>() == key && kv.second.IsScalar()) return kv.second.Scalar();
    if (auto v = find_scalar(kv.second, key)) return v;
  }
  return std::nullopt;
}

std::string raw(const std::string& text, const std::string& key) {
  std::string yaml = text;
  if (yaml.rfind("%YAML:", 0) == 0) yaml.erase(0, yaml.find('\n') + 1);
  YAML::Node doc;
  try {
    doc = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    ADD_FAILURE() << "not valid YAML (" << e.what() << "):\n" << text;
    return "nan";
  }
  if (auto v = find_scalar(doc, key)) return *v;
  ADD_FAILURE() << "no scalar '" << key << "' in\n" << text;
  return "nan";
}

double value(const std::string& text, const std::string& key) { return std::stod(raw(text, key)); }

// The k-th <name> element of an XML export (in document order), parsed by tinyxml2, as a number.
double element(const std::string& text, const std::string& name, int k = 0) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    ADD_FAILURE() << "not valid XML (" << doc.ErrorStr() << "):\n" << text;
    return std::nan("");
  }
  int seen = 0;
  const std::function<const tinyxml2::XMLElement*(const tinyxml2::XMLElement*)> find =
      [&](const tinyxml2::XMLElement* e) -> const tinyxml2::XMLElement* {
    for (; e; e = e->NextSiblingElement()) {
      if (name == e->Name() && seen++ == k) return e;
      if (const auto* f = find(e->FirstChildElement())) return f;
    }
    return nullptr;
  };
  const tinyxml2::XMLElement* e = find(doc.FirstChildElement());
  if (!e || !e->GetText()) {
    ADD_FAILURE() << "no <" << name << "> #" << k;
    return std::nan("");
  }
  return std::stod(e->GetText());
}

std::string write_file(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

class Export : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("export"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// --- Kalibr ---------------------------------------------------------------------------

TEST_F(Export, KalibrWritesTheEurocDensitiesAndTheImporterReadsThemBack) {
  const ExportResult r = render_export(euroc_six_axes(), options(ExportFormat::kKalibr), "test");
  // Kalibr's fields are the continuous densities themselves (IMU-Noise-Model wiki).
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 1.6968e-04, 1e-13);
  EXPECT_NEAR(value(r.content, "gyroscope_random_walk"), 1.9393e-05, 1e-14);
  EXPECT_NEAR(value(r.content, "accelerometer_noise_density"), 2.0e-03, 1e-12);
  EXPECT_NEAR(value(r.content, "accelerometer_random_walk"), 3.0e-03, 1e-12);
  EXPECT_EQ(raw(r.content, "update_rate"), "200.0");
  EXPECT_EQ(raw(r.content, "rostopic"), "/imu0");
  EXPECT_TRUE(r.warnings.empty());
  // Back through our importer at the data's 200 Hz: the same discrete values.
  const SimConfig c = read_kalibr_imu_yaml(write_file(dir_, "imu.yaml", r.content), 200.0, parse_units(""));
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(0), 5.75826048e-06, 1e-17);
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(1), 1.880442245e-12, 1e-23);
  EXPECT_NEAR(c.models.at(SensorKind::kAccel).given_values()(0), 8e-04, 1e-15);
  EXPECT_NEAR(c.models.at(SensorKind::kAccel).given_values()(1), 4.5e-08, 1e-19);
}

TEST_F(Export, KalibrConvertsDegreesPerSecondAndGDataToSi) {
  // ADIS16405 datasheet figures at 100 Hz, data in deg/s and g:
  //   gyro  N = 0.05 deg/s/sqrt(Hz): sigma2 = 0.05^2 x 100 = 0.25 (deg/s)^2
  //         -> N_SI = 0.05 x pi/180 = 8.7266463e-04 rad/s/sqrt(Hz)
  //         K = 0.002 deg/s^2/sqrt(Hz): gamma2 = 0.002^2 / 100 = 4e-08 -> K_SI = 0.002 x pi/180 = 3.4906585e-05
  //   accel N = 0.5 mg/sqrt(Hz) = 5e-04 g/sqrt(Hz): sigma2 = 2.5e-07 x 100 = 2.5e-05 g^2
  //         -> N_SI = 5e-04 x 9.80665 = 4.903325e-03 m/s^2/sqrt(Hz)
  const auto units = parse_units("gyro=deg/s,accel=g");
  std::vector<ExportColumn> v{
      column("gyro_x", "WN(sigma2=0.25)+RW(gamma2=4e-08)", 100.0, 65536, units.at(SensorKind::kGyro)),
      column("accel_x", "WN(sigma2=2.5e-05)", 100.0, 65536, units.at(SensorKind::kAccel))};
  const ExportResult r = render_export(v, options(ExportFormat::kKalibr), "test");
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 0.05 * kPi / 180.0, 1e-15);
  EXPECT_NEAR(value(r.content, "gyroscope_random_walk"), 0.002 * kPi / 180.0, 1e-16);
  EXPECT_NEAR(value(r.content, "accelerometer_noise_density"), 5e-04 * 9.80665, 1e-15);
  EXPECT_NE(r.content.find("gyro data in deg/s -> rad/s"), std::string::npos) << r.content;
  EXPECT_NE(r.content.find("accel data in g -> m/s^2"), std::string::npos) << r.content;
  // No accel RW: never 0 (Kalibr needs a positive value), but the upper bound that the
  // white noise leaves over the record (655 s at 100 Hz, its usable taus up to N / 8):
  // K <= min ADEV(tau) sqrt(3 / tau), reached at the longest usable tau, and the header
  // says it is a bound.
  const double k = value(r.content, "accelerometer_random_walk");
  const double n_si = 5e-04 * 9.80665;
  EXPECT_GT(k, 0.0);
  EXPECT_LT(k, n_si * std::sqrt(3.0) / 30.0) << "at most N sqrt(3) / tau at tau >= 30 s";
  EXPECT_GT(k, n_si * std::sqrt(3.0) / 100.0) << "the bound comes from within the record";
  EXPECT_NE(
      r.content.find("accel_x (g data): K not read in the model's Allan deviation (the data were not at hand): no +1/2 "
                     "slope: an upper bound"),
      std::string::npos)
      << r.content;
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
}

TEST_F(Export, KalibrHeaderSaysTheSourceTheModelsTheAggregationTheInflationAndTheUnits) {
  ExportOptions o = options(ExportFormat::kKalibr);
  o.inflate = 2.0;
  const ExportResult r = render_export(euroc_six_axes(), o, "gmwm fit result fit.json");
  for (const char* s :
       {"# Generated by gmwm", "# Source: gmwm fit result fit.json", "#   gyro_y (gyro, rad/s at 200 Hz",
        "WN(sigma2=5.7582604800000002e-06)+RW(gamma2=1.8804422449999999e-12)", "# Aggregation: mean",
        "# Inflation: x2 on every noise figure", "variances, which grow x4", "# Units: gyro data in rad/s",
        "# Not representable in Kalibr imu.yaml: none"})
    EXPECT_NE(r.content.find(s), std::string::npos) << "missing '" << s << "' in\n" << r.content;
}

// --- Aggregation and inflation --------------------------------------------------------

TEST_F(Export, MeanAndWorstAggregateEachFigureOverTheAxes) {
  // Gyro N = 1e-4, 2e-4, 6e-4 rad/s/sqrt(Hz) at 100 Hz: sigma2 = N^2 x 100 = 1e-6, 4e-6, 3.6e-5.
  // Mean N = (1 + 2 + 6) / 3 x 1e-4 = 3e-4; worst N = 6e-4.
  std::vector<ExportColumn> v{column("gyro_x", "WN(sigma2=1e-06)", 100.0), column("gyro_y", "WN(sigma2=4e-06)", 100.0),
                              column("gyro_z", "WN(sigma2=3.6e-05)", 100.0)};
  ExportOptions o = options(ExportFormat::kKalibr);
  EXPECT_NEAR(value(render_export(v, o, "t").content, "gyroscope_noise_density"), 3e-4, 1e-15);
  o.aggregation = Aggregation::kWorst;
  const ExportResult r = render_export(v, o, "t");
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 6e-4, 1e-15);
  EXPECT_NE(r.content.find("# Aggregation: worst: the largest value"), std::string::npos);
}

TEST_F(Export, InflationMultipliesTheDensitiesNotTheVariances) {
  // x3 on N = 1.6968e-4 -> 5.0904e-4; the importer's per-sample variance grows x9:
  // 9 x 5.75826048e-06 = 5.182434432e-05.
  ExportOptions o = options(ExportFormat::kKalibr);
  o.inflate = 3.0;
  const ExportResult r = render_export(euroc_six_axes(), o, "t");
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 5.0904e-04, 1e-13);
  EXPECT_NEAR(value(r.content, "gyroscope_random_walk"), 5.8179e-05, 1e-14);
  const SimConfig c = read_kalibr_imu_yaml(write_file(dir_, "imu.yaml", r.content), 200.0, parse_units(""));
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(0), 5.182434432e-05, 1e-16);
}

// --- Components a format cannot express ------------------------------------------------

TEST_F(Export, ComponentsKalibrCannotExpressAreListedInTheHeaderAndWarned) {
  std::vector<ExportColumn> v{column("gyro_x", std::string("AR1(phi=0.999,sigma2=1e-10)+QN(Q2=1e-9)+") + kGyroEuroc)};
  const ExportResult r = render_export(v, options(ExportFormat::kKalibr), "t");
  // The representable figures are unchanged by the others.
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 1.6968e-04, 1e-13);
  EXPECT_NE(r.content.find("# Not representable in Kalibr imu.yaml (left out):"), std::string::npos) << r.content;
  EXPECT_NE(r.content.find("#   gyro_x: AR1(phi=0.999"), std::string::npos) << r.content;
  EXPECT_NE(r.content.find("#   gyro_x: QN(Q2=1.0000000000000001e-09)"), std::string::npos) << r.content;
  bool warned = false;
  for (const auto& w : r.warnings) warned = warned || w.find("column 'gyro_x': AR1, QN not representable") == 0;
  EXPECT_TRUE(warned);
}

TEST_F(Export, AMissingSensorIsRefusedLeftOutOnRequestOrZeroForACallerThatReplacesIt) {
  // Refused by default: a 0 would read as a perfect accelerometer.
  ExportOptions o = options(ExportFormat::kOrbSlam3);
  o.missing = ExportOptions{}.missing;
  EXPECT_EQ(o.missing, MissingSensor::kRefuse);
  try {
    render_export({column("gyro_x", kGyroEuroc)}, o, "t");
    ADD_FAILURE() << "a gyroscope alone was exported to a file with accelerometer fields";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no accelerometer column in the source"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--partial"), std::string::npos) << e.what();
  }
  // --partial: the accelerometer's fields left out, warned, said in the header.
  o.missing = MissingSensor::kLeaveOut;
  ExportResult r = render_export({column("gyro_x", kGyroEuroc)}, o, "t");
  EXPECT_EQ(r.content.find("IMU.NoiseAcc"), std::string::npos) << r.content;
  EXPECT_EQ(r.content.find("IMU.AccWalk"), std::string::npos) << r.content;
  EXPECT_NE(r.content.find("IMU.NoiseGyro"), std::string::npos) << r.content;
  bool warned = false;
  for (const auto& w : r.warnings) warned = warned || w.find("No accelerometer column in the source (--partial)") == 0;
  EXPECT_TRUE(warned);
  // Zeros, for gap --corrected, which writes the input's values there.
  o.missing = MissingSensor::kZero;
  r = render_export({column("gyro_x", kGyroEuroc)}, o, "t");
  EXPECT_EQ(raw(r.content, "IMU.NoiseAcc"), "0.0");
}

// --- OpenVINS, VINS, ORB-SLAM3 ----------------------------------------------------------

TEST_F(Export, OpenVinsWritesTheKalibrDensitiesUnderImu0) {
  // OpenVINS reads imu0's densities as continuous-time noise (NoiseManager sigma_w etc.): the
  // same numbers as Kalibr.
  const ExportResult r = render_export(euroc_six_axes(), options(ExportFormat::kOpenVins), "t");
  EXPECT_EQ(r.content.rfind("%YAML:1.0", 0), 0u);
  EXPECT_NE(r.content.find("\nimu0:\n  T_i_b:\n    - [1.0, 0.0, 0.0, 0.0]\n"), std::string::npos) << r.content;
  EXPECT_NEAR(value(r.content, "gyroscope_noise_density"), 1.6968e-04, 1e-13);
  EXPECT_NEAR(value(r.content, "accelerometer_random_walk"), 3.0e-03, 1e-12);
  EXPECT_EQ(raw(r.content, "model"), "kalibr");  // a YAML string (written quoted)
  EXPECT_EQ(raw(r.content, "time_offset"), "0.0");
  EXPECT_EQ(raw(r.content, "update_rate"), "200.0");
  // The file's key: value lines are what our Kalibr importer reads too.
  const SimConfig c = read_kalibr_imu_yaml(write_file(dir_, "chain.yaml", r.content), 200.0, parse_units(""));
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(0), 5.75826048e-06, 1e-17);
}

TEST_F(Export, VinsWritesPerSampleDeviationsAtTheImuRate) {
  // VINS (integration_base.h): gyr_n = N sqrt(R), gyr_w = K sqrt(R) at R = 200 Hz, sqrt(200) = 14.1421356:
  //   gyr_n = 1.6968e-4 x 14.1421356 = 2.39963757e-03 rad/s (= sqrt(sigma2) = sqrt(5.75826048e-06))
  //   gyr_w = 1.9393e-5 x 14.1421356 = 2.7425844e-04 rad/s^2
  //   acc_n = 2e-3 x 14.1421356 = 2.8284271e-02 m/s^2,  acc_w = 3e-3 x 14.1421356 = 4.2426407e-02 m/s^3
  const ExportResult r = render_export(euroc_six_axes(), options(ExportFormat::kVins), "t");
  EXPECT_NEAR(value(r.content, "gyr_n"), 2.3996376e-03, 1e-10);
  EXPECT_NEAR(value(r.content, "gyr_w"), 2.7425844e-04, 1e-11);
  EXPECT_NEAR(value(r.content, "acc_n"), 2.8284271e-02, 1e-9);
  EXPECT_NEAR(value(r.content, "acc_w"), 4.2426407e-02, 1e-9);
  // At --rate 400: sqrt(400) = 20 -> gyr_n = 3.3936e-03.
  ExportOptions o = options(ExportFormat::kVins);
  o.rate = 400.0;
  EXPECT_NEAR(value(render_export(euroc_six_axes(), o, "t").content, "gyr_n"), 3.3936e-03, 1e-12);
}

TEST_F(Export, OrbSlam3WritesContinuousDensitiesAsReals) {
  // ORB-SLAM3 discretises IMU.NoiseGyro itself (x sqrt(IMU.Frequency)): the continuous N, K.
  const ExportResult r = render_export(euroc_six_axes(), options(ExportFormat::kOrbSlam3), "t");
  EXPECT_EQ(r.content.rfind("%YAML:1.0", 0), 0u);
  EXPECT_NEAR(value(r.content, "IMU.NoiseGyro"), 1.6968e-04, 1e-13);
  EXPECT_NEAR(value(r.content, "IMU.NoiseAcc"), 2.0e-03, 1e-12);
  EXPECT_NEAR(value(r.content, "IMU.GyroWalk"), 1.9393e-05, 1e-14);
  EXPECT_NEAR(value(r.content, "IMU.AccWalk"), 3.0e-03, 1e-12);
  // Settings::readParameter<float> aborts on an integer: every value has a '.'.
  EXPECT_EQ(raw(r.content, "IMU.Frequency"), "200.0");
  for (const char* k : {"IMU.NoiseGyro", "IMU.NoiseAcc", "IMU.GyroWalk", "IMU.AccWalk"})
    EXPECT_NE(raw(r.content, k).find('.'), std::string::npos) << k;
}

// --- Basalt ----------------------------------------------------------------------------

TEST_F(Export, BasaltWritesPerAxisVectorsAndItsHeaderToASidecar) {
  // Gyro N = 1e-4, 2e-4, 3e-4 rad/s/sqrt(Hz) at 100 Hz: sigma2 = N^2 x 100 = 1e-6, 4e-6, 9e-6;
  // K = 1e-5, 2e-5, 3e-5 rad/s^2/sqrt(Hz): gamma2 = K^2 / 100 = 1e-12, 4e-12, 9e-12.
  // Basalt's noise_std and bias_std are continuous densities (calibration.hpp), per axis.
  std::vector<ExportColumn> v{column("gyro_x", "WN(sigma2=1e-06)+RW(gamma2=1e-12)", 100.0),
                              column("gyro_y", "WN(sigma2=4e-06)+RW(gamma2=4e-12)", 100.0),
                              column("gyro_z", "WN(sigma2=9e-06)+RW(gamma2=9e-12)", 100.0)};
  ExportOptions o = options(ExportFormat::kBasalt);
  o.aggregation = Aggregation::kPerAxis;
  const ExportResult r = render_export(v, o, "t");
  const auto doc = nlohmann::json::parse(r.content);
  const auto& f = doc.at("value0");
  EXPECT_DOUBLE_EQ(f.at("imu_update_rate").get<double>(), 100.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(f.at("gyro_noise_std")[i].get<double>(), 1e-4 * (i + 1), 1e-16);
    EXPECT_NEAR(f.at("gyro_bias_std")[i].get<double>(), 1e-5 * (i + 1), 1e-17);
  }
  EXPECT_FALSE(f.contains("accel_noise_std")) << "no accel column: its fields left out (--partial), never 0";
  ASSERT_TRUE(r.sidecar.has_value());
  EXPECT_NE(r.sidecar->find("All noise parameters are continous time"), std::string::npos);
  EXPECT_NE(r.sidecar->find("Aggregation: per-axis"), std::string::npos);
  EXPECT_EQ(r.sidecar->find('#'), std::string::npos) << "plain text, not YAML comments";
  // Mean: (1 + 2 + 3) / 3 x 1e-4 = 2e-4 on each axis.
  o.aggregation = Aggregation::kMean;
  const auto mean = nlohmann::json::parse(render_export(v, o, "t").content);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(mean["value0"]["gyro_noise_std"][i].get<double>(), 2e-4, 1e-16);
}

// --- gz-sensors SDF --------------------------------------------------------------------

TEST_F(Export, GzSdfWritesPerSampleStddevAndDrivingDensitiesThatTheImporterReadsBack) {
  // gyro: WN N = 1.6968e-4 at 200 Hz -> stddev = N sqrt(200) = sqrt(5.75826048e-06) = 2.3996376e-03 rad/s
  //       AR1 with T = 1000 s, stationary sigma 1e-4 rad/s: phi = exp(-1/(200 x 1000)) = exp(-5e-06),
  //       innovation sigma2 = 1e-8 x (1 - phi^2) = 1e-8 x -expm1(-1e-5) = 9.9999500002e-14
  //       -> dynamic_bias_stddev = sigma sqrt(2/T) = 1e-4 x sqrt(0.002) = 4.4721360e-06 rad/s^2/sqrt(Hz),
  //          dynamic_bias_correlation_time = 1000 s
  // accel: RW K = 3e-3 (gamma2 4.5e-08) -> a bias driven by K = 3e-3 with T = 1000 x the record,
  //        65536 / 200 = 327.68 s -> T = 327680 s.
  const std::string ar1 = "AR1(phi=0.9999950000125,sigma2=9.999950000166666e-14)";
  std::vector<ExportColumn> v;
  for (const char* a : {"x", "y", "z"})
    v.push_back(column(std::string("gyro_") + a, ar1 + "+WN(sigma2=5.75826048e-06)"));
  for (const char* a : {"x", "y", "z"})
    v.push_back(column(std::string("accel_") + a, "WN(sigma2=8e-04)+RW(gamma2=4.5e-08)"));
  const ExportResult r = render_export(v, options(ExportFormat::kGzSdf), "t");
  EXPECT_NEAR(element(r.content, "stddev", 0), 2.3996376e-03, 1e-10);
  EXPECT_NEAR(element(r.content, "dynamic_bias_stddev", 0), 4.4721360e-06, 1e-12);
  EXPECT_NEAR(element(r.content, "dynamic_bias_correlation_time", 0), 1000.0, 1e-6);
  EXPECT_NEAR(element(r.content, "stddev", 3), std::sqrt(8e-4), 1e-15);  // accel <x>: 2e-3 x sqrt(200)
  EXPECT_NEAR(element(r.content, "dynamic_bias_stddev", 3), 3e-3, 1e-15);
  EXPECT_NEAR(element(r.content, "dynamic_bias_correlation_time", 3), 327680.0, 1e-6);
  EXPECT_NEAR(element(r.content, "update_rate"), 200.0, 0.0);
  EXPECT_NE(r.content.find("Random walk as a bias"), std::string::npos);
  // Back through io::read_gazebo_sdf at 200 Hz: the AR1 exactly, the random walk as an AR1
  // with phi = exp(-1/(200 x 327680)) whose innovation variance is K^2 (T/2)(1 - exp(-2/(f T)))
  // = gamma2 to within 1/(f T) = 1.5e-8.
  const SimConfig c = read_gazebo_sdf(write_file(dir_, "imu.sdf", r.content), 200.0, parse_units(""));
  const Eigen::VectorXd g = c.models.at(SensorKind::kGyro).given_values();
  ASSERT_EQ(c.models.at(SensorKind::kGyro).to_string(), "AR1+WN");
  EXPECT_NEAR(g(0), 0.9999950000125, 1e-15);
  EXPECT_NEAR(g(1), 9.999950000166666e-14, 1e-25);
  EXPECT_NEAR(g(2), 5.75826048e-06, 1e-17);
  const Eigen::VectorXd a = c.models.at(SensorKind::kAccel).given_values();
  EXPECT_NEAR(a(0), std::exp(-1.0 / (200.0 * 327680.0)), 1e-15);
  EXPECT_NEAR(a(1), 4.5e-08, 4.5e-08 * 1e-7);
  EXPECT_NEAR(a(2), 8e-04, 1e-15);
}

TEST_F(Export, GzSdfPerAxisWritesEachAxisItsOwnBlock) {
  // N = 1e-4, 2e-4, 3e-4 at 100 Hz -> stddev = N x 10 = 1e-3, 2e-3, 3e-3 rad/s. No random
  // walk: its bound is not simulated as a bias (the header says so), so the importer finds
  // the white noise alone.
  std::vector<ExportColumn> v{column("gyro_z", "WN(sigma2=9e-06)", 100.0), column("gyro_x", "WN(sigma2=1e-06)", 100.0),
                              column("gyro_y", "WN(sigma2=4e-06)", 100.0)};
  ExportOptions o = options(ExportFormat::kGzSdf);
  o.aggregation = Aggregation::kPerAxis;
  const ExportResult r = render_export(v, o, "t");
  EXPECT_NEAR(element(r.content, "stddev", 0), 1e-3, 1e-15);
  EXPECT_NEAR(element(r.content, "stddev", 1), 2e-3, 1e-15);
  EXPECT_NEAR(element(r.content, "stddev", 2), 3e-3, 1e-15);
  EXPECT_EQ(r.content.find("<linear_acceleration>", r.content.find("-->")), std::string::npos);  // no accel column
  const SimConfig c = read_gazebo_sdf(write_file(dir_, "imu.sdf", r.content), 100.0, parse_units(""));
  EXPECT_NEAR(c.axis_models.at("gyro_y").given_values()(0), 4e-06, 1e-18);
}

TEST_F(Export, GzSdfInflationScalesStddevAndDriveButNotTheCorrelationTime) {
  ExportOptions o = options(ExportFormat::kGzSdf);
  o.inflate = 2.0;
  const ExportResult r = render_export(euroc_six_axes(), o, "t");
  EXPECT_NEAR(element(r.content, "stddev", 0), 2.0 * 2.3996376e-03, 2e-10);
  EXPECT_NEAR(element(r.content, "dynamic_bias_stddev", 0), 2.0 * 1.9393e-05, 1e-15);
  EXPECT_NEAR(element(r.content, "dynamic_bias_correlation_time", 0), 327680.0, 1e-6);
}

// --- RotorS ----------------------------------------------------------------------------

TEST_F(Export, RotorsWritesDensitiesAndTheBiasAsItsGaussMarkovParameters) {
  // RotorS (gazebo_imu_plugin.h): NoiseDensity = N, RandomWalk = the bias driving density, with
  // BiasCorrelationTime. gyro: N = 1.6968e-4, K = 1.9393e-5 as a bias with T = 1000 x 327.68 s.
  // accel: AR1 with T = 300 s, sigma 0.01 m/s^2 at 200 Hz: phi = exp(-1/60000), innovation
  // 1e-4 x -expm1(-2/60000) = 3.3332777784e-09 -> drive = 0.01 sqrt(2/300) = 8.1649658e-04 m/s^3/sqrt(Hz).
  std::vector<ExportColumn> v{
      column("gyro_x", kGyroEuroc),
      column("accel_x", "AR1(phi=0.9999833334722215,sigma2=3.3332777783950565e-09)+WN(sigma2=8e-04)")};
  const ExportResult r = render_export(v, options(ExportFormat::kRotors), "t");
  EXPECT_NEAR(element(r.content, "gyroscopeNoiseDensity"), 1.6968e-04, 1e-13);
  EXPECT_NEAR(element(r.content, "gyroscopeRandomWalk"), 1.9393e-05, 1e-14);
  EXPECT_NEAR(element(r.content, "gyroscopeBiasCorrelationTime"), 327680.0, 1e-6);
  EXPECT_NEAR(element(r.content, "gyroscopeTurnOnBiasSigma"), 0.0, 0.0);
  EXPECT_NEAR(element(r.content, "accelerometerNoiseDensity"), 2.0e-03, 1e-12);
  EXPECT_NEAR(element(r.content, "accelerometerRandomWalk"), 8.1649658e-04, 1e-10);
  EXPECT_NEAR(element(r.content, "accelerometerBiasCorrelationTime"), 300.0, 1e-6);
  const SimConfig c = read_gazebo_sdf(write_file(dir_, "plugin.xml", r.content), 200.0, parse_units(""));
  EXPECT_EQ(c.source.rfind("RotorS/PX4", 0), 0u);
  EXPECT_NEAR(c.models.at(SensorKind::kAccel).given_values()(1), 3.3332777783950565e-09, 1e-20);
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(2), 5.75826048e-06, 1e-17);
}

TEST_F(Export, SimulatorsHoldOneBiasSoARandomWalkBesideAnAr1IsNotRepresentable) {
  std::vector<ExportColumn> v{column("gyro_x", std::string("AR1(phi=0.999,sigma2=1e-10)+") + kGyroEuroc)};
  const ExportResult r = render_export(v, options(ExportFormat::kRotors), "t");
  EXPECT_NE(r.content.find("gyro_x: RW (K = 1.9393e-05"), std::string::npos) << r.content;
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("RW not representable"), std::string::npos) << r.warnings[0];
}

// --- Bad options -----------------------------------------------------------------------

std::string error_of(const std::vector<ExportColumn>& v, const ExportOptions& o) {
  try {
    render_export(v, o, "t");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(Export, BadOptionsAreOneLineMessagesNamingTheOption) {
  ExportOptions o = options(ExportFormat::kKalibr);
  o.inflate = 0.0;
  EXPECT_EQ(o.Validate().rfind("--inflate 0: expected a positive factor", 0), 0u) << o.Validate();
  o.inflate = 1.0;
  o.rate = -5.0;
  EXPECT_EQ(o.Validate(), "--rate: found -5, expected a sampling rate in Hz from 1e-09 to 1e+09");
  o.rate.reset();
  o.aggregation = Aggregation::kPerAxis;
  EXPECT_EQ(o.Validate().rfind("--aggregate per-axis: the kalibr format has one value per sensor", 0), 0u);
  EXPECT_EQ(error_of(euroc_six_axes(), o), o.Validate());
  // Per-axis needs one column per axis.
  ExportOptions b = options(ExportFormat::kBasalt);
  b.aggregation = Aggregation::kPerAxis;
  const std::string e = error_of({column("gyro_x", kGyroEuroc), column("gyro_y", kGyroEuroc)}, b);
  EXPECT_EQ(e.rfind("--aggregate per-axis: expected one gyro column for each of the axes x, y and z", 0), 0u) << e;
  // Different rates need --rate.
  const std::string r = error_of({column("gyro_x", kGyroEuroc, 200.0), column("gyro_y", kGyroEuroc, 100.0)},
                                 options(ExportFormat::kKalibr));
  EXPECT_NE(r.find("different rates (gyro_x 200 Hz, gyro_y 100 Hz); give --rate HZ"), std::string::npos) << r;
  for (const std::string& m : {o.Validate(), e, r}) EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_EQ(parse_export_format("kalibr2"), std::nullopt);
  EXPECT_EQ(parse_export_format("gz-sdf"), ExportFormat::kGzSdf);
}

// --- Reading a fit/select result -------------------------------------------------------

TEST_F(Export, ReadsTheModelsOfAFitAndASelectResult) {
  const std::string fit =
      write_file(dir_, "fit.json",
                 R"J({"tool": "gmwm", "version": "0.1.0", "command": "fit", "input": "imu.csv", "columns": [
          {"name": "gyro_x", "n": 1000, "freq": 200, "model": "WN(sigma2=5.75826048e-06)", "unit": "rad/s",
           "status": "converged"},
          {"name": "w_RS_S_y", "n": 1000, "freq": 200, "model": null, "status": "failed"}]})J");
  ResultReadOptions o;
  o.columns = {"gyro_x"};
  const ResultColumns r = read_result_columns(fit, o);
  ASSERT_EQ(r.columns.size(), 1u);
  EXPECT_EQ(r.command, "fit");
  EXPECT_EQ(r.input, "imu.csv");
  EXPECT_EQ(r.columns[0].kind, SensorKind::kGyro);
  EXPECT_EQ(r.columns[0].n, 1000);
  EXPECT_NEAR(axis_noise(r.columns[0]).white, 1.6968e-04, 1e-13);
  // The failed column is an error once picked, naming it.
  try {
    read_result_columns(fit, {});
    ADD_FAILURE() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("column 'w_RS_S_y': no fitted model (\"model\" is null; status failed)"),
              std::string::npos)
        << e.what();
  }
  const std::string sel = write_file(dir_, "sel.json",
                                     R"J({"tool": "gmwm", "command": "select", "columns": [
          {"name": "acc", "n": 10, "freq": null, "best_model": "WN(sigma2=2.5e-05)", "unit": "g",
           "best_fit": {"status": "converged"}}]})J");
  ResultReadOptions so;
  so.rate = 100.0;
  const ResultColumns s = read_result_columns(sel, so);
  EXPECT_EQ(s.columns[0].unit.name, "g");  // the column's own unit
  EXPECT_NEAR(axis_noise(s.columns[0]).white, 5e-04 * 9.80665, 1e-15);
}

TEST_F(Export, ABadResultFileIsAnErrorNamingThePlace) {
  auto error = [&](const std::string& text) {
    try {
      read_result_columns(write_file(dir_, "r.json", text), {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("{\n  \"tool\": \"gmwm\",\n  oops\n}").find("r.json:3:3: invalid JSON"), std::string::npos);
  EXPECT_NE(
      error(R"J({"tool": "gmwm", "command": "wv", "columns": []})J").find("a gmwm wv document holds no fitted model"),
      std::string::npos);
  EXPECT_NE(
      error(
          R"J({"tool": "gmwm", "command": "fit", "columns": [{"name": "gyro_x", "freq": null, "model": "WN(sigma2=1)"}]})J")
          .find("column 'gyro_x': no sampling rate (\"freq\" is null); give --rate HZ"),
      std::string::npos);
}

// --- The Kalibr round trip ---------------------------------------------------------------

TEST(ExportKalibrRoundTrip, FitExportImportSimulateAndRefitAgreeWithinTheConfidenceIntervals) {
  // WN + RW with the EuRoC gyro figures, 2^17 samples at 200 Hz (655 s), fixed seeds.
  const double f = 200.0;
  const std::int64_t n = std::int64_t{1} << 17;
  const Model truth = parse_model(kGyroEuroc, ProcessContext{f, true});
  const Model family = parse_model("WN+RW", ProcessContext{f, true});
  const std::vector<double> x1 = simulate(truth, truth.given_values(), n, 20240611);
  const FitResult fit1 = fit_gmwm(classical_wv(x1.data(), n), family);
  ASSERT_EQ(fit1.status, FitStatus::kConverged) << fit1.message;

  ExportColumn c;
  c.name = "gyro_x";
  c.kind = SensorKind::kGyro;
  c.freq = f;
  c.n = n;
  c.model = fit1.model;
  c.theta = fit1.theta;
  c.unit = si_unit(SensorKind::kGyro);
  // Kalibr's file holds both sensors (its reader, like Kalibr's, needs all four figures): the
  // same fitted model as the accelerometer's too.
  ExportColumn a = c;
  a.name = "accel_x";
  a.kind = SensorKind::kAccel;
  a.unit = si_unit(SensorKind::kAccel);
  const ExportResult r = render_export({c, a}, ExportOptions{}, "round trip");
  const fs::path dir = gmwm::test::temp_dir("export_round_trip");
  const std::string path = write_file(dir, "imu.yaml", r.content);
  const SimConfig imported = read_kalibr_imu_yaml(path, f, parse_units(""));
  fs::remove_all(dir);
  const Model& m = imported.models.at(SensorKind::kGyro);
  ASSERT_EQ(m.to_string(), "WN+RW");
  const Eigen::VectorXd theta = m.given_values();
  // The numbers survive the text exactly (shortest round-trip digits): sigma2 = N^2 f, gamma2 = K^2 / f.
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(theta(k), fit1.theta(k), 1e-12 * fit1.theta(k)) << k;

  const std::vector<double> x2 = simulate(m, theta, n, 20240612);
  const FitResult fit2 = fit_gmwm(classical_wv(x2.data(), n), family);
  ASSERT_EQ(fit2.status, FitStatus::kConverged) << fit2.message;
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(family.parameter_label(k));
    // Each refit estimate lies in the other fit's confidence interval.
    EXPECT_GE(fit2.theta(k), fit1.ci_low(k));
    EXPECT_LE(fit2.theta(k), fit1.ci_high(k));
    EXPECT_GE(fit1.theta(k), fit2.ci_low(k));
    EXPECT_LE(fit1.theta(k), fit2.ci_high(k));
  }
}

}  // namespace
}  // namespace gmwm::io
