#pragma once
// What the binary log readers (PX4 ULog, rosbag2) share once they have a topic's values:
// picking --columns among the topic's axes, refusing a constant axis, and the timing report
// of the message stamps.

#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "timestamp.h"

namespace gmwm::io::detail {

/// One axis a topic gives.
struct LogAxis {
  std::string name, unit;
  std::vector<double> values;
};

/// The signal set of a log topic. `stamps` are the messages' times in `unit`, increasing;
/// `what` names the topic in messages ("topic sensor_combined"). Throws InputError for
/// fewer than kMinSamples messages, a --columns name the topic does not give, or a constant axis.
SignalSet log_signal_set(const std::string& path, const std::string& preset, const std::string& what,
                         std::vector<LogAxis> axes, const std::vector<double>& stamps, const TimeUnit& unit,
                         const std::string& unit_source, const ReadOptions& options);

}  // namespace gmwm::io::detail
