#pragma once
// Internals shared by the read-offs of a curve (noise_figures.cc) and the choice between the
// model's and the data's figures (noise_figure_choice.cc).

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/physical.h"

namespace gmwm::figures {

// The IEEE 952 read-off taus (seconds; IEEE Std 952-1997, Annex C, figure C.1): where each
// line's Allan deviation equals its coefficient.
inline constexpr double kWhiteTau = 1.0;                        // N = ADEV(1 s) on the -1/2 line
inline constexpr double kWalkTau = 3.0;                         // K = ADEV(3 s) on the +1/2 line
inline constexpr double kQuantizationTau = 1.7320508075688772;  // sqrt(3): Q = ADEV(sqrt(3) s) on the -1 line
inline constexpr double kRampTau = 1.4142135623730951;          // sqrt(2): R = ADEV(sqrt(2) s) on the +1 line
// B from the model only where its curve is within this share of the data's at their minimum
// (besides inside their interval): a minimum sits where the interval is widest, and an
// engineer reads a floor to about this (issue 43's acceptance bar for B is 25%).
inline constexpr double kFloorAgreement = 0.2;

inline std::string fmt(double x) { return significant(x, 3); }

// A figure's value at tau from the Allan deviation there: N = sigma sqrt(tau) on the -1/2
// line, K = sigma sqrt(3 / tau) on the +1/2 line, Q = sigma tau / sqrt(3) on the -1 line
// (AVAR = 3 Q^2 / tau^2), R = sigma sqrt(2) / tau on the +1 line (AVAR = R^2 tau^2 / 2).
inline double white_scale(double tau) { return std::sqrt(tau); }
inline double walk_scale(double tau) { return std::sqrt(kWalkTau / tau); }
inline double quantization_scale(double tau) { return tau / kQuantizationTau; }
inline double ramp_scale(double tau) { return kRampTau / tau; }

// A read value (not only a bound).
inline bool shows(const Readoff& r) { return r.available() && r.status != ReadoffStatus::kBound; }

// Which slope region a power-law figure is read on (slope_readoffs.cc, pick_region).
enum class RegionRule {
  kLongest,  // N: the white floor, the longest -1/2 stretch over the record
  kNearest,  // K: the one holding the IEEE tau, else the nearest to it
  kFirst,    // Q: the one starting at the curve's first usable point
  kLast,     // R: the one ending at the curve's last point
};

// A power-law figure of IEEE 952 Annex C: its Allan deviation slope, read tau, scale
// (figure = ADEV(tau) scale(tau)), the slope's name in the texts, its region rule and the
// kind of a component's exact continuous figure (physical.h).
struct SlopeFigure {
  double slope;
  double tau;
  double (*scale)(double);
  const char* slope_name;
  RegionRule rule;
  PhysicalKind kind;
};
inline constexpr SlopeFigure kWhiteSlope{
    -0.5, kWhiteTau, white_scale, "-1/2", RegionRule::kLongest, PhysicalKind::kNoiseDensity};
inline constexpr SlopeFigure kWalkSlope{
    0.5, kWalkTau, walk_scale, "+1/2", RegionRule::kNearest, PhysicalKind::kRandomWalk};
inline constexpr SlopeFigure kQuantizationSlope{-1.0, kQuantizationTau,   quantization_scale,
                                                "-1", RegionRule::kFirst, PhysicalKind::kQuantization};
inline constexpr SlopeFigure kRampSlope{1.0, kRampTau, ramp_scale, "+1", RegionRule::kLast, PhysicalKind::kDriftRate};

// An Allan deviation curve as the read-offs see it.
struct Curve {
  std::vector<double> tau, sigma;
  std::vector<bool> usable;     // points that decide slopes
  std::vector<bool> in_record;  // points a bound may come from (empty: the usable ones)
  bool bounds_from(std::size_t i) const { return in_record.empty() ? usable[i] : in_record[i]; }
};

// A run of consecutive usable points on a slope (indices into the curve).
struct Region {
  std::size_t first, last, count;
};

// Points in a slope region at least (one alone could be a wiggle of the curve).
inline constexpr std::size_t kMinRegionPoints = 2;

// The region figure `s` is read on (nullptr: none), by s.rule (slope_readoffs.cc).
const Region* pick_region(const Curve& c, const std::vector<Region>& regions, const SlopeFigure& s);

// Where two or more of the power-law figures (N, K, Q, R) are read off the data's curve,
// each read point still carries the other lines (the Allan variances add); the equations at
// the read points are solved to remove them (slope_readoffs.cc).
void separate_power_laws(NoiseFigures& f);

}  // namespace gmwm::figures
