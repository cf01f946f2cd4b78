// A simulator's configuration file edited in place (config_edit.h).
#include "config_edit.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace gmwm::pipeline::detail {
namespace {

// One replacement of the input's text: [at, at + length) becomes `with`.
struct Splice {
  std::size_t at = 0, length = 0;
  std::string with;
};

class Lines {
 public:
  explicit Lines(const std::string& text) : text_(text) {
    starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
  }
  /// Offset of 1-based line `n` (npos when there is no such line).
  std::size_t start(int n) const {
    return n >= 1 && static_cast<std::size_t>(n) <= starts_.size() ? starts_[static_cast<std::size_t>(n) - 1]
                                                                   : std::string::npos;
  }
  /// One past the line's '\n' (or the text's end) from any offset on it.
  std::size_t next(std::size_t at) const {
    const std::size_t nl = text_.find('\n', at);
    return nl == std::string::npos ? text_.size() : nl + 1;
  }
  /// The line's end of line ("\r\n", "\n" or "" on the last line) from any offset on it.
  std::string eol(std::size_t at) const {
    const std::size_t nl = text_.find('\n', at);
    if (nl == std::string::npos) return "\n";
    return nl > 0 && text_[nl - 1] == '\r' ? "\r\n" : "\n";
  }
  std::string indent(std::size_t line_start) const {
    std::size_t e = line_start;
    while (e < text_.size() && (text_[e] == ' ' || text_[e] == '\t')) ++e;
    return text_.substr(line_start, e - line_start);
  }

