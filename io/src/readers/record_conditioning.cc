// What reading does to a record's values after the readers (issue 47): the gaps its stamps
// show taken as --gaps says, then increments and decimation (timestamp.h), and what the
// values that come out say of themselves: held and interpolated samples.
#include <cstdio>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/repeated_samples.h"
#include "gmwm/engine/samples.h"
#include "gmwm/io/stamp_timing.h"
#include "timestamp.h"

namespace gmwm::io::detail {

void take_gaps(const std::string& path, SignalSet& set, const ReadOptions& options) {
  set.gaps = options.gaps;
  if (!set.timing || set.timing->gaps == 0 || options.gaps == GapHandling::kJoin) return;
  const TimingReport& t = *set.timing;
  if (t.rate_change) return;  // read only under --freq, which takes the samples as evenly spaced
  // Stamps this jittery cannot tell a lost sample from a late stamp: read as before.
  if (t.jitter > TimingReport::kMaxJitterToPlaceGaps) return;
  const std::string where = path + ": timestamps '" + t.column + "': ";
  const std::string join = "; give --gaps join to join the samples end to end";
  if (!t.gap_positions_known)
    throw InputError(where + std::to_string(t.gaps) + " steps longer than " + significant(TimingReport::kGapFactor) +
                     " median steps among more than " + std::to_string(StepStatistics::kMaxGapCandidates) +
                     " irregular ones, expected gaps that can be placed (stamps this irregular cannot tell a lost "
                     "sample from jitter)" +
                     join);
  if (t.first_uncertain_gap) {
    const TimingReport::UncertainGap& g = *t.first_uncertain_gap;
    const std::string more =
        t.uncertain_gaps > 1 ? " (and " + std::to_string(t.uncertain_gaps - 1) + " more such gaps)" : "";
    // The stamps to 9 digits (a nanosecond within a second, a microsecond within 1000 s).
    const auto stamp = [](double seconds) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.9g s", seconds);
      return std::string(buf);
    };
    throw InputError(where + "a gap of unknown length before sample " + std::to_string(g.sample) + ": from " +
                     stamp(g.from_seconds) + " to " + stamp(g.to_seconds) + " after the first stamp, a step of " +
                     format_duration(g.step_seconds) + " = " + significant(g.step_seconds / t.median_step_seconds) +
                     " periods of " + format_duration(t.median_step_seconds) + more +
                     ", expected a whole number of periods (to " + significant(TimingReport::kGapLengthTolerance) +
                     ")" + join);
  }
  set.missing = t.missing;
}

void condition_values(const std::string& path, SignalSet& set, const ReadOptions& options) {
  set.data = options.data;
  set.decimation = options.decimate;
  set.decimation_filter = options.decimate_filter;
  set.freq_before_decimation = set.freq;
  if (options.data == DataKind::kIncrement) {
    if (!set.freq_known)
      throw InputError(path +
                       ": --data increment: found no rate to divide the increments by, expected a timestamp "
                       "column or --freq HZ");
    for (Signal& s : set.signals) {
      std::vector<double> v(s.values.size());
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = s.values[i] * set.freq;
      s.values = Samples(std::move(v));
      s.unit.clear();  // the header's unit is the increment's; --units states the rate's
    }
  }
  if (options.data == DataKind::kPhase) take_phase_as_rate(set, path);
  const int k = options.decimate;
  if (k <= 1) return;
  if (!set.missing.empty())
    throw InputError(path + ": --decimate " + std::to_string(k) + ": found " + std::to_string(set.missing_samples()) +
                     " samples missing in " + std::to_string(set.missing.size()) +
                     " gaps, expected a regular record (a block across a gap has no mean of K samples); give "
                     "--gaps join to join the samples end to end");
  const std::size_t n = set.signals.empty() ? 0 : set.signals.front().values.size();
  const std::size_t blocks = n / static_cast<std::size_t>(k);
  if (static_cast<std::int64_t>(blocks) < kMinSamples)
    throw InputError(path + ": --decimate " + std::to_string(k) + ": found " + std::to_string(n) + " samples, " +
                     std::to_string(blocks) + " after decimation, expected at least " + std::to_string(kMinSamples));
  for (Signal& s : set.signals) {
    std::vector<double> v(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t first = b * static_cast<std::size_t>(k);
      if (options.decimate_filter == DecimationFilter::kNone) {
        v[b] = s.values[first];
        continue;
      }
      double sum = 0.0;
      for (std::size_t i = first; i < first + static_cast<std::size_t>(k); ++i) sum += s.values[i];
      v[b] = sum / k;
    }
    s.values = Samples(std::move(v));
  }
  set.freq /= k;
  set.spilled = false;  // n / K values, in memory
}

void finish_record(const std::string& path, SignalSet& set, const ReadOptions& options) {
  take_gaps(path, set, options);
  condition_values(path, set, options);
  find_repeated_samples(set);
}

}  // namespace gmwm::io::detail

namespace gmwm::io {

void take_phase_as_rate(SignalSet& set, const std::string& source) {
  const std::string what = source + ": --data phase: ";
  if (!set.freq_known)
    throw InputError(what + "found no rate to divide the phase steps by, expected a timestamp column or --freq HZ");
  // A step across a gap spans several periods, missing or joined end to end (--gaps join
  // leaves no missing run but the same step): either way not one period's frequency.
  const std::int64_t gaps = !set.missing.empty()                 ? static_cast<std::int64_t>(set.missing.size())
                            : set.timing && set.timing->gaps > 0 ? set.timing->gaps
                                                                 : 0;
  if (gaps > 0)
    throw InputError(what + "found " + std::to_string(gaps) +
                     " gaps, expected a regular record (a phase step across a gap spans several periods, joined or "
                     "not); cut the record at its gaps");
  const std::size_t n = set.signals.empty() ? 0 : set.signals.front().values.size();
  if (n < static_cast<std::size_t>(kMinSamples) + 1)
    throw InputError(what + "found " + std::to_string(n) + " phase samples, " + std::to_string(n > 0 ? n - 1 : 0) +
                     " steps, expected at least " + std::to_string(kMinSamples) + " steps");
  for (Signal& s : set.signals) {
    std::vector<double> v(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) v[i] = (s.values[i + 1] - s.values[i]) * set.freq;
    s.values = Samples(std::move(v));
    s.unit.clear();  // the header's unit is the phase's; --units states the rate's
  }
  set.data = DataKind::kPhase;
  set.spilled = false;  // n - 1 values, in memory
}

void find_repeated_samples(SignalSet& set) {
  gmwm::parallel_for(std::size_t{0}, set.signals.size(), [&](std::size_t k) {
    Signal& s = set.signals[k];
    const auto n = static_cast<std::int64_t>(s.values.size());
    s.repeated = detect_repeated_samples(s.values.data(), n);
  });
}

std::vector<MissingRun> missing_runs_of(const TimingReport& timing, const std::string& source, GapHandling gaps) {
  SignalSet set;
  set.timing = timing;
  ReadOptions options;
  options.gaps = gaps;
  detail::take_gaps(source, set, options);
  return set.missing;
}

std::vector<std::string> reading_notes(const SignalSet& set) {
  std::vector<std::string> out = set.notes;
  for (std::string& note : repeated_samples_notes(set)) out.push_back(std::move(note));
  return out;
}

std::vector<std::string> repeated_samples_notes(const SignalSet& set) {
  std::vector<std::string> out;
  for (const Signal& s : set.signals)
    if (s.repeated.detected())
      out.push_back(repeated_samples_text(s.repeated, s.name, set.freq_known ? set.freq : 0.0));
  return out;
}

}  // namespace gmwm::io
