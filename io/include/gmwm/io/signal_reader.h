#pragma once
// Reads the signals of a delimited text file (CSV, TSV, semicolon- or whitespace-
// separated), optionally gzip-compressed, into memory (docs/cli.md "Inputs").
//
// Format rules:
// - Delimiter detected from the header and the first data row: comma, tab, semicolon,
//   else runs of spaces/tabs. CRLF line ends and a UTF-8 byte-order mark are accepted.
// - A header row naming the columns is required: the first line with a non-numeric
//   token. Leading '#' lines are comments, except that the last of them is the header
//   when the next line is already data (EuRoC: '#timestamp [ns],w_RS_S_x [rad s^-1],...').
//   Header names may be double-quoted; data cells may not.
// - gzip is detected by content (magic bytes 1f 8b), never by the file name.
// - Blank lines are allowed only at the end of the file.
// - A column whose first data cell is not a number is a text column: skipped by
//   default, an error when picked with --columns.
// - A timestamp column (timestamp, time, t, stamp, '#timestamp [ns]', time_s, ...; the
//   first such column) gives the sampling rate, gaps and disorder; it is never a signal.
//
// Presets, recognised by their headers (original names stay valid in --columns):
// - EuRoC imu0/data.csv  '#timestamp [ns],w_RS_S_x [rad s^-1],...,a_RS_S_z [m s^-2]':
//     w_RS_S_x/y/z -> gyro_x/y/z (rad/s), a_RS_S_x/y/z -> accel_x/y/z (m/s^2).
// - Kalibr bagcreater CSV  'timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z'
//   (timestamp in ns): omega_x/y/z -> gyro_x/y/z, alpha_x/y/z -> accel_x/y/z (in Kalibr's
//   format "alpha" is the accelerometer, not an angular acceleration).
//
// Log files, detected by their magic bytes, give the IMU topic named by `topic`:
// PX4 ULog (io/src/readers/ulog_reader.cc, timestamps in us), and the sensor_msgs Imu
// topics of ROS 1 bags (rosbag1_reader.cc), rosbag2 sqlite3 bags (rosbag2_reader.cc) and
// MCAP files (mcap_reader.cc), times from the header stamps (ns): gyro_x..z in rad/s,
// accel_x..z in m/s^2.
//
// Every user error throws gmwm::InputError with one line:
//   "<path>:<line>:<column>: found <what>, expected <what>" (line/column when they apply).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/repeated_samples.h"
#include "gmwm/engine/samples.h"

