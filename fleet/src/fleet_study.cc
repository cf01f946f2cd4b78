// The fleet study: plan (cache keys and cached records) -> run (the rest, as tasks, each
// record cached when done) -> assemble (rows labelled from the manifest) -> summarise
// (fleet_study.h).
#include "gmwm/fleet/fleet_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/gap/gap.h"
#include "gmwm/fleet/fleet_cache.h"
#include "gmwm/fleet/fleet_joint.h"
#include "gmwm/fleet/fleet_record.h"
#include "gmwm/io/units.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::fleet {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Stage 1's result: per recording its cache key ("" when it has none) and its record when
// the cache held one; the tasks of the others.
struct Plan {
  std::vector<std::string> keys;
  std::vector<std::optional<FleetRecord>> records;
  std::vector<FleetTask> tasks;
  int cached = 0;
  std::vector<std::string> problems;  // entries there but not used, one line each
};

// Stage 1: the keys, and what the cache already holds.
Plan plan(const io::FleetManifest& manifest, const FleetStudyOptions& o, const FleetCache& cache) {
  Plan p;
  const std::size_t n = manifest.recordings.size();
  p.keys.resize(n);
  p.records.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const io::FleetRecording& r = manifest.recordings[i];
    if (cache.enabled()) {
      try {
        p.keys[i] = cache.key(r, o);
      } catch (const InputError&) {
        // Unreadable now: the task says why, as its row.
      }
    }
    if (!p.keys[i].empty()) {
      std::string why;
      if (const std::optional<std::string> text = cache.load(p.keys[i], &why)) {
        try {
          p.records[i] = parse_fleet_record(*text, cache.path_of(p.keys[i]));
          ++p.cached;
          continue;
        } catch (const InputError& e) {
          why = e.what();
        }
      }
      if (!why.empty()) {
        p.problems.push_back(why + "; not used: unit '" + r.unit + "' computed again");
        cache.forget(p.keys[i]);
      }
    }
    p.tasks.push_back({i, fleet_task_text(r, o)});
  }
  return p;
}

// The runner of a study that has none: the tasks here, one after another, through the same
// texts a worker elsewhere runs (with the selection's progress, the cancellation point).
void run_here(const std::vector<FleetTask>& tasks, const std::function<void(std::size_t, const std::string&)>& done,
              const std::function<void(int, int)>& select_progress) {
  for (std::size_t k = 0; k < tasks.size(); ++k) done(k, run_fleet_task(tasks[k].text, select_progress));
}

// Stage 2: the tasks, by the options' runner or here; each record cached as it arrives.
void run(Plan& p, const FleetStudyOptions& o, const FleetCache& cache) {
  const int all = static_cast<int>(p.records.size());
  int finished = p.cached;
  if (o.progress && p.cached > 0) o.progress(finished, all);
  const auto done = [&](std::size_t k, const std::string& text) {
    if (k >= p.tasks.size()) throw std::out_of_range("fleet: a runner handed back a task it was not given");
    const std::size_t i = p.tasks[k].index;
    if (p.records[i]) return;  // handed back twice (a retried task): the first stands
    try {
      p.records[i] = parse_fleet_record(text, "the record of recording " + std::to_string(i + 1));
    } catch (const InputError& e) {
      p.records[i] = parse_fleet_record(failed_record_text(e.what()), "a failed task's record");
    }
    if (!p.keys[i].empty() && p.records[i]->status == "ok") cache.store(p.keys[i], text);
    if (o.progress) o.progress(++finished, all);
  };
  if (o.runner)
    o.runner(p.tasks, done);
  else
    run_here(p.tasks, done, o.select.progress);
  for (const FleetTask& t : p.tasks)
    if (!p.records[t.index])
      p.records[t.index] = parse_fleet_record(failed_record_text("the runner gave no record for it"), "runner");
}

