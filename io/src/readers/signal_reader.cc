#include "gmwm/io/signal_reader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>
#include <unistd.h>

#include "column_sink.h"
#include "delimited_parser.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/samples.h"
#include "text_source.h"
#include "timestamp.h"
#include "gmwm/io/stamped_columns.h"
#include "mcap_reader.h"
#include "rosbag1_reader.h"
#include "rosbag2_reader.h"
#include "ulog_reader.h"

namespace gmwm::io {

namespace {

using detail::Delimiter;
using detail::FieldPlan;

std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 60;
  std::string out(1, '\'');
  out.append(s.substr(0, kMax));
  out.append(s.size() > kMax ? "...'" : "'");
  return out;
}

bool is_blank_line(std::string_view line) { return line.find_first_not_of(" \t") == std::string_view::npos; }

bool iequals(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  });
}

std::string where(const std::string& path, std::int64_t line) { return path + ":" + std::to_string(line) + ": "; }

// Known layouts, recognised by their header names without units (case-insensitive).
struct Preset {
  const char* name;
  std::array<const char*, 7> header;
  std::array<const char*, 7> renamed;
  std::array<const char*, 7> units;
  detail::TimeUnit time_unit;
};
const Preset kPresets[] = {
    {"euroc",
     {"timestamp", "w_RS_S_x", "w_RS_S_y", "w_RS_S_z", "a_RS_S_x", "a_RS_S_y", "a_RS_S_z"},
     {"timestamp", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"},
     {"ns", "rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2"},
     {1e-9, "ns"}},
    {"kalibr",
     {"timestamp", "omega_x", "omega_y", "omega_z", "alpha_x", "alpha_y", "alpha_z"},
     {"timestamp", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"},
     {"ns", "rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2"},
     {1e-9, "ns"}},
};

struct Column {
  std::string header;  // as written (without a leading '#')
  std::string base;    // without its bracketed unit
  std::string name;    // the signal's name (preset-renamed base)
  std::string unit;
  bool numeric = false;      // its first data cell is a number
  bool empty_first = false;  // its first data cell is empty (another sensor's row, stamped_columns.h)
  bool time_like = false;    // named like a timestamp
};

const Preset* find_preset(const std::vector<Column>& cols) {
  for (const Preset& p : kPresets) {
    if (cols.size() != p.header.size()) continue;
    bool match = true;
    for (std::size_t k = 0; k < cols.size() && match; ++k) match = iequals(cols[k].base, p.header[k]);
    if (match) return &p;
  }
  return nullptr;
}

std::string column_list(const std::vector<Column>& cols) {
  std::string s;
  for (std::size_t k = 0; k < cols.size(); ++k) s += (k ? ", " : "") + cols[k].name;
  return s;
}

// The field index a --columns entry names (a 1-based index, or a name, exact match first).
std::size_t resolve_column(const std::string& path, const std::string& raw_spec, const std::vector<Column>& cols) {
  const std::size_t b = raw_spec.find_first_not_of(" \t");
  const std::string spec = raw_spec.substr(b, raw_spec.find_last_not_of(" \t") + 1 - b);
  const std::string prefix = path + ": --columns: ";
  if (std::all_of(spec.begin(), spec.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    std::size_t index = 0;
    const auto [ptr, ec] = std::from_chars(spec.data(), spec.data() + spec.size(), index);
    if (ec != std::errc() || index < 1 || index > cols.size())
      throw InputError(prefix + "found index " + spec + ", expected 1.." + std::to_string(cols.size()) +
                       " (the file has " + std::to_string(cols.size()) + " columns: " + column_list(cols) + ")");
    return index - 1;
  }
  for (const bool exact : {true, false}) {
    std::vector<std::size_t> hits;
    for (std::size_t k = 0; k < cols.size(); ++k) {
      const Column& c = cols[k];
      for (const std::string* n : {&c.name, &c.header, &c.base}) {
        if (exact ? *n == spec : iequals(*n, spec)) {
          hits.push_back(k);
          break;
        }
      }
    }
    if (hits.size() > 1)
      throw InputError(prefix + "found the name '" + spec + "' in columns " + std::to_string(hits[0] + 1) + " and " +
                       std::to_string(hits[1] + 1) + ", expected a unique name (use the 1-based index instead)");
    if (hits.size() == 1) return hits[0];
  }
  throw InputError(prefix + "found no column named '" + spec + "', expected one of: " + column_list(cols) +
                   " (or a 1-based index)");
}

}  // namespace

std::string sampling_rate_expected() {
  char buf[64];
  std::snprintf(buf, sizeof buf, "a sampling rate in Hz from %g to %g", kMinFreq, kMaxFreq);
  return buf;
}

std::string missing_rate_problem(const std::string& source, const std::string& why) {
  return source + ": " + why + "; give the sampling rate with --freq HZ";
}

std::string sampling_rate_problem(double freq, const std::string& option) {
  if (freq >= kMinFreq && freq <= kMaxFreq) return {};
  char buf[32];
  std::snprintf(buf, sizeof buf, ": found %g", freq);
  return option + buf + ", expected " + sampling_rate_expected();
}

std::string levels_problem(int levels, std::int64_t n, const std::string& option) {
  int deepest = 0;
  while (deepest < 62 && (std::int64_t{2} << deepest) <= n) ++deepest;
  if (levels <= deepest) return {};
  return option + " " + std::to_string(levels) + ": the signals have " + std::to_string(n) +
         " samples, which give at most " + std::to_string(deepest) + " levels (2^" + std::to_string(deepest) +
         " <= " + std::to_string(n) + "), expected 1 to " + std::to_string(deepest);
}

double memory_budget_bytes() {
  const double pages = static_cast<double>(::sysconf(_SC_PHYS_PAGES));
  const double page = static_cast<double>(::sysconf(_SC_PAGESIZE));
  return pages > 0.0 && page > 0.0 ? kMemoryShare * pages * page : 0.0;
}

bool inflation_exceeds(std::uint64_t in, std::uint64_t out) {
  return out > kInflationRatioFloorBytes && static_cast<double>(out) > kMaxInflationRatio * static_cast<double>(in);
}

namespace {

// stamped_columns.h: the timestamp columns that each stamp the columns to their right, when
// two or more do. An empty first cell in them is another sensor's row: they count as numeric.
std::vector<StampedColumns> stamp_groups(std::vector<Column>& cols) {
  std::vector<StampedColumns> groups;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    if (cols[k].time_like) {
      groups.push_back({cols[k].header, k + 1, {}, {}});
    } else if (!groups.empty() && (cols[k].numeric || cols[k].empty_first)) {
      groups.back().fields.push_back(k + 1);
      groups.back().columns.push_back(cols[k].name);
    }
  }
  std::vector<StampedColumns> stamping;
  for (std::size_t g = 0; g < groups.size(); ++g)
    if (!groups[g].fields.empty()) stamping.push_back(groups[g]);
  if (stamping.size() < 2) return {};
  for (const StampedColumns& g : stamping) {
    Column& stamp = cols[g.stamp_field - 1];
    stamp.numeric = stamp.numeric || stamp.empty_first;
    for (const std::size_t f : g.fields) cols[f - 1].numeric = true;
  }
  return stamping;
}

// "gyro_timestamp (gyro_x, gyro_y); accel_timestamp (accel_x)": the groups, for a refusal.
std::string groups_text(const std::vector<StampedColumns>& groups) {
  std::string out;
  for (const StampedColumns& g : groups) {
    out += (out.empty() ? "" : "; ") + g.stamp + " (";
    for (std::size_t i = 0; i < g.columns.size(); ++i) out += (i ? ", " : "") + g.columns[i];
    out += ")";
  }
  return out;
}

// The timestamp column (0-based) of the selected columns of a file with stamp groups: the
// one stamp column they all belong to; refused when they belong to several (each would be
// timed by another sensor's clock).
std::size_t stamp_of(const std::string& path, std::int64_t header_line, const std::vector<StampedColumns>& groups,
                     const std::vector<std::size_t>& selected, const std::vector<Column>& cols,
                     const ReadOptions& options) {
  std::optional<std::size_t> group;
  bool several = false;
  for (const std::size_t k : selected)
    if (cols[k].time_like)
      throw InputError(path + ": --columns: found '" + cols[k].header +
                       "', a timestamp column, expected a signal column");
  for (const std::size_t k : selected)
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (std::find(groups[g].fields.begin(), groups[g].fields.end(), k + 1) != groups[g].fields.end()) {
        several = several || (group && *group != g);
        group = group.value_or(g);
      }
  if (!group || several) {
    const std::string what = std::to_string(groups.size()) +
                             " timestamp columns, each stamping the columns to its right (" + groups_text(groups) +
                             "), expected the columns of one: wv, fit and select (gmwm.read_parts) read each at the "
                             "rate of its own stamps";
    if (options.columns.empty())
      throw InputError(where(path, header_line) + "found " + what + ", or name one's columns with --columns");
    throw InputError(path + ": --columns: found columns of " + what);
  }
  return groups[*group].stamp_field - 1;
}

// Which fields become signals, in which order: --columns, else every numeric column that is
// not a timestamp.
std::vector<std::size_t> selected_fields(const std::string& path, std::int64_t header_line,
                                         const std::vector<Column>& cols, const ReadOptions& options,
                                         std::optional<std::size_t> time_col) {
  std::vector<std::size_t> selected;
  if (options.columns.empty()) {
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (cols[k].numeric && !cols[k].time_like) selected.push_back(k);
    if (selected.empty())
      throw InputError(where(path, header_line) + "found no numeric column besides timestamps (" + column_list(cols) +
                       "), expected at least one signal column");
    return selected;
  }
  for (const std::string& spec : options.columns) {
    const std::size_t k = resolve_column(path, spec, cols);
    if (time_col && k == *time_col)
      throw InputError(path + ": --columns: found '" + spec + "', the timestamp column '" + cols[k].header +
                       "', expected a signal column");
    if (std::find(selected.begin(), selected.end(), k) != selected.end())
      throw InputError(path + ": --columns: found column '" + cols[k].name + "' twice, expected each column once");
    selected.push_back(k);
  }
  return selected;
}

}  // namespace

bool is_timestamp_column_name(std::string_view name) { return detail::timestamp_name(name).has_value(); }

std::string_view gap_handling_name(GapHandling g) {
  switch (g) {
    case GapHandling::kCompleteWindows:
      return "windows";
    case GapHandling::kJoin:
      return "join";
  }
  return "windows";
}

std::optional<GapHandling> gap_handling_from_name(std::string_view name) {
  for (const GapHandling g : {GapHandling::kCompleteWindows, GapHandling::kJoin})
    if (name == gap_handling_name(g)) return g;
  return std::nullopt;
}

std::string gap_handling_expected() {
  return "'windows' (each scale from the windows without a missing sample) or 'join' (the samples end to end)";
}

GapHandling gap_handling_of(const std::string& text) {
  if (const std::optional<GapHandling> g = gap_handling_from_name(text)) return *g;
  throw InputError("--gaps: found '" + printable_line(text) + "', expected " + gap_handling_expected());
}

std::string gaps_summary(const SignalSet& set) {
  if (set.missing.empty()) return {};
  std::int64_t largest = 0;
  for (const MissingRun& r : set.missing) largest = std::max(largest, r.length);
  const std::int64_t lost = set.missing_samples();
  const auto grid = static_cast<std::int64_t>(set.signals.empty() ? 0 : set.signals.front().values.size()) + lost;
  return std::to_string(lost) + " of the record's " + std::to_string(grid) + " samples missing in " +
         std::to_string(set.missing.size()) + (set.missing.size() == 1 ? " gap" : " gaps") + " (the largest " +
         std::to_string(largest) + (largest == 1 ? " sample" : " samples") +
         "); each scale reads the windows that hold no missing sample, or those missing at most a tenth of each "
         "half (the Allan deviation from 10 samples a half, the WV where complete windows are scarce)";
}

void take_nan_rows_as_missing(SignalSet& set, const std::string& source) {
  if (set.signals.empty()) return;
  const std::size_t n = set.signals.front().values.size();
  std::vector<char> hole(n, 0);
  bool any = false;
  for (const Signal& s : set.signals)
    for (std::size_t i = 0; i < n && i < s.values.size(); ++i)
      if (std::isnan(s.values[i])) hole[i] = 1, any = true;
  if (!any) return;
  if (!set.missing.empty())
    throw InputError(source +
                     ": found NaN rows in a record whose timestamps already place gaps, expected one or the "
                     "other to mark the missing samples");
  std::vector<MissingRun> runs;
  std::int64_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!hole[i]) {
      ++kept;
      continue;
    }
    if (!runs.empty() && runs.back().start + runs.back().length == static_cast<std::int64_t>(i))
      ++runs.back().length;
    else
      runs.push_back({static_cast<std::int64_t>(i), 1});
  }
  if (kept < kMinSamples)
    throw InputError(source + ": found " + std::to_string(kept) + " rows without NaN of " + std::to_string(n) +
                     ", expected at least " + std::to_string(kMinSamples) +
                     " (NaN marks a missing sample; the wavelet variance needs 2^4 samples)");
  for (Signal& s : set.signals) {
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(kept));
    for (std::size_t i = 0; i < n; ++i)
      if (!hole[i]) v.push_back(s.values[i]);
    s.values = Samples(std::move(v));
  }
  set.missing = std::move(runs);
}

