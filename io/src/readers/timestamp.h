#pragma once
// Timestamp columns: recognising them by name (with the unit when the name states it),
// deciding the unit otherwise, and measuring the sampling (rate, gaps, disorder).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <string_view>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {

struct TimeUnit {
  double to_seconds = 0.0;  ///< 0 when the name gives no unit
  std::string label;        ///< "s", "ms", "us", "ns", "min", "h"
};

/// A time unit written as text ("ns", "sec", "us", "µs", "seconds", ...); nullopt if none.
std::optional<TimeUnit> parse_time_unit(std::string_view text);

/// nullopt when `name` does not name a timestamp column (timestamp, time, t, stamp,
/// time_stamp, '#timestamp [ns]', 'time (s)', time_s, timestamp_ns, %time, ..., and a sensor's
/// own labelled ones: gyro_timestamp, timestamp_accel, accel_time [ns]; case-insensitive);
/// otherwise the unit the name states (to_seconds 0 when none).
std::optional<TimeUnit> timestamp_name(std::string_view name);

/// The bracketed or parenthesised unit of a header name ('w_RS_S_x [rad s^-1]' ->
/// "rad s^-1") and the name without it; unit "" when there is none.
std::pair<std::string, std::string> split_unit(std::string_view name);

/// A sustained change of the sampling rate inside a record (rate_change()).
struct RateChange {
  double from_step = 0.0, to_step = 0.0;        ///< typical steps before and after, in the file's unit
  std::int64_t from_sample = 0, to_sample = 0;  ///< 0-based samples where each was seen
};

/// The steps between consecutive times, gathered while the times are read, so that the
/// times themselves need not be kept (8 bytes a sample that a long record cannot spare):
/// the exact median step, the gaps, the disorder and a change of rate. A uniformly sampled
/// log has a handful of distinct steps, counted in a table; times with more distinct steps
/// than kMaxDistinctSteps (jittery stamps) spill to a list of the increasing steps, kept in
/// memory or, beyond the memory budget (spill_to_file), in a temporary file.
class StepStatistics {
 public:
  /// Distinct steps counted before spilling to a list: a 2^16-entry table is about 3 MB.
  static constexpr std::size_t kMaxDistinctSteps = std::size_t{1} << 16;
  /// The rate-change check compares the typical step of consecutive blocks of this many
  /// increasing steps: the mean of each block's middle half (its interquartile mean),
  /// which ignores gaps (the longest quarter) and, unlike a median, does not flip between
  /// two values when stamps are rounded (2, 3, 2, 3 ms at 400 Hz). With a jitter of half a
  /// step (uniform), a block's interquartile mean varies by about 1%.
  static constexpr std::size_t kRateBlock = 1024;
  /// The last, partial block counts when it has at least this many steps.
  static constexpr std::size_t kRateBlockMin = 256;
  /// Typical steps of two blocks more than this factor apart are a change of rate: 20 times
  /// the blocks' jitter above, and below the factors of real rate switches (1.25 for 400 ->
  /// 500 Hz, 2 for 100 -> 200 Hz).
  static constexpr double kRateChangeRatio = 1.2;

  StepStatistics();
  ~StepStatistics();
  StepStatistics(StepStatistics&&) noexcept;
  StepStatistics& operator=(StepStatistics&&) noexcept;

  /// The next time, relative to the first one (the first call passes 0). `magnitude`: the
  /// largest |time| the offset was computed from when those times were held as doubles,
  /// whose spacing there bounds what the steps can show; 0 when the offset is exact
  /// (integer times subtracted as integers).
  void add(double offset, double magnitude = 0.0);
  std::int64_t samples() const { return samples_; }
  /// The largest `magnitude` added (0: every step exact).
  double largest_magnitude() const { return magnitude_; }
  /// Steps that are not increasing (zero or negative).
  std::int64_t disorder() const { return disorder_; }
  /// Steps of zero (a stamp that repeats the one before), and the 0-based samples of the
  /// first and last such stamp (-1 when none).
  std::int64_t duplicated() const { return duplicated_; }
  std::int64_t first_duplicated() const { return first_duplicated_; }
  std::int64_t last_duplicated() const { return last_duplicated_; }
  /// The 0-based sample of the first stamp earlier than the one before (-1 when none).
  std::int64_t first_backward() const { return first_backward_; }
  /// Median of the increasing steps (the mean of the two middle ones for an even count);
  /// 0 when there is none. Equal, bit for bit, to the median of the list of steps, wherever
  /// the list is kept.
  double median() const;
  /// The increasing steps above `limit`: how many, and the largest (0 when none).
  std::pair<std::int64_t, double> above(double limit) const;
  /// A step where samples may be missing: the 0-based sample that ends it, and the step.
  struct LongStep {
    std::int64_t sample = 0;
    double step = 0.0;
    double offset = 0.0;  ///< the stamp ending the step, from the first stamp (the file's unit)
  };
  /// The steps above `limit` with where they are, in time order, for a limit of at least
  /// kGapFactor times the median step (gap_positions_kept() says whether every one was kept).
  /// Each block of kRateBlock steps keeps those above kGapCandidateFactor times its own typical
  /// step, since the median is known only at the end.
  std::vector<LongStep> long_steps(double limit) const;
  /// False when more than kMaxGapCandidates steps were candidates (their positions were then
  /// not all kept: jittery stamps, where gaps cannot be told from jitter anyway).
  bool gap_positions_kept() const { return candidates_kept_; }
  /// The stamps' jitter: the median over the blocks of kRateBlock steps of (median step -
  /// 10th percentile step) / median step (0 without a whole block). Gaps only lengthen steps,
  /// so a regular clock gives 0 while under half of its steps are gaps; stamps each jittered
  /// uniformly by half a period either side (steps: triangular over +-1 period) give
  /// 1 - sqrt(0.2) = 0.553.
  double jitter() const;
  /// A block keeps its steps above this factor times its typical step (its interquartile
  /// mean): a gap is a step above TimingReport::kGapFactor (1.5) median steps, and the
  /// typical steps of the blocks of a one-rate record stay within kRateChangeRatio (1.2) of
  /// each other and of the median, so 1.5 / 1.2 = 1.25 keeps every gap.
  static constexpr double kGapCandidateFactor = 1.25;
  /// At most this many candidates are kept (16 MB).
  static constexpr std::size_t kMaxGapCandidates = std::size_t{1} << 20;
  /// The first and the most distant block typical steps when they differ by more than
  /// kRateChangeRatio (the earliest block against the one furthest from it), else nullopt.
  std::optional<RateChange> rate_change() const;
  /// From now on, a list of steps (jittery stamps) is kept in a temporary file: called when
  /// the record goes beyond the memory budget. Throws InputError when the temporary folder
  /// cannot take it.
  void spill_to_file();

