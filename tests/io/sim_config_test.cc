// Units (io/src/units.cc) and the Kalibr imu.yaml reader (io/src/kalibr_yaml.cc), against
// values computed by hand from Kalibr's documented conventions (continuous densities:
// sigma2 = N^2 f for the white noise per sample, gamma2 = K^2 / f for the random walk),
// with the EuRoC ADIS16448 figures Kalibr ships (imu_adis16448.yaml, update_rate 200).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "test_support.h"

namespace gmwm::io {
namespace {

namespace fs = std::filesystem;

class KalibrYaml : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("kalibr"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text) {
    const fs::path p = dir_ / "imu.yaml";
    std::ofstream(p) << text;
    return p.string();
  }
  std::string error_of(const std::string& text, double f = 200.0) {
    try {
      read_kalibr_imu_yaml(write(text), f, parse_units(""));
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

constexpr const char* kEuroc =
    "#Accelerometers\n"
    "accelerometer_noise_density: 2.0000e-3   #Noise density (continuous-time)\n"
    "accelerometer_random_walk:   3.0000e-3   #Bias random walk\n"
    "\n"
    "#Gyroscopes\n"
    "gyroscope_noise_density:     1.6968e-04  #Noise density (continuous-time)\n"
    "gyroscope_random_walk:       1.9393e-05  #Bias random walk\n"
    "\n"
    "rostopic:                    /imu0       #the IMU ROS topic\n"
    "update_rate:                 200.0       #Hz (for discretization of the values above)\n";

TEST_F(KalibrYaml, ConvertsTheEurocDensitiesToPerSampleVariancesAtTheDataRate) {
  const SimConfig c = read_kalibr_imu_yaml(write(kEuroc), 200.0, parse_units(""));
  const Model& gyro = c.models.at(SensorKind::kGyro);
  ASSERT_EQ(gyro.to_string(), "WN+RW");
  // (1.6968e-4)^2 x 200 = 5.7583e-6 (rad/s)^2; (1.9393e-5)^2 / 200 = 1.88044e-12.
  EXPECT_NEAR(gyro.given_values()(0), 5.758260e-06, 1e-12);
  EXPECT_NEAR(gyro.given_values()(1), 1.880442e-12, 1e-17);
  const Model& accel = c.models.at(SensorKind::kAccel);
  EXPECT_NEAR(accel.given_values()(0), 8.0e-4, 1e-15);  // (2e-3)^2 x 200
  EXPECT_NEAR(accel.given_values()(1), 4.5e-8, 1e-20);  // (3e-3)^2 / 200
  ASSERT_EQ(c.conversions.at(SensorKind::kGyro).size(), 2u);
  EXPECT_NE(c.conversions.at(SensorKind::kGyro)[0].find("gyroscope_noise_density = 0.00016968 rad/s/sqrt(Hz) -> WN "
                                                        "sigma2 = (N)^2 x f = 5.75826e-06 (rad/s)^2 per sample"),
            std::string::npos)
      << c.conversions.at(SensorKind::kGyro)[0];
  EXPECT_TRUE(c.notes.empty());
}

TEST_F(KalibrYaml, ConvertsToTheDataUnitsAndSaysWhenTheRatesDiffer) {
  const SimConfig c = read_kalibr_imu_yaml(write(kEuroc), 100.0, parse_units("gyro=deg/s,accel=g"));
  // 1.6968e-4 rad/s/sqrt(Hz) = 9.72194e-3 deg/s/sqrt(Hz); squared x 100 Hz.
  EXPECT_NEAR(c.models.at(SensorKind::kGyro).given_values()(0), 9.451627e-03, 1e-9);
  // 2e-3 m/s^2/sqrt(Hz) = 2.03943e-4 g/sqrt(Hz); squared x 100 Hz.
  EXPECT_NEAR(c.models.at(SensorKind::kAccel).given_values()(0), 4.159285e-06, 1e-12);
  EXPECT_NE(c.conversions.at(SensorKind::kGyro)[0].find("x 57.2958 deg/s per rad/s"), std::string::npos)
      << c.conversions.at(SensorKind::kGyro)[0];
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_NE(c.notes[0].find("update_rate 200 Hz differs from the data's 100 Hz"), std::string::npos) << c.notes[0];
}

TEST_F(KalibrYaml, LeavesOutAZeroFigure) {
  const SimConfig c = read_kalibr_imu_yaml(
      write("accelerometer_noise_density: 0\naccelerometer_random_walk: 1e-4\ngyroscope_noise_density: 1e-4\n"
            "gyroscope_random_walk: 0.0\nupdate_rate: 200\n"),
      200.0, parse_units(""));
  EXPECT_EQ(c.models.at(SensorKind::kAccel).to_string(), "RW");
  EXPECT_EQ(c.models.at(SensorKind::kGyro).to_string(), "WN");
}

TEST_F(KalibrYaml, RejectsMalformedNegativeOrMissingFiguresWithTheLine) {
  EXPECT_NE(error_of("gyroscope_noise_density: abc\n")
                .find("imu.yaml:1: gyroscope_noise_density: found 'abc', "
                      "expected a number"),
            std::string::npos)
      << error_of("gyroscope_noise_density: abc\n");
  EXPECT_NE(error_of("\ngyroscope_random_walk: -1e-5\n")
                .find("imu.yaml:2: gyroscope_random_walk: found -1e-5, "
                      "expected a non-negative noise figure"),
            std::string::npos);
  EXPECT_NE(error_of("gyroscope_noise_density: 1e-4\n").find("missing accelerometer_noise_density"), std::string::npos);
  try {
    read_kalibr_imu_yaml((dir_ / "absent.yaml").string(), 100.0, parse_units(""));
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.yaml: file not found, expected a Kalibr imu.yaml"), std::string::npos)
        << e.what();
  }
}

// An IMU chain as Kalibr's camchain-imucam / OpenVINS's kalibr_imu_chain.yaml write it:
// two IMUs whose figures differ by a factor of 10.
constexpr const char* kChain =
    "%YAML:1.0\n"
    "imu0:\n"
    "  accelerometer_noise_density: 2.0e-3\n"
    "  accelerometer_random_walk: 3.0e-3\n"
    "  gyroscope_noise_density: 1.0e-4\n"
    "  gyroscope_random_walk: 2.0e-5\n"
    "  update_rate: 200.0\n"
    "imu1:\n"
    "  accelerometer_noise_density: 2.0e-2\n"
    "  accelerometer_random_walk: 3.0e-2\n"
    "  gyroscope_noise_density: 1.0e-3\n"
    "  gyroscope_random_walk: 2.0e-4\n"
    "  update_rate: 200.0\n";

TEST_F(KalibrYaml, TakesTheNamedImuOfAChainAndRefusesToGuessBetweenSeveral) {
  const std::string path = write(kChain);
  const SimConfig c0 = read_kalibr_imu_yaml(path, 200.0, parse_units(""), "imu0");
  const SimConfig c1 = read_kalibr_imu_yaml(path, 200.0, parse_units(""), "imu1");
  EXPECT_NEAR(c0.models.at(SensorKind::kGyro).given_values()(0), 1e-8 * 200.0, 1e-18);  // (1e-4)^2 x 200
  EXPECT_NEAR(c1.models.at(SensorKind::kGyro).given_values()(0), 1e-6 * 200.0, 1e-16);  // (1e-3)^2 x 200
  EXPECT_NE(c1.source.find("imu1"), std::string::npos) << c1.source;
  const std::string why = error_of(kChain);
  EXPECT_NE(why.find("imu.yaml: an IMU chain with imu0, imu1: name the IMU, e.g. --kalibr "), std::string::npos) << why;
  try {
    read_kalibr_imu_yaml(path, 200.0, parse_units(""), "imu2");
    ADD_FAILURE() << "imu2 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no IMU 'imu2' in this file (it has imu0, imu1)"), std::string::npos)
        << e.what();
  }
  // A chain of one IMU needs no name.
  const std::string one(kChain, std::string(kChain).find("imu1:"));
  EXPECT_NEAR(read_kalibr_imu_yaml(write(one), 200.0, parse_units("")).models.at(SensorKind::kGyro).given_values()(0),
              2e-6, 1e-18);
}

TEST_F(KalibrYaml, RejectsDuplicateKeysHexFloatsBadYamlAndUnrepresentableFiguresWithTheLine) {
  std::string why = error_of(std::string(kEuroc) + "gyroscope_noise_density: 1e-3\n");
  EXPECT_NE(why.find("imu.yaml:11: duplicate key 'gyroscope_noise_density' (first at line 6)"), std::string::npos)
      << why;
  why = error_of("accelerometer_noise_density: 0x1p-9\n");
  EXPECT_NE(why.find("imu.yaml:1: accelerometer_noise_density: found '0x1p-9', expected a number"), std::string::npos)
      << why;
  why = error_of("gyroscope_noise_density: [1e-4\n");
  EXPECT_NE(why.find("imu.yaml:2:"), std::string::npos) << why;
  EXPECT_NE(why.find("not valid YAML"), std::string::npos) << why;
  why = error_of(
      "accelerometer_noise_density: 1e300\naccelerometer_random_walk: 1e-4\ngyroscope_noise_density: 1e-4\n"
      "gyroscope_random_walk: 1e-5\n");
  EXPECT_NE(why.find("imu.yaml:1: accelerometer_noise_density: 1e+300 gives WN sigma2 = inf per sample"),
            std::string::npos)
      << why;
  why = error_of(
      "accelerometer_noise_density: 1e-4\naccelerometer_random_walk: 1e-300\ngyroscope_noise_density: 1e-4\n"
      "gyroscope_random_walk: 1e-5\n");
  EXPECT_NE(why.find("imu.yaml:2: accelerometer_random_walk: 1e-300 gives RW gamma2 = 0 per sample"), std::string::npos)
      << why;
  EXPECT_NE(error_of("- 1\n- 2\n").find("expected a Kalibr imu.yaml"), std::string::npos);
  why = error_of("accelerometer_noise_density: 1e-3\ngyroscope_noise_density:\ngyroscope_random_walk: 1e-5\n");
  EXPECT_NE(why.find("imu.yaml:2: gyroscope_noise_density: found nothing, expected a number"), std::string::npos)
      << why;
  why = error_of("gyroscope_noise_density: 1e-400\n");
  EXPECT_NE(why.find("imu.yaml:1: gyroscope_noise_density: found 1e-400, beyond the range of a double"),
            std::string::npos)
      << why;
  // YAML 1.2 allows a leading '+'.
  const SimConfig plus = read_kalibr_imu_yaml(
      write("accelerometer_noise_density: +2.0e-3\naccelerometer_random_walk: 3.0e-3\ngyroscope_noise_density: "
            "1.0e-4\ngyroscope_random_walk: 2.0e-5\n"),
      200.0, parse_units(""));
  EXPECT_NEAR(plus.models.at(SensorKind::kAccel).given_values()(0), 8.0e-4, 1e-15);
}

TEST(Units, ParsesEachKindsUnitsAndRejectsOthersWithOneLine) {
  const auto u = parse_units("gyro=deg/h,accel=mg");
  EXPECT_NEAR(u.at(SensorKind::kGyro).per_si, 206264.80624709636, 1e-6);    // 180/pi x 3600
  EXPECT_NEAR(u.at(SensorKind::kAccel).per_si, 101.97162129779282, 1e-10);  // 1000 / 9.80665
  EXPECT_EQ(parse_units("").at(SensorKind::kGyro).name, "rad/s");
  auto message = [](const std::string& spec) {
    try {
      parse_units(spec);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("gyro=g").find("unit 'g' for gyro: expected rad/s, deg/s or deg/h"), std::string::npos);
  EXPECT_NE(message("mag=uT").find("unknown sensor kind 'mag'"), std::string::npos);
  EXPECT_NE(message("gyro").find("kind=unit pairs such as gyro=deg/s"), std::string::npos);
  EXPECT_NE(message("dge/s").find("--units 'dge/s': expected one unit (rad/s, deg/s, deg/h, m/s^2, g, mg)"),
            std::string::npos);
}

TEST(Units, OneUnitNameDeclaresItsKindAndLabelsColumnsWhoseNameTellsNone) {
  const UnitsSpec bare = parse_units_spec("deg/s");
  EXPECT_EQ(bare.declared.at(SensorKind::kGyro).name, "deg/s");
  EXPECT_EQ(unit_of_column(bare, "x1"), "deg/s");
  EXPECT_EQ(unit_of_column(bare, "gyro_x"), "deg/s");
  EXPECT_EQ(unit_of_column(bare, "accel_x"), "m/s^2");  // its kind is not declared: SI
  const UnitsSpec pairs = parse_units_spec("gyro=deg/h,accel=mg");
  EXPECT_EQ(unit_of_column(pairs, "accel_y"), "mg");
  EXPECT_EQ(unit_of_column(pairs, "x1"), "");  // no kind from the name, none given for it
  EXPECT_EQ(unit_of_column(parse_units_spec(""), "gyro_x"), "");
  EXPECT_EQ(parse_any_unit("M/S2").second.name, "m/s^2");
  EXPECT_EQ(parse_any_unit("mg").first, SensorKind::kAccel);
  EXPECT_THROW(parse_any_unit("dge/s"), InputError);
  EXPECT_THROW(parse_units_spec("deg/s,"), InputError);
  try {  // a kind given twice is refused, not settled by the last one
    parse_units_spec("gyro=deg/s,gyro=rad/s");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gyro given twice"), std::string::npos) << e.what();
  }
}

TEST(Units, TellsTheSensorKindFromTheColumnName) {
  EXPECT_EQ(sensor_kind_of_column("gyro_x"), SensorKind::kGyro);
  EXPECT_EQ(sensor_kind_of_column("w_RS_S_x"), SensorKind::kGyro);
  EXPECT_EQ(sensor_kind_of_column("accel_z"), SensorKind::kAccel);
  EXPECT_EQ(sensor_kind_of_column("alpha_y"), SensorKind::kAccel);
  EXPECT_THROW(sensor_kind_of_column("temperature"), InputError);
}

}  // namespace
}  // namespace gmwm::io
