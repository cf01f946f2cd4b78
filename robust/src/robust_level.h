#pragma once
// The pieces of the robust WV that the regular record's form (robust_wv.cc) and the form
// for a record with gaps (robust_wv_with_gaps.cc) share (internal to robust/): the
// estimating equation at one level from its coefficients, the spike screen's level-1
// scale, and the sentences the WV carries.

#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/spike_screen.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust::internal {

/// One buffer per thread for a level's coefficients (and the spike screen's jumps before
/// them): its pages stay, where each fresh 8 MB vector was page faults and zeroing.
std::vector<double>& level_buffer();

/// The robust scale of the level-1 jumps the spike screen measures spikes against (the
/// equation started from their mean square).
ScaleSolution solve_jumps(std::span<const double> jumps, const Tuning& t);

/// "spike screen not applied: the level-1 huber equation has no root (P% of the jumps are
/// exactly 0)".
std::string unscreened_note(const ScaleSolution& level_one, const Tuning& t);

/// Marks `w` (a classical WV about to be made robust) with the estimator, its efficiency,
/// the screen's replaced ranges and note, and the small-sample sentence.
void describe_robust(WaveletVariance& w, const Tuning& t, SpikeScreen screen);

/// Adds `note` to level i's notes (after those already there, e.g. a gappy level's windows).
void add_note(WaveletVariance& w, std::size_t i, const std::string& note);

/// True, with level j's note saying why, when the level has too few effective coefficients
/// (eta below kRobustMinEta) for the robust estimator and keeps its classical estimate.
bool keeps_classical(int j, WaveletVariance& w);

/// Level j of `w` from `coef`, the coefficients its classical estimate averaged the squares
/// of (those at most `floor` in magnitude set to 0: rounding of the sums, not signal): the
/// root of the estimating equation, its small-sample correction, eta times the efficiency
/// and the chi-square interval; NaN with a note when the equation has no root.
void robust_level_from(std::vector<double>& coef, double floor, int j, const Tuning& t, WaveletVariance& w);

/// Throws InvalidArgument "FN: why" when `o` is invalid.
void check_options(const char* fn, const RobustWvOptions& o);

}  // namespace gmwm::robust::internal
