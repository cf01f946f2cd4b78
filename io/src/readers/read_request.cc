#include "gmwm/io/read_request.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/io/stamped_columns.h"

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
  if (topic_list(request.topic).size() > 1)
    throw InputError("--topic '" + request.topic +
                     "': found several topics where one record is read; wv, fit and select (gmwm.read_parts) read "
                     "several, each at its own rate");
  SignalSet set = read_signals(request.path, request.options());
  if (!set.freq_known)
    throw InputError(request.path +
                     ":1: found no timestamp column in the header, expected one (timestamp, time, t, ...) or the "
                     "sampling rate as --freq HZ");
  return set;
}

std::vector<std::string> topic_list(const std::string& text) {
  if (text.empty()) return {};
  const std::vector<std::string> out = comma_list(text);
  std::set<std::string> seen;
  for (const std::string& t : out) {
    if (t.empty()) throw InputError("--topic '" + text + "': found an empty name, expected topics separated by commas");
    if (!seen.insert(t).second)
      throw InputError("--topic '" + text + "': found " + t + " twice, expected each topic once");
  }
  return out;
}

std::string RecordPart::label() const {
  if (!topic.empty()) return "topic " + topic;
  if (!stamps.empty()) return "stamps " + stamps;
  return "";
}

namespace {

// "A (gyro_x, gyro_y); B (accel_x)": what each part gives, for a --columns refusal.
std::string parts_columns(const std::vector<RecordPart>& parts) {
  std::string out;
  for (const RecordPart& p : parts) {
    out += (out.empty() ? "" : "; ") + p.label() + " (";
    for (std::size_t i = 0; i < p.set.signals.size(); ++i) out += (i ? ", " : "") + p.set.signals[i].name;
    out += ")";
  }
  return out;
}

// Several parts (`what`: "--topic 'A,B'", "the timestamp columns of PATH"): --columns names
// (not indices), no --freq.
void check_parts_request(const ReadRequest& request, const std::string& what) {
  if (request.freq)
    throw InputError("--freq with " + what +
                     ": each part is read at the rate of its own stamps; give --freq with one part");
  for (const std::string& c : request.columns)
    if (!c.empty() && c.find_first_not_of("0123456789") == std::string::npos)
      throw InputError("--columns " + c + " with " + what +
                       ": found an index, expected the names of the columns to keep (gyro_x, accel_y, ...)");
}

// Keeps the named columns of each part (every one when none is named); refuses a name no part
// gives and a name two parts give; leaves out a part left with none.
std::vector<RecordPart> keep_named_columns(const ReadRequest& request, std::vector<RecordPart> parts) {
  std::map<std::string, std::string> giver;  // column name -> the part giving it
  for (const RecordPart& p : parts)
    for (const Signal& s : p.set.signals)
      if (const auto [it, fresh] = giver.emplace(s.name, p.label()); !fresh)
        throw InputError(request.path + ": " + it->second + " and " + p.label() + " both give " + s.name +
                         ": read each in its own run (or one as a replicate of the other with --joint)");
  if (request.columns.empty()) return parts;
  const std::set<std::string> named(request.columns.begin(), request.columns.end());
  for (const std::string& c : request.columns)
    if (!giver.count(c))
      throw InputError("--columns " + c + ": found in none of the parts, expected a column of " + parts_columns(parts));
  std::vector<RecordPart> kept;
  for (RecordPart& p : parts) {
    std::erase_if(p.set.signals, [&](const Signal& s) { return !named.count(s.name); });
    if (!p.set.signals.empty()) kept.push_back(std::move(p));
  }
  return kept;
}

// One stamp column's part. A refusal of the whole part ("PATH: found 10 samples, expected at
// least 16") names the stamp column and its columns, since the file holds several; one that
// names its line and column already says where.
SignalSet read_stamped_part(const ReadRequest& one, const StampedColumns& g) {
  try {
    return read_request(one);
  } catch (const InputError& e) {
    const std::string message = e.what(), prefix = one.path + ": ";
    if (!message.starts_with(prefix)) throw;
    std::string columns;
    for (const std::string& c : g.columns) columns += (columns.empty() ? "" : ", ") + c;
    throw InputError(prefix + "the columns stamped by '" + g.stamp + "' (" + columns +
                     "): " + message.substr(prefix.size()));
  }
}

// A table's stamp columns, each with the columns it stamps, read as parts.
std::vector<RecordPart> read_stamp_parts(const ReadRequest& request, const std::vector<StampedColumns>& groups) {
  check_parts_request(request, "the timestamp columns of " + request.path);
  std::vector<RecordPart> parts;
  for (const StampedColumns& g : groups) {
    ReadRequest one = request;
    one.columns.clear();
    for (const std::size_t f : g.fields) one.columns.push_back(std::to_string(f));
    parts.push_back({"", read_stamped_part(one, g), g.stamp});
  }
  return keep_named_columns(request, std::move(parts));
}

}  // namespace

std::vector<RecordPart> read_request_parts(const ReadRequest& request) {
  const std::vector<std::string> topics = topic_list(request.topic);
  if (topics.empty())
    if (const std::vector<StampedColumns> groups = stamped_columns(request.path); groups.size() > 1)
      return read_stamp_parts(request, groups);
  if (topics.size() <= 1) return {{request.topic, read_request(request)}};
  check_parts_request(request, "--topic '" + request.topic + "'");
  std::vector<RecordPart> parts;
  for (const std::string& topic : topics) {
    ReadRequest one = request;
    one.topic = topic;
    one.columns.clear();  // each topic's own axes; the names are kept below
    parts.push_back({topic, read_request(one)});
  }
  return keep_named_columns(request, std::move(parts));
}

}  // namespace gmwm::io
