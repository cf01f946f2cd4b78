#pragma once
// The confidence intervals of the frequency-stability deviations (issue 48), as Stable32 and
// NIST SP 1065 (Riley 2008, sections 5.5-5.6) compute them: at each averaging factor,
//
//   1. the dominant power-law noise is identified: S_y(f) ~ f^alpha, alpha = 2 white PM,
//      1 flicker PM, 0 white FM, -1 flicker FM, -2 random-walk FM (-3, -4 for the Hadamard
//      kinds), by the lag-1 autocorrelation of the phase decimated by m (Riley and Greenhall
//      2004) when that leaves at least kMinAcfPoints points, else by Barnes' B1 ratio (the
//      standard over the Allan variance of the m-averaged frequencies) with the R(n) ratio
//      (MVAR / AVAR) telling white from flicker PM;
//   2. the equivalent degrees of freedom follow for that noise: Greenhall and Riley's
//      algorithm (2003 PTTI, "Uncertainty of stability variances based on finite
//      differences") for ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV; Howe's b (T / tau) - c for
//      TOTDEV (SP 1065 Table 7), its noises beyond white, flicker and random-walk FM read
//      with OADEV's (the total and the overlapping Allan variance agree for phase noise);
//      SP 1065 Table 8's for MTOTDEV and TTOTDEV; OHDEV's for HTOTDEV (no published rule:
//      a lower bound, so a conservative interval); none for Theo1, MTIE and TIE rms;
//   3. the interval at confidence p is the chi-square one: deviation * sqrt(edf / chi2_q),
//      q = (1 + p) / 2 for the low end, (1 - p) / 2 for the high (SP 1065 eq. 45): exact
//      quantiles, or Stable32's (the default: exact up to 100 degrees of freedom, Wilson and
//      Hilferty's approximation with the normal quantile of q rounded to two decimals beyond,
//      as its published intervals show: IntervalMethod).
//
// Checked against Stable32's published intervals for PHASE.DAT (tests/stability/
// confidence_test.cc); the tests name each kind's agreement.
//
//   const auto c = gmwm::stability::deviation(kind, x, tau0, m);
//   const auto ci = gmwm::stability::deviation_intervals(c, x, gmwm::stability::kStable32Confidence);

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gmwm/stability/deviation.h"

