// The simulator exports: a gz-sensors SDF <sensor type="imu"> with its <noise> blocks, and
// RotorS/PX4 IMU <plugin> parameters. Both read back with io::read_gazebo_sdf (sim_config.h).
//
// gz-sensors (GaussianNoiseModel::ApplyImpl, src/Noise... of gazebosim/gz-sensors; SDF
// <noise> of sdformat's noise.sdf): each output gets white noise drawn with standard
// deviation <stddev> per sample (NOT a density: for a density N at the sensor's rate R,
// stddev = N sqrt(R)), plus a bias b updated every sample dt as
//   b = exp(-dt/T) b + sqrt(-sigma_b^2 T/2 expm1(-2 dt/T)) w,  sigma_b = <dynamic_bias_stddev>,
//   T = <dynamic_bias_correlation_time>,
// a first-order Gauss-Markov process driven by the DENSITY sigma_b (stationary variance
// sigma_b^2 T / 2), written after RotorS. <bias_mean>/<bias_stddev> draw one constant
// turn-on bias, which a wavelet variance cannot see: written as 0.
//
// RotorS (ethz-asl/rotors_simulator, gazebo_imu_plugin.h/.cpp; PX4 sitl_gazebo's
// gazebo_imu_plugin has the same parameters): gyroscopeNoiseDensity [rad/s/sqrt(Hz)]
// ("two-sided spectrum"; discretised as noise_density / sqrt(dt), Kalibr's convention),
// gyroscopeRandomWalk [rad/s^2/sqrt(Hz)] with gyroscopeBiasCorrelationTime [s]: the same
// Gauss-Markov bias as above, driven by the "random walk" density; gyroscopeTurnOnBiasSigma
// [rad/s]: a constant; accelerometer* likewise in m/s^2/sqrt(Hz), m/s^3/sqrt(Hz), s, m/s^2.
//
// Neither has a random walk: a fitted RW of density K is written as a bias driven by K with
// a correlation time far beyond the record (export_internal.h, kRandomWalkTimeRecords).
#include <cmath>

#include "export_internal.h"

