// The export entry point (render_export), the format and aggregation names, the options'
// validation and the text helpers the renderers share (export_internal.h).
#include <cctype>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

#include "export_internal.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::io {
namespace {

struct FormatName {
  ExportFormat format;
  const char* name;
  const char* filename;  ///< the file name each consumer's documentation uses
};
// File names: Kalibr's imu.yaml, OpenVINS's kalibr_imu_chain.yaml, VINS-Fusion's and
// ORB-SLAM3's settings YAML, Basalt's calib.json, a gz-sensors SDF fragment and the RotorS
// IMU plugin's parameters (as their READMEs and examples name them).
constexpr FormatName kFormats[] = {
    {ExportFormat::kKalibr, "kalibr", "imu.yaml"},      {ExportFormat::kOpenVins, "openvins", "kalibr_imu_chain.yaml"},
    {ExportFormat::kVins, "vins", "vins_imu.yaml"},     {ExportFormat::kOrbSlam3, "orbslam3", "orbslam3_imu.yaml"},
    {ExportFormat::kBasalt, "basalt", "calib.json"},    {ExportFormat::kGzSdf, "gz-sdf", "imu_noise.sdf"},
    {ExportFormat::kRotors, "rotors", "rotors_imu.xml"}};

}  // namespace

const char* to_string(ExportFormat f) {
  for (const auto& n : kFormats)
    if (n.format == f) return n.name;
  return "?";
}

const char* default_export_filename(ExportFormat f) {
  for (const auto& n : kFormats)
    if (n.format == f) return n.filename;
  return "imu_noise.txt";
}

std::optional<ExportFormat> parse_export_format(const std::string& name) {
  for (const auto& n : kFormats)
    if (name == n.name) return n.format;
  return std::nullopt;
}

std::string export_format_names() {
  std::string out;
  for (const auto& n : kFormats) out += (out.empty() ? "" : ", ") + std::string(n.name);
  return out;
}

bool has_per_axis_fields(ExportFormat f) { return f == ExportFormat::kBasalt || f == ExportFormat::kGzSdf; }

bool allows_comments(ExportFormat f) { return f != ExportFormat::kBasalt; }

const char* to_string(Aggregation a) {
  switch (a) {
    case Aggregation::kPerAxis:
      return "per-axis";
    case Aggregation::kMean:
      return "mean";
    case Aggregation::kWorst:
      return "worst";
  }
  return "?";
}

std::optional<Aggregation> parse_aggregation(const std::string& name) {
  for (Aggregation a : {Aggregation::kPerAxis, Aggregation::kMean, Aggregation::kWorst})
    if (name == to_string(a)) return a;
  return std::nullopt;
}

std::string ExportOptions::Validate() const {
  if (!(inflate > 0.0) || !std::isfinite(inflate))
    return "--inflate " + export_detail::num(inflate) +
           ": expected a positive factor (it multiplies the noise densities and standard deviations; 1 = as fitted)";
  if (inflate_walk && (!(*inflate_walk > 0.0) || !std::isfinite(*inflate_walk)))
    return "the random walks' inflation " + export_detail::num(*inflate_walk) + ": expected a positive factor";
  if (rate)
    if (std::string why = sampling_rate_problem(*rate, "--rate"); !why.empty()) return why;
  if (aggregation == Aggregation::kPerAxis && !has_per_axis_fields(format))
    return std::string("--aggregate per-axis: the ") + to_string(format) +
           " format has one value per sensor, not per axis; expected --aggregate mean or worst (per-axis fields: "
           "basalt, gz-sdf)";
  if (rostopic.empty()) return "--rostopic: expected a topic name such as /imu0";
  // A ROS graph resource name (wiki.ros.org/Names): a letter, '/' or '~' first, then
  // letters, digits, '_' and '/'. Anything else could break out of the YAML value.
  const auto ros_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/'; };
  const bool valid =
      (std::isalpha(static_cast<unsigned char>(rostopic[0])) || rostopic[0] == '/' || rostopic[0] == '~') &&
      std::all_of(rostopic.begin() + 1, rostopic.end(), ros_char);
  if (!valid)
    return "--rostopic '" + rostopic +
           "': expected a ROS topic name (a letter, '/' or '~' first, then letters, digits, '_' and '/')";
  return "";
}