 private:
  const std::string& text_;
  std::vector<std::size_t> starts_;
};

bool name_ends(char c) { return c == '>' || c == '/' || std::isspace(static_cast<unsigned char>(c)); }

// An XML element `key` whose start tag begins on the line at `from`: the offsets of the
// start tag, of its content, of the close tag and one past it.
struct Element {
  std::size_t open = std::string::npos, content = 0, close = 0, end = 0;
};
Element xml_element(const std::string& text, std::size_t from, std::size_t line_end, const std::string& key) {
  Element e;
  const std::string tag = "<" + key;
  for (std::size_t at = text.find(tag, from); at != std::string::npos && at < line_end; at = text.find(tag, at + 1)) {
    if (at + tag.size() >= text.size() || !name_ends(text[at + tag.size()])) continue;
    const std::size_t gt = text.find('>', at);
    if (gt == std::string::npos || text[gt - 1] == '/') return e;  // an empty element holds no figure
    const std::size_t close = text.find("</" + key, gt);
    const std::size_t end = close == std::string::npos ? close : text.find('>', close);
    if (end == std::string::npos) return e;
    return {at, gt + 1, close, end + 1};
  }
  return e;
}

// A YAML "key: value" on the line at `from`: the offset just after the ':' (npos when the
// line is not that key's).
std::size_t yaml_value(const std::string& text, std::size_t from, std::size_t line_end, const std::string& key) {
  std::size_t at = from;
  while (at < line_end && (text[at] == ' ' || text[at] == '\t')) ++at;
  if (text.compare(at, key.size(), key) != 0) return std::string::npos;
  at += key.size();
  while (at < line_end && (text[at] == ' ' || text[at] == '\t')) ++at;
  return at < line_end && text[at] == ':' ? at + 1 : std::string::npos;
}

// The span of the figure `f` as written (its text, inside its element or after its key).
std::optional<Splice> figure_span(const std::string& text, const Lines& lines, ConfigSyntax syntax,
                                  const io::ConfigField& f) {
  const std::size_t from = lines.start(f.line);
  if (from == std::string::npos || f.text.empty()) return std::nullopt;
  const std::size_t line_end = lines.next(from);
  const std::string key = config_key(f.name);
  std::size_t lo = 0, hi = 0;
  if (syntax == ConfigSyntax::kXml) {
    const Element e = xml_element(text, from, line_end, key);
    if (e.open == std::string::npos) return std::nullopt;
    lo = e.content;
    hi = e.close;
  } else {
    lo = yaml_value(text, from, line_end, key);
    if (lo == std::string::npos) return std::nullopt;
    hi = line_end;
  }
  const std::size_t at = text.find(f.text, lo);
  if (at == std::string::npos || at + f.text.size() > hi) return std::nullopt;
  return Splice{at, f.text.size(), {}};
}

// The span of the whole figure `f`: its line when it holds nothing else, else its element.
std::optional<Splice> removal_span(const std::string& text, const Lines& lines, ConfigSyntax syntax,
                                   const io::ConfigField& f) {
  const std::size_t from = lines.start(f.line);
  if (from == std::string::npos) return std::nullopt;
  const std::size_t line_end = lines.next(from);
  if (syntax == ConfigSyntax::kYaml) {
    if (yaml_value(text, from, line_end, config_key(f.name)) == std::string::npos) return std::nullopt;
    return Splice{from, line_end - from, {}};
  }
  const Element e = xml_element(text, from, line_end, config_key(f.name));
  if (e.open == std::string::npos) return std::nullopt;
  const auto blank = [&](std::size_t a, std::size_t b) {
    return std::all_of(text.begin() + static_cast<std::ptrdiff_t>(a), text.begin() + static_cast<std::ptrdiff_t>(b),
                       [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
  };
  // What follows the element on its line: nothing, or a comment about it.
  std::size_t after = e.end;
  while (after < text.size() && (text[after] == ' ' || text[after] == '\t')) ++after;
  if (text.compare(after, 4, "<!--") == 0) {
    const std::size_t c = text.find("-->", after);
    after = c == std::string::npos ? after : c + 3;
  }
  const std::size_t element_line_end = lines.next(e.end > 0 ? e.end - 1 : e.end);
  if (blank(from, e.open) && blank(after, element_line_end)) return Splice{from, element_line_end - from, {}};
  return Splice{e.open, e.end - e.open, {}};
}

// Where a figure inserted after `f` goes: the start of the line after f's (after its close
// tag's line for an element spanning lines), with f's indentation.
std::optional<Splice> insertion(const std::string& text, const Lines& lines, ConfigSyntax syntax,
                                const io::ConfigField& f, const std::string& key, const std::string& value) {
  const std::size_t from = lines.start(f.line);
  if (from == std::string::npos) return std::nullopt;
  std::size_t last = from;
  if (syntax == ConfigSyntax::kXml) {
    const Element e = xml_element(text, from, lines.next(from), config_key(f.name));
    if (e.open == std::string::npos) return std::nullopt;
    last = e.end - 1;
  } else if (yaml_value(text, from, lines.next(from), config_key(f.name)) == std::string::npos) {
    return std::nullopt;
  }
  const std::string line =
      syntax == ConfigSyntax::kXml ? "<" + key + ">" + value + "</" + key + ">" : key + ": " + value;
  const std::size_t at = lines.next(last);
  // The last line of a file without a final newline gets one first.
  const std::string before = at == text.size() && (text.empty() || text.back() != '\n') ? lines.eol(from) : "";
  return Splice{at, 0, before + lines.indent(from) + line + lines.eol(from)};
}

}  // namespace

std::string config_key(const std::string& field_name) { return field_name.substr(field_name.rfind('/') + 1); }

std::optional<std::string> apply_config_edits(const std::string& text, ConfigSyntax syntax,
                                              const std::vector<ConfigEdit>& edits) {
  const Lines lines(text);
  std::vector<Splice> splices;
  std::map<std::size_t, std::size_t> inserted;  // offset -> its splice: figures added there, in order
  for (const ConfigEdit& e : edits) {
    if (!e.at) return std::nullopt;
    std::optional<Splice> s = e.op == ConfigEdit::kSet      ? figure_span(text, lines, syntax, *e.at)
                              : e.op == ConfigEdit::kRemove ? removal_span(text, lines, syntax, *e.at)
                                                            : insertion(text, lines, syntax, *e.at, e.key, e.value);
    if (!s) return std::nullopt;
    if (e.op == ConfigEdit::kSet) s->with = e.value;
    if (e.op == ConfigEdit::kInsert) {
      if (const auto it = inserted.find(s->at); it != inserted.end()) {
        splices[it->second].with += s->with;
        continue;
      }
      inserted[s->at] = splices.size();
    }
    splices.push_back(*s);
  }
  // Last first, so that every offset still points into the input's text; overlapping
  // edits (a figure set and removed) are refused.
  std::stable_sort(splices.begin(), splices.end(),
                   [](const Splice& a, const Splice& b) { return a.at != b.at ? a.at > b.at : a.length > b.length; });
  std::string out = text;
  std::size_t limit = std::string::npos;
  for (const Splice& s : splices) {
    if (limit != std::string::npos && s.at + s.length > limit) return std::nullopt;
    out.replace(s.at, s.length, s.with);
    limit = s.at;
  }
  return out;
}

}  // namespace gmwm::pipeline::detail