namespace gmwm::io::export_detail {
namespace {

// RotorS' defaults for the ADIS16448 (gazebo_imu_plugin.h), written when there is no bias
// term (the correlation time is then unused).
constexpr double kRotorsGyroCorrelationTime = 1.0e3;
constexpr double kRotorsAccelCorrelationTime = 300.0;

std::string element(const std::string& indent, const std::string& name, const std::string& value,
                    const std::string& comment = "") {
  return indent + "<" + name + ">" + value + "</" + name + ">" +
         (comment.empty() ? "" : "  <!-- " + xml_comment_text(comment) + " -->") + "\n";
}

std::string bias_comment(const WrittenNoise& w, const SiNames& si) {
  return w.bias_from_random_walk
             ? std::string("[") + si.walk + "] driving density: the random walk K (approximated, see the header)"
             : std::string("[") + si.walk + "] driving density sigma_b = sigma sqrt(2/T) of the Gauss-Markov bias";
}

// One gz-sensors <noise> block.
std::string noise_block(const std::string& in, const WrittenNoise& w, SensorKind kind, double rate) {
  const SiNames si = si_names(kind);
  std::string out = in + "<noise type=\"gaussian\">\n";
  const std::string i2 = in + "  ";
  out += element(i2, "mean", "0.0", "constant offset: none");
  out += element(i2, "stddev", real(w.noise_density * std::sqrt(rate)),
                 std::string("[") + si.value + "] per sample at " + num(rate) +
                     " Hz: N sqrt(rate), N = " + num(w.noise_density) + " " + si.density);
  out += element(i2, "bias_mean", "0.0", "turn-on bias: a constant, not seen by a wavelet variance");
  out += element(i2, "bias_stddev", "0.0");
  if (w.bias_drive > 0.0) {
    out += element(i2, "dynamic_bias_stddev", real(w.bias_drive), bias_comment(w, si));
    out += element(i2, "dynamic_bias_correlation_time", real(w.bias_correlation_time),
                   w.bias_from_random_walk ? "[s] far beyond the record: the bias drifts like the random walk"
                                           : "[s] the Gauss-Markov correlation time T");
  }
  return out + in + "</noise>\n";
}

}  // namespace

std::string render_gz_sdf(const ExportOptions& o, const ExportResult& r) {
  (void)o;
  std::vector<std::string> lines = r.header;
  lines.push_back("");
  for (const char* l :
       {"gz-sensors IMU noise (GaussianNoiseModel::ApplyImpl of gz-sensors; sdformat noise.sdf): <stddev> is the white",
        "noise's standard deviation PER SAMPLE at the sensor's update_rate (N sqrt(rate) for a density N);",
        "<dynamic_bias_stddev> is the DRIVING density sigma_b of a first-order Gauss-Markov bias with time",
        "constant <dynamic_bias_correlation_time> T (stationary deviation sigma_b sqrt(T/2)). Place the <sensor>",
        "in your model's <link>; read back by the gmwm gap command (Gazebo baseline)."})
    lines.push_back(l);
  std::string out = "<?xml version=\"1.0\"?>\n" + xml_comment(lines);
  out += "<sensor name=\"imu\" type=\"imu\">\n";
  out += element("  ", "always_on", "1");
  out += element("  ", "update_rate", real(r.rate), "[Hz] the rate stddev is per sample of");
  out += "  <imu>\n";
  struct Block {
    SensorKind kind;
    const char* element;
  };
  for (const Block b :
       {Block{SensorKind::kGyro, "angular_velocity"}, Block{SensorKind::kAccel, "linear_acceleration"}}) {
    const KindExport* k = find_kind(r, b.kind);
    if (!k) continue;
    out += std::string("    <") + b.element + ">\n";
    for (std::size_t s = 0; s < 3; ++s) {
      const char axis = static_cast<char>('x' + s);
      out += std::string("      <") + axis + ">";
      if (k->per_axis) {
        std::string column;
        for (const auto& a : r.columns)
          if (a.kind == b.kind && a.axis == axis) column = a.column;
        out += "  <!-- column " + xml_comment_text(column) + " -->";
      }
      out += '\n';
      out += noise_block("        ", k->per_axis ? k->axes[s] : k->combined, b.kind, r.rate);
      out += std::string("      </") + axis + ">\n";
    }
    out += std::string("    </") + b.element + ">\n";
  }
  out += "  </imu>\n</sensor>\n";
  return out;
}

std::string render_rotors(const ExportOptions& o, const ExportResult& r) {
  std::vector<std::string> lines = r.header;
  lines.push_back("");
  for (const char* l :
       {"RotorS/PX4 IMU plugin parameters (rotors_simulator gazebo_imu_plugin.h; PX4 sitl_gazebo gazebo_imu_plugin):",
        "*NoiseDensity is a continuous white noise density (discretised as density / sqrt(dt), as Kalibr);",
        "*RandomWalk is the DRIVING density of a first-order Gauss-Markov bias with time constant",
        "*BiasCorrelationTime (not a pure random walk); *TurnOnBiasSigma draws one constant bias, which a",
        "wavelet variance cannot see: written as 0. Add robotNamespace, linkName and imuTopic as your model needs;",
        "as xacro, paste the elements into your <plugin>. Read back by the gmwm gap command (Gazebo baseline)."})
    lines.push_back(l);
  std::string out = "<?xml version=\"1.0\"?>\n" + xml_comment(lines);
  out += "<plugin name=\"rotors_gazebo_imu_plugin\" filename=\"librotors_gazebo_imu_plugin.so\">\n";
  struct Kind {
    SensorKind kind;
    const char* prefix;
    double default_time;
  };
  for (const Kind k : {Kind{SensorKind::kGyro, "gyroscope", kRotorsGyroCorrelationTime},
                       Kind{SensorKind::kAccel, "accelerometer", kRotorsAccelCorrelationTime}}) {
    if (!writes_kind(o, r, k.kind)) continue;  // --partial: this sensor's elements left out
    const SiNames si = si_names(k.kind);
    const WrittenNoise w = combined_or_zero(r, k.kind);
    const std::string p = k.prefix;
    out += element("  ", p + "NoiseDensity", real(w.noise_density),
                   std::string("[") + si.density + "] white noise density N");
    const bool bias = w.bias_drive > 0.0;
    out += element("  ", p + "RandomWalk", real(w.bias_drive),
                   bias ? bias_comment(w, si) : std::string("[") + si.walk + "] no bias term");
    out += element("  ", p + "BiasCorrelationTime", real(bias ? w.bias_correlation_time : k.default_time),
                   !bias                     ? "[s] RotorS' default, unused without a bias"
                   : w.bias_from_random_walk ? "[s] far beyond the record: the bias drifts like the random walk"
                                             : "[s] the Gauss-Markov correlation time T");
    out += element("  ", p + "TurnOnBiasSigma", "0.0",
                   std::string("[") + si.value + "] constant turn-on bias, not seen by a wavelet variance");
  }
  out += "</plugin>\n";
  return out;
}

}  // namespace gmwm::io::export_detail
