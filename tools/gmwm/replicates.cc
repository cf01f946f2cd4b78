#include "replicates.h"

#include <filesystem>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::cli {
namespace {

struct Entry {
  std::string path;
  std::string column;  // empty: every INPUT column by name
};

// FILE[:COLUMN]: split at the last ':' only when what precedes it is a file and the whole
// entry is not (a file name may contain ':').
Entry parse_entry(const std::string& text) {
  namespace fs = std::filesystem;
  const auto colon = text.rfind(':');
  std::error_code ec;  // a name the system cannot even look up is "not a file", not a crash
  if (colon != std::string::npos && colon > 0 && !fs::exists(text, ec) && fs::exists(text.substr(0, colon), ec)) {
    if (colon + 1 == text.size())
      throw InputError("--joint " + text + ": expected FILE or FILE:COLUMN, got an empty column");
    return {text.substr(0, colon), text.substr(colon + 1)};
  }
  return {text, ""};
}

io::SignalSet read_columns(const std::string& path, const std::vector<std::string>& columns,
                           const InputOptions& options) {
  InputOptions o = options;
  o.input = path;
  std::string list;
  for (std::size_t i = 0; i < columns.size(); ++i) list += (i ? "," : "") + columns[i];
  o.columns = list;
  return read_input(o);
}

}  // namespace

std::string replicate_path(const std::string& entry) { return parse_entry(entry).path; }

std::vector<ReplicateGroup> read_replicates(const io::SignalSet& input, const std::vector<std::string>& entries,
                                            const InputOptions& options) {
  std::vector<std::string> names;
  for (const auto& s : input.signals) names.push_back(s.name);
  std::vector<pipeline::ReplicateRecording> recordings;
  for (const std::string& text : entries) {
    const Entry e = parse_entry(text);
    if (!e.column.empty() && names.size() != 1)
      throw InputError("--joint " + text + ": names one column, but INPUT has " + std::to_string(names.size()) +
                       " selected columns; select one with --columns");
    recordings.push_back({"--joint " + text,
                          read_columns(e.path, e.column.empty() ? names : std::vector<std::string>{e.column}, options),
                          !e.column.empty()});
  }
  return pipeline::group_replicates(input, "INPUT", std::move(recordings));
}

}  // namespace gmwm::cli
