#pragma once
// The memory budget of a reader (docs/cli.md "Memory and limits"), shared by every input
// format: the values read go to vectors up to the budget (ReadOptions::memory_budget at
// kBytesPerValue a value, or kMemoryShare of the machine's memory), then on in unlinked
// temporary files (gmwm::SampleFileWriter, samples.h), emptied into them every
// kRowsPerMemoryCheck rows; or, when spilling is off, the input is refused with one line.
// The values are the same whichever way they are held.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gmwm/engine/samples.h"
#include "gmwm/io/signal_reader.h"
#include "timestamp.h"

namespace gmwm::io::detail {

/// Rows between two checks of the memory budget (and, past it, between two emptyings of the
/// columns into their files).
inline constexpr std::int64_t kRowsPerMemoryCheck = std::int64_t{1} << 16;

/// How a reader names what it reads in its messages.
struct SinkNouns {
  const char* rows;     ///< "rows", "messages"
  const char* columns;  ///< "column(s)", "axes"
  const char* fewer;    ///< the way to read less: "read fewer columns with --columns"
};

class ColumnSink {
 public:
  /// `columns`: the vectors the reader appends each row's values to (the sink empties them
  /// into files past the budget); `path` names the input in messages. `steps`, when the
  /// input has timestamps: their steps count as one more column (jittery stamps keep a step
  /// a row) and go to a temporary file with the columns (StepStatistics::spill_to_file).
  ColumnSink(std::string path, std::vector<std::vector<double>>& columns, const ReadOptions& options, SinkNouns nouns,
             StepStatistics* steps = nullptr);
  ~ColumnSink();
  ColumnSink(const ColumnSink&) = delete;
  ColumnSink& operator=(const ColumnSink&) = delete;

  /// Rows kept in memory before the columns go to files.
  std::int64_t max_rows() const { return max_rows_; }

  /// Rows worth reserving for about `rows` rows: no more than the budget holds. Virtual
  /// memory, touched only when used, that saves regrowing the columns.
  std::size_t rows_to_reserve(std::uint64_t rows) const;

  /// Called after each row; `rows` counts the rows so far, `where()` gives the prefix of a
  /// refusal ("FILE:LINE: ", "FILE: topic T message N: ").
  template <class Where>
  void after_row(std::int64_t rows, Where&& where) {
    if (rows % kRowsPerMemoryCheck != 0) return;
    if (!files_.empty()) {
      empty_into_files();
      return;
    }
    if (rows <= max_rows_) return;
    spill(where());
  }

  bool spilled() const { return !files_.empty(); }

  /// The columns, moved out of the vectors or handed over by their files.
  std::vector<Samples> finish();

 private:
  void spill(const std::string& where);
  void empty_into_files();

  std::string path_;
  std::vector<std::vector<double>>& columns_;
  const ReadOptions& options_;
  SinkNouns nouns_;
  StepStatistics* steps_;
  double budget_;
  std::int64_t max_rows_;
  std::vector<std::unique_ptr<SampleFileWriter>> files_;
};

/// The value of a series whose values are all equal, else nullopt (a series in a file is read
/// in blocks whose pages are released behind).
std::optional<double> constant_value(const Samples& x);

}  // namespace gmwm::io::detail
