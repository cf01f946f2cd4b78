#include "gmwm/report/terminal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string_view>

#include "gmwm/engine/error.h"
#include "gmwm/io/units.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::report {
namespace {

// A column may leave the grid only when it is at least this wide: narrower columns are
// numbers, and a table of numbers split into notes would be harder to read than a wide one.
constexpr std::size_t kMinNoteColumn = 12;

// A wrapped line's continuations are indented this much more than the line itself: the
// terminal indents a line's own items by 2, so 4 reads as "the same sentence".
constexpr std::size_t kWrapHang = 4;
// wrap_to_width reserves the text plus this fraction of it (1/16) for the line breaks and
// hangs it adds: a cut costs at most 1 + width / 2 bytes every width / 2 columns or more,
// and about 1 + kWrapHang every width - kWrapHang for prose; beyond, the string grows.
constexpr std::size_t kWrapReserveDivisor = 16;

// Datasheet conversions (exact): 1 h = 3600 s, so 1/sqrt(s) = 60/sqrt(h); 1 g = 9.80665 m/s^2
// (CGPM 1901).
constexpr double kDegreesPerRadian = 57.295779513082320877;
constexpr double kSecondsPerHour = 3600.0;
constexpr double kSqrtSecondsPerHour = 60.0;
constexpr double kStandardGravity = 9.80665;
constexpr double kArcsecondsPerDegree = 3600.0;
constexpr double kSecondsPerHourSquared = kSecondsPerHour * kSecondsPerHour;

std::size_t width_of(std::string_view s) {
  // UTF-8 continuation bytes take no column.
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

std::string render(const std::vector<std::vector<std::string>>& rows, const std::vector<std::size_t>& cols, int left) {
  std::vector<std::size_t> width(cols.size(), 0);
  for (const auto& r : rows)
    for (std::size_t i = 0; i < cols.size(); ++i)
      if (cols[i] < r.size()) width[i] = std::max(width[i], width_of(r[cols[i]]));
  std::ostringstream os;
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t i = 0; i < cols.size(); ++i) {
      const std::string cell = cols[i] < r.size() ? r[cols[i]] : std::string();
      const std::string pad(width[i] - width_of(cell), ' ');
      if (i) line += "  ";
      line += static_cast<int>(cols[i]) < left ? cell + pad : pad + cell;
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    os << line << '\n';
  }
  return os.str();
}

std::size_t longest_line(const std::string& text) {
  std::size_t best = 0, start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    best = std::max(best, width_of(text.substr(start, end - start)));
    start = end + 1;
  }
  return best;
}

const Json* find(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && !j.at(key).is_null() ? &j.at(key) : nullptr;
}

double number_or_nan(const Json& j, const char* key) {
  const Json* v = find(j, key);
  return v && v->is_number() ? v->get<double>() : std::nan("");
}

std::string text_or(const Json& j, const char* key, const std::string& fallback = {}) {
  const Json* v = find(j, key);
  return v && v->is_string() ? v->get<std::string>() : fallback;
}

// The axis' model and goodness-of-fit: a select column's effective best and its fit's test,
// a fit column's own.
struct AxisFit {
  std::string model;
  const Json* gof = nullptr;
  bool rejected = false;
};

AxisFit axis_fit(const Json& c) {
  AxisFit a;
  if (const Json* best = find(c, "best_fit")) {
    a.model = text_or(c, "best", text_or(c, "best_model"));
    a.gof = find(*best, "gof");
    if (const Json* q = find(*best, "quality")) a.rejected = q->value("rejected", false);
  } else {
    a.model = text_or(c, "model_structure", text_or(c, "model"));
    a.gof = find(c, "gof");
    if (const Json* q = find(c, "quality")) a.rejected = q->value("rejected", false);
  }
  return a;
}

std::string verdict(const AxisFit& a, double alpha) {
  if (!a.gof) return "no goodness-of-fit test";
  const double p = number_or_nan(*a.gof, "p_value");
  if (!std::isfinite(p)) return "no goodness-of-fit test";
  const std::string level = fmt(100.0 * alpha, 3) + "%";
  if (p < alpha) return "GoF p = " + fmt(p, 2) + ": rejected at " + level + ", the model misses the data";
  if (a.rejected) return "GoF p = " + fmt(p, 2) + ", but levels depart from the model (see --verbose)";
  return "GoF p = " + fmt(p, 2) + ": not rejected at " + level;
}

void add_figure(TextTable& t, const char* label, char letter, const Json& f, const std::string& data_unit) {
  const double v = number_or_nan(f, "value");
  std::vector<std::string> row;
  if (!std::isfinite(v)) {
    row = {label, "-", "not read", text_or(f, "unit")};
  } else {
    const bool bound = text_or(f, "status") == "bound";
    const double lo = number_or_nan(f, "low"), hi = number_or_nan(f, "high");
    const std::string ci = bound                                    ? "upper bound"
                           : std::isfinite(lo) && std::isfinite(hi) ? fmt(lo, 3) + " .. " + fmt(hi, 3)
                                                                    : std::string();
    row = {label, (bound ? "< " : "") + fmt(v, 4), ci, text_or(f, "unit")};
    if (const auto d = datasheet_value(letter, v, data_unit))
      row.push_back((bound ? "< " : "") + fmt(d->value, 4) + " " + d->unit);
  }
  if (!data_unit.empty() && row.size() == 4) row.push_back("");
  t.add(std::move(row));
}

}  // namespace

