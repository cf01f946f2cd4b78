#pragma once
// The recordings a page opened: read once, kept in memory (or in the reader's temporary
// files beyond its budget) under a random id, the least recently used dropped beyond a
// count and a size. A job holds its dataset by shared pointer, so dropping one never pulls
// the data from under a running study.

#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"

namespace gmwm::serve::detail {

struct Dataset {
  std::string id;
  std::string name;  ///< the recording's path under FOLDER, or the upload's file name
  io::SignalSet set;
  double bytes = 0.0;  ///< 8 bytes per value held
};

class Datasets {
 public:
  Datasets(std::size_t max_count, double max_bytes) : max_count_(max_count), max_bytes_(max_bytes) {}

  /// Keeps `d` (its id set here); the least recently used beyond the limits are dropped.
  std::shared_ptr<const Dataset> add(Dataset d);
  /// The dataset of `id` (marked used), nullptr when unknown or dropped.
  std::shared_ptr<const Dataset> find(const std::string& id);
  std::size_t size() const;

 private:
  struct Entry {
    std::shared_ptr<const Dataset> data;
    std::chrono::steady_clock::time_point used;
  };
  std::size_t max_count_;
  double max_bytes_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

/// The set a study of `columns` runs on, in their order (the CLI's `--columns A,B,C`);
/// HttpError 400 naming the request's `field` and the dataset's columns when one is not a
/// column, or naming the column given twice.
io::SignalSet columns_set(const Dataset& d, const std::vector<std::string>& columns, const char* field,
                          const std::string& where);

/// The one-column set a study of `column` runs on (the CLI's `--columns COLUMN`); HttpError
/// 400 naming the columns when `column` is not one.
io::SignalSet column_set(const Dataset& d, const std::string& column, const std::string& where);

}  // namespace gmwm::serve::detail
