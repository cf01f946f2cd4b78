#include "log_signals.h"

#include <algorithm>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {

SignalSet log_signal_set(const std::string& path, const std::string& preset, const std::string& what,
                         std::vector<LogAxis> axes, const std::vector<double>& stamps, const TimeUnit& unit,
                         const std::string& unit_source, const ReadOptions& options) {
  if (static_cast<std::int64_t>(stamps.size()) < kMinSamples)
    throw InputError(path + ": " + what + " has " + std::to_string(stamps.size()) + " messages, expected at least " +
                     std::to_string(kMinSamples));
  std::vector<std::size_t> pick;
  if (options.columns.empty()) {
    for (std::size_t k = 0; k < axes.size(); ++k) pick.push_back(k);
  } else {
    for (const std::string& c : options.columns) {
      std::size_t k = 0;
      while (k < axes.size() && axes[k].name != c) ++k;
      if (k == axes.size()) {
        std::string names;
        for (const LogAxis& a : axes) names += (names.empty() ? "" : ", ") + a.name;
        throw InputError(path + ": --columns " + c + ": " + what + " gives " + names);
      }
      pick.push_back(k);
    }
  }
  SignalSet set;
  set.path = path;
  set.preset = preset;
  for (std::size_t k : pick) {
    const std::vector<double>& v = axes[k].values;
    if (std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); }))
      throw InputError(path + ": " + what + " " + axes[k].name + ": found all " + std::to_string(v.size()) +
                       " values equal to " + std::to_string(v.front()) +
                       ", expected a varying signal (a constant has a wavelet variance of zero)");
    set.signals.push_back({axes[k].name, std::move(axes[k].values), axes[k].unit});
  }
  std::vector<double> offsets(stamps.size());
  for (std::size_t i = 0; i < stamps.size(); ++i) offsets[i] = stamps[i] - stamps.front();
  set.timing = analyse_timing("stamp", offsets, stamps.front(), unit, unit_source);
  set.timing->given_freq = options.freq;
  check_one_rate(path, *set.timing, options);
  if (options.freq) {
    set.freq = *options.freq;
    set.freq_known = true;
  } else if (set.timing->estimated_freq > 0.0) {
    set.freq = set.timing->estimated_freq;
    set.freq_known = true;
  }
  return set;
}

}  // namespace gmwm::io::detail