std::string fmt(double x, int digits) { return significant(x, digits, NonFinite::kDash); }

TextTable::TextTable(std::vector<std::string> header, int left) : left_(left) { rows_.push_back(std::move(header)); }

void TextTable::add(std::vector<std::string> row) {
  // One printable line a cell (names from files may hold control bytes): the widths then
  // count what the terminal shows.
  for (std::string& cell : row) cell = printable_line(cell);
  rows_.push_back(std::move(row));
}

std::string TextTable::str(std::size_t width) const {
  std::size_t ncols = 0;
  for (const auto& r : rows_) ncols = std::max(ncols, r.size());
  std::vector<std::size_t> cols(ncols);
  for (std::size_t c = 0; c < ncols; ++c) cols[c] = c;
  std::vector<std::size_t> noted;
  std::string grid = render(rows_, cols, left_);
  while (longest_line(grid) > width) {
    // The widest column but the first leaves the grid.
    std::size_t pick = 0, pick_width = 0;
    for (std::size_t i = 1; i < cols.size(); ++i) {
      std::size_t w = 0;
      for (std::size_t r = 1; r < rows_.size(); ++r)
        if (cols[i] < rows_[r].size()) w = std::max(w, width_of(rows_[r][cols[i]]));
      if (w > pick_width) pick = i, pick_width = w;
    }
    if (pick == 0 || pick_width < kMinNoteColumn) break;
    noted.push_back(cols[pick]);
    cols.erase(cols.begin() + static_cast<std::ptrdiff_t>(pick));
    grid = render(rows_, cols, left_);
  }
  if (noted.empty()) return grid;
  std::sort(noted.begin(), noted.end());
  std::string notes;
  for (std::size_t r = 1; r < rows_.size(); ++r)
    for (const std::size_t c : noted)
      if (c < rows_[r].size() && !rows_[r][c].empty())
        notes += "  " + (rows_[r].empty() ? std::string() : rows_[r][0]) + ", " +
                 (c < rows_[0].size() ? rows_[0][c] : std::string()) + ": " + rows_[r][c] + "\n";
  return grid + wrap_to_width(notes, width);
}

std::string wrap_to_width(const std::string& text, std::size_t width) {
  // Linear in the text: a long line is consumed from its front through a view, each cut
  // looking at the next `width` columns only (the line used to be copied whole at each cut:
  // a 2 MB name took 28.6 s, issue 42).
  std::string out;
  // One allocation for the usual case: the text plus a line break and a hang every cut
  // (a cut every width - hang columns or so: a sixteenth covers widths from 40). Growing
  // from empty doubled it five times for 1 MiB, each a fresh block the kernel faults in.
  out.reserve(text.size() + text.size() / kWrapReserveDivisor + width);
  std::string piece;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    const std::size_t end = nl == std::string::npos ? text.size() : nl;
    std::string_view line(text.data() + start, end - start);
    std::size_t cols = width_of(line);
    // An indent past half the width is cut to half (a line of spaces alone, to nothing).
    if (const std::size_t lead = line.find_first_not_of(' '); lead == std::string_view::npos) {
      if (cols > width) {
        line = {};
        cols = 0;
      }
    } else if (lead > width / 2 && cols > width) {
      line.remove_prefix(lead - width / 2);
      cols -= lead - width / 2;
    }
    const std::size_t indent = std::min(line.find_first_not_of(' '), width / 2);
    // Continuations indented 4 past the line: clear of the 2-space items under a line.
    const std::string hang(std::min(indent + kWrapHang, width / 2), ' ');
    std::string_view prefix;  // what precedes the line's rest: nothing, then the hang
    while (prefix.size() + cols > width) {
      // The head the cut looks at: the prefix and the rest up to its (width + 1)-th column.
      std::size_t bytes = 0, seen = prefix.size();
      for (; bytes < line.size(); ++bytes)
        if ((static_cast<unsigned char>(line[bytes]) & 0xC0) != 0x80 && seen++ == width + 1) break;
      piece.assign(prefix);
      piece.append(line.substr(0, bytes));
      // Cut at the last space within the width that follows some text of this line (so that
      // every cut moves on), else within the word at the width.
      const std::size_t text_from = std::min(piece.find_first_not_of(' '), piece.size());
      std::size_t cut = std::string::npos, hard = 0, used = 0;
      for (std::size_t i = 0; i < piece.size(); ++i) {
        if ((static_cast<unsigned char>(piece[i]) & 0xC0) != 0x80 && ++used > width) break;
        hard = i + 1;
        if (piece[i] == ' ' && i > text_from) cut = i;
      }
      const bool at_space = cut != std::string::npos;
      const std::size_t take = std::min(at_space ? cut : std::max<std::size_t>(hard, text_from + 1), piece.size());
      std::size_t head = take;
      while (head > 0 && piece[head - 1] == ' ') --head;
      out.append(piece, 0, head);
      out += '\n';
      // The rest: after the cut (and its space), without the spaces that lead it.
      std::size_t consumed = take - prefix.size() + (at_space ? 1 : 0);
      while (consumed < line.size() && line[consumed] == ' ') ++consumed;
      cols -= width_of(line.substr(0, consumed));
      line.remove_prefix(consumed);
      prefix = hang;
    }
    out.append(prefix);
    out.append(line);
    if (nl != std::string::npos) out += '\n';
    start = end + 1;
  }
  return out;
}

