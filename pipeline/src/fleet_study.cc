// The fleet study: per recording (in manifest order) read -> select over the maximal model
// -> one row per axis; a failure becomes the recording's row (fleet_study.h).
#include "gmwm/pipeline/fleet_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>

#include "gmwm/engine/error.h"
#include "gmwm/io/units.h"

namespace gmwm::pipeline {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Stage 1: the recording's signals, as the manifest row says to read them.
io::SignalSet read_recording(const io::FleetRecording& r, const FleetStudyOptions& o) {
  io::ReadOptions read;
  if (!r.columns.empty()) read.columns = io::manifest_columns(r.columns);
  read.freq = r.rate;
  read.topic = r.topic;
  read.memory_budget = o.memory_budget;
  io::SignalSet set = io::read_signals(r.path, read);
  if (!set.freq_known) throw InputError(r.path + ": found no timestamp column, expected one or the row's rate");
  return set;
}

// Stage 2: each axis's row from the selection study.
std::vector<FleetRow> axis_rows(const io::FleetRecording& r, const io::SignalSet& set, const SelectStudy& study,
                                const FleetRow& base) {
  const io::UnitsSpec units = io::parse_units_spec(r.units);
  std::vector<FleetRow> rows;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const SelectColumnStudy& c = study.columns[k];
    FleetRow row = base;
    row.axis = c.name;
    row.data_unit = r.units.empty() ? set.signals[k].unit : io::unit_of_column(units, c.name);
    row.n = static_cast<std::int64_t>(set.signals[k].values.size());
    const FitResult& b = c.selection.best_fit;
    if (b.status == FitStatus::kFailed || b.theta.size() != b.model.num_parameters() || !b.theta.allFinite()) {
      row.status = "the chosen model's fit failed" + (b.message.empty() ? std::string() : ": " + b.message);
    } else {
      row.chosen = b.model.to_string(b.theta);
      row.chosen_structure = b.model.to_string();
      row.gof_p = b.gof.p_value;
    }
    if (c.figures) {
      row.figures = c.figures->chosen;
      row.figures_known = true;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string g4(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace

std::vector<FleetFigureSummary> fleet_summary(std::vector<FleetRow>& rows) {
  // Groups and axes in the order they first appear.
  std::vector<std::pair<std::string, std::string>> keys;
  for (const FleetRow& r : rows)
    if (!r.axis.empty() && std::find(keys.begin(), keys.end(), std::pair{r.group, r.axis}) == keys.end())
      keys.emplace_back(r.group, r.axis);
  std::vector<FleetFigureSummary> out;
  for (const auto& [group, axis] : keys)
    for (int k = 0; k < 3; ++k) {
      FleetFigureSummary s{group, axis, "NKB"[k]};
      std::vector<FleetRow*> members;
      std::vector<double> logs;
      for (FleetRow& r : rows) {
        if (r.group != group || r.axis != axis || !r.figures_known) continue;
        const ChosenFigure& f = k == 0 ? r.figures.white : k == 1 ? r.figures.walk : r.figures.instability;
        if (f.figure.status == ReadoffStatus::kBound || !(f.figure.value > 0.0)) continue;
        members.push_back(&r);
        logs.push_back(std::log(f.figure.value));
      }
      s.units = static_cast<int>(logs.size());
      if (!logs.empty()) {
        const double m = median_of(logs);
        std::vector<double> dev;
        for (double x : logs) dev.push_back(std::abs(x - m));
        const double mad = median_of(dev);
        s.median = std::exp(m);
        s.spread = std::exp(mad / kMadToSigma);
        for (std::size_t i = 0; s.units >= kMinUnitsForFlags && mad > 0.0 && i < logs.size(); ++i) {
          const double z = kMadToSigma * (logs[i] - m) / mad;
          if (std::abs(z) <= kFleetOutlierZ) continue;
          s.flagged.push_back(members[i]->unit);
          members[i]->flags.push_back(std::string(1, s.figure) + ": " + g4(std::exp(logs[i] - m)) +
                                      "x the fleet's median (robust z " + g4(z) + ")");
        }
      }
      out.push_back(std::move(s));
    }
  return out;
}

std::string FleetStudyOptions::Validate() const {
  if (model.empty()) return "the maximal model is empty";
  if (select.estimator) return "leave select.estimator null: the study sets it";
  if (std::string why = select.Validate(); !why.empty()) return why;
  if (std::string why = wv.Validate(); !why.empty()) return why;
  if (!(memory_budget >= 0.0)) return "memory_budget must be >= 0";
  return {};
}

FleetStudy study_fleet(const io::FleetManifest& manifest, const FleetStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("fleet: " + why);
  const auto start = std::chrono::steady_clock::now();
  FleetStudy study;
  study.manifest = manifest.path;
  study.model_spec = options.model.text();
  study.recordings = static_cast<int>(manifest.recordings.size());
  SelectStudyOptions so;
  so.models = {options.model};
  so.select = options.select;
  so.wv = options.wv;
  for (std::size_t i = 0; i < manifest.recordings.size(); ++i) {
    const io::FleetRecording& r = manifest.recordings[i];
    const auto t = std::chrono::steady_clock::now();
    FleetRow base;
    base.unit = r.unit;
    base.model = r.model;
    base.group = r.group;
    base.path = r.path;
    try {
      const io::SignalSet set = read_recording(r, options);
      base.freq = set.freq;
      const SelectStudy s = study_select(set, so);
      std::vector<FleetRow> rows = axis_rows(r, set, s, base);
      for (FleetRow& row : rows) row.seconds = seconds_since(t);
      study.rows.insert(study.rows.end(), rows.begin(), rows.end());
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      base.status = printable_line(e.what());
      base.seconds = seconds_since(t);
      study.rows.push_back(std::move(base));
      ++study.failed;
    }
    if (options.progress) options.progress(static_cast<int>(i + 1), study.recordings);
  }
  study.summary = fleet_summary(study.rows);
  study.seconds = seconds_since(start);
  return study;
}

}  // namespace gmwm::pipeline
