#pragma once
// Delimited-text parsing for the signal reader: delimiter detection, header splitting,
// number parsing with std::from_chars, and the one-pass row parser that appends each
// wanted cell to its column without allocating per line.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "timestamp.h"

namespace gmwm::io::detail {

enum class Delimiter : char { kComma = ',', kTab = '\t', kSemicolon = ';', kWhitespace = ' ' };

std::string delimiter_name(Delimiter d);

/// True when every token of `line` (split on , ; and blanks) is a number.
bool is_numeric_row(std::string_view line);

/// The delimiter of a file from its header and first data row (empty when none):
/// comma, tab or semicolon when the header has it as often as the data row, else runs of
/// whitespace.
Delimiter detect_delimiter(std::string_view header, std::string_view first_row);

/// Header names, trimmed, double quotes removed ("" inside quotes is one quote).
std::vector<std::string> split_header(std::string_view header, Delimiter d);

/// Fields of a data row, trimmed (no quote handling).
std::vector<std::string_view> split_fields(std::string_view line, Delimiter d);

enum class NumberStatus { kOk, kEmpty, kNotANumber, kNotFinite, kOutOfRange };

/// Parses a whole field (surrounding blanks allowed, a leading '+' too).
NumberStatus parse_number(std::string_view field, double& out);

/// What to do with each field of a row.
struct FieldPlan {
  enum Kind : std::uint8_t { kSkip, kValue, kTime };
  Kind kind = kSkip;
  int slot = 0;  // index into RowParser::values for kValue
};

class RowParser {
 public:
  /// `names` are the header names (used in error messages); `plan` has one entry per field.
  RowParser(std::string path, Delimiter d, std::vector<FieldPlan> plan, std::vector<std::string> names,
            int value_slots);

  /// Parses one data row; throws InputError naming the line and column on bad cells or a
  /// wrong number of fields.
  void parse(std::string_view line, std::int64_t line_number);

  /// A row whose field `field` (0-based) is empty is skipped, not parsed nor counted: another
  /// sensor's row in a file whose stamp columns each stamp their own (stamped_columns.h).
  void skip_rows_without(std::size_t field) { skip_without_ = field; }
  /// The rows skipped so.
  std::int64_t skipped_rows() const { return skipped_; }

  /// Reserves room for about `rows` rows in every column.
  void reserve(std::size_t rows);

  std::int64_t rows() const { return rows_; }
  std::vector<std::vector<double>>& values() { return values_; }
  /// The steps of the times, in the file's unit, taken from times relative to the first
  /// one: exact for integer timestamps such as nanoseconds since 1970 (which a double
  /// cannot hold exactly). The times themselves are not kept.
  const StepStatistics& time_steps() const { return time_steps_; }
  StepStatistics& time_steps() { return time_steps_; }
  double first_time() const { return first_time_; }
  bool has_time() const { return has_time_; }

 private:
  template <char kDelim>
  void parse_delimited(const char* p, const char* e, std::int64_t line_number);
  void parse_whitespace(const char* p, const char* e, std::int64_t line_number);
  void store(const FieldPlan& f, const char* b, const char* e, std::int64_t line_number, std::size_t field);
  void store_time(const char* b, const char* e, std::int64_t line_number, std::size_t field);
  [[noreturn]] void fail_cell(std::int64_t line_number, std::size_t field, std::string_view text,
                              NumberStatus status) const;
  [[noreturn]] void fail_count(std::int64_t line_number, std::size_t found, bool too_many,
                               std::string_view extra) const;

  std::string path_;
  Delimiter delim_;
  std::vector<FieldPlan> plan_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> values_;
  StepStatistics time_steps_;
  std::int64_t rows_ = 0;
  std::optional<std::size_t> skip_without_;
  std::int64_t skipped_ = 0;
  bool field_empty(std::string_view line, std::size_t field) const;
  bool has_time_ = false;
  bool first_time_is_int_ = false;
  std::int64_t first_time_int_ = 0;
  double first_time_ = 0.0;
};

}  // namespace gmwm::io::detail