std::optional<DatasheetValue> datasheet_value(char figure, double value, const std::string& data_unit) {
  if (data_unit.empty()) return std::nullopt;
  std::pair<io::SensorKind, io::Unit> u;
  try {
    u = io::parse_any_unit(data_unit);
  } catch (const InputError&) {
    return std::nullopt;
  }
  const double si = value / u.second.per_si;  // rad/s or m/s^2 (per sqrt(Hz), per s/sqrt(Hz))
  const bool gyro = u.first == io::SensorKind::kGyro;
  switch (figure) {
    case 'N':
      return gyro ? DatasheetValue{si * kDegreesPerRadian * kSqrtSecondsPerHour, "deg/sqrt(h)"}
                  : DatasheetValue{si / kStandardGravity * 1e6, "ug/sqrt(Hz)"};
    case 'K':
      return gyro ? DatasheetValue{si * kDegreesPerRadian * kSecondsPerHour * kSqrtSecondsPerHour, "deg/h/sqrt(h)"}
                  : DatasheetValue{si * kSqrtSecondsPerHour, "m/s^2/sqrt(h)"};
    case 'B':
      return gyro ? DatasheetValue{si * kDegreesPerRadian * kSecondsPerHour, "deg/h"}
                  : DatasheetValue{si / kStandardGravity * 1e3, "mg"};
    case 'Q':  // rad (the angle quantum) or m/s (the velocity quantum)
      return gyro ? DatasheetValue{si * kDegreesPerRadian * kArcsecondsPerDegree, "arcsec"}
                  : DatasheetValue{si * 1e3, "mm/s"};
    case 'R':  // rad/s^2 or m/s^3: IEEE 952's (deg/h)/h for a gyro
      return gyro ? DatasheetValue{si * kDegreesPerRadian * kSecondsPerHourSquared, "deg/h^2"}
                  : DatasheetValue{si / kStandardGravity * 1e3 * kSecondsPerHour, "mg/h"};
    default:
      return std::nullopt;
  }
}

std::string axis_summary(const Json& doc, std::size_t width) {
  const Json* columns = find(doc, "columns");
  if (!columns || !columns->is_array()) return {};
  std::string out;
  bool unit_missing = false;
  for (const Json& c : *columns) {
    const AxisFit a = axis_fit(c);
    const double alpha = std::isfinite(number_or_nan(c, "alpha")) ? number_or_nan(c, "alpha") : 0.05;
    const std::string unit = text_or(c, "unit");
    out += text_or(c, "name", "column") + ": " + (a.model.empty() ? "no model" : a.model) + "; " + verdict(a, alpha) +
           "\n";
    const Json* nf = find(c, "noise_figures");
    if (!nf) {
      out += "  no noise figures (the rate is unknown: give --freq)\n";
      continue;
    }
    std::vector<std::string> head = {"  figure (IEEE 952)", "value", fmt(100.0 * (1.0 - alpha), 3) + "% interval",
                                     "unit"};
    if (!unit.empty()) head.push_back("datasheet unit");
    unit_missing = unit_missing || unit.empty();
    TextTable t(head, 1);
    const Json none;
    add_figure(t, "  N white noise", 'N', nf->contains("white") ? nf->at("white") : none, unit);
    add_figure(t, "  K random walk", 'K', nf->contains("walk") ? nf->at("walk") : none, unit);
    add_figure(t, "  B bias instability", 'B', nf->contains("instability") ? nf->at("instability") : none, unit);
    // Q and R (issue 48): a document written before them has neither.
    if (nf->contains("quantization")) add_figure(t, "  Q quantization", 'Q', nf->at("quantization"), unit);
    if (nf->contains("ramp")) add_figure(t, "  R rate ramp", 'R', nf->at("ramp"), unit);
    out += t.str(width);
  }
  if (unit_missing)
    out += "(U: the data's unit; --units gyro=deg/s,accel=g (or one unit) adds the figures in datasheet units)\n";
  return out;
}

}  // namespace gmwm::report
