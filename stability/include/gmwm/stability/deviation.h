#pragma once
// The frequency-stability family (issue 48): the deviations metrologists and inertial
// engineers read, as NIST SP 1065 (Riley 2008, "Handbook of Frequency Stability Analysis")
// defines them, computed from phase (time-error) data x_0 .. x_{N-1} spaced tau0 apart; a
// rate or fractional-frequency series y becomes phase by x_{i+1} = x_i + y_i tau0
// (phase_from_frequency). At averaging factor m (tau = m tau0):
//
//   AVAR   = sum_i (X_{i+2} - 2 X_{i+1} + X_i)^2 / (2 tau^2 (n - 2)),  X_i = x_{im}, n = floor((N-1)/m) + 1
//   OAVAR  = sum_{i=0}^{N-2m-1} (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 tau^2 (N - 2m))
//   MVAR   = sum_{j=0}^{N-3m} (sum_{i=j}^{j+m-1} x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 m^2 tau^2 (N - 3m + 1))
//   TVAR   = tau^2 MVAR / 3
//   HVAR   = sum_i (X_{i+3} - 3 X_{i+2} + 3 X_{i+1} - X_i)^2 / (6 tau^2 (n - 3))
//   OHVAR  = sum_{i=0}^{N-3m-1} (x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i)^2 / (6 tau^2 (N - 3m))
//   TOTVAR = sum_{i=1}^{N-2} (x*_{i-m} - 2 x*_i + x*_{i+m})^2 / (2 tau^2 (N - 2)), x* the phase
//            reflected at both ends: x*_{-j} = 2 x_0 - x_j, x*_{N-1+j} = 2 x_{N-1} - x_{N-1-j}
//   MTOTVAR = sum_{n=0}^{N-3m} (1/6m) sum_{j=0}^{6m-1} z_{n,j}^2 / (2 tau^2 (N - 3m + 1)), the z_{n,j}
//            the second differences of m-point averages of the 3m points x_n .. x_{n+3m-1}, less
//            their half-average slope, reflected evenly at both ends to 9m points (SP 1065 eq. 27)
//   TTOTVAR = tau^2 MTOTVAR / 3
//   HTOTVAR = the same sum over the M = N - 1 frequencies y_i = (x_{i+1} - x_i) / tau0 and their
//            windows of 3m, / (6 (M - 3m + 1)) (SP 1065 eq. 29); OHVAR at m = 1, as Stable32
//   THEO1  = sum_{i=0}^{N-m-1} sum_{k=1}^{m/2} (x_i - x_{i+k} - x_{i+m-k} + x_{i+m})^2 / k
//            / (0.75 (N - m) (m tau0)^2), m even, 10 <= m <= N - 1, at tau = 0.75 m tau0 (eq. 30)
//   MTIE   = max_{i=0}^{N-m-1} (max - min of x_i .. x_{i+m}): windows of m + 1 points spanning tau
//   TIE rms = sqrt(sum_{i=0}^{N-m-1} (x_{i+m} - x_i)^2 / (N - m))
//
// each in O(N) per tau (MVAR's inner sums from prefix sums; the total variances' windows from
// prefix sums of the phase's running sums, stability/src/total_deviation.cc; MTIE's windows by
// running extremes) but Theo1, O(N log^2 m) (its 1/k weights need correlations:
// stability/src/theo1.cc); the taus in parallel; `terms` is the number of squares averaged
// (Stable32's "#" column). Checked against the NBS14 9-point set and Stable32's values for its
// 1000-point set (tests/stability/deviation_test.cc, total_deviation_test.cc). The deviations
// are the plain estimators: Stable32's bias corrections of MTOT, HTOT and Theo1 for an
// identified noise are not applied (docs/stability.md).
//
//   const auto x = gmwm::stability::phase_from_frequency(y, 0.01);
//   const auto f = gmwm::stability::factors(gmwm::stability::TauSet::kOctave, kind, x.size());
//   const gmwm::stability::DeviationCurve c = gmwm::stability::deviation(kind, x, 0.01, f);

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gmwm/engine/samples.h"

