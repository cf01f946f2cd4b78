#include "delimited_parser.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "gmwm/engine/error.h"

namespace gmwm::io::detail {

namespace {

// Longest cell text quoted in an error message.
constexpr std::size_t kMaxQuoted = 40;

bool is_blank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string quoted(std::string_view s) {
  std::string out(1, '\'');
  out.append(s.substr(0, kMaxQuoted));
  out.append(s.size() > kMaxQuoted ? "...'" : "'");
  return out;
}

// Counts `c` outside double quotes.
std::size_t count_unquoted(std::string_view s, char c) {
  std::size_t n = 0;
  bool in_quotes = false;
  for (char ch : s) {
    if (ch == '"')
      in_quotes = !in_quotes;
    else if (ch == c && !in_quotes)
      ++n;
  }
  return n;
}

}  // namespace

std::string delimiter_name(Delimiter d) {
  switch (d) {
    case Delimiter::kComma:
      return "comma";
    case Delimiter::kTab:
      return "tab";
    case Delimiter::kSemicolon:
      return "semicolon";
    case Delimiter::kWhitespace:
      return "whitespace";
  }
  return "?";
}

NumberStatus parse_number(std::string_view field, double& out) {
  field = trim(field);
  if (field.empty()) return NumberStatus::kEmpty;
  const char* b = field.data();
  const char* e = b + field.size();
  if (*b == '+' && e - b > 1 && b[1] != '-' && b[1] != '+') ++b;  // from_chars rejects '+'
  const auto [ptr, ec] = std::from_chars(b, e, out);
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc() || ptr != e) return NumberStatus::kNotANumber;
  if (!std::isfinite(out)) return NumberStatus::kNotFinite;
  return NumberStatus::kOk;
}

bool is_numeric_row(std::string_view line) {
  bool any = false;
  std::size_t i = 0;
  while (i < line.size()) {
    std::size_t j = line.find_first_of(",; \t", i);
    if (j == std::string_view::npos) j = line.size();
    if (j > i) {
      double v;
      const NumberStatus s = parse_number(line.substr(i, j - i), v);
      if (s != NumberStatus::kOk && s != NumberStatus::kNotFinite) return false;
      any = true;
    }
    i = j + 1;
  }
  return any;
}

Delimiter detect_delimiter(std::string_view header, std::string_view first_row) {
  constexpr Delimiter kCandidates[] = {Delimiter::kComma, Delimiter::kTab, Delimiter::kSemicolon};
  for (Delimiter d : kCandidates) {
    const char c = static_cast<char>(d);
    const std::size_t h = count_unquoted(header, c);
    if (h > 0 && (first_row.empty() || count_unquoted(first_row, c) == h)) return d;
  }
  // No exact agreement: take a delimiter both lines use (the row parser then reports the
  // row with the wrong number of fields), else whitespace.
  for (Delimiter d : kCandidates) {
    const char c = static_cast<char>(d);
    if (count_unquoted(header, c) > 0 && count_unquoted(first_row, c) > 0) return d;
  }
  return Delimiter::kWhitespace;
}

std::vector<std::string> split_header(std::string_view header, Delimiter d) {
  std::vector<std::string> names;
  if (d == Delimiter::kWhitespace) {
    for (std::string_view f : split_fields(header, d)) names.emplace_back(f);
    return names;
  }
  const char c = static_cast<char>(d);
  std::string cur;
  bool in_quotes = false;
  for (std::size_t i = 0; i <= header.size(); ++i) {
    if (i == header.size() || (header[i] == c && !in_quotes)) {
      names.emplace_back(trim(cur));
      cur.clear();
    } else if (header[i] == '"') {
      if (in_quotes && i + 1 < header.size() && header[i + 1] == '"') {
        cur += '"';
        ++i;
      } else {
        in_quotes = !in_quotes;
      }
    } else {
      cur += header[i];
    }
  }
  return names;
}

