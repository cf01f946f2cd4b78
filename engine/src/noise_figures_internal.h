#pragma once
// Internals shared by the read-offs of a curve (noise_figures.cc) and the choice between the
// model's and the data's figures (noise_figure_choice.cc).

#include <cmath>
#include <cstdio>
#include <string>

#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::figures {

// The IEEE 952 read-off taus (seconds).
inline constexpr double kWhiteTau = 1.0;  // N = ADEV(1 s) on the -1/2 line
inline constexpr double kWalkTau = 3.0;   // K = ADEV(3 s) on the +1/2 line
// B from the model only where its curve is within this share of the data's at their minimum
// (besides inside their interval): a minimum sits where the interval is widest, and an
// engineer reads a floor to about this (issue 43's acceptance bar for B is 25%).
inline constexpr double kFloorAgreement = 0.2;

inline std::string fmt(double x) { return significant(x, 3); }

// A figure's value at tau from the Allan deviation there: N = sigma sqrt(tau) on the -1/2
// line, K = sigma sqrt(3 / tau) on the +1/2 line.
inline double white_scale(double tau) { return std::sqrt(tau); }
inline double walk_scale(double tau) { return std::sqrt(kWalkTau / tau); }

// A read value (not only a bound).
inline bool shows(const Readoff& r) { return r.available() && r.status != ReadoffStatus::kBound; }

}  // namespace gmwm::figures
