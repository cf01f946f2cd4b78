#pragma once
// The three-cornered hat (issue 48): three sensors A, B, C recorded together (three clocks
// compared pairwise, three co-located IMUs' same axis) give three pairwise differences
// A - B, B - C, C - A, free of whatever input the sensors share (the reference's noise, the
// platform's true rotation). With independent noises, the variance of a difference is the
// sum of the two sensors' at every averaging time, so each sensor's own variance is
//
//   s_A^2 = (s_AB^2 + s_CA^2 - s_BC^2) / 2,  s_B^2 = (s_AB^2 + s_BC^2 - s_CA^2) / 2,
//   s_C^2 = (s_BC^2 + s_CA^2 - s_AB^2) / 2
//
// (J. E. Gray and D. W. Allan, "A method for estimating the frequency stability of an
// individual oscillator", 28th Frequency Control Symposium, 1974; NIST SP 1065, W. J. Riley,
// "Handbook of Frequency Stability Analysis", 2008, section on the three-cornered hat). It
// holds for every deviation here whose square is a quadratic form of the phase: every kind
// but MTIE (a maximum). The separated variances are unbiased but not always positive (finite
// records, correlated sensors): a negative one is kept as it is, flagged, and its deviation
// is NaN; nothing is clamped.
//
// Each separated variance's interval (docs/stability.md, "Three-cornered hat"): with the
// sensors' noises Gaussian and of one spectral shape, s_A^2's estimate is Q(a) - B(a, b) -
// B(a, c) + B(b, c) (Q the kind's quadratic form, B its bilinear form), whose terms are
// uncorrelated, so its variance is
//
//   Var = (2 s_A^4 + s_A^2 s_B^2 + s_A^2 s_C^2 + s_B^2 s_C^2) / nu
//
// with nu the pairs' equivalent degrees of freedom (Var Q = 2 E[Q]^2 / nu, confidence.h). The
// interval is the score interval (E. B. Wilson, JASA 22, 1927: the normal test inverted with
// the variance at the value tested): the a >= 0 with (s_A^2 - a)^2 <= z^2 (2 a^2 + a S + P) /
// nu, S = s_BC^2 (the estimate of s_B^2 + s_C^2), P = max(s_B^2, 0) max(s_C^2, 0), nu the
// smallest of the three pairs' edf, z the normal quantile of (1 + confidence) / 2. It gives
// an upper bound from 0 where the estimate is negative, and none where no a >= 0 fits or
// where nu < 4 z^2 (4 at 68.27%, 15.4 at 95%: the set is unbounded at nu <= 2 z^2, and
// below 4 z^2 the simulated coverage fell short). A chi-square interval with the
// moment-matched (Satterthwaite 1946) edf nu 2 s_A^4 / (the bracket above), read at the
// estimate, is what fails where a small sensor sits beside larger ones (docs/stability.md,
// "Three-cornered hat", gives the coverage measured of both).
//
//   const auto ab = deviation(kind, phase_of(a - b), tau0, m), ...;
//   const ThreeCorneredHat hat = three_cornered_hat(std::array{ab, bc, ca},
//       std::array{deviation_intervals(ab, ...), deviation_intervals(bc, ...), ...});

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "gmwm/stability/confidence.h"
#include "gmwm/stability/deviation.h"

namespace gmwm::stability {

/// Three sensors A, B, C; three pairs, read in the order A - B, B - C, C - A.
inline constexpr std::size_t kHatSensors = 3;

/// Whether the kind's square is a variance the hat can separate: every kind but MTIE (a
/// maximum over windows, not a quadratic form of the phase). TIE rms is the root of a mean
/// square, and separates.
bool separable(DeviationKind kind);

/// Each sensor's variance from the three pairwise variances ab = s_AB^2, bc = s_BC^2, ca =
/// s_CA^2: {(ab + ca - bc) / 2, (ab + bc - ca) / 2, (bc + ca - ab) / 2} (Gray and Allan 1974).
/// Any of them may be negative.
std::array<double, kHatSensors> separated_variances(double ab, double bc, double ca);

/// The variance of a separated variance's estimate for sensors of one noise shape:
/// (2 own^2 + own others_sum + others_product) / edf, others_sum = the other two sensors'
/// variances' sum, others_product their product.
double separated_variance_variance(double own, double others_sum, double others_product, double edf);

/// An interval of a variance (NaN ends where none is given; high +inf never: see below).
struct VarianceInterval {
  double low = NAN, high = NAN;
};

/// The score interval of a separated variance at `confidence` (header comment): the a >= 0
/// with (estimate - a)^2 <= z^2 separated_variance_variance(a, others_sum, others_product,
/// edf). NaN ends where no a >= 0 fits, or where edf < 4 z^2.
/// Throws InputError for a confidence outside (0, 1), an edf that is not positive, a negative
/// or non-finite others_sum or others_product, or a non-finite estimate.
VarianceInterval separated_variance_interval(double estimate, double others_sum, double others_product, double edf,
                                             double confidence);

/// One sensor's separated deviation at each factor of the hat.
struct HatSensor {
  std::vector<double> variance;   ///< the separated variance (negative where the estimate is)
  std::vector<double> value;      ///< its deviation sqrt(variance); NaN where variance < 0
  std::vector<bool> negative;     ///< variance < 0
  std::vector<double> low, high;  ///< the deviation's interval (sqrt of the variance's); NaN where none
};

struct ThreeCorneredHat {
  DeviationKind kind = DeviationKind::kOadev;
  double tau0 = 1.0;
  std::vector<std::int64_t> m;  ///< the pairs' averaging factors
  std::vector<double> tau;      ///< their averaging times (s)
  /// The degrees of freedom the intervals read: the smallest of the three pairs' at each
  /// factor; NaN where a pair has none (no intervals given, or the kind has no rule).
  std::vector<double> edf;
  double confidence = NAN;                     ///< the intervals' (NaN without intervals)
  std::array<HatSensor, kHatSensors> sensors;  ///< A, B, C
};

/// The hat of `pairs` (A - B, B - C, C - A: one kind, one tau0, the same factors and terms,
/// every value finite and >= 0) and, when given, their intervals (three, one per pair, at
/// one confidence: each pair's edf; the intervals then follow the rule above; without them
/// every interval is NaN). Throws InputError naming the problem: not three pairs (or not
/// three intervals), a kind that does not separate (MTIE), pairs of different kinds, tau0,
/// factors or terms (records of different lengths), a value that is negative or not finite,
/// intervals of another length or confidence.
ThreeCorneredHat three_cornered_hat(std::span<const DeviationCurve> pairs,
                                    std::span<const DeviationIntervals> intervals = {});

}  // namespace gmwm::stability
