// The "gap" command's column JSON (docs/cli.md).
#include <cmath>
#include <cstdio>

#include "gmwm/report/json_output.h"

#include <span>

#include "gmwm/engine/physical.h"

namespace gmwm::report {
namespace {

// A strength as an object key: %.6g, as the table prints it.
std::string number_key(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

using json = Json;

json seconds(double tau_samples, const ColumnInfo& c) {
  return c.freq_known && c.freq > 0.0 ? json_number(tau_samples / c.freq) : json(nullptr);
}

std::string data_unit(const ColumnInfo& c) { return c.unit.empty() ? "U" : c.unit; }

// The effect's continuous quantities with their intervals (the bootstrap bounds mapped).
json effect_physical(const FitResult& fit, const ColumnInfo& c) {
  json out = json::array();
  if (fit.status == FitStatus::kFailed || fit.theta.size() != fit.model.num_parameters() || !c.freq_known) return out;
  for (int k = 0; k < fit.model.num_components(); ++k) {
    const Process& p = *fit.model.components()[static_cast<std::size_t>(k)].process;
    const auto off = fit.model.offset(k);
    const std::span<const double> th(fit.theta.data() + off, static_cast<std::size_t>(p.size()));
    const auto q = p.physical(th, c.freq);
    std::vector<PhysicalInterval> iv;
    if (fit.ci_low.size() == fit.theta.size())
      iv = physical_interval(
          p, th, std::span<const double>(fit.ci_low.data() + off, static_cast<std::size_t>(p.size())),
          std::span<const double>(fit.ci_high.data() + off, static_cast<std::size_t>(p.size())), c.freq);
    for (std::size_t i = 0; i < q.size(); ++i)
      out.push_back({{"process", p.name()},
                     {"name", q[i].name},
                     {"value", json_number(q[i].value)},
                     {"ci_low", i < iv.size() ? json_number(iv[i].low) : json(nullptr)},
                     {"ci_high", i < iv.size() ? json_number(iv[i].high) : json(nullptr)},
                     {"unit", render_unit(q[i].unit_pattern, data_unit(c))},
                     {"convention", q[i].convention}});
  }
  return out;
}

// The flagged (window, level) cells; null when the series was too short for a map.
json windows_json(const gap::GapResult& g, const ColumnInfo& c) {
  if (!g.windows_checked) return nullptr;
  json out = json::array();
  for (const auto& w : g.windows)
    out.push_back({{"t_from_seconds", seconds(static_cast<double>(w.first_sample), c)},
                   {"t_to_seconds", seconds(static_cast<double>(w.last_sample + 1), c)},
                   {"first_sample", w.first_sample},
                   {"last_sample", w.last_sample},
                   {"tau_seconds", seconds(w.tau, c)},
                   {"tau", w.tau},
                   {"ratio", json_number(w.ratio)},
                   {"z", json_number(w.z)}});
  return out;
}

json split_half_json(const gap::GapResult& g, const ColumnInfo& c) {
  json out = json::array();
  for (const auto& h : g.split_half)
    out.push_back({{"tau", h.tau},
                   {"tau_seconds", seconds(h.tau, c)},
                   {"ratio", json_number(h.ratio)},
                   {"disjoint", h.disjoint}});
  return out;
}

json event_json(const gap::GapResult& g, const ColumnInfo& c) {
  if (!g.event) return nullptr;
  const auto& e = *g.event;
  return {
      {"effect", gap::to_string(e.effect)},
      {"sample", e.sample},
      {"time_seconds", seconds(static_cast<double>(e.sample), c)},
      {"size", json_number(e.size)},
      {"time_constant", json_number(e.time_constant)},
      {"time_constant_seconds", e.effect == gap::GapEffect::kTransient ? seconds(e.time_constant, c) : json(nullptr)},
      {"level", e.level},
      {"statistic", json_number(e.statistic)},
      {"threshold", json_number(e.threshold)}};
}

json trend_json(const gap::GapResult& g) {
  if (!g.trend) return nullptr;
  const auto& t = *g.trend;
  return {{"omega", json_number(t.omega)}, {"ci_low", json_number(t.ci_low)},       {"ci_high", json_number(t.ci_high)},
          {"z", json_number(t.z)},         {"threshold", json_number(t.threshold)}, {"significant", t.significant}};
}

json temperature_json(const gap::GapResult& g) {
  if (!g.temperature) return nullptr;
  const auto& t = *g.temperature;
  return {{"coupling", json_number(t.k)}, {"ci_low", json_number(t.ci_low)},       {"ci_high", json_number(t.ci_high)},
          {"z", json_number(t.z)},        {"threshold", json_number(t.threshold)}, {"significant", t.significant}};
}

json bands_json(const std::vector<gap::GapBand>& v, const ColumnInfo& column) {
  json bands = json::array();
  for (const auto& b : v)
    bands.push_back({{"tau_from_seconds", seconds(b.tau_from, column)},
                     {"tau_to_seconds", seconds(b.tau_to, column)},
                     {"tau_from", b.tau_from},
                     {"tau_to", b.tau_to},
                     {"direction", b.direction},
                     {"peak_ratio", json_number(b.peak_ratio)}});
  return bands;
}

}  // namespace

Json gap_column_json(const ColumnInfo& column, const gap::GapResult& g, const std::vector<std::string>& conversions) {
  json c = column_json(column);
  c["baseline_model"] = g.baseline.to_string(g.baseline_theta);
  json bands = bands_json(g.bands, column);
  json levels = json::array();
  for (const auto& l : g.levels)
    levels.push_back({{"tau", l.tau},
                      {"tau_seconds", seconds(l.tau, column)},
                      {"ratio", json_number(l.ratio)},
                      {"z", json_number(l.z)},
                      {"ref_low", json_number(l.ref_low)},
                      {"analytic_low", json_number(l.analytic_low)},
                      {"analytic_high", json_number(l.analytic_high)},
                      {"ref_high", json_number(l.ref_high)},
                      {"outside", l.outside}});
  c["gap"] = {{"detected", g.detected},
              {"first_level", g.first_level},  // levels below it shown, not compared (the notes say why)
              {"p_value", json_number(g.p_value)},
              {"statistic", json_number(g.statistic)},
              {"bands", std::move(bands)},
              {"levels", std::move(levels)},
              {"windows", windows_json(g, column)},
              {"split_half", split_half_json(g, column)},
              {"window_length_seconds",
               g.windows_checked ? seconds(static_cast<double>(g.window_length), column) : json(nullptr)}};
  json candidates = json::array();
  for (const auto& k : g.candidates)
    candidates.push_back({{"effect", gap::to_string(k.effect)},
                          {"improvement", json_number(k.improvement)},
                          {"threshold", json_number(k.threshold)},
                          {"optimism", json_number(k.optimism)},
                          {"wvic_confirmed", k.wvic_confirmed},
                          {"cleared", k.cleared},
                          {"model", k.model}});
  json steps = json::array();
  for (auto e : g.steps) steps.push_back(gap::to_string(e));
  c["attribution"] = {{"effect", gap::to_string(g.effect)},
                      {"steps", std::move(steps)},
                      {"model", g.final_model.to_string(g.final_theta)},
                      {"parameters", parameters_json(g.final_fit)},
                      {"physical", effect_physical(g.final_fit, column)},
                      {"event", event_json(g, column)},
                      {"event_test", g.event_tested ? json{{"statistic", json_number(g.event_statistic)},
                                                           {"threshold", json_number(g.event_threshold)}}
                                                    : json(nullptr)},
                      {"step_scan", g.step_scan_tested ? json{{"statistic", json_number(g.step_scan_statistic)},
                                                              {"threshold", json_number(g.step_scan_threshold)},
                                                              {"sample", g.step_scan_sample}}
                                                       : json(nullptr)},
                      {"temperature", temperature_json(g)},
                      {"drift", trend_json(g)},
                      {"step_drops", g.step_drops},
                      {"step_shares",
                       [&] {
                         json a = json::array();
                         for (double x : g.step_shares) a.push_back(json_number(x));  // NaN -> null
                         return a;
                       }()},
                      {"step_details", g.step_details},
                      {"refused", g.refused},
                      {"candidates", std::move(candidates)}};
  const auto& s = g.shrinkage;
  c["headline"] = g.headline;
  c["contamination"] = {{"screened", g.contamination_screened}, {"levels", g.contaminated_levels}};
  int outside_after = 0;
  for (const auto& l : g.levels_after) outside_after += l.outside;
  c["remaining"] = {
      {"closed", g.closed}, {"bands", bands_json(g.remaining, column)}, {"levels_outside", outside_after}};
  c["shrinkage"] = {{"objective_before", json_number(s.objective_before)},
                    {"objective_after", json_number(s.objective_after)},
                    {"null_mean", json_number(s.null_mean)},
                    {"null_mean_after", json_number(s.null_mean_after)},
                    {"distance_before", json_number(s.distance_before)},
                    {"distance_after", json_number(s.distance_after)},
                    {"null_distance_mean", json_number(s.null_distance_mean)},
                    {"excess_before", json_number(s.excess_before)},
                    {"excess_after", json_number(s.excess_after)},
                    {"excess_removed", json_number(s.excess_removed)},
                    {"rms_log_ratio_before", json_number(s.rms_log_ratio_before)},
                    {"rms_log_ratio_after", json_number(s.rms_log_ratio_after)},
                    {"levels_outside_before", s.levels_outside_before},
                    {"levels_outside_after", s.levels_outside_after},
                    {"p_value_before", json_number(s.p_value_before)},
                    {"p_value_after", json_number(s.p_value_after)}};
  c["navigation"] = {{"horizon_seconds", g.navigation.horizon_seconds},
                     {"rms_without", json_number(g.navigation.rms_without)},
                     {"rms_with", json_number(g.navigation.rms_with)},
                     {"unit", render_unit("U*s", data_unit(column))}};
  c["conversions"] = conversions;
  c["notes"] = g.notes;
  return c;
}

Json gap_document(const io::SignalSet& set, const pipeline::GapStudy& study) {
  Json doc = json_document("gap");
  doc["input"] = set.path;
  doc["baseline_source"] = study.baseline_source;
  doc["replicates"] = study.replicates;
  doc["seed"] = study.seed;
  add_record_json(doc, set);
  if (!study.temperature_column.empty()) doc["temperature_column"] = study.temperature_column;
  Json significant = Json::array();
  for (const auto& p : study.cross_axis)
    if (p.significant)
      significant.push_back({{"a", study.columns[static_cast<std::size_t>(p.a)].name},
                             {"b", study.columns[static_cast<std::size_t>(p.b)].name},
                             {"tau", p.tau},
                             {"tau_seconds", set.freq_known ? Json(p.tau / set.freq) : Json(nullptr)},
                             {"rho", json_number(p.rho)},
                             {"z", json_number(p.z)}});
  doc["cross_axis"] = {{"tested", study.cross_axis.size()}, {"significant", std::move(significant)}};
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::GapColumnStudy& c = study.columns[k];
    const ColumnInfo info{c.name, static_cast<std::int64_t>(set.signals[k].values.size()), set.freq, set.freq_known,
                          c.unit};
    doc["columns"].push_back(gap_column_json(info, c.result, c.conversions));
  }
  return doc;
}

Json gap_check_document(const gap::GapCheckOptions& options, const gap::GapCheckResult& r) {
  Json doc = json_document("gap-check");
  doc["n"] = options.n;
  doc["replicates"] = options.replicates;
  doc["strengths"] = options.strengths;
  doc["seed"] = options.seed;
  doc["cases"] = static_cast<int>(r.cases.size());
  doc["correct"] = r.correct;
  doc["false_alarms"] = r.false_alarms;
  doc["confusion"] = r.confusion;
  Json power = Json::object(), families = Json::object();
  for (const auto& [t, f] : r.families) {
    Json p = Json::object();
    for (const auto& [s, share] : f.power) p[number_key(s)] = share;
    if (!f.power.empty()) power[t] = p;
    families[t] = {{"cases", f.cases},
                   {"correct", f.correct},
                   {"detected", f.detected},
                   {"located", f.located},
                   {"median_excess_removed", json_number(f.median_excess_removed)},
                   {"strength_90", json_number(f.strength_90)},
                   {"strength_90_crossing", f.power.empty() ? "" : gap::to_string(f.crossing)},
                   {"oracle_strength_90", json_number(f.oracle_strength_90)},
                   {"oracle_ratio", json_number(f.oracle_ratio)}};
  }
  doc["power"] = power;
  doc["families"] = families;
  Json list = Json::array();
  for (const auto& c : r.cases)
    list.push_back({{"truth", gap::to_string(c.truth)},
                    {"strength", c.strength},
                    {"injected", c.injected},
                    {"reported", gap::to_string(c.reported)},
                    {"detected", c.detected},
                    {"located", c.located},
                    {"correct", c.correct},
                    {"excess_removed", json_number(c.excess_removed)},
                    {"parameter_error", json_number(c.parameter_error)},
                    {"oracle_nc", json_number(c.oracle_nc)},
                    {"oracle", c.oracle_time_domain ? "series" : "wv"}});
  doc["case_list"] = list;
  return doc;
}

Json corrected_config_json(const pipeline::CorrectedConfig& c, double freq) {
  ColumnInfo info;
  info.freq = freq;
  info.freq_known = freq > 0.0;
  const auto assessment = [&](const gap::GapAssessment& a) {
    return json{{"objective", json_number(a.objective)},
                {"null_mean", json_number(a.null_mean)},
                {"levels_outside", a.levels_outside},
                {"p_value", json_number(a.p_value)},
                {"navigation_rms", json_number(a.navigation_rms)},
                {"remaining", bands_json(a.remaining, info)}};
  };
  json changes = json::array();
  for (const auto& ch : c.changes)
    changes.push_back({{"field", ch.field},
                       {"input", json_number(ch.input)},
                       {"corrected", json_number(ch.corrected)},
                       {"unit", ch.unit},
                       {"changed", ch.changed}});
  json columns = json::array();
  for (const auto& col : c.columns)
    columns.push_back(
        {{"name", col.name},
         {"expressible",
          col.expressible.num_components() ? json(col.expressible.to_string(col.expressible_theta)) : json(nullptr)},
         {"full", col.full.to_string(col.full_theta)},
         {"not_expressible", col.not_expressible},
         {"verdict", pipeline::to_string(col.verdict)},
         {"why", col.why},
         {"warnings", col.warnings},
         {"gap_left",
          {{"input", assessment(col.before)},
           {"config", assessment(col.with_config)},
           {"full", assessment(col.with_full)}}}});
  return {
      {"format", c.format}, {"content", c.content}, {"header", c.header}, {"changes", changes}, {"columns", columns}};
}

}  // namespace gmwm::report