namespace gmwm::io {

/// Fewest samples accepted per signal. The WV has J = floor(log2 N) levels, and the
/// smallest models worth fitting (e.g. WN + RW + QN, or AR1 + WN with 3 parameters)
/// need more WV moments than parameters: 4 levels, i.e. N >= 2^4 = 16.
inline constexpr std::int64_t kMinSamples = 16;

/// Limits on a delimited text file (docs/cli.md "Limits"). Beyond them the file is
/// refused with one line before its memory or time runs away; none is near a real
/// recording's size.
/// A line (one row) is at most 1 MiB: 4096 columns of 256 characters.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;
/// A file has at most 4096 columns (IMU logs have tens; a whole vehicle's log hundreds).
inline constexpr std::size_t kMaxColumns = 4096;
/// Compressed input may inflate to at most 250 times its compressed size once past 256 MiB,
/// counted over the file: gzip text as it inflates, and the bz2, lz4 and zstd chunks of ROS 1
/// bags and MCAP files by the uncompressed sizes they state, before they are inflated (each
/// then inflates into exactly that size). Text of numbers compresses 3-10 times (the ADIS
/// files 7.6, simulated 3.4), IMU messages in chunks 5-8 times (the bags of
/// tools/bench/log_readers.py: lz4 5.4, bz2 8.2), while a decompression bomb reaches zlib's
/// limit of about 1000, and bz2's, lz4's and zstd's far beyond.
inline constexpr double kMaxInflationRatio = 250.0;
inline constexpr std::uint64_t kInflationRatioFloorBytes = std::uint64_t{256} << 20;
/// True when `out` bytes inflated (or stated) from `in` compressed bytes break that rule.
bool inflation_exceeds(std::uint64_t in, std::uint64_t out);
/// The values read are refused when, at kBytesPerValue each (the value and the Haar
/// transform's prefix sum built from it), they would exceed kMemoryShare of the machine's
/// physical memory; `simulate` applies the same budget to what it generates.
inline constexpr double kMemoryShare = 0.75;
inline constexpr double kBytesPerValue = 16.0;
/// kMemoryShare of the physical memory in bytes; 0 when the system does not say.
double memory_budget_bytes();

/// The sampling rates accepted (Hz): one sample in ~30 years to 1 GHz. Beyond them a rate
/// is a typo, and its reciprocal (the tau in seconds) leaves the range of doubles.
inline constexpr double kMinFreq = 1e-9;
inline constexpr double kMaxFreq = 1e9;

/// "" when `freq` is within [kMinFreq, kMaxFreq], else "OPTION: found F, expected a
/// sampling rate in Hz from 1e-09 to 1e+09" with `option` naming where it came from. The
/// one rule for every rate: the options (--freq, --rate, ...), a manifest's, and the rate
/// a timestamp column gives (read_signals refuses stamps beyond it).
std::string sampling_rate_problem(double freq, const std::string& option);
/// "a sampling rate in Hz from 1e-09 to 1e+09": what sampling_rate_problem expects.
std::string sampling_rate_expected();
/// The refusal of data that carry no timing when no rate was given: "SOURCE: WHY; give the
/// sampling rate with --freq HZ". The one rule for every face: a file without a timestamp
/// column (read_signals), an array given to Python (each face says --freq in its own words,
/// io::option_wording). No face guesses a rate: every figure in seconds would rest on it.
std::string missing_rate_problem(const std::string& source, const std::string& why);

/// "" when `levels` (0: all) is at most J = floor(log2 n), the deepest level a series of
/// n samples has; else "OPTION LEVELS: the signals have N samples, which give at most J
/// levels, expected 1 to J" (a deeper request would otherwise be cut silently).
std::string levels_problem(int levels, std::int64_t n, const std::string& option);

/// True when the reader takes a column of this header name as timestamps ("time",
/// "timestamp", "#timestamp [ns]", ...), not as a signal.
bool is_timestamp_column_name(std::string_view name);

/// --gaps: what the studies do with samples a record's timestamps show missing (issue 47).
enum class GapHandling {
  /// "windows" (the default): each scale reads the windows of samples that hold no missing
  /// sample, or those missing at most a tenth of each half (the Allan deviation from 10
  /// samples a half, the WV where complete windows are scarce)
  /// (classical_wv_with_gaps, allan_deviation_with_gaps); a gap whose length
  /// the stamps do not tell is refused.
  kCompleteWindows,
  /// "join": the samples are joined end to end as if none were missing (each gap then
  /// puts a jump inside the windows across it).
  kJoin,
};
/// "windows" or "join": the one spelling of every face.
std::string_view gap_handling_name(GapHandling g);
/// The GapHandling named `name`; nullopt for any other text.
std::optional<GapHandling> gap_handling_from_name(std::string_view name);
/// "'windows' (each scale from the windows without a missing sample) or 'join' (the
/// samples end to end)".
std::string gap_handling_expected();
/// The GapHandling named `text`; throws InputError "--gaps: found 'TEXT', expected ..." for
/// any other text (every face fills its request through this one rule).
GapHandling gap_handling_of(const std::string& text);

/// --data: what each sample is (issue 47, item 5).
enum class DataKind {
  /// "rate" (the default): a rate (angular rate, specific force), as the WV models take it.
  kRate,
  /// "increment": a delta-angle or delta-velocity over one sampling period (an IMU's
  /// integrated output); read as the rate increment x freq (rad -> rad/s, m/s -> m/s^2).
  kIncrement,
  /// "phase": a phase or time error x (a clock's, in s), or an angle; read as the rate of its
  /// first differences (x_{i+1} - x_i) x freq (s -> fractional frequency, rad -> rad/s), one
  /// sample fewer (NIST SP 1065's y from x). A regular record only: a difference across a gap
  /// spans several periods.
  kPhase,
};
std::string_view data_kind_name(DataKind d);
/// The DataKind named `text`; throws InputError "--data: found 'TEXT', expected ...".
DataKind data_kind_of(const std::string& text);

/// --decimate-filter: the anti-alias filter before keeping every K-th sample (issue 47, item 4).
enum class DecimationFilter {
  /// "average" (the default): the mean of each block of K samples, a boxcar whose nulls fall
  /// on the multiples of the new rate. White noise's variance a sample falls K times, so its
  /// density N (units/sqrt(Hz)) and the figures of the band below the new Nyquist frequency
  /// (K, B) stay those of the record.
  kAverage,
  /// "none": every K-th sample as it is. Everything above the new Nyquist frequency folds in
  /// (aliasing): white noise keeps its variance a sample, so N grows sqrt(K) times.
  kNone,
};
std::string_view decimation_filter_name(DecimationFilter f);
/// The DecimationFilter named `text`; throws InputError "--decimate-filter: found ...".
DecimationFilter decimation_filter_of(const std::string& text);
/// --decimate K is at most this (a record of 2^20 blocks still needs 16 samples after it).
inline constexpr int kMaxDecimation = 1 << 20;

struct ReadOptions {
  /// Column names or 1-based field indices (as text). Empty: every numeric column that is
  /// not a timestamp, in file order.
  std::vector<std::string> columns;
  /// --freq HZ: the sampling rate. Overrides the timestamp column's estimate.
  std::optional<double> freq;
  /// --topic NAME[:INSTANCE]: the topic of a log file (PX4 ULog: sensor_combined, the
  /// default, sensor_gyro or sensor_accel; ROS bags: a sensor_msgs Imu topic, default the
  /// only one). Refused for a delimited text file.
  std::string topic;
  /// Bytes the values read may take at kBytesPerValue each; 0: memory_budget_bytes().
  double memory_budget = 0.0;
  /// Beyond the budget: true, the columns go on in temporary files (in $TMPDIR: 8 bytes a
  /// value on disk, memory that no longer grows with the record; samples.h); false, the
  /// file is refused with one line.
  bool spill = true;
  /// --gaps: what the studies do with the samples the timestamps show missing.
  GapHandling gaps = GapHandling::kCompleteWindows;
  /// --data: rates (default) or increments, converted to rates at the record's rate.
  DataKind data = DataKind::kRate;
  /// --decimate K (1: none) and its filter; the rate becomes freq / K.
  int decimate = 1;
  DecimationFilter decimate_filter = DecimationFilter::kAverage;

