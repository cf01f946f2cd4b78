#include "log_signals.h"

#include <algorithm>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {
namespace {

std::vector<std::size_t> picked(const std::string& path, const std::string& what, const std::vector<LogAxis>& axes,
                                const ReadOptions& options) {
  std::vector<std::size_t> pick;
  if (options.columns.empty()) {
    for (std::size_t k = 0; k < axes.size(); ++k) pick.push_back(k);
    return pick;
  }
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
  return pick;
}

}  // namespace

LogColumns::LogColumns(std::string path, std::string what, std::vector<LogAxis> axes, const ReadOptions& options)
    : path_(std::move(path)),
      what_(std::move(what)),
      axes_(std::move(axes)),
      options_(options),
      pick_(picked(path_, what_, axes_, options)),
      columns_(pick_.size()),
      sink_(path_, columns_, options, SinkNouns{"messages", "axes", "read fewer axes with --columns"}, &steps_) {}

void LogColumns::reserve(std::uint64_t messages) {
  const std::size_t n = sink_.rows_to_reserve(messages);
  for (auto& c : columns_) c.reserve(n);
}

SignalSet LogColumns::finish(const std::string& preset, const TimeUnit& unit, const std::string& unit_source) && {
  if (count_ < kMinSamples)
    throw InputError(path_ + ": " + what_ + " has " + std::to_string(count_) + " messages, expected at least " +
                     std::to_string(kMinSamples));
  SignalSet set;
  set.path = path_;
  set.preset = preset;
  set.spilled = sink_.spilled();
  std::vector<Samples> values = sink_.finish();
  // Axes left unpicked that are 0 in every message are a sensor the topic does not carry
  // (RealSense's gyro topic has linear_acceleration 0, its accel topic angular_velocity 0):
  // left out with a note while another axis varies. An axis named by --columns is refused.
  std::vector<bool> absent(pick_.size(), false);
  std::string absent_names;
  bool varying = false;
  for (std::size_t k = 0; k < pick_.size(); ++k) {
    const std::optional<double> c = constant_value(values[k]);
    absent[k] = options_.columns.empty() && c && *c == 0.0;
    varying = varying || !c;
    if (absent[k]) absent_names += (absent_names.empty() ? "" : ", ") + axes_[pick_[k]].name;
  }
  for (std::size_t k = 0; k < pick_.size(); ++k) {
    const LogAxis& a = axes_[pick_[k]];
    if (absent[k] && varying) continue;
    if (const std::optional<double> c = constant_value(values[k]))
      throw InputError(path_ + ": " + what_ + " " + a.name + ": found all " + std::to_string(count_) +
                       " values equal to " + std::to_string(*c) +
                       ", expected a varying signal (a constant has a wavelet variance of zero)");
    set.signals.push_back({a.name, std::move(values[k]), a.unit});
  }
  if (varying && !absent_names.empty())
    set.notes.push_back(what_ + ": " + absent_names + " are 0 in every one of its " + std::to_string(count_) +
                        " messages (a sensor the topic does not carry): left out");
  set.timing = analyse_timing("stamp", steps_, first_, unit, unit_source);
  set.timing->given_freq = options_.freq;
  check_timestamp_rate(path_, *set.timing, options_);
  if (options_.freq) {
    set.freq = *options_.freq;
    set.freq_known = true;
  } else if (set.timing->estimated_freq > 0.0) {
    set.freq = set.timing->estimated_freq;
    set.freq_known = true;
  } else {
    refuse_never_increasing(path_, *set.timing);
  }
  finish_record(path_, set, options_);
  return set;
}

}  // namespace gmwm::io::detail
