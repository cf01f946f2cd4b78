#include "gmwm/report/json_output.h"

#include <cmath>
#include <ctime>

#include <unistd.h>

#include "gmwm/version.h"

namespace gmwm::report {

using json = Json;

std::string version() { return library_version(); }

json json_number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json json_document(const std::string& command) {
  json doc = json::object();
  doc["tool"] = "gmwm";
  doc["version"] = version();
  doc["command"] = command;
  doc["columns"] = json::array();
  return doc;
}

namespace {

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return {};
  return buf;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

Json parameters_json(const FitResult& fit) {
  json params = json::array();
  const bool has_theta =
      fit.theta.size() == fit.model.num_parameters() && fit.model.num_parameters() > 0 && fit.theta.allFinite();
  if (!has_theta) return params;
  for (const ParameterRow& r : parameter_rows(fit))
    params.push_back({{"process", r.process},
                      {"component", r.component},
                      {"name", r.name},
                      {"value", json_number(r.value)},
                      {"se", json_number(r.se)},
                      {"ci_low", json_number(r.ci_low)},
                      {"ci_high", json_number(r.ci_high)},
                      {"interval", r.interval.empty() ? json(nullptr) : json(r.interval)}});
  return params;
}

Json fit_quality_json(const FitResult& fit, double freq, bool freq_known) {
  const std::string verdict = rejection_summary(fit, freq, freq_known);
  const std::string degeneracy = degeneracy_summary(fit);
  json worst = json::array();
  for (const auto& m : fit.worst_levels(3))
    worst.push_back({{"level", m.level},
                     {"tau", json_number(m.tau)},
                     {"tau_seconds", freq_known ? json_number(m.tau / freq) : json(nullptr)},
                     {"ratio", json_number(m.ratio)},
                     {"z", json_number(m.z)}});
  return {{"rejected", std::isfinite(fit.gof.p_value) && fit.gof.p_value < 0.05},
          {"verdict", verdict.empty() ? json(nullptr) : json(verdict)},
          {"worst_levels", std::move(worst)},
          {"degenerate", fit.degenerate()},
          {"degeneracy", degeneracy.empty() ? json(nullptr) : json(degeneracy)}};
}

void add_run_info(json& doc, const RunInfo& run) {
  json r = json::object();
  r["threads"] = run.threads;
  json secs = json::object();
  for (const auto& [name, s] : run.seconds) secs[name] = json_number(s);
  r["seconds"] = std::move(secs);
  r["host"] = host_name();
  r["date"] = utc_now();
  r["argv"] = run.argv;
  doc["run"] = std::move(r);
}

json timing_json(const io::TimingReport& t) {
  return {{"column", t.column},
          {"unit", t.unit},
          {"unit_source", t.unit_source},
          {"samples", t.samples},
          {"median_step_seconds", json_number(t.median_step_seconds)},
          {"estimated_freq", json_number(t.estimated_freq)},
          {"gaps", t.gaps},
          {"largest_gap_seconds", json_number(t.largest_gap_seconds)},
          {"disorder", t.disorder},
          {"given_freq", t.given_freq ? json_number(*t.given_freq) : json(nullptr)},
          {"duplicated_stamps", t.duplicated},  // of the disorder: zero steps, then where
          {"first_duplicated", t.first_duplicated >= 0 ? json(t.first_duplicated) : json(nullptr)},
          {"last_duplicated", t.last_duplicated >= 0 ? json(t.last_duplicated) : json(nullptr)},
          {"first_backward", t.first_backward >= 0 ? json(t.first_backward) : json(nullptr)}};
}

json record_timing_json(const io::SignalSet& set) {
  json j = timing_json(*set.timing);
  std::int64_t placed = 0;
  for (const MissingRun& r : set.timing->missing) placed += r.length;
  j["missing_samples"] = placed;
  j["gap_handling"] = std::string(io::gap_handling_name(set.gaps));
  // What the studies read: the gap-resistant windows (the gaps' samples missing) or the samples
  // joined end to end (--gaps join, or --freq across a change of rate).
  j["gaps_read_as_missing"] = !set.missing.empty();
  return j;
}

json repeated_samples_json(const io::Signal& signal, double freq, bool freq_known) {
  const RepeatedSamples& r = signal.repeated;
  const double tau = std::ldexp(1.0, r.first_clean_level);
  return {{"column", signal.name},
          {"held_share", json_number(r.held_share)},
          {"zero_step_share", json_number(r.zero_step_share)},
          {"expected_zero_step_share", json_number(r.expected_zero_step_share)},
          {"interpolated_share", json_number(r.interpolated_share)},
          {"period", r.period},
          {"first", r.first},
          {"last", r.last},
          {"samples_per_measurement", json_number(r.samples_per_measurement)},
          {"first_clean_level", r.first_clean_level},
          {"first_clean_tau", json_number(tau)},
          {"first_clean_tau_seconds", freq_known && freq > 0.0 ? json_number(tau / freq) : json(nullptr)},
          {"summary", repeated_samples_text(r, signal.name, freq_known ? freq : 0.0)}};
}

void add_record_json(json& doc, const io::SignalSet& set) {
  if (set.timing) doc["timing"] = record_timing_json(set);
  json repeated = json::array();
  for (const io::Signal& s : set.signals)
    if (s.repeated.detected()) repeated.push_back(repeated_samples_json(s, set.freq, set.freq_known));
  if (!repeated.empty()) doc["repeated_samples"] = std::move(repeated);
  if (set.data == io::DataKind::kRate && set.decimation <= 1) return;
  doc["conditioning"] = {
      {"data", std::string(io::data_kind_name(set.data))},
      {"decimation", set.decimation},
      {"decimation_filter",
       set.decimation > 1 ? json(std::string(io::decimation_filter_name(set.decimation_filter))) : json(nullptr)},
      {"freq_before_decimation", json_number(set.freq_before_decimation)},
      {"summary", io::conditioning_summary(set)}};
}

json column_json(const ColumnInfo& column) {
  json c = json::object();
  c["name"] = column.name;
  c["n"] = column.n;
  c["freq"] = column.freq_known ? json_number(column.freq) : json(nullptr);
  return c;
}

json wv_levels_json(const WaveletVariance& wv, double freq, bool freq_known) {
  json levels = json::array();
  for (int j = 0; j < wv.levels(); ++j) {
    const auto k = static_cast<std::size_t>(j);
    json l = json::object();
    l["level"] = j + 1;
    l["tau"] = json_number(wv.tau[k]);
    l["tau_seconds"] = freq_known && freq > 0 ? json_number(wv.tau[k] / freq) : json(nullptr);
    l["wv"] = json_number(wv.wv[k]);
    l["ci_low"] = json_number(wv.ci_low[k]);
    l["ci_high"] = json_number(wv.ci_high[k]);
    l["coefficients"] = wv.coefficients[k];
    if (k < wv.partial.size()) l["partial"] = wv.partial[k];
    if (k < wv.notes.size() && !wv.notes[k].empty()) l["note"] = wv.notes[k];
    levels.push_back(std::move(l));
  }
  return levels;
}

// The WV's own fields of a column (wv and fit): estimator, efficiency, alpha, levels.
void add_wv_fields(json& c, const ColumnInfo& column, const WaveletVariance& wv) {
  c["estimator"] = wv.estimator;
  c["efficiency"] = wv.efficiency ? json_number(*wv.efficiency) : json(nullptr);
  if (!wv.small_sample.empty()) c["small_sample"] = wv.small_sample;
  if (!wv.screening.empty()) {
    json ranges = json::array();
    std::int64_t samples = 0;
    for (const auto& [a, b] : wv.replaced) {
      ranges.push_back(json::array({a, b}));
      samples += b - a + 1;
    }
    c["screening"] = {{"note", wv.screening}, {"replaced_samples", samples}, {"replaced_ranges", std::move(ranges)}};
  }
  c["alpha"] = json_number(wv.alpha);
  c["levels"] = wv_levels_json(wv, column.freq, column.freq_known);
}

json wv_column_json(const ColumnInfo& column, const WaveletVariance& wv) {
  json c = column_json(column);
  add_wv_fields(c, column, wv);
  return c;
}

json robust_wv_column_json(const ColumnInfo& column, const WaveletVariance& robust,
                           const std::vector<robust::LevelDiagnostic>& diagnostic,
                           const robust::Quantization& quantization) {
  json c = wv_column_json(column, robust);
  json q = json::object();
  q["detected"] = quantization.detected;
  q["quantum"] = quantization.detected ? json_number(quantization.quantum) : json(nullptr);
  c["quantization"] = std::move(q);
  auto& levels = c["levels"];
  for (std::size_t j = 0; j < levels.size() && j < diagnostic.size(); ++j) {
    const auto& d = diagnostic[j];
    levels[j]["classical_wv"] = json_number(d.classical_wv);
    levels[j]["robust_to_classical"] = json_number(d.robust_to_classical);
    levels[j]["ci_disjoint"] = d.ci_disjoint;
    levels[j]["contaminated"] = d.contaminated;
    levels[j]["rounding_ratio"] = json_number(d.expected_ratio);
    levels[j]["tail_share"] = json_number(d.tail_share);
  }
  return c;
}

std::vector<ParameterRow> parameter_rows(const FitResult& fit) {
  const Model& m = fit.model;
  std::vector<ParameterRow> rows;
  const double nan = std::nan("");
  auto at = [&](const Eigen::VectorXd& v, int k) { return k < v.size() ? v(k) : nan; };
  for (int k = 0; k < m.num_parameters(); ++k) {
    const int c = m.component_of(k);
    const Process& p = *m.components()[static_cast<std::size_t>(c)].process;
    const int local = k - m.offset(c);
    ParameterRow r;
    r.process = p.name();
    r.component = c + 1;
    r.name = m.spec_of(k).name;
    const double value = at(fit.theta, k);
    r.value = std::isfinite(value) ? p.to_display(local, value) : value;
    // Display units are an affine change of unit at most: map the interval ends and
    // scale the standard error by the same factor.
    const double se = at(fit.se, k);
    r.se = std::isfinite(se) && std::isfinite(value) ? std::abs(p.to_display(local, value + se) - r.value) : se;
    const double lo = at(fit.ci_low, k), hi = at(fit.ci_high, k);
    r.ci_low = std::isfinite(lo) ? p.to_display(local, lo) : lo;
    r.ci_high = std::isfinite(hi) ? p.to_display(local, hi) : hi;
    if (r.ci_low > r.ci_high) std::swap(r.ci_low, r.ci_high);
    if (static_cast<std::size_t>(k) < fit.interval.size())
      r.interval = to_string(fit.interval[static_cast<std::size_t>(k)]);
    rows.push_back(std::move(r));
  }
  return rows;
}

json fit_column_json(const ColumnInfo& column, const WaveletVariance& wv, const FitResult& fit, OmegaKind omega) {
  json c = column_json(column);
  const bool has_theta =
      fit.theta.size() == fit.model.num_parameters() && fit.model.num_parameters() > 0 && fit.theta.allFinite();
  c["model"] = has_theta ? json(fit.model.to_string(fit.theta)) : json(nullptr);
  c["model_structure"] = fit.model.to_string();
  c["parameters"] = parameters_json(fit);
  c["quality"] = fit_quality_json(fit, column.freq, column.freq_known);
  c["objective"] = json_number(fit.objective);
  c["gof"] = {{"statistic", json_number(fit.gof.statistic)},
              {"df", json_number(fit.gof.df)},
              {"p_value", json_number(fit.gof.p_value)},
              {"method", fit.gof.method}};
  c["status"] = to_string(fit.status);
  c["message"] = fit.message;
  c["notes"] = fit.notes;
  c["evaluations"] = fit.evaluations;
  c["omega"] = to_string(omega);  // the library's one spelling
  json implied = json::array();
  for (Eigen::Index j = 0; j < fit.implied_wv.size(); ++j) implied.push_back(json_number(fit.implied_wv(j)));
  c["implied_wv"] = std::move(implied);
  add_wv_fields(c, column, wv);
  return c;
}

namespace {

// A ranking row's effective model and parameters as a FitResult (values only).
// Each member's own objective (null where its fit failed).
json member_objectives(const selection::RankedModel& r) {
  json a = json::array();
  for (double g : r.member_objectives) a.push_back(std::isfinite(g) ? json_number(g) : json(nullptr));
  return a;
}

}  // namespace

FitResult ranking_row_fit(const selection::Selection& sel, const selection::RankedModel& r) {
  if (r.rank == 1) return sel.best_fit;
  FitResult f;
  f.model = r.effective.model;
  f.theta = r.effective.theta;
  f.status = r.fit.status;
  f.message = r.fit.message;
  f.objective = r.objective;
  f.gof = r.gof;
  return f;
}

json select_column_json(const ColumnInfo& column, const WaveletVariance& wv, const selection::Selection& sel,
                        selection::Penalty penalty) {
  (void)penalty;
  json c = column_json(column);
  c["full_model"] = sel.full_model;
  c["best"] = sel.ranking.empty() ? json(nullptr) : json(sel.ranking.front().model);
  const FitResult& b = sel.best_fit;
  c["best_model"] = b.theta.size() == b.model.num_parameters() && b.theta.allFinite() ? json(b.model.to_string(b.theta))
                                                                                      : json(nullptr);
  c["penalty"] = selection::to_string(penalty);
  c["omega"] = selection::to_string(sel.omega_source);
  c["models"] = sel.models;
  c["representation_violations"] = sel.representation_violations;
  json ranking = json::array();
  for (const auto& r : sel.ranking) {
    json e = {
        {"rank", r.rank},
        {"model", r.model},
        {"objective", json_number(r.objective)},
        {"optimism", json_number(r.optimism)},
        {"criterion", json_number(r.criterion)},
        {"optimism_analytic", r.optimism_analytic ? json_number(*r.optimism_analytic) : json(nullptr)},
        {"optimism_bootstrap", r.optimism_bootstrap ? json_number(*r.optimism_bootstrap) : json(nullptr)},
        {"optimism_bootstrap_se", r.optimism_bootstrap_se ? json_number(*r.optimism_bootstrap_se) : json(nullptr)},
        {"rank_analytic", r.rank_analytic ? json(*r.rank_analytic) : json(nullptr)},
        {"rank_bootstrap", r.rank_bootstrap ? json(*r.rank_bootstrap) : json(nullptr)},
        {"gof_p_value", json_number(r.gof.p_value)},
        {"status", to_string(r.fit.status)},
        {"effective_parameters", r.parameters},
        {"members", r.members},
        {"member_objectives", member_objectives(r)},
        {"reductions", r.effective.reductions},
        {"parameters", parameters_json(ranking_row_fit(sel, r))}};
    if (!r.analytic.message.empty()) e["optimism_note"] = r.analytic.message;
    if (r.optimism_bootstrap && r.optimism_analytic)
      e["optimism_difference"] = json_number(*r.optimism_bootstrap - *r.optimism_analytic);
    if (r.bootstrap_failed > 0) e["bootstrap_failed"] = r.bootstrap_failed;
    if (r.bootstrap_not_converged > 0) e["bootstrap_not_converged"] = r.bootstrap_not_converged;
    ranking.push_back(std::move(e));
  }
  c["ranking"] = std::move(ranking);
  json candidates = json::array();
  for (const auto& cf : sel.candidates)
    candidates.push_back({{"model", cf.model},
                          {"objective", json_number(cf.fit.objective)},
                          {"status", to_string(cf.fit.status)},
                          {"effective", cf.effective.model.to_string()},
                          {"reductions", cf.effective.reductions}});
  c["candidates"] = std::move(candidates);
  c["not_converged"] = sel.not_converged;
  c["failed"] = sel.failed;
  c["best_fit"] = {{"objective", json_number(b.objective)},
                   {"status", to_string(b.status)},
                   {"gof",
                    {{"statistic", json_number(b.gof.statistic)},
                     {"df", json_number(b.gof.df)},
                     {"p_value", json_number(b.gof.p_value)},
                     {"method", b.gof.method}}},
                   {"notes", b.notes},
                   {"quality", fit_quality_json(b, column.freq, column.freq_known)}};
  c["all_rejected"] = sel.all_rejected;
  add_wv_fields(c, column, wv);
  return c;
}

std::string dump_json(const json& doc) { return doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n"; }

namespace {

// Column k of a study on `set`: its name, length and rate, and its declared unit.
ColumnInfo study_column(const io::SignalSet& set, std::size_t k, const std::string& name,
                        const std::vector<std::string>& units) {
  return {name, static_cast<std::int64_t>(set.signals[k].values.size()), set.freq, set.freq_known,
          k < units.size() ? units[k] : std::string()};
}

void add_physical_fields(json& col, const FitResult& fit, const ColumnInfo& info, double filter_rate,
                         const std::optional<FigureReport>& figures, const char* continuous_key,
                         const char* kalman_key) {
  add_physical_fields(col, fit, info, filter_rate, figures ? &figures->chosen : nullptr,
                      figures ? allan_json(figures->adev, figures->model_adev) : json(nullptr), continuous_key,
                      kalman_key);
}

}  // namespace

void add_physical_fields(Json& col, const FitResult& fit, const ColumnInfo& info, double filter_rate,
                         const ChosenFigures* figures, Json allan, const char* continuous_key, const char* kalman_key) {
  col["unit"] = info.unit.empty() ? json(nullptr) : json(info.unit);
  col[continuous_key] = continuous_json(fit, info);
  col[kalman_key] = kalman_json(fit, info, filter_rate, figures);
  col["allan"] = std::move(allan);
  col["noise_figures"] = figures ? noise_figures_json(*figures, info.unit) : json(nullptr);
}

json wv_document(const io::SignalSet& set, const pipeline::WvStudy& study, const std::vector<std::string>& units) {
  json doc = json_document("wv");
  doc["input"] = set.path;
  add_record_json(doc, set);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::WvColumnStudy& c = study.columns[k];
    const ColumnInfo info = study_column(set, k, c.name, units);
    json col = c.robust ? robust_wv_column_json(info, c.wv, c.robust->diagnostic, c.robust->quantization)
                        : wv_column_json(info, c.wv);
    // The data's unit whenever it is known (--units), not only beside the Allan deviation: a
    // WV's plot and table label its values (unit^2) with it.
    if (c.allan || !info.unit.empty()) col["unit"] = info.unit.empty() ? json(nullptr) : json(info.unit);
    if (c.allan) {
      col["allan"] = allan_json(c.allan->adev, {});
      col["noise_figures"] = noise_figures_json(c.allan->chosen, info.unit);
    }
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

json fit_document(const io::SignalSet& set, const pipeline::FitStudy& study, const std::vector<std::string>& units,
                  double filter_rate) {
  json doc = json_document("fit");
  doc["input"] = set.path;
  doc["model_spec"] = study.model_spec;
  doc["seed"] = study.seed;
  add_record_json(doc, set);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::FitColumnStudy& c = study.columns[k];
    const ColumnInfo info = study_column(set, k, c.name, units);
    json col = fit_column_json(info, c.wv, c.fit, study.omega);
    col["first_level"] = c.first_level;  // levels below it shown, not fitted (the notes say why)
    add_physical_fields(col, c.fit, info, filter_rate, c.figures, "continuous", "kalman");
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

json select_document(const io::SignalSet& set, const pipeline::SelectStudy& study,
                     const std::vector<std::string>& units, double filter_rate) {
  json doc = json_document("select");
  doc["input"] = set.path;
  std::string spec;
  for (const ModelSpec& m : study.models) spec += (spec.empty() ? "" : ";") + m.text();
  doc["model_spec"] = spec;
  doc["mode"] = study.listed ? "listed" : "sub-models";
  if (study.listed) doc["duplicate_models"] = study.duplicates;
  doc["optimism"] = selection::to_string(study.options.optimism);
  doc["omega"] = selection::to_string(study.options.omega);
  doc["seed"] = study.options.seed;
  add_record_json(doc, set);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::SelectColumnStudy& c = study.columns[k];
    const ColumnInfo info = study_column(set, k, c.name, units);
    json col = select_column_json(info, c.wv, c.selection, study.options.penalty);
    col["first_level"] = c.first_level;  // levels below it shown, not fitted (the best fit's notes say why)
    add_physical_fields(col, c.selection.best_fit, info, filter_rate, c.figures, "best_continuous", "best_kalman");
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

}  // namespace gmwm::report
