// A given curve's file (curve_reader.h): delimited text with a header, one or more curves.
#include "gmwm/io/curve_reader.h"

#include <algorithm>
#include <cctype>
#include <sstream>
#include <utility>

#include "config_text.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/choice.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/side_file.h"
#include "yaml_figures.h"

namespace gmwm::io {
namespace {

using detail::trim;

// A column's name as the rules compare it: lower case, a trailing unit in brackets or
// parentheses dropped ("tau [s]" -> "tau"), blanks trimmed.
std::string rule_name(const std::string& name) {
  std::string s = trim(name);
  if (!s.empty() && (s.back() == ']' || s.back() == ')')) {
    const auto open = s.find_last_of(s.back() == ']' ? '[' : '(');
    if (open != std::string::npos && open > 0) s = trim(s.substr(0, open));
  }
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The value columns' names of each quantity (curve_reader.h), and the one that says none.
const std::vector<std::pair<CurveQuantity, std::vector<std::string>>>& quantity_names() {
  static const std::vector<std::pair<CurveQuantity, std::vector<std::string>>> names{
      {CurveQuantity::kAdev, {"adev", "oadev"}},
      {CurveQuantity::kAvar, {"avar", "oavar"}},
      {CurveQuantity::kWv, {"wv"}}};
  return names;
}
constexpr const char* kGenericValue = "value";

// Where each role's column is (0-based; -1: absent) and what the values are.
struct Header {
  int tau = -1, value = -1, low = -1, high = -1, edf = -1, column = -1;
  CurveQuantity quantity = CurveQuantity::kAdev;
  std::vector<std::string> names;  // as written
};

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The one column whose rule name is among `accepted` (-1: none); two are refused.
int find_column(const std::vector<std::string>& names, const std::vector<std::string>& accepted,
                const std::string& where, const std::string& role) {
  int found = -1;
  for (int i = 0; i < static_cast<int>(names.size()); ++i) {
    const std::string n = rule_name(names[static_cast<std::size_t>(i)]);
    if (std::find(accepted.begin(), accepted.end(), n) == accepted.end()) continue;
    if (found >= 0)
      throw InputError(where + "found two " + role + " columns (" + std::to_string(found + 1) + " and " +
                       std::to_string(i + 1) + "), expected one");
    found = i;
  }
  return found;
}

// The value column and its quantity: --value's (or "value"), else the one a name says.
void find_value(Header& h, const CurveReadOptions& o, const std::string& where) {
  const std::string header = " (the header: " + listed(h.names) + ")";
  if (o.quantity) {
    std::vector<std::string> accepted;
    for (const auto& [q, names] : quantity_names())
      if (q == *o.quantity) accepted = names;
    h.quantity = *o.quantity;
    h.value = find_column(h.names, accepted, where, to_string(*o.quantity));
    if (h.value < 0) h.value = find_column(h.names, {kGenericValue}, where, kGenericValue);
    if (h.value < 0)
      throw InputError(where + "found no " + std::string(to_string(*o.quantity)) + " column" + header +
                       ", expected one named " + in_words(accepted) + " or value (--value " + to_string(*o.quantity) +
                       ")");
    return;
  }
  std::vector<CurveQuantity> seen;
  for (const auto& [q, names] : quantity_names())
    if (const int c = find_column(h.names, names, where, to_string(q)); c >= 0) {
      seen.push_back(q);
      h.value = c;
      h.quantity = q;
    }
  if (seen.size() > 1)
    throw InputError(where + "found columns of " + to_string(seen[0]) + " and " + to_string(seen[1]) + header +
                     ", expected one (--value adev, avar or wv picks it)");
  if (!seen.empty()) return;
  if (find_column(h.names, {kGenericValue}, where, kGenericValue) >= 0)
    throw InputError(where + "found a value column" + header +
                     ", expected --value adev, avar or wv to say what it holds");
  throw InputError(where + "found no value column" + header + ", expected one named adev, avar, wv or value");
}

Header header_of(const std::vector<std::string>& names, const CurveReadOptions& o, const std::string& where) {
  Header h;
  h.names = names;
  h.tau = find_column(names, {"tau_seconds"}, where, "tau_seconds");
  if (h.tau < 0) h.tau = find_column(names, {"tau", "tau_s"}, where, "tau");
  if (h.tau < 0)
    throw InputError(where + "found no tau column (the header: " + listed(names) +
                     "), expected one named tau or tau_seconds (seconds)");
  find_value(h, o, where);
  h.low = find_column(names, {"ci_low", "low"}, where, "ci_low");
  h.high = find_column(names, {"ci_high", "high"}, where, "ci_high");
  if ((h.low < 0) != (h.high < 0))
    throw InputError(where + "found " + (h.low < 0 ? "ci_high without ci_low" : "ci_low without ci_high") +
                     ", expected both ends of the intervals or neither");
  h.edf = find_column(names, {"edf", "dof"}, where, "edf");
  h.column = find_column(names, {"column"}, where, "column");
  return h;
}

// The fields of a line: at `delimiter` (a field in double quotes may hold it, "" is a quote),
// or at runs of blanks when the delimiter is ' '.
std::vector<std::string> fields_of(const std::string& line, char delimiter) {
  std::vector<std::string> out;
  if (delimiter == ' ') {
    std::istringstream in(line);
    for (std::string f; in >> f;) out.push_back(f);
    return out;
  }
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cur += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == delimiter && !quoted) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

char delimiter_of(const std::string& header) {
  for (char d : {',', '\t', ';'})
    if (header.find(d) != std::string::npos) return d;
  return ' ';
}

// The text's lines that hold data or the header: number, text (blank and '#' lines skipped).
std::vector<std::pair<std::int64_t, std::string>> content_lines(const std::string& text, const std::string& path) {
  if (text.find('\0') != std::string::npos)
    throw InputError(path + ": found a NUL byte (binary data), expected a curve as delimited text");
  std::vector<std::pair<std::int64_t, std::string>> out;
  std::istringstream in(text.rfind("\xEF\xBB\xBF", 0) == 0 ? text.substr(3) : text);
  std::int64_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (!t.empty() && t.front() != '#') out.emplace_back(number, line);
  }
  return out;
}

// One field as a number, refused naming its place.
double number_at(const std::vector<std::string>& fields, int index, const std::string& at, const std::string& what) {
  const std::string place = at + std::to_string(index + 1) + ": ";
  if (index >= static_cast<int>(fields.size()))
    throw InputError(place + "found " + std::to_string(fields.size()) + " fields, expected " + what + " in field " +
                     std::to_string(index + 1));
  bool out_of_range = false;
  const std::string& f = fields[static_cast<std::size_t>(index)];
  if (const auto v = detail::decimal(f, out_of_range)) return *v;
  throw InputError(place + "found '" + f + "'" + (out_of_range ? " (beyond a double)" : "") + ", expected " + what +
                   " (a finite decimal number)");
}

GivenCurve empty_curve(const Header& h, const std::string& source, const std::string& name) {
  GivenCurve c;
  c.name = name;
  c.source = source;
  c.quantity = h.quantity;
  auto field = [&](int i) { return CurveField{i >= 0 ? h.names[static_cast<std::size_t>(i)] : "", i + 1}; };
  c.tau_field = field(h.tau);
  c.value_field = field(h.value);
  c.low_field = field(h.low);
  c.high_field = field(h.high);
  c.edf_field = field(h.edf);
  return c;
}

// A data line's point into its curve.
void add_point(GivenCurve& c, const Header& h, const std::vector<std::string>& f, const std::string& at,
               std::int64_t line) {
  c.line.push_back(line);
  c.tau.push_back(number_at(f, h.tau, at, "tau in seconds"));
  c.value.push_back(number_at(f, h.value, at, std::string("the ") + to_string(h.quantity)));
  if (h.low >= 0) {
    c.low.push_back(number_at(f, h.low, at, "the interval's low end"));
    c.high.push_back(number_at(f, h.high, at, "the interval's high end"));
  }
  if (h.edf >= 0) c.edf.push_back(number_at(f, h.edf, at, "the degrees of freedom"));
}

// The curves --columns keeps, in its order; a name no row has is refused.
std::vector<GivenCurve> kept(std::vector<GivenCurve> curves, const CurveReadOptions& o, const std::string& path) {
  if (o.columns.empty()) return curves;
  std::vector<GivenCurve> out;
  std::vector<std::string> names;
  for (const GivenCurve& c : curves) names.push_back(c.name);
  for (const std::string& want : o.columns) {
    const auto it = std::find_if(curves.begin(), curves.end(), [&](const GivenCurve& c) { return c.name == want; });
    if (it == curves.end())
      throw InputError(path + ": --columns: found no curve named '" + want + "', expected one of: " + listed(names));
    out.push_back(*it);
  }
  return out;
}

}  // namespace

std::vector<GivenCurve> read_curves(const std::string& path, const CurveReadOptions& options) {
  const std::string text = read_side_file(path, "a curve (delimited text of tau and its values)", kMaxCurveBytes);
  const auto lines = content_lines(text, path);
  if (lines.empty()) throw InputError(path + ": found no header, expected a header row naming tau and the values");
  const char delimiter = delimiter_of(lines.front().second);
  const Header h = header_of(fields_of(lines.front().second, delimiter), options,
                             path + ":" + std::to_string(lines.front().first) + ": ");
  std::vector<GivenCurve> curves;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto& [number, line] = lines[i];
    const std::vector<std::string> f = fields_of(line, delimiter);
    const std::string at = path + ":" + std::to_string(number) + ":";
    std::string name = h.names[static_cast<std::size_t>(h.value)];
    if (h.column >= 0) {
      if (h.column >= static_cast<int>(f.size()))
        throw InputError(at + std::to_string(h.column + 1) + ": found " + std::to_string(f.size()) +
                         " fields, expected the curve's name in field " + std::to_string(h.column + 1));
      name = f[static_cast<std::size_t>(h.column)];
    }
    auto it = std::find_if(curves.begin(), curves.end(), [&](const GivenCurve& c) { return c.name == name; });
    if (it == curves.end()) it = curves.insert(curves.end(), empty_curve(h, path, name));
    add_point(*it, h, f, at, number);
  }
  if (curves.empty())
    throw InputError(path + ": found a header and no point, expected a row of tau and " +
                     std::string(to_string(h.quantity)) + " per point");
  std::vector<GivenCurve> out = kept(std::move(curves), options, path);
  for (const GivenCurve& c : out)
    if (std::string why = curve_problem(c); !why.empty()) throw InputError(why);
  return out;
}

GivenCurve curve_from_columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns,
                              const std::string& source, const CurveReadOptions& options) {
  if (names.size() != columns.size())
    throw InvalidArgument("curve_from_columns: " + std::to_string(names.size()) + " names for " +
                          std::to_string(columns.size()) + " columns");
  const Header h = header_of(names, options, source + ": ");
  if (h.column >= 0)
    throw InputError(source + ": found a 'column' field, expected the columns of one curve (pick its rows first)");
  GivenCurve c = empty_curve(h, source, names[static_cast<std::size_t>(h.value)]);
  for (CurveField* f : {&c.tau_field, &c.value_field, &c.low_field, &c.high_field, &c.edf_field}) f->column = 0;
  auto column = [&](int i) { return i >= 0 ? columns[static_cast<std::size_t>(i)] : std::vector<double>{}; };
  c.tau = column(h.tau);
  c.value = column(h.value);
  c.low = column(h.low);
  c.high = column(h.high);
  c.edf = column(h.edf);
  if (std::string why = curve_problem(c); !why.empty()) throw InputError(why);
  return c;
}

}  // namespace gmwm::io
