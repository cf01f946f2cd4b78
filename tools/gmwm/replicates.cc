#include "replicates.h"

#include <cmath>
#include <filesystem>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::cli {
namespace {

// Rates that differ by less than this (relative) are the same rate (timestamps jitter).
constexpr double kRateTolerance = 1e-6;

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
  std::vector<ReplicateGroup> groups;
  std::vector<std::string> names;
  for (const auto& s : input.signals) {
    groups.push_back({s.name, {input.path + ":" + s.name}, {s.values}});
    names.push_back(s.name);
  }
  for (const std::string& text : entries) {
    const Entry e = parse_entry(text);
    if (!e.column.empty() && groups.size() != 1)
      throw InputError("--joint " + text + ": names one column, but INPUT has " + std::to_string(groups.size()) +
                       " selected columns; select one with --columns");
    const io::SignalSet set =
        read_columns(e.path, e.column.empty() ? names : std::vector<std::string>{e.column}, options);
    if (std::abs(set.freq / input.freq - 1.0) > kRateTolerance)
      throw InputError("--joint " + text + ": sampled at " + fmt(set.freq) + " Hz, INPUT at " + fmt(input.freq) +
                       " Hz; replicates must share the rate");
    for (std::size_t k = 0; k < set.signals.size(); ++k) {
      ReplicateGroup& g = groups[e.column.empty() ? k : 0];
      const std::string source = e.path + ":" + set.signals[k].name;
      for (std::size_t r = 0; r < g.series.size(); ++r)
        if (g.series[r] == set.signals[k].values)
          throw InputError("--joint " + text + ": " + source + " is the same recording as " + g.sources[r] +
                           " (a replicate given twice)");
      g.sources.push_back(source);
      g.series.push_back(set.signals[k].values);
    }
  }
  return groups;
}

std::string replicate_estimator_text(const robust::RobustWvOptions* robust) {
  return robust ? "robust WV (Gaussian efficiency " + fmt(robust->efficiency) + ")" : std::string("classical WV");
}

report::ReplicateReport replicate_report(const ReplicateGroup& group, const std::string& estimator) {
  report::ReplicateReport r;
  r.sources = group.sources;
  for (const auto& s : group.series) r.n.push_back(static_cast<std::int64_t>(s.size()));
  r.estimator = estimator;
  return r;
}

std::string joint_physical_tables(const ReplicateGroup& group, const io::SignalSet& set, const FitResult& joint,
                                  const std::optional<ChosenFigures>& figures, const UnitsOptions& units,
                                  double filter_rate) {
  const report::ColumnInfo info =
      with_unit({group.axis, group.series.empty() ? 0 : static_cast<std::int64_t>(group.series.front().size()),
                 set.freq, set.freq_known, ""},
                units);
  return continuous_table(joint, info) + (figures ? noise_figures_table(*figures, info.unit) : "") +
         kalman_table(joint, info, filter_rate, figures ? &*figures : nullptr);
}

void fill_joint_report_column(report::ReportColumn& column, const ReplicateGroup& group,
                              const std::vector<WaveletVariance>& wvs, const JointAnalysis& analysis,
                              const std::string& estimator) {
  column.wvs = wvs;
  column.fit = analysis.fit.joint;
  column.replicates = replicate_report(group, estimator);
  column.replicates->joint = analysis.fit;
  column.replicates->test = analysis.test;
  column.replicates->bootstrap = analysis.bootstrap;
}

}  // namespace gmwm::cli
