// A fleet's manifest (fleet_manifest.h): CSV (RFC 4180 quoting) or YAML rows, read and
// checked before any recording is analysed.
#include "gmwm/io/fleet_manifest.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <yaml-cpp/yaml.h>

#include "config_text.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"
#include "yaml_figures.h"

namespace gmwm::io {
namespace {

namespace fs = std::filesystem;
using detail::trim;

// The fields a row may have, in the order a CSV header lists them in the docs.
const char* const kFields[] = {"path", "unit", "model", "topic", "columns", "units", "rate", "group"};

std::string known_fields() {
  std::string out;
  for (const char* f : kFields) out += (out.empty() ? "" : ", ") + std::string(f);
  return out;
}

bool is_field(const std::string& name) {
  for (const char* f : kFields)
    if (name == f) return true;
  return false;
}

std::string at(const std::string& path, int line) { return path + ":" + std::to_string(line) + ": "; }

// Whether `s` is UTF-8 (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF).
bool is_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const int c = static_cast<unsigned char>(s[i]);
    // The sequence's length and its second byte's range (the Unicode Standard, table 3-7).
    const auto [n, lo, hi] = c < 0x80    ? std::tuple{1, 0x80, 0xBF}
                             : c < 0xC2  ? std::tuple{0, 0, 0}
                             : c < 0xE0  ? std::tuple{2, 0x80, 0xBF}
                             : c == 0xE0 ? std::tuple{3, 0xA0, 0xBF}
                             : c == 0xED ? std::tuple{3, 0x80, 0x9F}
                             : c < 0xF0  ? std::tuple{3, 0x80, 0xBF}
                             : c == 0xF0 ? std::tuple{4, 0x90, 0xBF}
                             : c < 0xF4  ? std::tuple{4, 0x80, 0xBF}
                             : c == 0xF4 ? std::tuple{4, 0x80, 0x8F}
                                         : std::tuple{0, 0, 0};
    if (n == 0 || i + static_cast<std::size_t>(n) > s.size()) return false;
    for (int k = 1; k < n; ++k) {
      const int b = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xBF)) return false;
    }
    i += static_cast<std::size_t>(n);
  }
  return true;
}

// The fields of one CSV line (RFC 4180: a field in double quotes may hold commas, a doubled
// quote is a quote). Throws InputError for an unterminated quote or text after a closing one.
std::vector<std::string> csv_fields(const std::string& line, const std::string& where) {
  std::vector<std::string> out;
  std::string cur;
  std::size_t i = 0;
  while (true) {
    cur.clear();
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i < line.size() && line[i] == '"') {
      ++i;
      while (true) {
        if (i >= line.size()) throw InputError(where + "found an unterminated quoted field, expected a closing '\"'");
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            cur += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        cur += line[i++];
      }
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i < line.size() && line[i] != ',')
        throw InputError(where + "found text after a quoted field, expected ',' or the end of the line");
    } else {
      while (i < line.size() && line[i] != ',') cur += line[i++];
      cur = trim(cur);
    }
    out.push_back(cur);
    if (i >= line.size()) break;
    ++i;  // the comma
  }
  return out;
}

// A row's fields by name into a recording (rate parsed; the rest as text).
FleetRecording recording_of(const std::map<std::string, std::string>& f, int row, const std::string& where) {
  FleetRecording r;
  r.row = row;
  auto get = [&](const char* k) {
    const auto it = f.find(k);
    return it == f.end() ? std::string() : it->second;
  };
  for (const auto& [name, value] : f)
    if (value.size() > kMaxManifestFieldBytes)
      throw InputError(where + name + ": found " + std::to_string(value.size()) + " bytes, expected at most " +
                       std::to_string(kMaxManifestFieldBytes) + " (a path's longest, PATH_MAX)");
  r.path = get("path");
  r.unit = get("unit");
  r.model = get("model");
  r.topic = get("topic");
  r.columns = get("columns");
  r.units = get("units");
  r.group = get("group");
  if (const std::string rate = get("rate"); !rate.empty()) {
    bool out_of_range = false;
    const auto v = detail::decimal(rate, out_of_range);
    if (!v) throw InputError(where + "rate: found '" + rate + "', expected a sampling rate in Hz (a decimal number)");
    r.rate = *v;
  }
  return r;
}