std::vector<std::string_view> split_fields(std::string_view line, Delimiter d) {
  std::vector<std::string_view> fields;
  if (d == Delimiter::kWhitespace) {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_blank(line[i])) ++i;
      if (i == line.size()) break;
      std::size_t j = i;
      while (j < line.size() && !is_blank(line[j])) ++j;
      fields.push_back(line.substr(i, j - i));
      i = j;
    }
    return fields;
  }
  const char c = static_cast<char>(d);
  std::size_t i = 0;
  for (;;) {
    const std::size_t j = line.find(c, i);
    if (j == std::string_view::npos) {
      fields.push_back(trim(line.substr(i)));
      return fields;
    }
    fields.push_back(trim(line.substr(i, j - i)));
    i = j + 1;
  }
}

RowParser::RowParser(std::string path, Delimiter d, std::vector<FieldPlan> plan, std::vector<std::string> names,
                     int value_slots)
    : path_(std::move(path)),
      delim_(d),
      plan_(std::move(plan)),
      names_(std::move(names)),
      values_(static_cast<std::size_t>(value_slots)) {}

void RowParser::reserve(std::size_t rows) {
  for (auto& v : values_) v.reserve(rows);
}

bool RowParser::field_empty(std::string_view line, std::size_t field) const {
  if (delim_ == Delimiter::kWhitespace) return false;  // no empty field between blanks
  const char c = delim_ == Delimiter::kComma ? ',' : delim_ == Delimiter::kTab ? '\t' : ';';
  std::size_t begin = 0;
  for (std::size_t k = 0; k < field; ++k) {
    const std::size_t next = line.find(c, begin);
    if (next == std::string_view::npos) return false;  // too few fields: the parser says so
    begin = next + 1;
  }
  const std::size_t end = line.find(c, begin);
  return trim(line.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin)).empty();
}

void RowParser::parse(std::string_view line, std::int64_t line_number) {
  if (skip_without_ && field_empty(line, *skip_without_)) {
    ++skipped_;
    return;
  }
  const char* p = line.data();
  const char* e = p + line.size();
  switch (delim_) {
    case Delimiter::kComma:
      parse_delimited<','>(p, e, line_number);
      break;
    case Delimiter::kTab:
      parse_delimited<'\t'>(p, e, line_number);
      break;
    case Delimiter::kSemicolon:
      parse_delimited<';'>(p, e, line_number);
      break;
    case Delimiter::kWhitespace:
      parse_whitespace(p, e, line_number);
      break;
  }
  ++rows_;
}

template <char kDelim>
void RowParser::parse_delimited(const char* p, const char* e, std::int64_t line_number) {
  // Blanks around a number are allowed; in a TSV only spaces are (a tab is the delimiter).
  auto pad = [](char c) { return c == ' ' || (kDelim != '\t' && c == '\t'); };
  auto field_end = [e](const char* from) {
    const void* q = std::memchr(from, kDelim, static_cast<std::size_t>(e - from));
    return q ? static_cast<const char*>(q) : e;
  };
  const std::size_t n = plan_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const FieldPlan& f = plan_[k];
    const char* q = nullptr;
    if (f.kind == FieldPlan::kValue) {
      // Fast path: a plain finite number followed by the delimiter or the line end.
      const char* s = p;
      while (s < e && pad(*s)) ++s;
      double v;
      const auto [ptr, ec] = std::from_chars(s, e, v);
      if (ec == std::errc() && std::isfinite(v)) {
        const char* t = ptr;
        while (t < e && pad(*t)) ++t;
        if (t == e || *t == kDelim) {
          values_[static_cast<std::size_t>(f.slot)].push_back(v);
          q = t;
        }
      }
    }
    if (!q) {
      q = field_end(p);
      if (f.kind != FieldPlan::kSkip) store(f, p, q, line_number, k);
    }
    if (k + 1 < n) {
      if (q == e) fail_count(line_number, k + 1, false, {});
      p = q + 1;
    } else if (q != e) {
      fail_count(line_number, n, true, std::string_view(q + 1, static_cast<std::size_t>(e - q - 1)));
    }
  }
}