// Stage 3: the rows (and their curves), labelled from the manifest.
void assemble(const io::FleetManifest& manifest, std::vector<std::optional<FleetRecord>>& records,
              const std::vector<bool>& from_cache, FleetStudy& study) {
  for (std::size_t i = 0; i < records.size(); ++i) {
    const io::FleetRecording& r = manifest.recordings[i];
    FleetRecord& rec = *records[i];
    const auto label = [&](FleetRow& row) {
      row.unit = r.unit;
      row.model = r.model;
      row.group = r.group;
      row.path = r.path;
      row.cached = from_cache[i];
    };
    if (rec.status != "ok") {
      FleetRow row;
      label(row);
      row.status = rec.status;
      row.freq = rec.freq;
      row.seconds = rec.seconds;
      study.rows.push_back(std::move(row));
      study.curves.emplace_back();
      ++study.failed;
      continue;
    }
    for (std::size_t k = 0; k < rec.axes.size(); ++k) {
      label(rec.axes[k]);
      study.rows.push_back(std::move(rec.axes[k]));
      study.curves.push_back(std::move(rec.curves[k]));
    }
  }
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string g4(double x) { return significant(x, 3); }

}  // namespace

namespace {

// The unit a group's axis is summarised in: the data unit its rows share, else (units
// declared differently, e.g. one unit recorded in deg/s and another in rad/s) the SI unit
// of the kind, every figure converted to it. Per row the factor to that unit.
struct SummaryUnit {
  std::string unit;
  std::vector<double> factor;  // per member row: figure x factor = figure in `unit`
};

double per_si_of(const FleetRow& r) {
  if (r.data_unit.empty()) return 1.0;  // undeclared: SI, the convention of --units
  try {
    return io::parse_any_unit(r.data_unit).second.per_si;
  } catch (const std::exception&) {
    return 1.0;
  }
}

SummaryUnit summary_unit(const std::vector<FleetRow*>& members) {
  SummaryUnit u;
  bool same = true;
  for (const FleetRow* r : members) same = same && r->data_unit == members.front()->data_unit;
  if (same) {
    u.unit = members.empty() ? std::string() : members.front()->data_unit;
    u.factor.assign(members.size(), 1.0);
    return u;
  }
  try {
    u.unit = io::si_unit(io::sensor_kind_of_column(members.front()->axis)).name;
  } catch (const std::exception&) {
    u.unit = "SI";
  }
  for (const FleetRow* r : members) u.factor.push_back(1.0 / per_si_of(*r));
  return u;
}

const ChosenFigure& figure_of(const FleetRow& r, int k) { return r.figures[k]; }

// One figure of one group's axis: the median and spread of the logs, the units beyond the
// outlier rule (their rows flagged), the units above the spec.
FleetFigureSummary summarise_figure(std::vector<FleetRow>& rows, const std::string& group, const std::string& axis,
                                    int k, double z_half) {
  FleetFigureSummary s;
  s.group = group;
  s.axis = axis;
  s.figure = kFigureNames[k].symbol;
  std::vector<FleetRow*> all, members;
  for (FleetRow& r : rows)
    if (r.group == group && r.axis == axis) all.push_back(&r);
  for (FleetRow* r : all) {
    for (const SpecCheck& c : r->spec)
      if (c.figure == s.figure && c.verdict == SpecVerdict::kFail) s.out_of_spec.push_back(r->unit);
    if (!r->figures_known) continue;
    const ChosenFigure& f = figure_of(*r, k);
    if (f.figure.status != ReadoffStatus::kBound && f.figure.value > 0.0) members.push_back(r);
  }
  const SummaryUnit u = summary_unit(members);
  s.unit = members.empty() ? summary_unit(all).unit : u.unit;
  std::vector<double> logs, se, se2;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Readoff& f = figure_of(*members[i], k).figure;
    logs.push_back(std::log(f.value * u.factor[i]));
    // The unit's own standard error on the log scale, from its interval (0 when it has none).
    se.push_back(log_standard_error(f.low, f.high, z_half));
    se2.push_back(se.back() * se.back());
  }
  s.units = static_cast<int>(logs.size());
  if (logs.empty()) return s;
  const double m = median_of(logs);
  std::vector<double> dev;
  for (double x : logs) dev.push_back(std::abs(x - m));
  const double mad = median_of(dev);
  const double total = mad / kMadToSigma;
  // The spread between units net of the read-offs' own noise (the random-effects split of
  // the total: a unit's deviation is the fleet's spread plus its own estimation error).
  s.yardstick.typical_se2 = median_of(se2);
  s.yardstick.between2 = std::max(0.0, total * total - s.yardstick.typical_se2);
  s.median = std::exp(m);
  s.spread = std::exp(total);
  s.unit_spread = std::exp(std::sqrt(s.yardstick.between2));
  for (std::size_t i = 0; s.units >= kMinUnitsForFlags && mad > 0.0 && i < logs.size(); ++i) {
    const double scale = s.yardstick.scale(se[i]);
    const double z = scale > 0.0 ? (logs[i] - m) / scale : 0.0;
    if (std::abs(z) <= kFleetOutlierZ) continue;
    s.flagged.push_back(members[i]->unit);
    members[i]->flags.push_back(std::string(1, s.figure) + ": " + g4(std::exp(logs[i] - m)) +
                                "x the fleet's median (robust z " + g4(z) + ")");
  }
  return s;
}

}  // namespace

