#pragma once
// The frequency-stability study of a signal set (issue 48): each column's deviations of the
// kinds asked (stability/deviation.h) at the averaging times asked, from the column read as
// a rate (or fractional frequency) and turned into phase, or read as phase (--data phase);
// with three_cornered_hat, the hat of three columns recorded together (each column's own
// deviation separated from what the three share: stability/three_cornered_hat.h).
// What `gmwm stability` and Python's gmwm.stability run; report::stability_document writes it.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/stability/confidence.h"
#include "gmwm/stability/deviation.h"
#include "gmwm/stability/three_cornered_hat.h"

namespace gmwm::pipeline {

struct StabilityStudyOptions {
  /// The kinds, in the order asked (each once).
  std::vector<stability::DeviationKind> kinds = {stability::DeviationKind::kOadev};
  /// The averaging factors of each kind: every one, the octaves or the decades' 1-2-4 steps
  /// up to the kind's largest (stability::factors) ...
  stability::TauSet taus = stability::TauSet::kOctave;
  /// ... or these averaging times in seconds (--taus 1,10,100), each a whole number of
  /// sampling periods (to kWholePeriodTolerance) and within every kind's largest factor.
  std::vector<double> tau_list;
  /// Each deviation's interval: confidence, quantiles, a fixed noise (stability/confidence.h).
  stability::IntervalOptions intervals;
  /// The three-cornered hat of the record's three columns (--hat): their pairwise differences'
  /// deviations of every kind asked (each kind separable: not MTIE) and each column's own.
  bool three_cornered_hat = false;
  /// Told (steps done, steps in all) after each averaging factor's deviation and each kind's
  /// intervals, one call at a time; it may throw (gmwm::Cancelled) to stop the study, which
  /// then ends with that exception (the web app's and Python's cancellation).
  std::function<void(int, int)> progress;

  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// A tau of --taus is a whole number m of sampling periods when |tau / tau0 - m| <= this
/// times m: stamps and decimal taus (0.1 s at 100 Hz is 10.000000000000002 periods) agree to
/// the last digits of a double, never to a whole period.
inline constexpr double kWholePeriodTolerance = 1e-9;

/// --taus all reads every factor up to about N / 2: O(N log N) points in all for ADEV and
/// HDEV (N / m a factor), O(N^2) for the others (N a factor: 5e11 points for OADEV's 5e5
/// factors of 1e6 samples). The points read over the kinds asked (stability::factor_work) are
/// bounded by this, 2^39: about 3.5 minutes on two cores for a phase beyond the caches (every
/// OADEV factor of 1e6 samples, 5e11 points, in 193 s; 0.14 ns a point within them, 2^17
/// samples' 8.6e9 in 1.24 s: tools/bench/RESULTS.md, "Every factor"); beyond, the study is
/// refused, naming octave, decade, a list of times or fewer kinds instead.
inline constexpr double kMaxAllTausWork = 549755813888.0;  // 2^39

struct StabilityColumn {
  std::string name;
  std::vector<stability::DeviationCurve> deviations;     ///< per kind, in the order asked
  std::vector<stability::DeviationIntervals> intervals;  ///< per kind: noise, edf, interval at each factor
};

/// The three-cornered hat of three columns A, B, C recorded together: the pairs' deviations
/// and intervals (A - B, B - C, C - A: each difference of the rates read as a column is, its
/// mean removed) and per kind each column's separated deviation with its interval.
struct StabilityHat {
  std::array<std::string, stability::kHatSensors> sensors;  ///< the columns' names, A, B, C
  std::vector<StabilityColumn> pairs;                       ///< named "A - B", "B - C", "C - A"
  std::vector<stability::ThreeCorneredHat> kinds;           ///< per kind, in the order asked
};

struct StabilityStudy {
  double tau0 = 0.0;              ///< the sampling period (s)
  std::int64_t phase_points = 0;  ///< the phase points each deviation read (the samples + 1 for a rate)
  std::vector<StabilityColumn> columns;
  std::optional<StabilityHat> hat;  ///< with three_cornered_hat
  double seconds = 0.0;             ///< wall time of the phases and the deviations
  double interval_seconds = 0.0;    ///< wall time of the noise identifications and intervals
};

/// The hat's rule on the record: three columns recorded together (stability::kHatSensors).
/// Throws InputError naming --hat, --columns A,B,C and the columns found otherwise: what
/// study_stability refuses with three_cornered_hat, for a face that checks a request before
/// running it (the web app's 400).
void require_hat_columns(const io::SignalSet& set);

/// Throws InputError (one line naming the file or the option) for invalid options, a record
/// without a known rate, a record with missing samples (the deviations read a regular record:
/// --gaps join), a tau that is no whole number of periods or beyond a kind's largest factor,
/// and with three_cornered_hat a record of other than three columns.
StabilityStudy study_stability(const io::SignalSet& set, const StabilityStudyOptions& options);

}  // namespace gmwm::pipeline
