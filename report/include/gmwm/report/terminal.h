#pragma once
// The terminal's rendering, shared by the CLI and Python: tables that fit a terminal's width
// (a cell too long for its column goes below the table as a note), text wrapped to it, and
// the per-axis summary of a fit or select document (model, N, K, B in the data's units and
// in datasheet units, the goodness-of-fit verdict), read from the JSON document itself so
// that the terminal shows the numbers the JSON holds.
//
//   report::TextTable t({"level", "tau", "wv"}, 1);
//   t.add({"1", "0.01", "1.2e-05"});
//   std::cout << t.str();                        // <= kTerminalWidth columns
//   std::cout << report::axis_summary(doc);      // a fit/select --json document

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// The width every table and line of the terminal fits (the README's example commands are
/// tested against it): the common 100-column terminal. Long explanations go below the
/// tables, wrapped, never as a column.
inline constexpr std::size_t kTerminalWidth = 100;

/// A number for tables and text: %.<digits>g, "-" when not finite.
std::string fmt(double x, int digits = 6);

/// A table of text: the first `left` columns left-aligned, the rest right-aligned. When the
/// table is wider than `width`, its widest columns (other than the first, the row's name)
/// leave the grid one by one until it fits: their cells follow the table as notes
/// ("  <row name>, <column>: <cell>"), wrapped to `width`. Cells are printable lines.
class TextTable {
 public:
  explicit TextTable(std::vector<std::string> header, int left = 0);
  void add(std::vector<std::string> row);
  std::string str(std::size_t width = kTerminalWidth) const;

 private:
  std::vector<std::vector<std::string>> rows_;
  int left_;
};

/// `text` with every line longer than `width` wrapped at spaces, the continuation lines
/// indented four more than the line's own indent (a word longer than the room is cut).
std::string wrap_to_width(const std::string& text, std::size_t width = kTerminalWidth);

/// A noise figure in a datasheet's unit: N in deg/sqrt(h) (gyro) or ug/sqrt(Hz) (accel), K in
/// deg/h/sqrt(h) or m/s^2/sqrt(h), B in deg/h or mg, Q in arcsec or mm/s (the angle or
/// velocity quantum), R in deg/h^2 or mg/h. `figure` is 'N', 'K', 'B', 'Q' or 'R'; `value` is
/// in the data's unit `data_unit` (rad/s, deg/s, deg/h, m/s^2, g, mg) per sqrt(Hz), per
/// s/sqrt(Hz), as is, times s or per s. nullopt when the data's unit is not one of those
/// (unknown).
struct DatasheetValue {
  double value = 0.0;
  std::string unit;
};
std::optional<DatasheetValue> datasheet_value(char figure, double value, const std::string& data_unit);

/// The per-axis summary of a fit, select or joint document (`doc["columns"]`): for each
/// axis its model, goodness-of-fit verdict at the column's level, and N, K, B (and Q, R where
/// the document has them) with their intervals in the data's units and in datasheet units;
/// one block per axis, <= width.
std::string axis_summary(const Json& doc, std::size_t width = kTerminalWidth);

}  // namespace gmwm::report