  /// "" when valid, otherwise a one-line message naming the option.
  std::string Validate() const;
};

/// What the timestamp column says about the sampling (present when there is one).
struct TimingReport {
  std::string column;            ///< the timestamp column's header name
  double unit_to_seconds = 1.0;  ///< e.g. 1e-9 for '#timestamp [ns]'
  std::string unit;              ///< "s", "ms", "us" or "ns"
  std::string unit_source;       ///< how the unit was decided (header, preset, ...)
  std::int64_t samples = 0;
  double median_step_seconds = 0.0;
  double estimated_freq = 0.0;       ///< 1 / median step; 0 when the times never increase
  std::int64_t gaps = 0;             ///< steps > kGapFactor x median step
  double largest_gap_seconds = 0.0;  ///< largest step counted as a gap (0 when no gap)
  std::int64_t disorder = 0;         ///< non-increasing steps (repeated or backwards times)
  /// Of those, the stamps that repeat the one before (steps of zero: a message sent twice, a
  /// clock that did not advance) and the 0-based samples of the first and last; the rest go
  /// backwards, the first at first_backward. -1 where there is none.
  std::int64_t duplicated = 0, first_duplicated = -1, last_duplicated = -1, first_backward = -1;
  /// Where the gaps left samples out (issue 47): runs on the grid of the record's samples
  /// with the missing ones between them, round(step / median step) - 1 samples each, in time
  /// order. Only the gaps whose length is known (uncertain_gaps counts the others).
  std::vector<MissingRun> missing;
  /// Gaps whose step is further than kGapLengthTolerance from a whole number of median steps:
  /// how many, and the first (the 0-based sample after it, the step in seconds, and the two
  /// stamps around it in seconds from the first stamp).
  std::int64_t uncertain_gaps = 0;
  struct UncertainGap {
    std::int64_t sample = 0;
    double step_seconds = 0.0;
    double from_seconds = 0.0, to_seconds = 0.0;
  };
  std::optional<UncertainGap> first_uncertain_gap;
  /// The stamps' jitter: how far the 10th percentile step falls short of the median step, in
  /// median steps (the median over blocks of 1024 steps; gaps, which lengthen steps, do not
  /// count). Above kMaxJitterToPlaceGaps the gaps are not placed
  /// (a late stamp cannot be told from a lost sample) and the samples are read end to end.
  double jitter = 0.0;
  /// False when the gaps' places could not all be kept (more than a million candidate steps:
  /// jittery stamps); `missing` is then empty.
  bool gap_positions_known = true;
  /// Stamps read as decimals are held as doubles: the spacing of doubles (one unit in the
  /// last place) at the largest stamp, in seconds, and that stamp. A step between two such
  /// stamps is off by up to about that spacing, so the readers refuse (without --freq) a
  /// median step less than 1 / kDisagreement times it: 1.7e9 s since 1970 are held to
  /// 0.24 us, too coarse for steps under 24 us. 0 when the steps are exact (integer stamps,
  /// subtracted as integers).
  double resolution_seconds = 0.0;
  double largest_stamp_seconds = 0.0;
  std::optional<double> given_freq;  ///< --freq, when it was given as well
  /// A sustained change of the sampling rate inside the record (blocks of 1024 steps whose
  /// typical steps differ by more than 1.2x; gaps and jitter do not count): the rate at the
  /// start, the rate furthest from it and the 0-based sample where that block starts. The
  /// readers refuse such a record unless --freq says to take the samples as evenly spaced.
  struct RateChange {
    double from_hz = 0.0, to_hz = 0.0;
    std::int64_t sample = 0;
  };
  std::optional<RateChange> rate_change;

