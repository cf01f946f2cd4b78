#include "column_sink.h"

#include <algorithm>
#include <limits>

#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {

ColumnSink::ColumnSink(std::string path, std::vector<std::vector<double>>& columns, const ReadOptions& options,
                       SinkNouns nouns, StepStatistics* steps)
    : path_(std::move(path)),
      columns_(columns),
      options_(options),
      nouns_(nouns),
      steps_(steps),
      budget_(options.memory_budget > 0.0 ? options.memory_budget : memory_budget_bytes()),
      max_rows_(budget_ > 0.0
                    ? static_cast<std::int64_t>(budget_ / (kBytesPerValue * static_cast<double>(std::max<std::size_t>(
                                                                                columns.size() + (steps ? 1 : 0), 1))))
                    : std::numeric_limits<std::int64_t>::max()) {}

ColumnSink::~ColumnSink() = default;

std::size_t ColumnSink::rows_to_reserve(std::uint64_t rows) const {
  return static_cast<std::size_t>(std::min<std::uint64_t>(rows, static_cast<std::uint64_t>(max_rows_) + 1));
}

void ColumnSink::spill(const std::string& where) {
  const std::string limit =
      "the memory budget of " + std::to_string(static_cast<long long>(budget_ / 1e6)) + " MB" +
      (options_.memory_budget > 0.0
           ? std::string()
           : " (" + std::to_string(static_cast<int>(100 * kMemoryShare)) + "% of this machine's memory)");
  if (!options_.spill)
    throw InputError(where + "found more than " + std::to_string(max_rows_) + " " + nouns_.rows + " of " +
                     std::to_string(columns_.size()) + " " + nouns_.columns +
                     (steps_ ? std::string(" and a timestamp column") : std::string()) + ", expected at most " +
                     std::to_string(max_rows_) + ": at " + std::to_string(static_cast<int>(kBytesPerValue)) +
                     " bytes a value they exceed " + limit + "; " + nouns_.fewer);
  spdlog::info("{}: more than {} {} exceed {}: the values go to temporary files in {}", path_, max_rows_, nouns_.rows,
               limit, gmwm::detail::temporary_folder());
  for (std::size_t i = 0; i < columns_.size(); ++i) files_.push_back(std::make_unique<SampleFileWriter>());
  empty_into_files();
  if (steps_) steps_->spill_to_file();  // the steps of jittery stamps, 8 bytes a row, too
  for (auto& v : columns_) {
    std::vector<double>().swap(v);  // give the budget's memory back
    v.reserve(static_cast<std::size_t>(kRowsPerMemoryCheck));
  }
}

void ColumnSink::empty_into_files() {
  for (std::size_t i = 0; i < files_.size(); ++i) {
    std::vector<double>& v = columns_[i];
    files_[i]->append(v.data(), v.size());
    v.clear();
  }
}

std::vector<Samples> ColumnSink::finish() {
  std::vector<Samples> out;
  if (spilled()) empty_into_files();
  for (std::size_t i = 0; i < columns_.size(); ++i)
    out.push_back(spilled() ? files_[i]->finish() : Samples(std::move(columns_[i])));
  return out;
}

std::optional<double> constant_value(const Samples& x) {
  if (x.empty()) return std::nullopt;
  const double first = x.front();
  bool constant = true;
  for_each_block(x, [&](std::span<const double> part, std::size_t) {
    constant = constant && std::all_of(part.begin(), part.end(), [&](double v) { return v == first; });
  });
  return constant ? std::optional<double>(first) : std::nullopt;
}

}  // namespace gmwm::io::detail