void RowParser::parse_whitespace(const char* p, const char* e, std::int64_t line_number) {
  const std::size_t n = plan_.size();
  for (std::size_t k = 0; k < n; ++k) {
    while (p < e && is_blank(*p)) ++p;
    if (p == e) fail_count(line_number, k, false, {});
    const char* q = p;
    while (q < e && !is_blank(*q)) ++q;
    const FieldPlan& f = plan_[k];
    if (f.kind == FieldPlan::kValue) {
      double v;
      const auto [ptr, ec] = std::from_chars(p, q, v);
      if (ec == std::errc() && ptr == q && std::isfinite(v))
        values_[static_cast<std::size_t>(f.slot)].push_back(v);
      else
        store(f, p, q, line_number, k);
    } else if (f.kind == FieldPlan::kTime) {
      store_time(p, q, line_number, k);
    }
    p = q;
  }
  while (p < e && is_blank(*p)) ++p;
  if (p != e) fail_count(line_number, n, true, std::string_view(p, static_cast<std::size_t>(e - p)));
}

void RowParser::store(const FieldPlan& f, const char* b, const char* e, std::int64_t line_number, std::size_t field) {
  if (f.kind == FieldPlan::kTime) {
    store_time(b, e, line_number, field);
    return;
  }
  double v;
  const std::string_view text(b, static_cast<std::size_t>(e - b));
  const NumberStatus s = parse_number(text, v);
  if (s != NumberStatus::kOk) fail_cell(line_number, field, trim(text), s);
  values_[static_cast<std::size_t>(f.slot)].push_back(v);
}

void RowParser::store_time(const char* b, const char* e, std::int64_t line_number, std::size_t field) {
  const std::string_view text = trim(std::string_view(b, static_cast<std::size_t>(e - b)));
  // Integer times first: nanoseconds since 1970 (~1.7e18) exceed a double's 2^53, but
  // their differences, taken in 64-bit integers, are exact.
  std::int64_t i = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), i);
  const bool is_int = ec == std::errc() && ptr == text.data() + text.size() && !text.empty();
  double v = static_cast<double>(i);
  if (!is_int) {
    const NumberStatus s = parse_number(text, v);
    if (s != NumberStatus::kOk) fail_cell(line_number, field, text, s);
  }
  if (!has_time_) {
    has_time_ = true;
    first_time_is_int_ = is_int;
    first_time_int_ = i;
    first_time_ = v;
  }
  std::int64_t diff = 0;
  if (is_int && first_time_is_int_ && !__builtin_sub_overflow(i, first_time_int_, &diff))
    time_steps_.add(static_cast<double>(diff));
  else
    time_steps_.add(v - first_time_, std::max(std::fabs(v), std::fabs(first_time_)));
}

void RowParser::fail_cell(std::int64_t line_number, std::size_t field, std::string_view text,
                          NumberStatus status) const {
  const std::string where = path_ + ":" + std::to_string(line_number) + ":" + std::to_string(field + 1) + ": ";
  const std::string col = " in column '" + names_[field] + "'";
  switch (status) {
    case NumberStatus::kEmpty:
      throw InputError(where + "found an empty cell" + col + ", expected a number");
    case NumberStatus::kNotFinite:
      throw InputError(where + "found " + quoted(text) + col +
                       ", expected a finite number (NaN and Inf are not allowed)");
    case NumberStatus::kOutOfRange:
      throw InputError(where + "found " + quoted(text) + col + ", expected a number within the range of a double");
    default: {
      const bool decimal_comma = delim_ != Delimiter::kComma && text.find(',') != std::string_view::npos;
      throw InputError(where + "found " + quoted(text) + col + ", expected a number" +
                       (decimal_comma ? " (with '.' as the decimal separator)" : ""));
    }
  }
}

void RowParser::fail_count(std::int64_t line_number, std::size_t found, bool too_many, std::string_view extra) const {
  const std::size_t n = plan_.size();
  const std::string head = path_ + ":" + std::to_string(line_number) + ":";
  if (!too_many) {  // name the first missing column
    throw InputError(head + std::to_string(found + 1) + ": found " + std::to_string(found) +
                     (found == 1 ? " field" : " fields") + ", expected " + std::to_string(n) +
                     " like the header (no value for column '" + names_[found] + "')");
  }
  const std::size_t total = n + split_fields(extra, delim_).size();
  throw InputError(head + std::to_string(n + 1) + ": found " + std::to_string(total) + " fields, expected " +
                   std::to_string(n) + " like the header (extra value " + quoted(trim(extra)) + ")");
}

}  // namespace gmwm::io::detail