std::vector<FleetRecording> read_csv(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> header;
  std::vector<FleetRecording> out;
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    const std::string where = at(path, line_no);
    std::vector<std::string> fields = csv_fields(line, where);
    if (header.empty()) {
      for (const std::string& h : fields) {
        if (!is_field(h))
          throw InputError(where + "found the header field '" + h + "', expected some of " + known_fields());
        for (const std::string& seen : header)
          if (seen == h) throw InputError(where + "found the header field '" + h + "' twice");
        header.push_back(h);
      }
      for (const char* required : {"path", "unit", "model"})
        if (std::find(header.begin(), header.end(), required) == header.end())
          throw InputError(where + "found a header without '" + required + "', expected at least path, unit, model");
      continue;
    }
    if (fields.size() != header.size())
      throw InputError(where + "found " + std::to_string(fields.size()) + " fields, expected " +
                       std::to_string(header.size()) + " (as the header)");
    std::map<std::string, std::string> f;
    for (std::size_t k = 0; k < header.size(); ++k) f[header[k]] = fields[k];
    out.push_back(recording_of(f, line_no, where));
  }
  if (header.empty())
    throw InputError(path + ": found no header, expected 'path,unit,model[,...]' and one row per recording");
  return out;
}

std::vector<FleetRecording> read_yaml(const std::string& path, const std::string& text) {
  const YAML::Node root = detail::load_yaml(text, path);
  YAML::Node list = root;
  if (root.IsMap()) {
    detail::check_unique_keys(root, path);
    if (!root["recordings"])
      throw InputError(path + ": found a map without 'recordings', expected a list of recordings");
    list = root["recordings"];
  }
  if (!list.IsSequence())
    throw InputError(detail::yaml_at(path, list.Mark()) + ": expected a list of recordings (path, unit, model, ...)");
  std::vector<FleetRecording> out;
  for (const YAML::Node& item : list) {
    const int line = item.Mark().line + 1;
    const std::string where = at(path, line);
    if (!item.IsMap()) throw InputError(where + "expected a recording: a map with path, unit, model, ...");
    detail::check_unique_keys(item, path);
    std::map<std::string, std::string> f;
    for (const auto& kv : item) {
      const std::string key = kv.first.as<std::string>();
      if (!is_field(key)) throw InputError(where + "found the field '" + key + "', expected some of " + known_fields());
      if (!kv.second.IsScalar()) throw InputError(where + key + ": expected a single value");
      f[key] = trim(kv.second.as<std::string>());
    }
    out.push_back(recording_of(f, line, where));
  }
  return out;
}

// The manifest's text as UTF-8 lines: a byte-order mark (a spreadsheet's "CSV UTF-8")
// skipped, UTF-16, NUL bytes and CR-only line ends refused naming them (the header was
// refused as an unknown field, the mark unseen in the message, or a NUL quoted as its first
// name).
std::string utf8_text(const std::string& path, std::string text) {
  if (text.starts_with("\xFF\xFE") || text.starts_with("\xFE\xFF"))
    throw InputError(path + ":1: found UTF-16 text (its byte-order mark " + (text[0] == '\xFF' ? "FF FE" : "FE FF") +
                     "), expected UTF-8 (save the manifest as UTF-8)");
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    throw InputError(at(path, static_cast<int>(line)) + "found a NUL byte, expected text (UTF-8)");
  }
  // Line ends of CR alone (a classic Mac file) made the file one line: its header took the
  // first row's fields for names ("found the header field 'model base.csv'").
  if (text.find('\n') == std::string::npos && text.find('\r') != std::string::npos)
    throw InputError(path +
                     ":1: found carriage returns (CR) as line ends and no line feed, expected LF or CRLF "
                     "line ends (convert it: tr '\\r' '\\n')");
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  return text;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