std::string_view data_kind_name(DataKind d) {
  switch (d) {
    case DataKind::kIncrement:
      return "increment";
    case DataKind::kPhase:
      return "phase";
    case DataKind::kRate:
      break;
  }
  return "rate";
}

DataKind data_kind_of(const std::string& text) {
  for (const DataKind d : {DataKind::kRate, DataKind::kIncrement, DataKind::kPhase})
    if (text == data_kind_name(d)) return d;
  throw InputError("--data: found '" + printable_line(text) +
                   "', expected 'rate' (angular rates, specific forces), 'increment' (delta-angles, "
                   "delta-velocities over one sampling period) or 'phase' (a phase or time error, an angle)");
}

std::string_view decimation_filter_name(DecimationFilter f) {
  return f == DecimationFilter::kNone ? "none" : "average";
}

DecimationFilter decimation_filter_of(const std::string& text) {
  for (const DecimationFilter f : {DecimationFilter::kAverage, DecimationFilter::kNone})
    if (text == decimation_filter_name(f)) return f;
  throw InputError("--decimate-filter: found '" + printable_line(text) +
                   "', expected 'average' (the mean of each K samples) or 'none' (every K-th sample, aliased)");
}

std::string conditioning_summary(const SignalSet& set) {
  std::string out;
  const auto hz = [](double f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g Hz", f);
    return std::string(buf);
  };
  if (set.data == DataKind::kIncrement)
    out = "read as increments x " + hz(set.freq_before_decimation) + " (rates: rad -> rad/s, m/s -> m/s^2)";
  if (set.data == DataKind::kPhase)
    out = "read as phase: its first differences x " + hz(set.freq_before_decimation) +
          " (s -> fractional frequency, rad -> rad/s), one sample fewer";
  if (set.decimation > 1) {
    const std::string k = std::to_string(set.decimation);
    out += (out.empty() ? "" : "; ") + std::string("decimated by ") + k +
           (set.decimation_filter == DecimationFilter::kAverage ? " (the mean of each " + k + " samples)"
                                                                : " (every " + k + "-th sample, no filter)") +
           " from " + hz(set.freq_before_decimation) + " to " + hz(set.freq) + ": " +
           (set.decimation_filter == DecimationFilter::kAverage
                ? "N, K and B are those of the band below " + hz(set.freq / 2.0) + ", as in the record"
                : "the band above " + hz(set.freq / 2.0) + " folds in, white noise's N grows sqrt(" + k + ") times");
  }
  return out;
}