  /// A step longer than this many median steps is a gap. Timestamp jitter of a regular
  /// stream stays well under half a period, while one dropped sample makes a step of two
  /// periods: 1.5 sits halfway, so every lost sample counts and jitter never does.
  static constexpr double kGapFactor = 1.5;
  /// A gap's step within this many median steps of a whole number k gives k - 1 missing
  /// samples; further, its length is unknown. Half of kGapFactor's margin (a regular stream's
  /// jitter stays well under half a period): 0.25 of a period either side.
  static constexpr double kGapLengthTolerance = 0.25;
  /// Stamps whose 10th percentile step falls more than this share of a period short of the
  /// median cannot place a gap to a sample: a step's error then reaches kGapLengthTolerance
  /// (a quarter period) in a tenth of the steps. Each stamp jittered uniformly by a quarter
  /// period either side gives 0.276.
  static constexpr double kMaxJitterToPlaceGaps = 0.25;
  /// --freq and the estimate "disagree" above this relative difference (1%): more than
  /// timestamp jitter explains, typical of a wrong rate or a wrong time unit.
  static constexpr double kDisagreement = 0.01;

  /// One line for the terminal; mentions a disagreement with --freq above 1%.
  std::string summary() const;
  /// What the steps out of order are and where: "2 repeat the stamp before (0.1% of the
  /// samples, from sample 7 to 907), 1 goes backwards (first at sample 10)"; "" when none.
  std::string disorder_text() const;
  /// "the sampling rate changes within the record, from about 100 Hz at its start to about
  /// 200 Hz from sample 2049"; "" without a rate change.
  std::string rate_change_text() const;
};

struct Signal {
  std::string name;
  /// In memory, or in a temporary file when the record exceeds the memory budget
  /// (ReadOptions::spill).
  Samples values;
  std::string unit = {};  ///< from the header ('[rad s^-1]') or the preset; "" when unknown
  /// Held and interpolated samples in the values (find_repeated_samples; issue 47).
  RepeatedSamples repeated = {};
};

struct SignalSet {
  std::string path;
  std::vector<Signal> signals;
  double freq = 0.0;  ///< from --freq, else from the timestamp column
  bool freq_known = false;
  std::optional<TimingReport> timing;
  /// The samples the timestamps show missing, on the grid of observed and missing samples
  /// together (the values hold the observed ones only), shared by every column; empty for a
  /// regular record and under GapHandling::kJoin. Every study reads the gap-resistant
  /// windows from them (gappy_wv.h) or refuses the record (pipeline::require_regular).
  std::vector<MissingRun> missing;
  /// How the gaps were taken (kJoin: the samples end to end, missing stays empty).
  GapHandling gaps = GapHandling::kCompleteWindows;
  /// The missing samples in all (the sum of the runs' lengths).
  std::int64_t missing_samples() const;
  /// What the values are: increments were converted to rates (x the rate at reading).
  DataKind data = DataKind::kRate;
  /// --decimate: the factor (1: none), its filter and the rate before it.
  int decimation = 1;
  DecimationFilter decimation_filter = DecimationFilter::kAverage;
  double freq_before_decimation = 0.0;
  /// True when the columns are held in temporary files (the record exceeded the budget).
  bool spilled = false;
  /// What reading left out, a line each (a log topic's axes that are zero in every message:
  /// a gyroscope-only topic's linear_acceleration); reading_notes says them with the rest.
  std::vector<std::string> notes;
  std::string preset;       ///< "euroc", "kalibr" or "" when recognised by header
  std::string delimiter;    ///< "comma", "tab", "semicolon" or "whitespace"
  bool compressed = false;  ///< gzip content
};

/// One line for the terminal and the documents on a record read with gaps: "N of the
/// record's G samples missing in K gaps (the largest L samples); each scale reads the windows
/// that hold no missing sample, or those missing at most a tenth of each half (...)"; "" for a regular record (or one read
/// --gaps join).
std::string gaps_summary(const SignalSet& set);

/// Reads every column for held and interpolated samples (engine/repeated_samples.h) into
/// its Signal::repeated, in parallel over the columns: done by read_signals and for the
/// arrays handed to Python, after the gaps and the conditioning, so that every face says
/// the same of the values its studies read.
void find_repeated_samples(SignalSet& set);
/// One line a column whose samples repeat (repeated_samples_text, with the record's rate);
/// empty when none does.
std::vector<std::string> repeated_samples_notes(const SignalSet& set);
/// What reading says of the record besides its timing: set.notes (what it left out), then
/// repeated_samples_notes. The terminal's warnings, the report's notes, Python's warnings.
std::vector<std::string> reading_notes(const SignalSet& set);

/// The rows where a column holds NaN are samples missing from a regular record (a pandas
/// frame or a numpy array marks them so, as gmwm.read's Recording does for the gaps of its
/// stamps; issue 47): they leave every column, and set.missing places them on the grid (a
/// row missing in one column is missing in all: a row is one sample of every axis). No-op
/// without NaN. Throws InputError "SOURCE: ..." when the set already has missing runs, or
/// fewer than 16 rows would remain.
void take_nan_rows_as_missing(SignalSet& set, const std::string& source);

/// --data phase (DataKind::kPhase): each column, a phase or time error, becomes the rate of
/// its first differences (x_{i+1} - x_i) x freq, one sample fewer; set.data says so. Throws
/// InputError "SOURCE: --data phase: ..." without a known rate, with gaps (missing samples, or
/// gaps the stamps show that --gaps join joined: a step across a gap spans several periods),
/// or with fewer than 16 steps. What reading does for --data phase, and what Python's
/// functions do for phase=True.
void take_phase_as_rate(SignalSet& set, const std::string& source);

/// One line for the terminal and the documents on what reading did to the values: "read as
/// increments x 200 Hz (rates); decimated by 4 (the mean of each 4 samples) from 200 Hz to
/// 50 Hz: N, K, B are those of the band below 25 Hz"; "" when nothing was done.
std::string conditioning_summary(const SignalSet& set);

/// The longest run of observed samples between the missing ones (the record's length
/// without gaps): no window longer than it is complete, so the longer scales are read from
/// near-complete windows (each half missing at most a tenth) or not at all.
std::int64_t longest_stretch(const SignalSet& set);
/// "the longest stretch between gaps holds N samples (S s) of the record's G: the longer
/// scales are read from the windows whose halves each miss at most a tenth of their samples,
/// ..." when that stretch is under half the record
/// (frequent gaps leave no long window); "" otherwise. The terminal's warning and the
/// report's note.
std::string long_scales_note(const SignalSet& set);

/// Reads the selected columns of `path`. Throws gmwm::InputError on bad input (see above).
SignalSet read_signals(const std::string& path, const ReadOptions& options);

/// What read_signals would refuse, checked before the data are read: the options; for
/// delimited text the file's header, its timestamp (or --freq) and --columns (names or
/// indices), with read_signals' messages; a log or bag is only told apart (its topics and
/// fields are read with the data). For a run over many files that refuses bad ones up front.
void check_signals(const std::string& path, const ReadOptions& options);

}  // namespace gmwm::io
