#include "gmwm/io/read_request.h"

#include <cmath>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::io {

std::string memory_expected() {
  static_assert(kMinMemoryMb == 1.0 && kMaxMemoryMb == 1e12, "the text below states the range");
  return "a number of MB from 1 to 1e12";
}

std::string memory_problem(double mb, const std::string& text) {
  if (mb >= kMinMemoryMb && mb <= kMaxMemoryMb) return "";
  return "found '" + text + "', expected " + memory_expected();
}

ReadOptions ReadRequest::options() const {
  ReadOptions o;
  o.columns = columns;
  o.freq = freq;
  o.topic = topic;
  if (memory_mb) {
    if (const std::string why = memory_problem(*memory_mb, significant(*memory_mb)); !why.empty())
      throw InputError("--memory: " + why);
    o.memory_budget = *memory_mb * 1e6;
  }
  o.spill = spill;
  o.gaps = gaps;
  o.data = data;
  o.decimate = decimate;
  o.decimate_filter = decimate_filter;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(why);
  return o;
}

std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  std::string entry;
  std::istringstream is(text);
  while (std::getline(is, entry, ',')) {
    const auto b = entry.find_first_not_of(" \t");
    const auto e = entry.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? std::string() : entry.substr(b, e - b + 1));
  }
  return out;
}

std::vector<std::string> column_list(const std::string& text) {
  const std::vector<std::string> out = comma_list(text);
  if (out.empty())
    throw InputError("--columns: found an empty list, expected names or 1-based indices separated by commas");
  for (const std::string& c : out)
    if (c.empty())
      throw InputError("--columns '" + text +
                       "': found an empty name, expected names or 1-based indices separated by commas");
  return out;
}

SignalSet read_request(const ReadRequest& request) {
  SignalSet set = read_signals(request.path, request.options());
  if (!set.freq_known)
    throw InputError(request.path +
                     ":1: found no timestamp column in the header, expected one (timestamp, time, t, ...) or the "
                     "sampling rate as --freq HZ");
  return set;
}

}  // namespace gmwm::io
