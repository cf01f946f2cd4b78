#pragma once
// Continuous-time ("physical") quantities of a process's discrete, per-sample parameters
// at a sampling rate f in Hz: the numbers a navigation engineer reads off a datasheet
// (noise density, rate random walk, correlation time, bias instability, ...), with unit
// patterns in which "U" stands for the data's unit. Each process implements the
// conversion (Process::physical, process.h); this header holds the quantity type, the
// unit rendering and the mapping of parameter confidence intervals.
//
// IEEE Std 952 relations used to derive the conversions (AVAR(m) = 2 WV(tau = 2m), m
// samples = T f seconds; docs/design.md section 1): white noise AVAR = N^2 / T, rate random walk
// AVAR = K^2 T / 3, quantization AVAR = 3 Q^2 / T^2, rate ramp AVAR = R^2 T^2 / 2, flicker
// floor AVAR = (2 ln2 / pi) B^2. Each process file writes its derivation next to its code.

#include <span>
#include <string>
#include <vector>

namespace gmwm {

class Process;

/// What a physical quantity is: code (the exporters, the noise-figure refinement) picks
/// quantities by kind, never by their display name.
enum class PhysicalKind {
  kParameter,           ///< a discrete parameter without a standard physical meaning
  kNoiseDensity,        ///< white noise: U/sqrt(Hz)
  kRandomWalk,          ///< rate random walk: U/s/sqrt(Hz)
  kCorrelationTime,     ///< Gauss-Markov: s
  kStationarySigma,     ///< Gauss-Markov: U
  kDriftRate,           ///< U/s
  kFlickerCoefficient,  ///< U
  kBiasInstability,     ///< U (the Allan deviation's flicker floor)
  kQuantization,        ///< U*s
  kAmplitude,           ///< sinusoid: U
  kFrequency,           ///< sinusoid: Hz
};

struct PhysicalQuantity {
  std::string name;  ///< for people: "noise density", "correlation time"
  double value = 0.0;
  std::string unit_pattern;  ///< "U" is the data unit: "U/sqrt(Hz)", "s", "U*s"; "" if none
  std::string convention;    ///< one line: the formula and its convention
  PhysicalKind kind = PhysicalKind::kParameter;
};

/// The value of the quantity of `kind` among `q`, or NaN when none is of that kind.
double quantity_of_kind(const std::vector<PhysicalQuantity>& q, PhysicalKind kind);

/// The unit of a pattern for data in `data_unit`: each factor "U" becomes the data unit's
/// factors (inverted when U is in a denominator) and powers of seconds are collected into
/// one factor, written first among the denominators:
///   render_unit("U/sqrt(Hz)", "deg/s")   == "deg/s/sqrt(Hz)"
///   render_unit("U/s/sqrt(Hz)", "rad/s") == "rad/s^2/sqrt(Hz)"
///   render_unit("U*s", "deg/s") == "deg",   render_unit("U*s", "g") == "g*s"
///   render_unit("U/s", "m/s^2") == "m/s^3", render_unit("U", "") == ""
/// Factors are split at '*' and '/' outside parentheses; only "s" and "s^n" (integer n)
/// count as seconds. An empty data unit is dimensionless ("U/s" -> "1/s").
std::string render_unit(const std::string& pattern, const std::string& data_unit);

struct PhysicalInterval {
  double low = 0.0;
  double high = 0.0;
};

/// Interval of each quantity of process.physical(theta, freq) (same order) from the
/// parameters' intervals [ci_low_k, ci_high_k]: the range of the quantity over the box of
/// parameter intervals. A quantity depends on the parameters that change it (found by
/// evaluation); it is evaluated at every combination of their candidate values, the two
/// bounds plus 0 when 0 is strictly inside (the quantities here are monotone in each
/// parameter on each side of 0: AR1's depend on |phi|), and at theta itself, and the
/// minimum and maximum are taken. For a quantity of one parameter this is the exact image
/// of that parameter's interval (decreasing maps included); for two or more it is
/// conservative: the box of marginal intervals is wider than their joint region, so the
/// interval is wider than a delta-method one. Bounds on the edge of a parameter's domain
/// give the limiting values (phi = 1 -> correlation time inf); NaN bounds (parameters
/// without inference) give NaN for the quantities depending on them. Throws
/// InvalidArgument (check.h) for sizes that do not match theta, a non-positive freq,
/// ci_low_k > ci_high_k, or a quantity depending jointly on more than 8 parameters.
std::vector<PhysicalInterval> physical_interval(const Process& process, std::span<const double> theta,
                                                std::span<const double> ci_low, std::span<const double> ci_high,
                                                double freq);

}  // namespace gmwm
