#pragma once
// What the binary log readers (PX4 ULog, ROS 1, rosbag2, MCAP) share once they decode a
// topic's messages: the axes --columns picks, kept as they come within the memory budget
// and in temporary files beyond it (ColumnSink, as the text reader does), the stamps reduced
// to their steps as they come (StepStatistics), and at the end the checks of a signal set
// (enough messages, no constant axis) and the timing report.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "column_sink.h"
#include "gmwm/io/signal_reader.h"
#include "timestamp.h"

namespace gmwm::io::detail {

/// One axis a topic gives.
struct LogAxis {
  std::string name, unit;
};

class LogColumns {
 public:
  /// `axes`: every axis the topic gives, in the order add() takes their values; `what` names
  /// the topic in messages ("topic sensor_combined"). Throws InputError for a --columns name
  /// the topic does not give.
  LogColumns(std::string path, std::string what, std::vector<LogAxis> axes, const ReadOptions& options);

  /// Reserves room for up to `messages` messages (within the budget).
  void reserve(std::uint64_t messages);

  /// The next message: its stamp (in the log's unit; increasing, checked by the caller) and
  /// the values of every axis. `where()` gives the prefix of a refusal for this message
  /// ("FILE: topic T message N: ").
  template <class Where>
  void add(double stamp, const double* values, Where&& where) {
    if (count_ == 0) first_ = stamp;
    steps_.add(stamp - first_, std::max(std::fabs(stamp), std::fabs(first_)));
    last_ = stamp;
    for (std::size_t k = 0; k < pick_.size(); ++k) columns_[k].push_back(values[pick_[k]]);
    sink_.after_row(++count_, where);
  }

  std::int64_t size() const { return count_; }
  /// The last stamp added (meaningless before the first).
  double last() const { return last_; }

  /// The signal set. Throws InputError for fewer than kMinSamples messages or a constant axis.
  SignalSet finish(const std::string& preset, const TimeUnit& unit, const std::string& unit_source) &&;

 private:
  std::string path_, what_;
  std::vector<LogAxis> axes_;
  const ReadOptions& options_;
  std::vector<std::size_t> pick_;  // the axes kept, as indices into axes_
  std::vector<std::vector<double>> columns_;
  StepStatistics steps_;  // before sink_, which holds its address
  ColumnSink sink_;
  std::int64_t count_ = 0;
  double first_ = 0.0, last_ = 0.0;
};

}  // namespace gmwm::io::detail