namespace gmwm::stability {

enum class DeviationKind {
  kAdev,     ///< "adev": the Allan deviation (non-overlapping)
  kOadev,    ///< "oadev": the overlapping Allan deviation
  kMdev,     ///< "mdev": the modified Allan deviation
  kTdev,     ///< "tdev": the time deviation, tau MDEV / sqrt(3), in the phase's unit
  kHdev,     ///< "hdev": the Hadamard deviation (non-overlapping)
  kOhdev,    ///< "ohdev": the overlapping Hadamard deviation
  kTotdev,   ///< "totdev": the total deviation (the phase reflected at both ends)
  kMtotdev,  ///< "mtotdev": the modified total deviation
  kTtotdev,  ///< "ttotdev": the time total deviation, tau MTOTDEV / sqrt(3), in the phase's unit
  kHtotdev,  ///< "htotdev": the Hadamard total deviation (OHDEV at m = 1, as Stable32)
  kTheo1,    ///< "theo1": Theo1, at the even factors m >= 10 and tau = 0.75 m tau0
  kMtie,     ///< "mtie": the maximum time interval error, in the phase's unit
  kTierms,   ///< "tierms": the rms time interval error, in the phase's unit
};

/// Every kind, in the order above.
std::span<const DeviationKind> deviation_kinds();
/// "adev", "oadev", ...: the one spelling of every face.
std::string_view deviation_name(DeviationKind kind);
/// The kind named `name`; nullopt for any other text.
std::optional<DeviationKind> deviation_from_name(std::string_view name);
/// The kind named `text`; throws InputError "--kind: found 'TEXT', expected adev, oadev, ...
/// or tierms" for any other.
DeviationKind deviation_of(const std::string& text);

/// The phase of a rate or fractional-frequency series less `offset` (its mean, say: the
/// phase of a rate with an offset grows linearly, which no deviation sees but the doubles'
/// digits do): x_0 = 0, x_{i+1} = x_i + (y_i - offset) tau0 (N + 1 points, summed in long
/// double, from each 2^16-sample chunk's start: the chunks run in parallel, the values the same
/// whatever the thread count). Throws InputError for a tau0 that is not positive and finite,
/// an offset or a sample that is not finite (naming it).
std::vector<double> phase_from_frequency(std::span<const double> y, double tau0, double offset = 0.0);
/// The phase of a record's rate less its mean (what `gmwm stability` reads: no deviation sees
/// the line a rate's offset draws in its phase, but the doubles' digits do). A record in a
/// temporary file (beyond the memory budget, samples.h) gets its phase in one too, written as
/// it is summed, and the deviations read it in pieces, releasing the pages behind them
/// (docs/stability.md, "Records beyond the memory budget"); in memory otherwise. Both sum in
/// the same chunks (in parallel in memory): the same values.
Samples phase_from_record(const Samples& y, double tau0);

/// The fewest phase points a kind needs for one term at its smallest factor: 3 for the Allan
/// family, MDEV, TDEV and the total, modified total and time total deviations, 4 for the
/// Hadamard family (HTOTDEV too), 11 for Theo1 (m = 10), 2 for MTIE and TIE rms (NBS14's
/// 9-point frequency set, 10 phase points, reaches m = 3 of every kind but Theo1).
std::int64_t min_phase_points(DeviationKind kind);

/// The largest averaging factor with at least one term on N phase points (0 when none):
/// (N - 1) / 2 for ADEV, OADEV and TOTDEV, (N - 1) / 3 for HDEV, OHDEV and HTOTDEV, N / 3 for
/// MDEV, TDEV, MTOTDEV and TTOTDEV, the largest even factor below N for Theo1, N - 1 for MTIE
/// and TIE rms (integer division).
std::int64_t max_factor(DeviationKind kind, std::int64_t phase_points);

/// The number of squares averaged at factor m (Stable32's "#"): floor((N-1)/m) - 1 (ADEV),
/// N - 2m (OADEV), N - 3m + 1 (MDEV, TDEV, MTOTDEV, TTOTDEV), floor((N-1)/m) - 2 (HDEV),
/// N - 3m (OHDEV, HTOTDEV: the M - 3m + 1 windows of the M = N - 1 frequencies), N - 2
/// (TOTDEV), (N - m) m / 2 (Theo1), N - m (the windows of MTIE, the differences of TIE rms).
std::int64_t terms(DeviationKind kind, std::int64_t phase_points, std::int64_t m);

/// The work of factor m on N phase points, in OADEV's points read (a proxy for time: 0.14
/// to 0.39 ns a point on two cores, within the caches and beyond: tools/bench/RESULTS.md):
/// N / m for ADEV and HDEV (one point in m), N for the other kinds read in O(N) per factor,
/// N m for Theo1 up to m = 256 (its terms summed directly) and 7 N log2(m)^2 beyond (through
/// correlations). What bounds a study of every factor (pipeline::kMaxAllTausWork).
double factor_work(DeviationKind kind, std::int64_t phase_points, std::int64_t m);

/// Whether the kind is in the phase's unit (time, for phase in seconds: TDEV, TTOTDEV, MTIE,
/// TIE rms) rather than the fractional frequency's (the others).
bool in_time_units(DeviationKind kind);

/// The averaging time of factor m: m tau0, Theo1's 0.75 m tau0.
double averaging_time(DeviationKind kind, std::int64_t m, double tau0);

/// Which averaging factors: every one (1, 2, ..., max), the octaves (1, 2, 4, ...), the
/// decades' 1-2-4 steps (1, 2, 4, 10, 20, 40, 100, ...: Stable32's and allantools' decade).
enum class TauSet { kAll, kOctave, kDecade };
std::string_view tau_set_name(TauSet set);  ///< "all", "octave", "decade"
std::optional<TauSet> tau_set_from_name(std::string_view name);

/// The factors of `set` up to max_factor(kind, phase_points), increasing. Theo1's are even and
/// start at 10: all 10, 12, 14, ...; octave 10, 20, 40, ...; decade 10, 20, 40, 100, ....
/// MTIE's octave is Stable32's windows of 2^k points: 1, 3, 7, 15, ....
std::vector<std::int64_t> factors(TauSet set, DeviationKind kind, std::int64_t phase_points);

struct DeviationCurve {
  DeviationKind kind = DeviationKind::kOadev;
  double tau0 = 1.0;                ///< the phase's spacing (s)
  std::vector<std::int64_t> m;      ///< averaging factors
  std::vector<double> tau;          ///< averaging_time(kind, m, tau0) (s)
  std::vector<double> value;        ///< the deviation (in_time_units: the phase's unit; else dimensionless)
  std::vector<std::int64_t> terms;  ///< squares averaged at each factor
};

/// Called as each averaging factor is done, with (factors done, factors in all), one call at a
/// time; it may throw (gmwm::Cancelled) to stop the work, which then ends with that exception.
using FactorProgress = std::function<void(std::size_t done, std::size_t total)>;

/// The deviation of `phase` (tau0 apart) at each factor of `m` (each in 1 .. max_factor;
/// Theo1's even, in 10 .. max_factor), computed in parallel over the factors (the same values
/// whatever the thread count), `progress` told after each. Throws InputError naming the problem: tau0 not positive and
/// finite, a phase point that is not finite (its index), fewer phase points than
/// min_phase_points, a factor outside 1 .. max_factor or, for Theo1, not among the even
/// factors 10 .. max_factor (the factor and the bounds).
DeviationCurve deviation(DeviationKind kind, std::span<const double> phase, double tau0,
                         std::span<const std::int64_t> m, const FactorProgress& progress = {});

}  // namespace gmwm::stability
