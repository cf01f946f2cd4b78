#pragma once
// The studies' first stage: every column's classical wavelet variance and, when asked, its
// overlapping Allan deviation from the same Haar transforms (one set of prefix sums per
// column instead of two; the deviation's octave points are the WV's own level sums), each
// stage timed. What `fit`, `select` and `wv --adev` share.
#include <memory>
#include <optional>
#include <string>
#include <span>
#include <vector>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::pipeline::detail {

struct ColumnWvs {
  std::vector<WaveletVariance> wvs;
  /// With the robust WVs: the classical ones beside them, for the report's comparison (the
  /// fits use `wvs`); else empty.
  std::vector<WaveletVariance> classical;
  /// Per column when asked, else empty.
  std::vector<AllanDeviation> allan;
  double wv_seconds = 0.0, allan_seconds = 0.0;
  /// The columns' Haar transforms the classical WVs came from (classical_column_wvs), for the
  /// robust WV and its diagnostic to reuse instead of transforming each column again;
  /// empty after column_wvs_for_fit (the fits do not read them).
  std::vector<std::unique_ptr<HaarModwt>> transforms;
};

/// The classical WVs of `series` and, when `allan` is given, their Allan deviations at
/// `freq` Hz.
ColumnWvs classical_column_wvs(const std::vector<std::span<const double>>& series, const WvOptions& wv, double freq,
                               const std::optional<AllanOptions>& allan);

/// "PATH: N samples missing in K gaps of the timestamps 'COL'; WHAT reads a regular record: give
/// --gaps join to join the samples end to end" (InputError; for an array's NaN rows, "drop the
/// NaN rows ...") when `set` holds missing samples
/// (set.missing); nothing otherwise. Every study and estimator that has no complete-window
/// form yet says so instead of joining the samples silently.
void require_regular(const io::SignalSet& set, const std::string& what);

/// A record with gaps is simulated over its whole grid (observed and missing samples
/// together) wherever a study draws series like it: the gap diagnosis's reference, a
/// bootstrap Omega or optimism. Each replicate holds its grid in memory (8 bytes a sample,
/// and a Haar transform of 16 more, a replicate per core), so the grid is bounded at this many
/// times the observed samples, the memory a regular record of those samples takes already:
/// without a bound a crafted file of a few rows and one far stamp asked for gigabytes per
/// replicate (a review of session 22: 10 000 rows at 1 kHz, then one stamp a day later).
inline constexpr double kMaxSimulatedGridFactor = 4.0;

/// "PATH: WHAT simulates the record's whole grid of N samples, R times its M observed ones (at
/// most 4): cut the record at its longest gap (G samples at S), or give --gaps join to join
/// the samples end to end" (InputError) when `set` has gaps and its grid is beyond that bound;
/// nothing otherwise.
void check_simulated_grid(const io::SignalSet& set, const std::string& what);

/// The WV estimator a fit's bootstrap draws recompute on simulated series: the data's own,
/// robust or classical, read through the record's gaps when it has some; null for the
/// classical WV of a regular record (the fits' default).
std::unique_ptr<WvEstimator> draw_estimator(const io::SignalSet& set,
                                            const std::optional<robust::RobustWvOptions>& robust);
/// The same for a series read through `missing` (a replicate's own gaps).
std::unique_ptr<WvEstimator> draw_estimator(const std::vector<MissingRun>& missing,
                                            const std::optional<robust::RobustWvOptions>& robust);

/// The WV of one series with gaps (its observed samples, its missing runs on the grid):
/// classical_wv_with_gaps, or robust_wv_with_gaps when `robust` is given, with the spike
/// screen off when `repeated` says the samples are held (robust_wvs_of's rule and note); cut
/// to its consecutive levels with a usable window (drop_incomplete_levels).
WaveletVariance gappy_wv_of(std::span<const double> observed, const std::vector<MissingRun>& missing,
                            const RepeatedSamples* repeated, const WvOptions& wv,
                            const robust::RobustWvOptions* robust);

/// The classical WVs and, when `allan` is given, the gap-resistant Allan deviations of the
/// columns of a record with gaps, from the complete windows or, where those are scarce, the
/// near-complete ones (classical_wv_with_gaps, allan_deviation_with_gaps), each WV cut to
/// its consecutive levels with a usable window.
ColumnWvs gappy_column_wvs(const io::SignalSet& set, const WvOptions& wv, const std::optional<AllanOptions>& allan);

/// The robust WVs of the set's columns (robust::robust_wv, reusing `transforms` when given;
/// robust::robust_wv_with_gaps on a record with gaps, cut to its usable levels as the
/// classical one),
/// with the spike screen off for a column whose samples are held: its copies' steps of
/// exactly zero (half of them for a 2x copy) deflate the level-1 robust scale the screen
/// measures spikes against, and the screen would replace most of the record (71% of a
/// RealSense-like accelerometer's). Its screening note says so.
std::vector<WaveletVariance> robust_column_wvs(const io::SignalSet& set, const robust::RobustWvOptions& options,
                                               const std::vector<std::unique_ptr<HaarModwt>>& transforms = {});

/// The same rule for series that are not a set's columns (replicates): `repeated[k]` is
/// series k's reading of held samples, or null when none is known.
std::vector<WaveletVariance> robust_wvs_of(const std::vector<std::span<const double>>& series,
                                           const std::vector<const RepeatedSamples*>& repeated,
                                           const robust::RobustWvOptions& options,
                                           const std::vector<std::unique_ptr<HaarModwt>>& transforms = {});

/// The fit and selection studies' stage: the robust WVs when `robust` is given (the noise
/// figures then read the robust WV itself), else the classical ones with the Allan
/// deviations at intervals of level 1 - alpha when the rate is known; on a record with gaps
/// each from the windows without one (gappy_column_wvs, robust_column_wvs).
ColumnWvs column_wvs_for_fit(const io::SignalSet& set, const WvOptions& wv,
                             const std::optional<robust::RobustWvOptions>& robust, double alpha);

}  // namespace gmwm::pipeline::detail