std::int64_t longest_stretch(const SignalSet& set) {
  const std::int64_t observed = set.signals.empty() ? 0 : static_cast<std::int64_t>(set.signals.front().values.size());
  std::int64_t longest = 0, from = 0, before = 0;  // grid position after the last run; missing before it
  for (const MissingRun& r : set.missing) {
    longest = std::max(longest, r.start - from);
    from = r.start + r.length;
    before += r.length;
  }
  return std::max(longest, observed + before - from);
}

std::string long_scales_note(const SignalSet& set) {
  if (set.missing.empty() || set.signals.empty()) return {};
  const std::int64_t longest = longest_stretch(set);
  const std::int64_t grid = static_cast<std::int64_t>(set.signals.front().values.size()) + set.missing_samples();
  if (2 * longest >= grid) return {};
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.6g", static_cast<double>(longest) / set.freq);
  return "the longest stretch between gaps holds " + std::to_string(longest) + " samples (" + seconds +
         " s) of the record's " + std::to_string(grid) +
         ": the longer scales are read from the windows whose halves each miss at most a tenth of their samples, "
         "each half averaged over its observed ones (the WV's level notes say which; --gaps join reads them end to "
         "end)";
}

std::int64_t SignalSet::missing_samples() const { return gmwm::missing_samples(missing); }

