#include "datasets.h"

#include <algorithm>

#include "jobs.h"
#include "request.h"

namespace gmwm::serve::detail {

std::shared_ptr<const Dataset> Datasets::add(Dataset d) {
  d.id = random_id("d");
  auto data = std::make_shared<const Dataset>(std::move(d));
  std::lock_guard lock(mutex_);
  entries_[data->id] = {data, std::chrono::steady_clock::now()};
  // Drop the least recently used beyond the limits, never the one just added.
  for (;;) {
    double bytes = 0.0;
    for (const auto& [id, e] : entries_) bytes += e.data->bytes;
    if (entries_.size() <= max_count_ && (bytes <= max_bytes_ || entries_.size() == 1)) break;
    auto oldest = entries_.end();
    for (auto it = entries_.begin(); it != entries_.end(); ++it)
      if (it->first != data->id && (oldest == entries_.end() || it->second.used < oldest->second.used)) oldest = it;
    if (oldest == entries_.end()) break;
    entries_.erase(oldest);
  }
  return data;
}

std::shared_ptr<const Dataset> Datasets::find(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(id);
  if (it == entries_.end()) return nullptr;
  it->second.used = std::chrono::steady_clock::now();
  return it->second.data;
}

std::size_t Datasets::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

io::SignalSet columns_set(const Dataset& d, const std::vector<std::string>& columns, const char* field,
                          const std::string& where) {
  io::SignalSet s = d.set;  // the samples are shared, not copied
  s.signals.clear();
  for (const std::string& column : columns) {
    const auto it =
        std::find_if(d.set.signals.begin(), d.set.signals.end(), [&](const io::Signal& x) { return x.name == column; });
    if (it == d.set.signals.end()) {
      std::string names;
      for (const io::Signal& x : d.set.signals) names += (names.empty() ? "" : ", ") + x.name;
      throw HttpError(
          400, where + ": field '" + field + "': '" + column + "' is not a column of " + d.name + " (" + names + ")");
    }
    for (const io::Signal& kept : s.signals)
      if (kept.name == column)
        throw HttpError(
            400, where + ": field '" + field + "': found column '" + column + "' twice, expected each column once");
    s.signals.push_back(*it);
  }
  return s;
}

io::SignalSet column_set(const Dataset& d, const std::string& column, const std::string& where) {
  return columns_set(d, {column}, "column", where);
}

}  // namespace gmwm::serve::detail
