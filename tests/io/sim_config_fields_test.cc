// The figures a simulator's configuration gives, as the file gives them (SimConfig::fields):
// what `gap --corrected` compares its corrected file with, field by field.
#include <gtest/gtest.h>

#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/sim_config.h"

namespace {

using gmwm::io::ConfigField;
using gmwm::io::SimConfig;

const ConfigField* field(const SimConfig& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name) return &f;
  return nullptr;
}

TEST(SimConfigFields, AKalibrYamlGivesItsFiveFiguresInTheirOwnUnits) {
  const SimConfig c = gmwm::io::parse_kalibr_imu_yaml(
      "accelerometer_noise_density: 4.9e-03\naccelerometer_random_walk: 3.0e-04\ngyroscope_noise_density: 8.73e-04\n"
      "gyroscope_random_walk: 2.0e-05\nupdate_rate: 200.0\nrostopic: /imu0\n",
      "text.yaml", 100.0, {});
  EXPECT_EQ(c.format, gmwm::io::SimFormat::kKalibr);
  ASSERT_EQ(c.fields.size(), 5u);
  ASSERT_NE(field(c, "gyroscope_noise_density"), nullptr);
  EXPECT_DOUBLE_EQ(field(c, "gyroscope_noise_density")->value, 8.73e-4);
  EXPECT_EQ(field(c, "gyroscope_noise_density")->unit, "rad/s/sqrt(Hz)");
  EXPECT_EQ(field(c, "accelerometer_random_walk")->unit, "m/s^3/sqrt(Hz)");
  EXPECT_EQ(field(c, "update_rate")->unit, "Hz");
  EXPECT_DOUBLE_EQ(field(c, "update_rate")->value, 200.0);
}

TEST(SimConfigFields, AKalibrTextIsNamedInItsErrors) {
  try {
    gmwm::io::parse_kalibr_imu_yaml("gyroscope_noise_density: [1]\n", "the corrected configuration", 100.0, {});
    FAIL() << "no error";
  } catch (const gmwm::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("the corrected configuration:1", 0), 0u) << e.what();
  }
}

TEST(SimConfigFields, AGzSensorsBlockGivesEveryFigureByItsPathAndUnit) {
  std::string xml = "<sensor type=\"imu\"><update_rate>100</update_rate><imu>";
  for (const char* kind : {"angular_velocity", "linear_acceleration"}) {
    xml += std::string("<") + kind + ">";
    for (const char* axis : {"x", "y", "z"})
      xml += std::string("<") + axis +
             "><noise type=\"gaussian\"><stddev>0.01</stddev><dynamic_bias_stddev>2e-5</dynamic_bias_stddev>"
             "<dynamic_bias_correlation_time>300</dynamic_bias_correlation_time></noise></" +
             axis + ">";
    xml += std::string("</") + kind + ">";
  }
  xml += "</imu></sensor>";
  const SimConfig c = gmwm::io::parse_gazebo_sdf(xml, "text.sdf", 100.0, {});
  EXPECT_EQ(c.format, gmwm::io::SimFormat::kGzSensors);
  const ConfigField* s = field(c, "angular_velocity/y/noise/stddev");
  ASSERT_NE(s, nullptr);
  EXPECT_DOUBLE_EQ(s->value, 0.01);
  EXPECT_EQ(s->unit, "rad/s");
  EXPECT_EQ(field(c, "linear_acceleration/z/noise/dynamic_bias_stddev")->unit, "m/s^3/sqrt(Hz)");
  EXPECT_EQ(field(c, "angular_velocity/x/noise/dynamic_bias_correlation_time")->unit, "s");
  EXPECT_EQ(field(c, "sensor/update_rate")->unit, "Hz");
}

TEST(SimConfigFields, ARotorsPluginGivesItsParametersInTheirUnits) {
  const SimConfig c = gmwm::io::parse_gazebo_sdf(
      "<plugin name=\"imu\" filename=\"libgazebo_imu_plugin.so\"><gyroscopeNoiseDensity>0.0003</gyroscopeNoiseDensity>"
      "<gyroscopeRandomWalk>3.8e-05</gyroscopeRandomWalk><gyroscopeBiasCorrelationTime>1000</"
      "gyroscopeBiasCorrelationTime>"
      "<gyroscopeTurnOnBiasSigma>0.0087</gyroscopeTurnOnBiasSigma>"
      "<accelerometerNoiseDensity>0.004</accelerometerNoiseDensity></plugin>",
      "text.sdf", 100.0, {});
  EXPECT_EQ(c.format, gmwm::io::SimFormat::kRotors);
  EXPECT_EQ(field(c, "gyroscopeNoiseDensity")->unit, "rad/s/sqrt(Hz)");
  EXPECT_EQ(field(c, "gyroscopeRandomWalk")->unit, "rad/s^2/sqrt(Hz)");
  EXPECT_EQ(field(c, "gyroscopeBiasCorrelationTime")->unit, "s");
  EXPECT_EQ(field(c, "gyroscopeTurnOnBiasSigma")->unit, "rad/s");
  EXPECT_EQ(field(c, "accelerometerNoiseDensity")->unit, "m/s^2/sqrt(Hz)");
}

}  // namespace