std::string ReadOptions::Validate() const {
  if (freq)
    if (std::string why = sampling_rate_problem(*freq, "--freq"); !why.empty()) return why;
  for (const std::string& c : columns)
    if (c.find_first_not_of(" \t") == std::string::npos)
      return "--columns: found an empty entry, expected column names or 1-based indices "
             "separated by commas";
  if (decimate < 1 || decimate > kMaxDecimation)
    return "--decimate: found " + std::to_string(decimate) + ", expected a whole number from 1 to " +
           std::to_string(kMaxDecimation);
  if (!(memory_budget >= 0.0) || !std::isfinite(memory_budget))
    return "memory_budget: found " + std::to_string(memory_budget) +
           ", expected a finite number of bytes >= 0 (0: the default)";
  return "";
}

namespace {

bool is_log(const std::string& path) {
  return detail::is_ulog(path) || detail::is_rosbag2_sqlite(path) || detail::is_rosbag1(path) || detail::is_mcap(path);
}

// A delimited text file's signals; `header_only`: the header, the timestamp and the columns
// checked as read_signals checks them, no data row read past the first (the set has no values).
SignalSet read_delimited(const std::string& path, const ReadOptions& options, bool header_only,
                         std::vector<StampedColumns>* groups = nullptr);

}  // namespace