namespace export_text {

std::string real(double x) {
  if (!std::isfinite(x)) return x != x ? ".nan" : x > 0 ? ".inf" : "-.inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  std::string s(buf, res.ptr);
  const auto e = s.find_first_of("eE");
  const std::string mantissa = s.substr(0, e);
  std::string exponent = e == std::string::npos ? "" : s.substr(e + 1);
  std::string out = mantissa.find('.') == std::string::npos ? mantissa + ".0" : mantissa;
  if (!exponent.empty()) {
    if (exponent[0] != '-' && exponent[0] != '+') exponent = "+" + exponent;
    out += "e" + exponent;
  }
  return out;
}

std::string num(double x, int digits) { return significant(x, digits); }

// Comment lines carry names from files (columns, sources): as one printable line each
// (printable_line), so that a newline in a name cannot start a key of its own.
std::string yaml_comments(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& line : lines) {
    const std::string l = printable_line(line);
    out += l.empty() ? "#\n" : "# " + l + "\n";
  }
  return out;
}

std::string xml_comment_text(std::string_view text) {
  std::string l = printable_line(text);
  // XML 1.0 (2.5): a comment holds no "--" and does not end with '-' ("--->").
  for (std::size_t p; (p = l.find("--")) != std::string::npos;) l.replace(p, 2, "- -");
  if (!l.empty() && l.back() == '-') l += ' ';
  return l;
}

std::string xml_comment(const std::vector<std::string>& lines, const std::string& indent) {
  std::string out = indent + "<!--\n";
  for (const std::string& line : lines) out += indent + "  " + xml_comment_text(line) + "\n";
  return out + indent + "-->\n";
}

const KindExport* find_kind(const ExportResult& r, SensorKind kind) {
  for (const auto& k : r.kinds)
    if (k.kind == kind && !k.columns.empty()) return &k;
  return nullptr;
}

}  // namespace export_text

namespace export_detail {

SiNames si_names(SensorKind kind) {
  return kind == SensorKind::kGyro ? SiNames{"rad/s", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)"}
                                   : SiNames{"m/s^2", "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)"};
}

WrittenNoise combined_or_zero(const ExportResult& r, SensorKind kind) {
  const KindExport* k = find_kind(r, kind);
  return k ? k->combined : WrittenNoise{};
}

bool writes_kind(const ExportOptions& o, const ExportResult& r, SensorKind kind) {
  return export_text::find_kind(r, kind) != nullptr || o.missing == MissingSensor::kZero;
}

bool simulates_bias(ExportFormat f) { return f == ExportFormat::kGzSdf || f == ExportFormat::kRotors; }

}  // namespace export_detail

ExportResult render_export(const std::vector<ExportColumn>& columns, const ExportOptions& options,
                           const std::string& source) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  if (columns.empty()) throw InputError("export: no column to export");
  std::set<std::string> names;
  for (const auto& c : columns) {
    if (!names.insert(c.name).second) throw InputError("export: column '" + c.name + "' appears twice");
    // A rate outside what a sampling rate can be (a subnormal "freq" in a hand-edited
    // result) would make every per-second figure infinite.
    if (std::string why = sampling_rate_problem(c.freq, "\"freq\""); !why.empty())
      throw InputError(source + ": column '" + c.name + "': " + why);
  }
  ExportResult r;
  export_detail::plan_export(columns, options, source, r);
  switch (options.format) {
    case ExportFormat::kKalibr:
      r.content = export_detail::render_kalibr(options, r);
      break;
    case ExportFormat::kOpenVins:
      r.content = export_detail::render_openvins(options, r);
      break;
    case ExportFormat::kVins:
      r.content = export_detail::render_vins(options, r);
      break;
    case ExportFormat::kOrbSlam3:
      r.content = export_detail::render_orbslam3(options, r);
      break;
    case ExportFormat::kBasalt: {
      std::string sidecar;
      r.content = export_detail::render_basalt(options, r, sidecar);
      r.sidecar = std::move(sidecar);
      break;
    }
    case ExportFormat::kGzSdf:
      r.content = export_detail::render_gz_sdf(options, r);
      break;
    case ExportFormat::kRotors:
      r.content = export_detail::render_rotors(options, r);
      break;
  }
  return r;
}

}  // namespace gmwm::io
