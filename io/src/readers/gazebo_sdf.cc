// Gazebo IMU noise as a baseline model (docs/gap.md, method note 1): gz-sensors SDF <noise> blocks and
// RotorS/PX4 sitl_gazebo IMU <plugin> parameters, converted to discrete processes at the
// data's rate and in the data's units (the conversions are listed in sim_config.h).
//
// Both simulators drive their bias with a first-order Gauss-Markov process written the
// same way (gz-sensors GaussianNoiseModel::ApplyImpl, RotorS GazeboImuPlugin::addNoise):
//   b_t = phi b_{t-1} + sqrt(sigma_b^2 (T/2)(1 - exp(-2 dt / T))) z_t,  phi = exp(-dt / T),
// so sigma_b is a driving density (rad/s^2/sqrt(Hz)), not the stationary deviation; the
// stationary variance is sigma_b^2 T / 2. gmwm's AR1(phi, sigma2) takes the innovation
// variance, so the bias is AR1(phi=exp(-1/(f T)), sigma2=sigma_b^2 (T/2)(1 - exp(-2/(f T)))).
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <tinyxml2.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/sim_config.h"
#include "config_text.h"

namespace gmwm::io {
namespace {

using tinyxml2::XMLElement;

// gz-sensors treats a precision within 1e-6 of zero as no rounding at all
// (GaussianNoiseModel::Load: math::equal(precision, 0.0, 1e-6)).
constexpr double kGzPrecisionTolerance = 1e-6;

constexpr const char* kAxes[] = {"x", "y", "z"};

// The names and SI units of one sensor kind in both formats.
struct Kind {
  SensorKind kind;
  const char* sdf;     // gz-sensors element under <imu>
  const char* rotors;  // RotorS parameter prefix
  const char* si;      // unit of a value
  const char* white;   // unit of a white-noise density
  const char* drive;   // unit of a bias driving density
};
constexpr Kind kKinds[] = {
    {SensorKind::kGyro, "angular_velocity", "gyroscope", "rad/s", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)"},
    {SensorKind::kAccel, "linear_acceleration", "accelerometer", "m/s^2", "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)"}};

constexpr const char* kRotorsParameters[] = {"NoiseDensity", "RandomWalk", "BiasCorrelationTime", "TurnOnBiasSigma"};

using detail::exact;
using detail::g;
using detail::trim;

struct Figure {
  double value = 0.0;
  int line = 0;
};
using Opt = std::optional<Figure>;

bool same(const Opt& a, const Opt& b) { return a.has_value() == b.has_value() && (!a || a->value == b->value); }
double value_or_zero(const Opt& x) { return x ? x->value : 0.0; }

// One gz-sensors <noise> block.
struct NoiseBlock {
  std::string type;  // gaussian, gaussian_quantized or none
  Opt mean, stddev, bias_mean, bias_stddev, dyn_stddev, dyn_time, precision;
  std::string where;  // "angular_velocity/x/noise", for messages
  bool alike(const NoiseBlock& o) const {
    return type == o.type && same(mean, o.mean) && same(stddev, o.stddev) && same(bias_mean, o.bias_mean) &&
           same(bias_stddev, o.bias_stddev) && same(dyn_stddev, o.dyn_stddev) && same(dyn_time, o.dyn_time) &&
           same(precision, o.precision);
  }
};

// A first-order Gauss-Markov bias driven by density `drive` (data units) with time
// constant T, sampled at f: AR1 coefficient, innovation and stationary variances.
struct GaussMarkov {
  double phi, innovation, stationary;
};
GaussMarkov gauss_markov(double drive, double T, double f) {
  const double x = 1.0 / (f * T);
  const double half = drive * drive * T / 2.0;
  return {std::exp(-x), half * -std::expm1(-2.0 * x), half};
}

const XMLElement* child(const XMLElement* e, const char* name) { return e ? e->FirstChildElement(name) : nullptr; }

const XMLElement* noise_of(const XMLElement* imu, const Kind& k, int axis) {
  return child(child(child(imu, k.sdf), kAxes[axis]), "noise");
}

bool is_gz_imu(const XMLElement* e) {
  if (std::string(e->Name()) != "imu") return false;
  for (const Kind& k : kKinds)
    for (int a = 0; a < 3; ++a)
      if (noise_of(e, k, a)) return true;
  return false;
}

bool is_rotors_plugin(const XMLElement* e) {
  if (std::string(e->Name()) != "plugin") return false;
  for (const Kind& k : kKinds)
    for (const char* p : kRotorsParameters)
      if (e->FirstChildElement((std::string(k.rotors) + p).c_str())) return true;
  return false;
}

// Every IMU noise source in document order.
void collect_sources(const XMLElement* e, std::vector<const XMLElement*>& out) {
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (is_gz_imu(c) || is_rotors_plugin(c)) out.push_back(c);
    collect_sources(c, out);
  }
}

const XMLElement* enclosing_sensor(const XMLElement* e) {
  for (const tinyxml2::XMLNode* n = e->Parent(); n; n = n->Parent())
    if (const XMLElement* p = n->ToElement(); p && std::string(p->Name()) == "sensor") return p;
  return nullptr;
}

// "<sensor name="imu"> at line 12", "<plugin name="imu" filename="x.so"> at line 40".
std::string describe(const XMLElement* e) {
  const XMLElement* shown = std::string(e->Name()) == "imu" && enclosing_sensor(e) ? enclosing_sensor(e) : e;
  std::ostringstream out;  // (not string concatenation: GCC 12 warns -Wrestrict wrongly on it here)
  out << '<' << shown->Name();
  for (const char* a : {"name", "type", "filename"})
    if (const char* v = shown->Attribute(a)) out << ' ' << a << "=\"" << v << '"';
  out << "> at line " << shown->GetLineNum();
  return out.str();
}

// "XML_ERROR_MISMATCHED_ELEMENT" -> "mismatched element".
std::string error_words(const char* name) {
  std::string s = name ? name : "unknown error";
  if (s.rfind("XML_ERROR_", 0) == 0) s = s.substr(10);
  for (char& ch : s) ch = ch == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

class Reader {
 public:
  Reader(std::string path, double f, const std::map<SensorKind, Unit>& units, const std::string* text = nullptr)
      : path_(std::move(path)), f_(f), units_(units), text_(text) {}

  SimConfig read() const;

 private:
  Unit unit(SensorKind kind) const {
    const auto it = units_.find(kind);
    return it != units_.end() ? it->second : si_unit(kind);
  }
  std::string at(int line) const { return path_ + ":" + std::to_string(line) + ": "; }
  Figure number(const XMLElement* e, const std::string& where, bool signed_ok) const;
  Opt figure(const XMLElement* parent, const std::string& name, const std::string& where, bool signed_ok) const {
    const XMLElement* e = child(parent, name.c_str());
    return e ? Opt(number(e, where, signed_ok)) : std::nullopt;
  }
  NoiseBlock noise_block(const XMLElement* noise, const std::string& where) const;
  std::string convert_noise(const NoiseBlock& b, const Kind& k, const std::string& label,
                            std::vector<std::string>& lines) const;
  void gz_kind(const XMLElement* imu, const Kind& k, SimConfig& c) const;
  void rotors_kind(const XMLElement* plugin, const Kind& k, SimConfig& c) const;
  std::string gm_text(const GaussMarkov& gm, const std::string& symbol, const std::string& per, const Unit& u) const;
  void check_variance(double v, const Figure& from, const std::string& where, const std::string& unit,
                      const std::string& what) const;
  void check_time_constant(const GaussMarkov& gm, const Figure& T, const std::string& where) const;

  std::string path_;
  double f_;
  const std::map<SensorKind, Unit>& units_;
  const std::string* text_;  ///< the file's text when given, else read from path_
  /// Every figure read, in order (SimConfig::fields).
  mutable std::vector<ConfigField> fields_;
};

// The unit of a figure from its place: a gz-sensors path "angular_velocity/x/noise/NAME"
// or a RotorS parameter "gyroscopeNAME" (gz-sensors and RotorS documentation).
std::string field_unit(const std::string& where) {
  const auto ends = [&](const std::string& tail) {
    return where.size() >= tail.size() && where.compare(where.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends("update_rate")) return "Hz";
  if (ends("correlation_time") || ends("CorrelationTime")) return "s";
  for (const Kind& k : kKinds) {
    if (where.rfind(k.sdf, 0) == 0) return ends("dynamic_bias_stddev") ? k.drive : k.si;
    if (where.rfind(k.rotors, 0) == 0) return ends("NoiseDensity") ? k.white : ends("RandomWalk") ? k.drive : k.si;
  }
  return "";
}

Figure Reader::number(const XMLElement* e, const std::string& where, bool signed_ok) const {
  const char* raw = e->GetText();
  const std::string text = trim(raw ? raw : "");
  const std::string place = at(e->GetLineNum()) + where;
  if (text.empty()) throw InputError(place + ": found an empty element, expected a number");
  std::size_t used = 0;
  double v = 0.0;
  bool out_of_range = false;
  try {
    v = std::stod(text, &used);
  } catch (const std::out_of_range&) {  // beyond 1.8e308, or below 2.2e-308 (subnormal or 0)
    out_of_range = true;
  } catch (const std::exception&) {
    used = 0;
  }
  if (out_of_range)
    throw InputError(place + ": found " + text + ", beyond the range of a double (magnitudes " +
                     g(std::numeric_limits<double>::min()) + " to " + g(std::numeric_limits<double>::max()) +
                     ", or 0)");
  if (used == 0 || used != text.size() || !std::isfinite(v))
    throw InputError(place + ": found '" + text + "', expected a number");
  if (v < 0.0 && !signed_ok) throw InputError(place + ": found " + text + ", expected a non-negative noise figure");
  fields_.push_back({where, v, field_unit(where), e->GetLineNum(), text});
  return {v, e->GetLineNum()};
}

// A variance derived from a figure (in the data's unit) must be a normal positive double:
// refused otherwise with the figure's line and element, never as a model string.
void Reader::check_variance(double v, const Figure& from, const std::string& where, const std::string& unit,
                            const std::string& what) const {
  if (v > 0.0 && detail::within_double(v)) return;
  throw InputError(at(from.line) + where + ": " + g(from.value) + " " + unit + " gives " + what + " = " + g(v) +
                   " per sample, outside the range of a double (expected a figure near the sensor's)");
}

// A Gauss-Markov time constant so long that phi = exp(-1/(f T)) rounds to 1 is a random walk
// a double cannot tell from it.
void Reader::check_time_constant(const GaussMarkov& gm, const Figure& T, const std::string& where) const {
  if (gm.phi < 1.0) return;
  throw InputError(at(T.line) + where + ": " + g(T.value) + " s is beyond what a double tells from a random walk at " +
                   g(f_) + " Hz (phi = exp(-1/(f T)) rounds to 1), expected a shorter time constant");
}

NoiseBlock Reader::noise_block(const XMLElement* noise, const std::string& where) const {
  NoiseBlock b;
  b.where = where;
  const char* type = noise->Attribute("type");
  const XMLElement* type_element = child(noise, "type");  // SDF 1.4 wrote <type> as an element
  std::string t = type ? type : type_element && type_element->GetText() ? type_element->GetText() : "";
  t = trim(t);
  for (char& ch : t) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (t != "gaussian" && t != "gaussian_quantized" && t != "none")
    throw InputError(at(noise->GetLineNum()) + where + ": found " + (t.empty() ? "no type" : "type '" + t + "'") +
                     ", expected type=\"gaussian\", \"gaussian_quantized\" or \"none\"");
  b.type = t;
  auto get = [&](const char* name, bool signed_ok) { return figure(noise, name, where + "/" + name, signed_ok); };
  b.mean = get("mean", true);
  b.stddev = get("stddev", false);
  b.bias_mean = get("bias_mean", true);
  b.bias_stddev = get("bias_stddev", false);
  b.dyn_stddev = get("dynamic_bias_stddev", false);
  b.dyn_time = get("dynamic_bias_correlation_time", false);
  b.precision = get("precision", false);
  return b;
}

std::string Reader::gm_text(const GaussMarkov& gm, const std::string& symbol, const std::string& per,
                            const Unit& u) const {
  return " -> first-order Gauss-Markov: AR1 phi = exp(-1/(f T)) = " + g(gm.phi, 10) + ", innovation variance (" +
         symbol + per + ")^2 (T/2)(1 - exp(-2/(f T))) = " + g(gm.innovation) + " (" + u.name +
         ")^2 per sample, stationary variance (" + symbol + per + ")^2 T/2 = " + g(gm.stationary) + " (" + u.name +
         ")^2 (sd " + g(std::sqrt(gm.stationary)) + " " + u.name + ") at f = " + g(f_) + " Hz";
}

// One line per figure of the block; returns the model spec ("" without any term).
std::string Reader::convert_noise(const NoiseBlock& b, const Kind& k, const std::string& label,
                                  std::vector<std::string>& lines) const {
  const Unit u = unit(k.kind);
  const std::string per = u.per_si == 1.0 ? "" : " x " + g(u.per_si) + " " + u.name + " per " + k.si;
  const std::string sq = " (" + u.name + ")^2";
  const std::string L = label + " ";
  if (b.type == "none") {
    lines.push_back(L + "<noise type=\"none\">: gz-sensors adds no noise: no term");
    return {};
  }
  const double sb = value_or_zero(b.dyn_stddev), T = value_or_zero(b.dyn_time);
  if (sb > 0.0 && !(T > 0.0))
    throw InputError(at(b.dyn_stddev->line) + b.where + "/dynamic_bias_stddev = " + g(sb) +
                     " needs a positive dynamic_bias_correlation_time (the time constant T, in s, of the "
                     "Gauss-Markov bias it drives), found " +
                     (b.dyn_time ? "0" : "none") + " (gz-sensors would drop the dynamic bias silently)");
  const bool dynamic = sb > 0.0;
  const std::string transient = dynamic
                                    ? "; gz-sensors starts the dynamic bias from it, so it decays over T = " + g(T) +
                                          " s: a slow transient the stationary baseline leaves out"
                                    : "";
  if (b.mean)
    lines.push_back(b.mean->value == 0.0 ? L + "mean = 0: no offset"
                                         : L + "mean = " + g(b.mean->value) + " " + k.si +
                                               ": a constant offset, invisible to the Haar WV: no term");
  if (b.bias_mean)
    lines.push_back(b.bias_mean->value == 0.0
                        ? L + "bias_mean = 0: no turn-on bias mean"
                        : L + "bias_mean = " + g(b.bias_mean->value) + " " + k.si +
                              ": the mean of the turn-on bias (drawn once, random sign), a constant, invisible to "
                              "the Haar WV: no term" +
                              transient);
  if (b.bias_stddev)
    lines.push_back(b.bias_stddev->value == 0.0
                        ? L + "bias_stddev = 0: no turn-on bias spread"
                        : L + "bias_stddev = " + g(b.bias_stddev->value) + " " + k.si +
                              ": the spread of the turn-on bias (drawn once), a constant, invisible to the Haar "
                              "WV: no term" +
                              transient);
  double white = 0.0, rounding = 0.0;
  const double s = value_or_zero(b.stddev);
  if (b.stddev) {
    white = (s * u.per_si) * (s * u.per_si);
    if (s > 0.0) check_variance(white, *b.stddev, b.where + "/stddev", k.si, "WN sigma2");
    lines.push_back(s == 0.0 ? L + "stddev = 0: no white noise from it"
                             : L + "stddev = " + g(s) + " " + k.si + " per sample (not a density) -> WN sigma2 = (s" +
                                   per + ")^2 = " + g(white) + sq + " per sample");
  }
  if (b.precision) {
    const double p = b.precision->value;
    if (p == 0.0) {
      lines.push_back(L + "precision = 0: no rounding");
    } else if (p <= kGzPrecisionTolerance) {
      lines.push_back(L + "precision = " + g(p) + " " + k.si +
                      ": gz-sensors treats a precision within 1e-6 of zero as none: no rounding, no term");
    } else {
      rounding = (p * u.per_si) * (p * u.per_si) / 12.0;
      check_variance(rounding, *b.precision, b.where + "/precision", k.si, "a rounding variance p^2 / 12");
      std::string line = L + "precision = " + g(p) + " " + k.si + " (the output rounded to multiples of it) -> " +
                         "white noise (p" + per + ")^2 / 12 = " + g(rounding) + sq +
                         " per sample, added to the WN: valid once the noise spans a few LSBs (not QN, which "
                         "rounds an integrated output)";
      if (s < p)
        line += "; here stddev / precision = " + g(s / p, 3) +
                " < 1: the rounding is hardly noise-like and this is a rough approximation";
      lines.push_back(line);
    }
  }
  if (white > 0.0 && rounding > 0.0) {
    check_variance(white + rounding, *b.stddev, b.where + "/stddev", k.si, "WN sigma2 with the precision's rounding");
    lines.push_back(L + "white noise: WN sigma2 = " + g(white) + " + " + g(rounding) + " = " + g(white + rounding) +
                    sq + " per sample");
  }
  std::string spec;
  if (dynamic) {
    const GaussMarkov gm = gauss_markov(sb * u.per_si, T, f_);
    check_time_constant(gm, *b.dyn_time, b.where + "/dynamic_bias_correlation_time");
    check_variance(gm.innovation, *b.dyn_stddev, b.where + "/dynamic_bias_stddev", k.drive,
                   "AR1 sigma2 (with dynamic_bias_correlation_time " + g(T) + " s)");
    lines.push_back(L + "dynamic_bias_stddev = " + g(sb) + " " + k.drive +
                    " (a driving density, not the stationary deviation) with dynamic_bias_correlation_time = " + g(T) +
                    " s" + gm_text(gm, "sigma_b", per, u));
    spec = "AR1(phi=" + exact(gm.phi) + ",sigma2=" + exact(gm.innovation) + ")";
  } else if (b.dyn_stddev) {
    lines.push_back(L + "dynamic_bias_stddev = 0: no dynamic bias" +
                    (b.dyn_time ? " (dynamic_bias_correlation_time " + g(T) + " s unused)" : std::string()));
  } else if (b.dyn_time) {
    lines.push_back(L + "dynamic_bias_correlation_time = " + g(T) +
                    " s without a dynamic_bias_stddev: no dynamic bias");
  }
  if (white + rounding > 0.0)
    spec += (spec.empty() ? "" : "+") + std::string("WN(sigma2=") + exact(white + rounding) + ")";
  if (spec.empty()) lines.push_back(L + "has no nonzero stddev, precision or dynamic bias: no term");
  return spec;
}

void Reader::gz_kind(const XMLElement* imu, const Kind& k, SimConfig& c) const {
  const std::string kind = to_string(k.kind);
  std::array<std::optional<NoiseBlock>, 3> blocks;
  for (int a = 0; a < 3; ++a)
    if (const XMLElement* n = noise_of(imu, k, a))
      blocks[static_cast<std::size_t>(a)] = noise_block(n, std::string(k.sdf) + "/" + kAxes[a] + "/noise");
  if (!blocks[0] && !blocks[1] && !blocks[2]) {
    c.conversions[k.kind] = {std::string(k.sdf) + ": no <noise> block: no " + kind + " term"};
    return;
  }
  const bool alike =
      blocks[0] && blocks[1] && blocks[2] && blocks[0]->alike(*blocks[1]) && blocks[0]->alike(*blocks[2]);
  if (alike) {
    std::vector<std::string> lines{std::string(k.sdf) + ": the <x>, <y> and <z> noise blocks are alike: one " + kind +
                                   " model for every axis"};
    const std::string spec = convert_noise(*blocks[0], k, k.sdf, lines);
    c.conversions[k.kind] = lines;
    if (!spec.empty()) c.models.emplace(k.kind, parse_model(spec));
    return;
  }
  c.conversions[k.kind] = {std::string(k.sdf) + ": the <x>, <y> and <z> noise blocks differ: one " + kind +
                           " model per axis (for the columns whose names end in x, y or z)"};
  for (int a = 0; a < 3; ++a) {
    const std::string key = kind + "_" + kAxes[a];
    const std::string label = std::string(k.sdf) + " <" + kAxes[a] + ">";
    std::vector<std::string> lines;
    std::string spec;
    if (const auto& b = blocks[static_cast<std::size_t>(a)])
      spec = convert_noise(*b, k, label, lines);
    else
      lines.push_back(label + ": no <noise> block: no term");
    c.axis_conversions[key] = lines;
    if (!spec.empty()) c.axis_models.emplace(key, parse_model(spec));
  }
}

void Reader::rotors_kind(const XMLElement* plugin, const Kind& k, SimConfig& c) const {
  const Unit u = unit(k.kind);
  const std::string per = u.per_si == 1.0 ? "" : " x " + g(u.per_si) + " " + u.name + " per " + k.si;
  const std::string p = k.rotors;
  const std::string n_name = p + "NoiseDensity", k_name = p + "RandomWalk", t_name = p + "BiasCorrelationTime",
                    b_name = p + "TurnOnBiasSigma";
  const Opt N = figure(plugin, n_name, n_name, false), K = figure(plugin, k_name, k_name, false),
            T = figure(plugin, t_name, t_name, false), B = figure(plugin, b_name, b_name, false);
  auto& lines = c.conversions[k.kind];
  auto missing = [&](const std::string& name) {
    lines.push_back(name + " not given (the plugin then uses its built-in default): no term here");
  };
  const double k_value = value_or_zero(K), t_value = value_or_zero(T);
  if (k_value > 0.0 && !(t_value > 0.0))
    throw InputError(at(K->line) + k_name + " = " + g(k_value) + " needs a positive " + t_name +
                     " (the time constant T, in s, of the Gauss-Markov bias it drives), found " + (T ? "0" : "none"));
  std::string ar1, wn;
  if (!N) {
    missing(n_name);
  } else if (N->value == 0.0) {
    lines.push_back(n_name + " = 0: no white noise term");
  } else {
    const double sigma2 = (N->value * u.per_si) * (N->value * u.per_si) * f_;
    check_variance(sigma2, *N, n_name, k.white, "WN sigma2");
    lines.push_back(n_name + " = " + g(N->value) + " " + k.white + " -> WN sigma2 = (N" + per +
                    ")^2 x f = " + g(sigma2) + " (" + u.name + ")^2 per sample at f = " + g(f_) + " Hz");
    wn = "WN(sigma2=" + exact(sigma2) + ")";
  }
  if (!K) {
    missing(k_name);
  } else if (k_value == 0.0) {
    lines.push_back(k_name + " = 0: no bias process" + (T ? " (" + t_name + " " + g(t_value) + " s unused)" : ""));
  } else {
    const GaussMarkov gm = gauss_markov(k_value * u.per_si, t_value, f_);
    check_time_constant(gm, *T, t_name);
    check_variance(gm.innovation, *K, k_name, k.drive, "AR1 sigma2 (with " + t_name + " " + g(t_value) + " s)");
    lines.push_back(k_name + " = " + g(k_value) + " " + k.drive + " with " + t_name + " = " + g(t_value) +
                    " s (the driving density of a Gauss-Markov bias, not a random walk)" + gm_text(gm, "K", per, u));
    ar1 = "AR1(phi=" + exact(gm.phi) + ",sigma2=" + exact(gm.innovation) + ")";
  }
  if (!T && !(K && k_value == 0.0)) missing(t_name);
  if (!B)
    missing(b_name);
  else
    lines.push_back(B->value == 0.0 ? b_name + " = 0: no turn-on bias"
                                    : b_name + " = " + g(B->value) + " " + k.si +
                                          ": a constant turn-on bias (drawn once), invisible to the Haar WV: no term");
  const std::string spec = ar1 + (!ar1.empty() && !wn.empty() ? "+" : "") + wn;
  if (!spec.empty()) c.models.emplace(k.kind, parse_model(spec));
}

SimConfig Reader::read() const {
  if (!(f_ > 0.0) || !std::isfinite(f_))
    throw InputError(path_ + ": the data's sampling rate is needed to convert the noise figures (give --freq)");
  const std::string xml = text_ ? *text_ : read_side_file(path_, "a Gazebo SDF file");
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    const int line = doc.ErrorLineNum();
    throw InputError((line > 0 ? at(line) : path_ + ": ") + "XML parse error (" + error_words(doc.ErrorName()) +
                     "): expected a well-formed SDF/XML file");
  }
  std::vector<const XMLElement*> sources;
  if (doc.RootElement()) {
    if (is_gz_imu(doc.RootElement()) || is_rotors_plugin(doc.RootElement())) sources.push_back(doc.RootElement());
    collect_sources(doc.RootElement(), sources);
  }
  if (sources.empty()) throw InputError(path_ + ": no IMU <noise> block or RotorS/PX4 IMU plugin parameters found");
  const XMLElement* used = sources.front();
  const bool plugin = std::string(used->Name()) == "plugin";
  SimConfig c;
  c.source = (plugin ? "RotorS/PX4 IMU plugin parameters (" : "gz-sensors SDF <noise> blocks (") + path_ + ")";
  c.format = plugin ? SimFormat::kRotors : SimFormat::kGzSensors;
  for (const Kind& k : kKinds) plugin ? rotors_kind(used, k, c) : gz_kind(used, k, c);
  if (!plugin) {
    if (const XMLElement* sensor = enclosing_sensor(used)) {
      if (const XMLElement* rate = child(sensor, "update_rate")) {
        const double r = number(rate, "sensor/update_rate", false).value;
        if (r > 0.0 && std::abs(r - f_) > 1e-9 * f_)
          c.notes.push_back("the sensor's update_rate " + g(r) + " Hz differs from the data's " + g(f_) +
                            " Hz: stddev is taken as per sample of the data (true when the data are the "
                            "simulator's samples, not averages of them); the bias is discretised at the data's rate");
      }
    }
  }
  if (sources.size() > 1) {
    std::string others;
    for (std::size_t i = 1; i < sources.size(); ++i) others += (i > 1 ? ", " : "") + describe(sources[i]);
    c.notes.push_back("the file has " + std::to_string(sources.size()) +
                      " IMU noise sources: the baseline is the first, " + describe(used) + "; not used: " + others);
  }
  c.fields = fields_;
  c.text = xml;
  return c;
}

}  // namespace

SimConfig read_gazebo_sdf(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units) {
  return Reader(path, data_freq, units).read();
}

SimConfig parse_gazebo_sdf(const std::string& text, const std::string& name, double data_freq,
                           const std::map<SensorKind, Unit>& units) {
  return Reader(name, data_freq, units, &text).read();
}

const char* to_string(SimFormat f) {
  switch (f) {
    case SimFormat::kKalibr:
      return "kalibr";
    case SimFormat::kGzSensors:
      return "gz-sdf";
    case SimFormat::kRotors:
      return "rotors";
    case SimFormat::kDatasheet:
      return "datasheet";
  }
  return "kalibr";
}

std::optional<SimFormat> parse_sim_format(const std::string& name) {
  for (SimFormat f : {SimFormat::kKalibr, SimFormat::kGzSensors, SimFormat::kRotors, SimFormat::kDatasheet})
    if (name == to_string(f)) return f;
  return std::nullopt;
}

}  // namespace gmwm::io