std::vector<StampedColumns> stamped_columns(const std::string& path) {
  if (is_log(path)) return {};
  std::vector<StampedColumns> groups;
  ReadOptions options;
  options.freq = 1.0;  // a file without stamps has no groups; its rate is not asked here
  read_delimited(path, options, true, &groups);
  return groups;
}

void check_signals(const std::string& path, const ReadOptions& options) {
  if (const std::string msg = options.Validate(); !msg.empty()) throw InputError(msg);
  if (is_log(path)) return;  // its topics and fields are read with the data
  read_delimited(path, options, true);
}

SignalSet read_signals(const std::string& path, const ReadOptions& options) {
  if (const std::string msg = options.Validate(); !msg.empty()) throw InputError(msg);
  if (detail::is_ulog(path)) return detail::read_ulog(path, options);
  if (detail::is_rosbag2_sqlite(path)) return detail::read_rosbag2_sqlite(path, options);
  if (detail::is_rosbag1(path)) return detail::read_rosbag1(path, options);
  if (detail::is_mcap(path)) return detail::read_mcap(path, options);
  return read_delimited(path, options, false);
}

namespace {

SignalSet read_delimited(const std::string& path, const ReadOptions& options, bool header_only,
                         std::vector<StampedColumns>* groups_out) {
  // Opened first: a path the format sniffers found no log at may be missing, a folder or
  // unreadable, which is said as such before anything about its format.
  detail::TextSource src(path);
  if (!options.topic.empty())
    throw InputError(path + ": --topic " + options.topic +
                     ": the file is delimited text, which has no topics "
                     "(--topic reads a PX4 ULog file or a ROS bag: .bag, .db3, .mcap)");
  if (src.empty()) throw InputError(path + ": found an empty file, expected a header row and data rows");

  // Header: the first line with a non-numeric token; or the last '#' line when the next
  // line is already data (EuRoC). Earlier '#' lines are comments.
  std::string header, comment, first_row;
  std::int64_t header_line = 0, comment_line = 0, first_row_line = 0;
  std::string_view line;
  while (src.next_line(line)) {
    if (is_blank_line(line)) {
      src.skip_blank_lines();
      continue;
    }
    const std::string_view t = line.substr(line.find_first_not_of(" \t"));
    if (t.front() == '#') {
      comment.assign(t);
      comment_line = src.line_number();
      continue;
    }
    if (detail::is_numeric_row(line)) {
      if (comment_line == 0)
        throw InputError(where(path, src.line_number()) + "found a data row " + quoted(line) +
                         " where the header belongs, expected a header row naming the columns "
                         "(e.g. 'time,gyro_x,gyro_y')");
      header = comment;
      header_line = comment_line;
      first_row.assign(line);
      first_row_line = src.line_number();
    } else {
      header.assign(line);
      header_line = src.line_number();
    }
    break;
  }
  if (header_line == 0) {
    if (src.line_number() == 0)  // e.g. a gzip file holding no text
      throw InputError(path + ": found no text, expected a header row and data rows");
    if (comment_line == 0) throw InputError(path + ": found only blank lines, expected a header row and data rows");
    header = comment;
    header_line = comment_line;
  }
  std::int64_t blank_line = 0;  // first blank line seen after the header
  if (first_row_line == 0) {
    while (src.next_line(line)) {
      if (is_blank_line(line)) {
        if (!blank_line) blank_line = src.line_number();
        src.skip_blank_lines();
        continue;
      }
      first_row.assign(line);
      first_row_line = src.line_number();
      break;
    }
  }
  if (first_row_line == 0)
    throw InputError(where(path, header_line) + "found a header but no data rows, expected at least " +
                     std::to_string(kMinSamples) + " rows of samples");
  auto fail_blank = [&](std::int64_t at) {
    throw InputError(where(path, at) +
                     "found an empty line, expected a data row (blank lines are allowed only at "
                     "the end of the file)");
  };
  if (blank_line) fail_blank(blank_line);

  if (!header.empty() && header.front() == '#') header.erase(0, header.find_first_not_of("# \t"));
  const Delimiter delim = detail::detect_delimiter(header, first_row);
  std::vector<std::string> names = detail::split_header(header, delim);
  if (names.size() > kMaxColumns)
    throw InputError(where(path, header_line) + "found " + std::to_string(names.size()) +
                     " columns, expected at most " + std::to_string(kMaxColumns));

  // Rows with the wrong number of fields are reported by the row parser itself.
  detail::RowParser(path, delim, std::vector<FieldPlan>(names.size()), names, 0).parse(first_row, first_row_line);
  const std::vector<std::string_view> first_fields = detail::split_fields(first_row, delim);

  std::vector<Column> cols(names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    Column& c = cols[k];
    if (names[k].empty()) names[k] = "column_" + std::to_string(k + 1);
    c.header = names[k];
    std::tie(c.base, c.unit) = detail::split_unit(c.header);
    c.name = c.base;
    double v;
    const detail::NumberStatus s = detail::parse_number(first_fields[k], v);
    c.numeric = s != detail::NumberStatus::kEmpty && s != detail::NumberStatus::kNotANumber;
    c.empty_first = s == detail::NumberStatus::kEmpty;
    c.time_like = detail::timestamp_name(c.header).has_value();
  }
  SignalSet set;
  set.path = path;
  set.delimiter = detail::delimiter_name(delim);
  set.compressed = src.compressed();
  const Preset* preset = find_preset(cols);
  if (preset) {
    set.preset = preset->name;
    for (std::size_t k = 0; k < cols.size(); ++k) {
      cols[k].name = preset->renamed[k];
      cols[k].unit = preset->units[k];
    }
  }
  const std::vector<StampedColumns> groups = stamp_groups(cols);
  if (groups_out) {
    *groups_out = groups;
    return set;
  }
  std::optional<std::size_t> time_col;
  const auto time_like = std::find_if(cols.begin(), cols.end(), [](const Column& c) { return c.time_like; });
  if (time_like != cols.end()) time_col = static_cast<std::size_t>(time_like - cols.begin());
  if (time_col && !cols[*time_col].numeric) {
    if (!options.freq)
      throw InputError(path + ":" + std::to_string(first_row_line) + ":" + std::to_string(*time_col + 1) + ": found " +
                       quoted(first_fields[*time_col]) + " in timestamp column '" + cols[*time_col].header +
                       "', expected a number; give the sampling rate with --freq HZ");
    time_col.reset();  // not usable for timing; --freq rules anyway
  }
  if (!time_col && !options.freq) throw InputError(missing_rate_problem(path, "no timestamp column found"));

  const std::vector<std::size_t> selected = selected_fields(path, header_line, cols, options, time_col);
  if (!groups.empty()) time_col = stamp_of(path, header_line, groups, selected, cols, options);
  if (header_only) {
    for (const std::size_t k : selected) set.signals.push_back({cols[k].name, {}, cols[k].unit});
    return set;
  }
  std::vector<FieldPlan> plan(cols.size());
  for (std::size_t i = 0; i < selected.size(); ++i) plan[selected[i]] = {FieldPlan::kValue, static_cast<int>(i)};
  if (time_col) plan[*time_col].kind = FieldPlan::kTime;

  detail::RowParser parser(path, delim, std::move(plan), names, static_cast<int>(selected.size()));
  if (!groups.empty()) parser.skip_rows_without(*time_col);  // another sensor's rows
  // A timestamp column counts as a column: jittery stamps keep a step a row (StepStatistics).
  detail::ColumnSink sink(path, parser.values(), options, {"rows", "column(s)", "read fewer columns with --columns"},
                          time_col ? &parser.time_steps() : nullptr);
  parser.reserve(sink.rows_to_reserve(src.text_size_hint() / (first_row.size() + 1) + 1));
  parser.parse(first_row, first_row_line);
  while (src.next_line(line)) {
    if (line.empty() || is_blank_line(line)) {
      if (!blank_line) blank_line = src.line_number();
      src.skip_blank_lines();  // a run of them at the cost of its bytes (a bomb's padding)
      continue;
    }
    if (blank_line) fail_blank(blank_line);
    parser.parse(line, src.line_number());
    sink.after_row(parser.rows(), [&] { return where(path, src.line_number()); });
  }
  std::vector<Samples> columns = sink.finish();
  set.spilled = sink.spilled();

  const std::int64_t rows = parser.rows();
  if (rows < kMinSamples)
    throw InputError(path + ": found " + std::to_string(rows) + (rows == 1 ? " sample" : " samples") +
                     ", expected at least " + std::to_string(kMinSamples) +
                     " (the wavelet variance needs 4 levels, 2^4 samples)");
  for (std::size_t i = 0; i < selected.size(); ++i) {
    if (const std::optional<double> c = detail::constant_value(columns[i])) {
      char buf[64];
      *std::to_chars(buf, buf + sizeof buf - 1, *c).ptr = '\0';
      throw InputError(path + ": column " + std::to_string(selected[i] + 1) + " '" + cols[selected[i]].header +
                       "': found all " + std::to_string(rows) + " values equal to " + buf +
                       ", expected a varying signal (a constant has a wavelet variance of zero)");
    }
  }
  for (std::size_t i = 0; i < selected.size(); ++i) {
    const Column& c = cols[selected[i]];
    set.signals.push_back(Signal{c.name, std::move(columns[i]), c.unit});
  }

  if (time_col) {
    const Column& c = cols[*time_col];
    detail::TimeUnit unit = detail::timestamp_name(c.header).value_or(detail::TimeUnit{});
    std::string source = "stated in the header";
    if (unit.to_seconds == 0.0 && preset) {
      unit = preset->time_unit;
      source = std::string(preset->name) + " layout";
    }
    set.timing = detail::analyse_timing(c.header, parser.time_steps(), parser.first_time(), unit, source);
    set.timing->given_freq = options.freq;
    detail::check_timestamp_rate(path, *set.timing, options);
  }
  if (options.freq) {
    set.freq = *options.freq;
    set.freq_known = true;
  } else if (set.timing && set.timing->estimated_freq > 0.0) {
    set.freq = set.timing->estimated_freq;
    set.freq_known = true;
  } else {
    detail::refuse_never_increasing(path, *set.timing);
  }
  detail::finish_record(path, set, options);
  return set;
}

}  // namespace

}  // namespace gmwm::io