namespace gmwm::stability {

/// Stable32's default confidence, printed "0.683": the one-sigma interval's erf(1 / sqrt 2)
/// = 0.682689... (its intervals on PHASE.DAT at 9.6-94 degrees of freedom are the exact
/// chi-square ones at 0.6827 to their printed digits, and miss them at 0.683).
inline constexpr double kStable32Confidence = 0.68268949213708590;

/// The lag-1 autocorrelation needs about 30 analysis points to tell the noises apart (Riley
/// and Greenhall 2004, section 4); with fewer, B1 and R(n) decide.
inline constexpr std::int64_t kMinAcfPoints = 30;

/// How the noise at a factor was identified.
enum class NoiseIdMethod {
  kLag1Acf,  ///< "acf": the lag-1 autocorrelation of the decimated phase
  kB1,       ///< "b1": Barnes' B1 ratio
  kB1Rn,     ///< "b1+rn": B1, then R(n) = MVAR / AVAR between white and flicker PM
  kDefault,  ///< "default": too few points for either (under 4 averaged frequencies): white FM assumed
  kFixed,    ///< "fixed": given (IntervalOptions::noise_alpha), as Stable32's fixed-alpha runs
};
std::string_view noise_id_method_name(NoiseIdMethod method);

/// "white PM", "flicker PM", "white FM", "flicker FM", "random-walk FM", "flicker-walk FM",
/// "random-run FM" for alpha 2 .. -4; "unknown" otherwise.
std::string_view noise_name(int alpha);

struct NoiseIdentification {
  int alpha = 0;          ///< the dominant noise's integer exponent
  double estimate = NAN;  ///< the ACF's continuous estimate (NaN from B1)
  NoiseIdMethod method = NoiseIdMethod::kDefault;
};

/// The dominant noise of `phase` at factor m for a deviation of `kind` (its difference order
/// bounds alpha from below: -2 for the Allan family and the total deviation, -4 for the
/// Hadamard). m in 1 .. max_factor(kind, N).
NoiseIdentification identify_noise(DeviationKind kind, std::span<const double> phase, std::int64_t m);

/// Greenhall and Riley's equivalent degrees of freedom of a difference variance of order d
/// (2 Allan, 3 Hadamard) at factor m on N phase points, filter factor F (1 modified, m
/// unmodified) and stride S (1 non-overlapping, m overlapping), for noise alpha in
/// 2 - 2d .. 2 (an alpha below is read as 2 - 2d). Throws InputError for d outside 1 .. 3,
/// m < 1, F or S not 1 or m, or fewer than d m + 1 phase points.
double greenhall_edf(int alpha, int d, std::int64_t m, std::int64_t phase_points, std::int64_t filter,
                     std::int64_t stride);

/// The equivalent degrees of freedom of `kind` at factor m on N phase points for noise
/// alpha; nullopt for a kind without a published rule.
std::optional<double> equivalent_dof(DeviationKind kind, int alpha, std::int64_t phase_points, std::int64_t m);

/// How the chi-square quantiles are taken.
enum class IntervalMethod {
  /// "stable32": as Stable32 prints them: exact up to kStable32ExactDof degrees of freedom;
  /// beyond, Wilson and Hilferty's chi2_q ~ edf (1 - 2 / (9 edf) + z sqrt(2 / (9 edf)))^3
  /// with z the normal quantile of q rounded to two decimals (0.8415 -> 0.84 at 0.683). Its
  /// intervals on PHASE.DAT show both: at edf 131-1501 they are the exact ones at confidence
  /// 0.680 (z = 0.9945 = the normal quantile of 0.84), at edf 9.6-94 at 0.683. The two
  /// methods' ends differ by less than 0.3% of the deviation.
  kStable32,
  kExact,  ///< "exact": Boost.Math's chi-square quantiles
};
std::string_view interval_method_name(IntervalMethod method);
std::optional<IntervalMethod> interval_method_from_name(std::string_view name);

/// Stable32's largest degrees of freedom with exact chi-square quantiles (see kStable32).
inline constexpr double kStable32ExactDof = 100.0;

struct ChiSquareInterval {
  double low = NAN, high = NAN;
};
/// The chi-square interval of a deviation with `edf` degrees of freedom at `confidence`
/// (0 < confidence < 1; SP 1065 eq. 45). Throws InputError for a confidence outside (0, 1)
/// or an edf that is not positive.
ChiSquareInterval chi_square_interval(double deviation, double edf, double confidence,
                                      IntervalMethod method = IntervalMethod::kStable32);

struct IntervalOptions {
  double confidence = kStable32Confidence;  ///< in (0, 1)
  IntervalMethod method = IntervalMethod::kStable32;
  /// The noise exponent of every factor (-4 .. 2), instead of identifying it per factor.
  std::optional<int> noise_alpha;
  /// Empty when valid, else one line naming the field ("confidence: ...", "noise_alpha: ...").
  std::string Validate() const;
};

/// Each factor's noise, degrees of freedom and interval (NaN where the kind has no rule).
struct DeviationIntervals {
  IntervalOptions options;
  std::vector<NoiseIdentification> noise;
  std::vector<double> edf, low, high;
};

/// The intervals of `curve`, computed from the phase it was computed from, in parallel over
/// its factors (the same whatever the thread count). Throws InputError for invalid options
/// or a factor the phase's length does not allow.
DeviationIntervals deviation_intervals(const DeviationCurve& curve, std::span<const double> phase,
                                       const IntervalOptions& options = {});

}  // namespace gmwm::stability