double OutlierYardstick::scale(double se) const { return std::sqrt(between2 + se * se); }

double OutlierYardstick::reach(double se) const { return std::exp(kFleetOutlierZ * scale(se)); }

double log_standard_error(double low, double high, double z_half) {
  const double se = low > 0.0 && high > low ? std::log(high / low) / (2.0 * z_half) : 0.0;
  return std::isfinite(se) ? se : 0.0;
}

std::vector<FleetFigureSummary> fleet_summary(std::vector<FleetRow>& rows, double alpha) {
  const double z_half = boost::math::quantile(boost::math::normal(), 1.0 - alpha / 2.0);
  // Groups and axes in the order they first appear.
  std::vector<std::pair<std::string, std::string>> keys;
  for (const FleetRow& r : rows)
    if (!r.axis.empty() && std::find(keys.begin(), keys.end(), std::pair{r.group, r.axis}) == keys.end())
      keys.emplace_back(r.group, r.axis);
  std::vector<FleetFigureSummary> out;
  for (const auto& [group, axis] : keys)
    for (int k = 0; k < kFigureCount; ++k) out.push_back(summarise_figure(rows, group, axis, k, z_half));
  return out;
}

std::string FleetStudyOptions::Validate() const {
  if (model.empty()) return "the maximal model is empty";
  if (select.estimator) return "leave select.estimator null: the study sets it";
  if (select.bootstrap_draw) return "leave select.bootstrap_draw empty: a task carries its settings as text";
  if (select.fit.omega_matrix || !select.fit.starts.empty() || select.fit.estimator)
    return "leave select.fit's omega_matrix, starts and estimator empty: the selection sets them per model";
  if (std::string why = select.Validate(); !why.empty()) return why;
  if (std::string why = wv.Validate(); !why.empty()) return why;
  if (std::string why = pipeline::first_level_problem(first_level); !why.empty()) return why;
  if (!(memory_budget >= 0.0)) return "memory_budget must be >= 0";
  if (joint.enabled) {
    ReplicateTestOptions t;
    t.bootstrap = joint.test_draws;
    if (std::string why = t.Validate(); !why.empty()) return "joint test " + why;
  }
  if (gap) {
    gap::GapOptions g;
    g.replicates = gap->replicates;
    if (std::string why = g.Validate(); !why.empty()) return "gap " + why;
    if (gap->format == io::SimFormat::kRotors) return "gap: a RotorS baseline is read as gz-sdf (format gz-sdf)";
  }
  return {};
}

FleetStudy study_fleet(const io::FleetManifest& manifest, const FleetStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("fleet: " + why);
  check_fleet_cache_dir(options.cache_dir);
  const auto start = std::chrono::steady_clock::now();
  const FleetCache cache(options.cache_dir);
  FleetStudy study;
  study.manifest = manifest.path;
  study.model_spec = options.model.text();
  study.recordings = static_cast<int>(manifest.recordings.size());
  study.cache_dir = options.cache_dir;
  if (options.spec) study.spec_path = options.spec->path;
  if (options.gap) study.gap_baseline = options.gap->name;

  Plan p = plan(manifest, options, cache);
  std::vector<bool> from_cache(p.records.size());
  for (std::size_t i = 0; i < p.records.size(); ++i) from_cache[i] = p.records[i].has_value();
  study.cached = p.cached;
  study.cache_problems = std::move(p.problems);
  run(p, options, cache);
  if (!cache.store_problem().empty())
    study.cache_problems.push_back(cache.store_problem() + "; the records of this run from then on were not cached");
  assemble(manifest, p.records, from_cache, study);
  if (options.spec) check_spec(study.rows, *options.spec);
  study.summary = fleet_summary(study.rows, options.wv.alpha);
  if (options.joint.enabled) study.joint = fleet_joint_models(study, options);
  study.seconds = seconds_since(start);
  return study;
}

}  // namespace gmwm::fleet
