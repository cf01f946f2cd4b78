// A datasheet's noise figures as a gap baseline (docs/gap.md, "A datasheet as the baseline"):
// the figures in the units the datasheet prints them in, converted to discrete processes at
// the data's rate and in the data's units, every conversion written out (sim_config.h).
//
// Pipeline: load (YAML) -> figures (each "<number> <unit>", the unit's dimension checked
// against the figure's) -> per sensor: white noise, bias, random walk in SI -> terms at the
// data's rate and unit -> the bias term sized against the whole curve where the figure is
// the Allan deviation's minimum.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/sim_config.h"
#include "config_text.h"
#include "datasheet_limits.h"
#include "yaml_figures.h"

namespace gmwm::io {
namespace {

using detail::exact;
using detail::g;
using detail::trim;

// IEEE Std 952-1997, Annex C: the Allan deviation floor of flicker (bias-instability) noise
// of coefficient B is B sqrt(2 ln 2 / pi) = 0.664 B.
const double kFlickerFloorPerB = std::sqrt(2.0 * std::numbers::ln2 / std::numbers::pi);

// The averaging times searched for a Gauss-Markov bias's peak: one sample to 2^40 samples,
// at 32 points an octave (the curve near its extremum is flat: a step of 2^(1/32) moves
// the extremum's value by well under 0.1%).
constexpr int kSearchOctaves = 40;
constexpr int kSearchPointsPerOctave = 32;
// The Allan deviation's minimum is searched up to 1e5 s (past the end of every datasheet's
// Allan plot, a day and more) and at most 2^30 samples: FLICKER's octaves end at 2^40
// samples, and its curve falls off by ~tau / 2^40 beyond that (0.1% at 2^30), which a
// search further out would take for a minimum.
constexpr double kMinimumSearchSeconds = 1e5;
constexpr double kMinimumSearchSamples = 1073741824.0;  // 2^30

// ---------------------------------------------------------------------------------------
// Units as a dimension: the base quantity (an angle for a gyroscope, a length for an
// accelerometer) and the power of time in halves, with the factor to SI (rad, m, s).

enum class Base { kNone, kAngle, kLength };

struct Dimension {
  Base base = Base::kNone;
  int half_time = 0;  // the power of seconds, times two (sqrt(Hz) in a denominator: +1)
  double si = 1.0;    // SI value of one unit
};

struct Atom {
  const char* name;
  Dimension dim;
};

const double kDeg = std::numbers::pi / 180.0;
const double kStandardGravity = 9.80665;  // m/s^2 (CGPM 1901; the g of "mg", "ug")

// The unit atoms a datasheet writes (lower case; "u" also for the micro sign).
const Atom kAtoms[] = {
    {"rad", {Base::kAngle, 0, 1.0}},
    {"mrad", {Base::kAngle, 0, 1e-3}},
    {"urad", {Base::kAngle, 0, 1e-6}},
    {"deg", {Base::kAngle, 0, kDeg}},
    {"degree", {Base::kAngle, 0, kDeg}},
    {"degrees", {Base::kAngle, 0, kDeg}},
    {"mdeg", {Base::kAngle, 0, 1e-3 * kDeg}},
    {"dps", {Base::kAngle, -2, kDeg}},
    {"mdps", {Base::kAngle, -2, 1e-3 * kDeg}},
    {"m", {Base::kLength, 0, 1.0}},
    {"mm", {Base::kLength, 0, 1e-3}},
    {"ft", {Base::kLength, 0, 0.3048}},
    {"g", {Base::kLength, -4, kStandardGravity}},
    {"mg", {Base::kLength, -4, 1e-3 * kStandardGravity}},
    {"ug", {Base::kLength, -4, 1e-6 * kStandardGravity}},
    {"s", {Base::kNone, 2, 1.0}},
    {"sec", {Base::kNone, 2, 1.0}},
    {"ms", {Base::kNone, 2, 1e-3}},
    {"min", {Base::kNone, 2, 60.0}},
    {"h", {Base::kNone, 2, 3600.0}},
    {"hr", {Base::kNone, 2, 3600.0}},
    {"hz", {Base::kNone, -2, 1.0}},
};

// The unit text in a canonical spelling: no blanks, lower case, the degree, micro,
// square-root and superscript signs spelled out.
std::string canonical(const std::string& unit) {
  std::string s;
  for (std::size_t i = 0; i < unit.size();) {
    auto starts = [&](const char* u) { return unit.compare(i, std::char_traits<char>::length(u), u) == 0; };
    if (starts("\xC2\xB0")) {
      s += "deg";
      i += 2;
    }  // degree sign
    else if (starts("\xC2\xB5") || starts("\xCE\xBC")) {
      s += "u";
      i += 2;
    }  // micro sign, mu
    else if (starts("\xE2\x88\x9A")) {
      s += "sqrt";
      i += 3;
    }  // square root sign
    else if (starts("\xC2\xB2")) {
      s += "^2";
      i += 2;
    } else if (starts("\xC2\xB3")) {
      s += "^3";
      i += 2;
    } else if (std::isspace(static_cast<unsigned char>(unit[i])))
      ++i;
    else {
      s += static_cast<char>(std::tolower(static_cast<unsigned char>(unit[i])));
      ++i;
    }
  }
  return s;
}

// One factor of a unit: "deg", "s^2", "s2", "sqrt(hz)", "sqrthz", "rthz", "rt(h)", "h^0.5".
std::optional<Dimension> factor(std::string t) {
  bool root = false;
  for (const char* r : {"sqrt", "rt"})
    if (t.rfind(r, 0) == 0) {
      root = true;
      t.erase(0, std::char_traits<char>::length(r));
      break;
    }
  if (root && t.size() >= 2 && t.front() == '(' && t.back() == ')') t = t.substr(1, t.size() - 2);
  int power = 1;
  if (const auto caret = t.find('^'); caret != std::string::npos) {
    const std::string p = t.substr(caret + 1);
    if (p == "0.5" || p == ".5") {
      if (root) return std::nullopt;  // sqrt(h^0.5)
      root = true;
    } else if (p == "2" || p == "3") {
      power = p[0] - '0';
    } else {
      return std::nullopt;
    }
    t.erase(caret);
  } else if (t.size() >= 2 && (t.back() == '2' || t.back() == '3') &&
             std::isalpha(static_cast<unsigned char>(t[t.size() - 2]))) {
    power = t.back() - '0';
    t.pop_back();
  }
  for (const Atom& a : kAtoms)
    if (t == a.name) {
      if ((root || power != 1) && a.dim.base != Base::kNone) return std::nullopt;  // no sqrt(deg), no m^2
      Dimension d = a.dim;
      d.half_time *= power;
      d.si = std::pow(d.si, power);
      if (root) {
        if (d.half_time % 2 != 0) return std::nullopt;
        d.half_time /= 2;
        d.si = std::sqrt(d.si);
      }
      return d;
    }
  return std::nullopt;
}

// A unit "numerator/denominator/...": the numerator's dimension divided by each denominator's.
std::optional<Dimension> dimension(const std::string& unit) {
  const std::string u = canonical(unit);
  if (u.empty()) return std::nullopt;
  std::vector<std::string> parts;
  std::size_t from = 0;
  for (std::size_t i = 0; i <= u.size(); ++i)
    if (i == u.size() || u[i] == '/') {
      parts.push_back(u.substr(from, i - from));
      from = i + 1;
    }
  std::optional<Dimension> d = factor(parts.front());
  if (!d) return std::nullopt;
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::optional<Dimension> den = factor(parts[k]);
    if (!den || den->base != Base::kNone) return std::nullopt;
    d->half_time -= den->half_time;
    d->si /= den->si;
  }
  return d;
}

// ---------------------------------------------------------------------------------------
// The figures of one sensor.

enum class Role { kWhite, kBias, kTime, kWalk };

struct Key {
  const char* name;
  Role role;
  int half_time;        // the dimension a figure of this role must have (time power x 2)
  const char* meaning;  // for conversions and messages
};

struct SensorSpec {
  SensorKind kind;
  const char* key;
  const char* alias;
  Base base;
  std::vector<Key> keys;
  const char* examples;  // one unit per role, for messages
  const char* density_si;
  const char* bias_si;
  const char* walk_si;
};

// Gyroscope figures have an angle in the numerator, accelerometer figures a length (a
// velocity or an acceleration); both powers of time below are those of the SI units.
const SensorSpec kSensors[] = {
    {SensorKind::kGyro,
     "gyroscope",
     "gyro",
     Base::kAngle,
     {{"noise_density", Role::kWhite, -1, "white noise density"},
      {"angle_random_walk", Role::kWhite, -1, "angle random walk"},
      {"bias_instability", Role::kBias, -2, "bias instability B (IEEE 952: Allan deviation floor 0.664 B)"},
      {"in_run_bias_stability", Role::kBias, -2, "in-run bias stability (the Allan deviation's minimum)"},
      {"bias_correlation_time", Role::kTime, 2, "bias correlation time"},
      {"rate_random_walk", Role::kWalk, -3, "rate random walk"},
      {"random_walk", Role::kWalk, -3, "rate random walk"}},
     "noise_density 0.05 deg/s/sqrt(Hz) or angle_random_walk 2 deg/sqrt(h); bias 0.007 deg/s or 25 deg/h; "
     "bias_correlation_time 100 s; rate_random_walk 10 deg/h/sqrt(h)",
     "rad/s/sqrt(Hz)",
     "rad/s",
     "rad/s^2/sqrt(Hz)"},
    {SensorKind::kAccel,
     "accelerometer",
     "accel",
     Base::kLength,
     {{"noise_density", Role::kWhite, -3, "white noise density"},
      {"velocity_random_walk", Role::kWhite, -3, "velocity random walk"},
      {"bias_instability", Role::kBias, -4, "bias instability B (IEEE 952: Allan deviation floor 0.664 B)"},
      {"in_run_bias_stability", Role::kBias, -4, "in-run bias stability (the Allan deviation's minimum)"},
      {"bias_correlation_time", Role::kTime, 2, "bias correlation time"},
      {"acceleration_random_walk", Role::kWalk, -5, "acceleration random walk"},
      {"random_walk", Role::kWalk, -5, "acceleration random walk"}},
     "noise_density 150 ug/sqrt(Hz) or velocity_random_walk 0.2 m/s/sqrt(h); bias 0.2 mg; "
     "bias_correlation_time 100 s; acceleration_random_walk 0.05 m/s^2/sqrt(h)",
     "m/s^2/sqrt(Hz)",
     "m/s^2",
     "m/s^3/sqrt(Hz)"},
};

struct Figure {
  std::string key;
  double value = 0.0;  // as written
  std::string unit;    // as written
  double si = 0.0;     // in SI (rad, m, s)
  std::string where;   // "<path>:<line>"
  int line = 0;        // the key's 1-based line
  std::string text;    // the scalar as written ("0.05 deg/s/sqrt(Hz)")
};

std::string allowed_keys(const SensorSpec& s) {
  std::string out;
  for (const Key& k : s.keys) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

// The SI unit of a figure of this role.
const char* role_si_unit(Role role, const SensorSpec& s) {
  switch (role) {
    case Role::kWhite:
      return s.density_si;
    case Role::kBias:
      return s.bias_si;
    case Role::kTime:
      return "s";
    case Role::kWalk:
      return s.walk_si;
  }
  return "";
}

// "<number> <unit>" with the unit's dimension that of the key.
Figure read_figure(const YAML::Node& value, const Key& key, const SensorSpec& s, const std::string& where) {
  const std::string name = std::string(s.key) + "." + key.name;
  if (value.IsNull()) throw InputError(where + ": " + name + ": found nothing, expected a number and a unit");
  if (!value.IsScalar())
    throw InputError(where + ": " + name + ": found " + (value.IsMap() ? "a map" : "a list") +
                     ", expected a number and a unit such as '" + s.examples + "'");
  const std::string text = trim(value.Scalar());
  std::size_t split = 0;
  while (split < text.size() && !std::isspace(static_cast<unsigned char>(text[split]))) ++split;
  const std::string number = text.substr(0, split), unit = trim(text.substr(split));
  bool out_of_range = false;
  const std::optional<double> v = detail::decimal(number, out_of_range);
  if (out_of_range) throw InputError(where + ": " + name + ": found " + number + ", beyond the range of a double");
  if (!v)
    throw InputError(where + ": " + name + ": found '" + text + "', expected a number and a unit (" + s.examples + ")");
  if (*v < 0.0 || (key.role == Role::kTime && *v == 0.0))
    throw InputError(where + ": " + name + ": found " + number + ", expected " +
                     (key.role == Role::kTime ? "a positive time" : "a non-negative figure"));
  if (unit.empty())
    throw InputError(where + ": " + name + ": found " + number + " without a unit; datasheets differ by factors of " +
                     "60 and 3600 between units, so the unit is required (" + s.examples + ")");
  const std::optional<Dimension> d = dimension(unit);
  const Base want = key.role == Role::kTime ? Base::kNone : s.base;
  if (!d || d->base != want || d->half_time != key.half_time)
    throw InputError(where + ": " + name + ": '" + unit + "' is not a unit of a " + key.meaning + " (" + s.examples +
                     ")");
  const double si = *v * d->si;
  if (*v != 0.0 && !detail::within_double(si))
    throw InputError(where + ": " + name + ": found " + number + " " + unit + ", which is " + g(si) + " in SI units (" +
                     role_si_unit(key.role, s) +
                     "), outside the range of a double (expected a figure near the sensor's)");
  return {key.name, *v, unit, si, where};
}

// The Allan variance of `model` at averaging times of m samples, m = 2^(k / points) rounded
// to whole samples over the searched range: AVAR(m) = 2 WV(tau = 2m) (the WV of a process
// is defined at even whole tau).
// max_m bounds m (samples).
std::vector<double> allan_curve(const Model& model, const Eigen::VectorXd& theta, double max_m) {
  std::vector<double> tau;
  for (int k = 0; k <= kSearchOctaves * kSearchPointsPerOctave; ++k) {
    const double m = std::round(std::exp2(static_cast<double>(k) / kSearchPointsPerOctave));
    if (m > max_m && !tau.empty()) break;
    if (tau.empty() || 2.0 * m > tau.back()) tau.push_back(2.0 * m);
  }
  const Eigen::VectorXd wv = model.wv(theta, tau);
  std::vector<double> avar(static_cast<std::size_t>(wv.size()));
  for (Eigen::Index i = 0; i < wv.size(); ++i) avar[static_cast<std::size_t>(i)] = 2.0 * wv(i);
  return avar;
}

// The largest m searched for a minimum at rate f.
double minimum_search_samples(double f) { return std::min(kMinimumSearchSeconds * f, kMinimumSearchSamples); }

double min_of(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
double max_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// The factor c >= 0 that makes min_m (others(m) + c unit(m)) equal target^2 (a minimum of
// the whole Allan curve, as a datasheet's in-run stability is read). The minimum grows with
// c, so bisection; c = 0 when the other terms alone already sit above the target.
double scale_for_minimum(const std::vector<double>& others, const std::vector<double>& unit, double target2) {
  auto minimum = [&](double c) {
    double m = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < unit.size(); ++i) m = std::min(m, others[i] + c * unit[i]);
    return m;
  };
  if (minimum(0.0) >= target2) return 0.0;
  double hi = target2 / min_of(unit);
  while (minimum(hi) < target2) hi *= 2.0;
  double lo = 0.0;
  constexpr int kBisections = 200;  // far beyond double precision: stops when lo and hi meet
  for (int i = 0; i < kBisections && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (minimum(mid) < target2 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The bias term's shape at unit size: a flicker (no correlation time) or an AR1 with
// phi = exp(-1/(f T)), with its Allan variance over the minimum's search range.
struct BiasShape {
  Model unit_model;
  Eigen::VectorXd unit_theta;
  std::vector<double> curve;
  double peak = 0.0;  // the Allan variance's largest value over the whole range
  bool gauss_markov = false;
  std::string text;
};

BiasShape bias_shape(double T, double f) {
  BiasShape b;
  b.gauss_markov = T > 0.0;
  if (b.gauss_markov) {
    const double phi = std::exp(-1.0 / (f * T));
    b.unit_model = parse_model("AR1(phi=" + exact(phi) + ",sigma2=1)");
    b.text = "a Gauss-Markov bias (AR1, phi = exp(-1/(f T)) = " + g(phi, 8) + " with T = " + g(T) + " s)";
  } else {
    b.unit_model = parse_model("FLICKER(B2=1)");
    b.text = "flicker noise (FLICKER, a flat Allan deviation)";
  }
  b.unit_theta = b.unit_model.given_values();
  b.curve = allan_curve(b.unit_model, b.unit_theta, minimum_search_samples(f));
  // The peak over the whole range (a slow bias peaks at 1.89 T, possibly past 1e5 s); a
  // flicker's curve is flat, and its plateau is inside the minimum's range.
  b.peak = T > 0.0 ? max_of(allan_curve(b.unit_model, b.unit_theta, std::exp2(kSearchOctaves))) : max_of(b.curve);
  return b;
}

// IEEE 952's B (data unit): the flicker floor is 0.664 B; a Gauss-Markov bias gets that as
// its peak. The factor on the unit-size term.
double scale_for_b(const BiasShape& shape, double B) {
  if (!shape.gauss_markov) return B * B;  // FLICKER's B2 is B^2 by definition (processes/flicker.cc)
  const double floor = kFlickerFloorPerB * B;
  return floor * floor / shape.peak;
}

std::string bias_spec(const BiasShape& shape, double c) {
  return shape.gauss_markov ? "AR1(phi=" + exact(shape.unit_theta(0)) + ",sigma2=" + exact(c) + ")"
                            : "FLICKER(B2=" + exact(c) + ")";
}

struct SensorFigures {
  std::optional<Figure> white, bias, time, walk;
};

SensorFigures read_sensor(const YAML::Node& node, const SensorSpec& s, const std::string& path) {
  detail::check_unique_keys(node, path);
  SensorFigures f;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    const std::string where = detail::yaml_at(path, kv.first.Mark());
    const auto k = std::find_if(s.keys.begin(), s.keys.end(), [&](const Key& x) { return key == x.name; });
    if (k == s.keys.end())
      throw InputError(where + ": unknown figure '" + std::string(s.key) + "." + key + "' (expected one of " +
                       allowed_keys(s) + ")");
    Figure fig = read_figure(kv.second, *k, s, where);
    fig.line = kv.first.Mark().line + 1;
    fig.text = kv.second.IsScalar() ? kv.second.Scalar() : std::string();
    std::optional<Figure>& slot = k->role == Role::kWhite  ? f.white
                                  : k->role == Role::kBias ? f.bias
                                  : k->role == Role::kTime ? f.time
                                                           : f.walk;
    if (slot)
      throw InputError(where + ": " + std::string(s.key) + "." + key + " and " + s.key + "." + slot->key + " (" +
                       slot->where + ") give the same figure twice: keep one");
    slot = std::move(fig);
  }
  if (f.time && !f.bias)
    throw InputError(f.time->where + ": " + s.key +
                     ".bias_correlation_time without a bias figure (give "
                     "bias_instability or in_run_bias_stability)");
  return f;
}

std::string written(const Figure& f) { return f.key + " = " + g(f.value) + " " + f.unit; }

// A per-sample variance from a figure must be a normal positive double.
void check_representable(double v, const Figure& f, const SensorSpec& s, const std::string& what) {
  if (v > 0.0 && detail::within_double(v)) return;
  throw InputError(f.where + ": " + s.key + "." + f.key + ": " + g(f.value) + " " + f.unit + " gives " + what + " = " +
                   g(v) + ", outside the range of a double (expected a figure near the sensor's)");
}

// The terms of one sensor at the data's rate f and unit u, with a line per conversion.
std::string sensor_model(const SensorFigures& fig, const SensorSpec& s, double f, const Unit& u,
                         std::vector<std::string>& lines) {
  const std::string un = u.name;
  std::string spec_wn, spec_rw;
  if (fig.white && fig.white->si > 0.0) {
    const double N = fig.white->si * u.per_si, sigma2 = N * N * f;
    check_representable(sigma2, *fig.white, s, "WN sigma2 per sample");
    lines.push_back(written(*fig.white) + " = " + g(fig.white->si) + " " + s.density_si +
                    " -> WN sigma2 = N^2 f = " + g(sigma2) + " (" + un + ")^2 per sample at f = " + g(f) + " Hz");
    spec_wn = "WN(sigma2=" + exact(sigma2) + ")";
  } else {
    lines.push_back(fig.white ? written(*fig.white) + ": no white noise term"
                              : "no white noise figure: no white noise term");
  }
  if (fig.walk && fig.walk->si > 0.0) {
    const double K = fig.walk->si * u.per_si, gamma2 = K * K / f;
    check_representable(gamma2, *fig.walk, s, "RW gamma2 per sample");
    lines.push_back(written(*fig.walk) + " = " + g(fig.walk->si) + " " + s.walk_si +
                    " -> RW gamma2 = K^2 / f = " + g(gamma2) + " (" + un + ")^2 per sample");
    spec_rw = "RW(gamma2=" + exact(gamma2) + ")";
  }
  std::string spec_bias;
  if (fig.bias && fig.bias->si > 0.0) {
    const bool minimum = fig.bias->key == "in_run_bias_stability";
    const double b = fig.bias->si * u.per_si;  // in the data's unit
    check_representable(b * b, *fig.bias, s, "a bias variance");
    if (fig.time && !(std::exp(-1.0 / (f * fig.time->si)) < 1.0))
      throw InputError(fig.time->where + ": " + s.key + ".bias_correlation_time: " + g(fig.time->value) + " " +
                       fig.time->unit + " is beyond what a double tells from a random walk at " + g(f) +
                       " Hz (phi = exp(-1/(f T)) rounds to 1): give a random_walk figure instead");
    const std::string rate = "at f = " + g(f) + " Hz";
    const BiasShape shape = bias_shape(fig.time ? fig.time->si : 0.0, f);
    const std::vector<double>& unit_curve = shape.curve;
    double c = 0.0;
    std::string how;
    if (minimum) {
      // The datasheet's figure is the minimum of the whole curve: the bias term is sized so
      // that white noise + bias + random walk has that minimum.
      std::vector<double> others(unit_curve.size(), 0.0);
      if (!spec_wn.empty() || !spec_rw.empty()) {
        const std::string o = spec_wn + (spec_wn.empty() || spec_rw.empty() ? "" : "+") + spec_rw;
        const Model m = parse_model(o);
        others = allan_curve(m, m.given_values(), minimum_search_samples(f));
      }
      c = scale_for_minimum(others, unit_curve, b * b);
      how = "sized so that the whole Allan deviation (white noise + bias + random walk) has its minimum at " +
            g(fig.bias->value) + " " + fig.bias->unit;
      if (c == 0.0)
        lines.push_back(written(*fig.bias) +
                        ": the white noise and random walk alone never fall to this minimum "
                        "(their Allan deviation stays above it): no bias term");
    } else {
      c = scale_for_b(shape, b);
      how = fig.time
                ? "sized so that its Allan deviation peaks at 0.664 B = " + g(kFlickerFloorPerB * fig.bias->value) +
                      " " + fig.bias->unit + " (IEEE 952's flicker floor for B)"
                : "B2 = B^2: Allan deviation floor 0.664 B = " + g(kFlickerFloorPerB * fig.bias->value) + " " +
                      fig.bias->unit;
    }
    if (c > 0.0) {
      check_representable(c, *fig.bias, s, "a bias variance");
      spec_bias = bias_spec(shape, c);
      lines.push_back(written(*fig.bias) + (fig.time ? ", " + written(*fig.time) : std::string()) + " -> " +
                      shape.text + (fig.time ? ", sigma2 = " : ", B2 = ") + g(c) + " (" + un + ")^2" +
                      (fig.time ? " per sample " + rate : std::string()) + ", " + how);
    }
  }
  std::string spec = spec_wn;
  for (const std::string* t : {&spec_bias, &spec_rw})
    if (!t->empty()) spec += (spec.empty() ? "" : "+") + *t;
  return spec;
}

// A corrected figure's digits: four, as a datasheet prints them; a figure estimated from a
// recording is uncertain by far more than the 0.05% this rounds (and the corrected file's
// model is read back from this text, so the gap left is that of what is written).
constexpr int kWrittenDigits = 4;
std::string written_value(double x) { return g(x, kWrittenDigits); }

// The unit a corrected datasheet writes a figure in when the input had none for it.
const char* common_unit(Role role, SensorKind kind) {
  const bool gyro = kind == SensorKind::kGyro;
  switch (role) {
    case Role::kWhite:
      return gyro ? "deg/s/sqrt(Hz)" : "ug/sqrt(Hz)";
    case Role::kBias:
      return gyro ? "deg/h" : "mg";
    case Role::kTime:
      return "s";
    case Role::kWalk:
      return gyro ? "deg/h/sqrt(h)" : "m/s^2/sqrt(h)";
  }
  return "";
}

}  // namespace

SimConfig read_datasheet_yaml(const std::string& path, double data_freq, const std::map<SensorKind, Unit>& units) {
  return parse_datasheet_yaml(read_side_file(path, "a datasheet yaml", kMaxKalibrYamlBytes), path, data_freq, units);
}

namespace {

// Every sensor's figures of a datasheet map (gyroscope / accelerometer, an optional name);
// `source` gets the part's name when the map gives one.
std::map<SensorKind, SensorFigures> read_sensors(const YAML::Node& root, const std::string& path, std::string* source) {
  if (!root.IsMap())
    throw InputError(path +
                     ": expected a datasheet yaml: 'gyroscope:' and/or 'accelerometer:' maps of figures "
                     "such as 'noise_density: 0.05 deg/s/sqrt(Hz)'");
  detail::check_unique_keys(root, path);
  std::map<SensorKind, SensorFigures> read;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    const std::string where = detail::yaml_at(path, kv.first.Mark());
    if (key == "name" || key == "part") {
      if (!kv.second.IsScalar()) throw InputError(where + ": " + key + ": expected the part's name as text");
      if (source) *source = "datasheet of " + kv.second.Scalar() + " (" + path + ")";
      continue;
    }
    const auto s = std::find_if(std::begin(kSensors), std::end(kSensors),
                                [&](const SensorSpec& x) { return key == x.key || key == x.alias; });
    if (s == std::end(kSensors))
      throw InputError(where + ": unknown key '" + key + "' (expected gyroscope, accelerometer or name)");
    if (read.count(s->kind))
      throw InputError(where + ": " + key + ": the " + s->key + " is given twice (" + s->key + " and " + s->alias +
                       ")");
    if (!kv.second.IsMap()) throw InputError(where + ": " + key + ": expected a map of figures (" + s->examples + ")");
    read[s->kind] = read_sensor(kv.second, *s, path);
  }
  if (read.empty()) throw InputError(path + ": no gyroscope or accelerometer figures");
  return read;
}

std::optional<SpecLimit> limit_of(const std::optional<Figure>& f) {
  if (!f) return std::nullopt;
  return SpecLimit{f->si, f->value, f->unit, g(f->value) + " " + f->unit, f->where, f->key};
}

}  // namespace

bool is_datasheet_key(const std::string& key) {
  if (key == "name" || key == "part") return true;
  return std::any_of(std::begin(kSensors), std::end(kSensors),
                     [&](const SensorSpec& x) { return key == x.key || key == x.alias; });
}

std::map<SensorKind, SensorLimits> datasheet_limits(const YAML::Node& root, const std::string& path) {
  std::map<SensorKind, SensorLimits> out;
  for (const auto& [kind, fig] : read_sensors(root, path, nullptr)) {
    SensorLimits l;
    l.white = limit_of(fig.white);
    l.walk = limit_of(fig.walk);
    l.instability = limit_of(fig.bias);
    l.instability_is_minimum = fig.bias && fig.bias->key == "in_run_bias_stability";
    out.emplace(kind, std::move(l));
  }
  return out;
}

SimConfig parse_datasheet_yaml(const std::string& text, const std::string& path, double data_freq,
                               const std::map<SensorKind, Unit>& units) {
  const YAML::Node root = detail::load_yaml(text, path);
  SimConfig c;
  c.source = "datasheet (" + path + ")";
  c.format = SimFormat::kDatasheet;
  c.text = text;
  const std::map<SensorKind, SensorFigures> read = read_sensors(root, path, &c.source);
  for (const SensorSpec& s : kSensors) {
    const auto it = read.find(s.kind);
    if (it == read.end()) continue;
    for (const std::optional<Figure>* f : {&it->second.white, &it->second.bias, &it->second.time, &it->second.walk})
      if (*f)
        c.fields.push_back({std::string(s.key) + "/" + (*f)->key, (*f)->value, (*f)->unit, (*f)->line, (*f)->text});
    const auto uit = units.find(s.kind);
    const Unit u = uit != units.end() ? uit->second : si_unit(s.kind);
    std::vector<std::string>& lines = c.conversions[s.kind];
    const std::string spec = sensor_model(it->second, s, data_freq, u, lines);
    if (!spec.empty()) c.models.emplace(s.kind, parse_model(spec));
  }
  return c;
}

// The in-run bias stability a datasheet with these figures (SI) prints: the minimum of the
// whole Allan deviation of white noise + the bias of IEEE 952's B + random walk, so that
// reading it back (parse_datasheet_yaml) gives that bias again.
double in_run_stability(const DatasheetFigures& d, double f) {
  std::string spec = "WN(sigma2=" + exact(std::max(d.white * d.white * f, std::numeric_limits<double>::min())) + ")";
  if (d.walk > 0.0) spec += "+RW(gamma2=" + exact(d.walk * d.walk / f) + ")";
  if (d.instability > 0.0) {
    const BiasShape shape = bias_shape(d.correlation_time, f);
    spec += "+" + bias_spec(shape, scale_for_b(shape, d.instability));
  }
  const Model m = parse_model(spec);
  return allan_deviation_minimum(m, m.given_values(), f);
}

std::string write_datasheet_yaml(const SimConfig& input, const std::map<SensorKind, DatasheetFigures>& figures,
                                 double freq) {
  std::string out;
  for (const SensorSpec& s : kSensors) {
    const std::string prefix = std::string(s.key) + "/";
    std::vector<const ConfigField*> given;
    for (const ConfigField& f : input.fields)
      if (f.name.rfind(prefix, 0) == 0) given.push_back(&f);
    const auto it = figures.find(s.kind);
    if (it == figures.end() && given.empty()) continue;
    out += std::string(s.key) + ":\n";
    if (it == figures.end()) {  // not diagnosed: the input's figures as they were
      for (const ConfigField* f : given)
        out += "  " + f->name.substr(prefix.size()) + ": " + written_value(f->value) + " " + f->unit + "\n";
      continue;
    }
    const DatasheetFigures& d = it->second;
    bool bias_written = false;  // a correlation time alone would not read back
    for (Role role : {Role::kWhite, Role::kBias, Role::kTime, Role::kWalk}) {
      const ConfigField* in = nullptr;
      for (const ConfigField* f : given)
        for (const Key& k : s.keys)
          if (k.role == role && f->name == prefix + k.name) in = f;
      std::string key = in ? in->name.substr(prefix.size()) : std::string();
      const std::string unit = in ? in->unit : common_unit(role, s.kind);
      double si = 0.0;
      switch (role) {
        case Role::kWhite:
          si = d.white;
          if (!in) key = "noise_density";
          break;
        case Role::kBias:
          if (!in) key = "bias_instability";
          si = key == "in_run_bias_stability" ? in_run_stability(d, freq) : d.instability;
          break;
        case Role::kTime:
          si = in && bias_written ? d.correlation_time : 0.0;
          break;
        case Role::kWalk:
          si = d.walk;
          if (!in) key = s.kind == SensorKind::kGyro ? "rate_random_walk" : "acceleration_random_walk";
          break;
      }
      if (!(si > 0.0) && (!in || role == Role::kTime)) continue;
      const std::optional<Dimension> dim = dimension(unit);
      if (role == Role::kBias) bias_written = si > 0.0;
      out += "  " + key + ": " + written_value(std::max(si, 0.0) / dim->si) + " " + unit + "\n";
    }
  }
  return out;
}

double allan_deviation_minimum(const Model& model, const Eigen::VectorXd& theta, double freq) {
  return std::sqrt(min_of(allan_curve(model, theta, minimum_search_samples(freq))));
}

}  // namespace gmwm::io