std::vector<std::string> manifest_columns(const std::string& columns) {
  std::vector<std::string> out;
  std::stringstream in(columns);
  for (std::string c; std::getline(in, c, ',');) out.push_back(trim(c));
  return out;
}

FleetManifest read_fleet_manifest(const std::string& path) {
  const std::string text = utf8_text(path, read_side_file(path, "a fleet manifest (CSV or YAML)", kMaxManifestBytes));
  FleetManifest m;
  m.path = path;
  m.recordings = ends_with(path, ".yaml") || ends_with(path, ".yml") ? read_yaml(path, text) : read_csv(path, text);
  if (m.recordings.empty()) throw InputError(path + ": found no recording, expected one row per recording");
  const fs::path folder = fs::path(path).parent_path();
  for (FleetRecording& r : m.recordings) {
    if (!r.path.empty() && fs::path(r.path).is_relative() && !folder.empty()) r.path = (folder / r.path).string();
    if (r.group.empty()) r.group = r.model;
  }
  return m;
}

std::vector<std::string> fleet_manifest_problems(const FleetManifest& manifest) {
  std::vector<std::string> problems;
  std::map<std::string, int> first_row;
  for (const FleetRecording& r : manifest.recordings) {
    const std::string where = at(manifest.path, r.row);
    std::string why;
    for (const auto& [name, value] :
         {std::pair<const char*, const std::string*>{"path", &r.path}, {"unit", &r.unit}, {"model", &r.model}})
      if (why.empty() && value->empty()) why = std::string(name) + ": empty, expected a value";
    // Names reach the table, the JSON and the terminal: printable text only.
    for (const auto& [name, value] :
         {std::pair<const char*, const std::string*>{"unit", &r.unit}, {"model", &r.model}, {"group", &r.group}})
      if (why.empty() && std::any_of(value->begin(), value->end(),
                                     [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
        why = std::string(name) + ": found a control character in '" + printable_line(*value) +
              "', expected printable text";
    // ... and UTF-8, as the JSON holds them: other bytes were replaced there (U+FFFD) and kept
    // raw in the CSV, so that two units could be one in the JSON.
    for (const auto& [name, value] :
         {std::pair<const char*, const std::string*>{"unit", &r.unit}, {"model", &r.model}, {"group", &r.group}})
      if (why.empty() && !is_utf8(*value))
        why = std::string(name) + ": found bytes that are not UTF-8 in '" + printable_line(*value) +
              "', expected UTF-8 text";
    if (why.empty())
      if (const auto [it, fresh] = first_row.emplace(r.unit, r.row); !fresh)
        why = "unit '" + r.unit + "' given twice (first at row " + std::to_string(it->second) + ")";
    if (why.empty() && r.rate) why = sampling_rate_problem(*r.rate, "rate");
    if (why.empty() && !r.units.empty()) {
      try {
        parse_units_spec(r.units);
      } catch (const InputError& e) {
        why = std::string("units: ") + e.what();
      }
    }
    if (why.empty()) {
      ReadOptions o;
      if (!r.columns.empty()) o.columns = manifest_columns(r.columns);
      o.freq = r.rate;
      o.topic = r.topic;
      try {
        check_signals(r.path, o);
      } catch (const InputError& e) {
        why = e.what();
        // The reader names the CLI's option; a manifest's row says it in its rate field.
        if (why.find("--freq") != std::string::npos) why += " (a manifest row: its rate field)";
      }
    }
    if (!why.empty()) problems.push_back(where + why);
  }
  return problems;
}

}  // namespace gmwm::io
