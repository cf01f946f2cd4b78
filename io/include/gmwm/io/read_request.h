#pragma once
// What every face reads a recording with: the command line's --columns, --freq, --topic and
// --memory, the web app's /api/open fields and gmwm.read's keywords fill one ReadRequest,
// read and refused by one function (issue 45: the CLI alone split --columns and refused a
// recording without a rate in its own words; Python could not read a file at all).

#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io {

/// --memory's range in MB: a megabyte at least (below, not even a header's worth of values),
/// a terabyte at most (beyond any machine's memory, so a typo rather than a budget).
inline constexpr double kMinMemoryMb = 1.0;
inline constexpr double kMaxMemoryMb = 1e12;
/// "" when `mb` is within [kMinMemoryMb, kMaxMemoryMb], else "found 'TEXT', expected a
/// number of MB from 1 to 1e12" (`text`: the value as the user wrote it).
std::string memory_problem(double mb, const std::string& text);
/// "a number of MB from 1 to 1e12": what memory_problem expects.
std::string memory_expected();

struct ReadRequest {
  std::string path;
  /// --columns: names or 1-based indices; empty: every numeric column that is not a timestamp.
  std::vector<std::string> columns;
  std::optional<double> freq;       ///< --freq HZ: overrides the timestamps' rate
  std::string topic;                ///< --topic NAME[:INSTANCE] of a log or bag
  std::optional<double> memory_mb;  ///< --memory MB (default: kMemoryShare of physical memory)
  /// Beyond the memory: true, the columns go on in temporary files; false (a face that hands
  /// the values over in memory, as Python's arrays), refused with one line.
  bool spill = true;
  /// --gaps windows|join (gap_handling_name).
  GapHandling gaps = GapHandling::kCompleteWindows;
  /// --data rate|increment, --decimate K, --decimate-filter average|none.
  DataKind data = DataKind::kRate;
  int decimate = 1;
  DecimationFilter decimate_filter = DecimationFilter::kAverage;

  /// The reader's options; throws InputError (naming the option) for a bad value.
  ReadOptions options() const;
};

/// "a, b,,c" as {"a", "b", "", "c"}: entries split at commas, blanks around them trimmed
/// (every comma-separated option of every face: --columns, --targets, --units, ...).
std::vector<std::string> comma_list(const std::string& text);

/// --columns "a, b,3" as a list: entries split at commas, blanks around them trimmed.
/// Throws InputError for an empty list or an empty entry ("--columns 'a,,b': found an empty
/// name, expected names or 1-based indices separated by commas").
std::vector<std::string> column_list(const std::string& text);

/// Reads the request (read_signals) and refuses a recording whose rate is unknown (no
/// timestamp column and no --freq): "PATH:1: found no timestamp column in the header,
/// expected one (timestamp, time, t, ...) or the sampling rate as --freq HZ"; and a --topic
/// list (several topics are parts: read_request_parts), for every face that reads one record
/// (gap, export, the fleet's rows, the web app, gmwm.read).
SignalSet read_request(const ReadRequest& request);

/// One part of a recording, read at its own rate: a topic of --topic A,B (the RealSense case:
/// the gyroscope and the accelerometer on separate topics at different rates), the columns
/// of one timestamp column of a table whose stamp columns each stamp their own
/// (stamped_columns.h; `stamps` names it, `topic` empty), or the whole record (topic as
/// requested).
struct RecordPart {
  std::string topic;
  SignalSet set;
  std::string stamps = {};
  /// "topic /camera/gyro/sample", "stamps gyro_timestamp [ns]" or "" (the whole record).
  std::string label() const;
};

/// --topic "A, B" as {"A", "B"}: entries split at commas, blanks trimmed; {} for "" and one
/// entry for one topic. Throws InputError for an empty entry or a topic named twice
/// ("--topic 'A,,B': found an empty name, expected topics separated by commas").
std::vector<std::string> topic_list(const std::string& text);

/// The request's parts: one per topic of a --topic list, or per timestamp column of a table
/// whose stamp columns each stamp their own (stamped_columns), each read by read_request with
/// its own stamps, rate, gaps and repeated samples (no resampling); else the one record. With
/// several parts --columns names the columns to keep from whichever part gives them (a part
/// left with none is left out); refused (InputError, one line): --freq (each part's rate is
/// its stamps'), a column index, a name no part gives, a name two parts give.
std::vector<RecordPart> read_request_parts(const ReadRequest& request);

}  // namespace gmwm::io
