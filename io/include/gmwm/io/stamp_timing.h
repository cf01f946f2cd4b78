#pragma once
// Timestamps that come without a file: a pandas DatetimeIndex or TimedeltaIndex handed to
// Python, as integer nanoseconds. Measured and refused by the readers' own rules, so that an
// index gives the rate a file's timestamp column with the same times would give, or the
// same refusal (issue 45: input reading shared by every face).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io {

/// The sampling of `stamps_ns` (integer nanoseconds, any origin): median step, rate, gaps,
/// disorder and a change of rate, as TimingReport gives a file's timestamp column named
/// `column`. Throws InputError starting "SOURCE: timestamps 'COLUMN'" for what the readers
/// refuse: a rate outside sampling_rate_problem's range, a rate that changes within the
/// record, or times that never increase. `freq` (the rate given with the data) takes the
/// samples as evenly spaced, as --freq does for a file: nothing is then refused but times
/// that never increase are still reported.
TimingReport timing_of_stamps(std::span<const std::int64_t> stamps_ns, const std::string& source,
                              const std::string& column, std::optional<double> freq);

/// The samples `timing`'s stamps show missing, taken as reading a file takes them with
/// `gaps` (read_signals: the gaps' runs on the grid; none under GapHandling::kJoin, across a
/// change of rate or with stamps too jittery to place a lost sample). Throws InputError
/// "SOURCE: timestamps 'COLUMN': ..." for gaps that cannot be placed, with read_signals' words.
/// What a pandas index with gaps becomes: NaN rows at these runs (issue 47).
std::vector<MissingRun> missing_runs_of(const TimingReport& timing, const std::string& source, GapHandling gaps);

}  // namespace gmwm::io