 private:
  struct Store;
  void flush_run() const;
  void end_block() const;
  void finish_blocks() const;
  void keep_long_steps(double limit) const;

  std::int64_t samples_ = 0;
  std::int64_t disorder_ = 0;
  std::int64_t duplicated_ = 0, first_duplicated_ = -1, last_duplicated_ = -1, first_backward_ = -1;
  double previous_ = 0.0;
  double magnitude_ = 0.0;
  // The current run of equal steps, counted before it is added to the table (consecutive
  // steps of a uniform log are mostly equal: one comparison instead of a hash lookup).
  mutable double run_step_ = 0.0;
  mutable std::int64_t run_length_ = 0;
  mutable std::unordered_map<double, std::int64_t> counts_;
  mutable std::unique_ptr<Store> spilled_;  // the list of steps once the table is full
  bool to_file_ = false;
  // The rate-change check: the current block, and the first and most distant typical steps.
  mutable std::vector<double> block_;
  mutable std::vector<std::int64_t> block_samples_;  // the sample ending each step of block_
  mutable std::vector<double> block_offsets_;        // the stamp ending each step of block_
  mutable std::vector<double> scratch_;              // block_ reordered for its interquartile mean
  mutable std::vector<LongStep> candidates_;         // the steps that may be gaps, in time order
  mutable std::vector<double> block_spreads_;        // each block's interquartile range / typical step
  mutable bool candidates_kept_ = true;
  mutable std::int64_t block_start_ = 0;
  mutable double first_typical_ = 0.0, far_typical_ = 0.0;
  mutable std::int64_t far_start_ = 0;
  mutable bool have_first_ = false;
};

/// Measures the sampling from the steps of the times (in the file's unit; `first_time` is
/// the first raw time). `unit.to_seconds` 0: decided here from the first time (a Unix time
/// in s/ms/us/ns) or from the median step.
TimingReport analyse_timing(const std::string& column, const StepStatistics& steps, double first_time,
                            const TimeUnit& unit, const std::string& unit_source);
/// Refuses (InputError naming the file and the column) a rate the stamps give that cannot
/// be used: one outside sampling_rate_problem's range (the rule every rate option follows),
/// or one that changes within the record. Nothing is refused when options.freq gives the
/// rate (and says to take the samples as evenly spaced).
void check_timestamp_rate(const std::string& path, const TimingReport& timing, const ReadOptions& options);

/// Refuses (InputError naming the file and the column) timestamps that never increase when
/// no rate was given: nothing to measure the sampling from.
[[noreturn]] void refuse_never_increasing(const std::string& path, const TimingReport& timing);

/// "25 ms", "1.5 us", "3.2 s": a duration to 4 significant digits in its unit.
std::string format_duration(double seconds);

/// Takes the gaps the stamps show (set.timing) as options.gaps says: kCompleteWindows puts
/// timing->missing in set.missing, refusing (InputError naming the file, the column and the
/// first such stamps) a gap whose length the stamps do not tell and stamps too irregular to
/// place the gaps; kJoin leaves set.missing empty. A record read at --freq across a change
/// of rate is taken as evenly spaced (no gaps).
void take_gaps(const std::string& path, SignalSet& set, const ReadOptions& options);

/// Applies options.data (increments x the rate) and options.decimate (the mean of each block
/// of K samples, or every K-th sample) to the values of `set`, in that order, and records them
/// in the set. Throws InputError naming the file and the option: increments without a rate,
/// decimation of a record with gaps read as missing, fewer than 16 samples after it.
void condition_values(const std::string& path, SignalSet& set, const ReadOptions& options);
/// What every reader does last with the record it read: take_gaps, condition_values, then
/// find_repeated_samples on the values that come out.
void finish_record(const std::string& path, SignalSet& set, const ReadOptions& options);

/// The same from times relative to the first one.
TimingReport analyse_timing(const std::string& column, const std::vector<double>& offsets, double first_time,
                            const TimeUnit& unit, const std::string& unit_source);

}  // namespace gmwm::io::detail
