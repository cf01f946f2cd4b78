// The JSON documents of the studies over replicates (docs/cli.md "JSON"): the joint fit of
// each axis and the selection over replicates.
#include <cmath>

#include "gmwm/report/json_output.h"

namespace gmwm::report {
namespace {

// A group's column head: its name, the primary recording's length, the rate, the declared unit.
ColumnInfo group_info(const pipeline::ReplicateGroup& g, const io::SignalSet& set,
                      const std::vector<std::string>& units, std::size_t i) {
  return {g.axis, g.series.empty() ? 0 : static_cast<std::int64_t>(g.series.front().size()), set.freq, set.freq_known,
          i < units.size() ? units[i] : std::string()};
}

double kalman_rate(const io::SignalSet& set, double filter_rate) {
  return filter_rate > 0.0 ? filter_rate : set.freq_known ? set.freq : 0.0;
}

Json joint_column_json(const pipeline::ReplicateGroup& g, const JointFitResult& r, const ReplicateTest* test,
                       const ReplicateBootstrap* boot, const io::SignalSet& set) {
  Json col;
  col["name"] = g.axis;
  col["freq"] = set.freq;
  Json reps = Json::array();
  for (std::size_t k = 0; k < g.sources.size(); ++k) {
    const FitResult& s = r.singles[k];
    reps.push_back({{"source", g.sources[k]},
                    {"n", g.series[k].size()},
                    {"missing_samples", g.missing_samples(k)},
                    {"gaps", g.gaps(k)},
                    {"levels", r.levels[k]},
                    {"objective_share", json_number(k < r.objective_share.size() ? r.objective_share[k] : NAN)},
                    {"fit",
                     {{"model", s.theta.allFinite() ? s.model.to_string(s.theta) : s.model.to_string()},
                      {"status", to_string(s.status)},
                      {"objective", json_number(s.objective)},
                      {"parameters", parameters_json(s)}}}});
  }
  col["replicates"] = reps;
  const FitResult& j = r.joint;
  col["model"] = j.theta.allFinite() ? j.model.to_string(j.theta) : j.model.to_string();
  col["model_structure"] = j.model.to_string();
  col["parameters"] = parameters_json(j);
  Json agmwm = Json::array();
  for (const auto& p : parameter_rows(agmwm_as_fit(r)))
    agmwm.push_back({{"value", json_number(p.value)}, {"se", json_number(p.se)}});
  col["agmwm"] = agmwm;
  col["objective"] = json_number(j.objective);
  col["gof"] = {{"statistic", json_number(j.gof.statistic)},
                {"df", j.gof.df},
                {"p_value", json_number(j.gof.p_value)},
                {"method", j.gof.method}};
  col["status"] = to_string(j.status);
  col["message"] = j.message;
  col["notes"] = j.notes;
  if (boot) {
    Json lo = Json::array(), hi = Json::array();
    for (const auto& p : parameter_rows(replicate_bootstrap_as_fit(r, *boot))) {
      lo.push_back(json_number(p.ci_low));
      hi.push_back(json_number(p.ci_high));
    }
    col["replicate_bootstrap"] = {{"method", "replicate-t"},
                                  {"ci_low", lo},
                                  {"ci_high", hi},
                                  {"draws", boot->draws},
                                  {"exhaustive", boot->exhaustive}};
  } else {
    col["replicate_bootstrap"] = nullptr;
  }
  col["replicate_test"] = test ? Json{{"heterogeneity", json_number(test->heterogeneity)},
                                      {"heterogeneity_p_value", json_number(test->heterogeneity_p)},
                                      {"statistic", json_number(test->statistic)},
                                      {"p_value", json_number(test->p_value)},
                                      {"own_minimum", test->own_minimum},
                                      {"draws", test->draws},
                                      {"calibration", to_string(test->calibration)},
                                      {"df_heterogeneity", json_number(test->df_heterogeneity)},
                                      {"df_statistic", json_number(test->df_statistic)}}
                               : Json(nullptr);
  return col;
}

}  // namespace

FitResult agmwm_as_fit(const JointFitResult& r) {
  FitResult f;
  f.model = r.joint.model;
  f.theta = r.agmwm;
  f.se = r.agmwm_se;
  return f;
}

FitResult replicate_bootstrap_as_fit(const JointFitResult& r, const ReplicateBootstrap& b) {
  FitResult f;
  f.model = r.joint.model;
  f.theta = r.joint.theta;
  f.ci_low = b.ci_low;
  f.ci_high = b.ci_high;
  return f;
}

Json joint_fit_document(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                        const pipeline::JointFitStudy& study, const std::vector<std::string>& units,
                        double filter_rate) {
  Json doc = json_document("fit");
  doc["input"] = set.path;
  doc["model_spec"] = study.model_spec;
  doc["seed"] = study.seed;
  doc["joint"] = true;
  doc["estimator"] = study.robust ? "robust" : "classical";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const JointAnalysis& a = study.groups[i].analysis;
    Json col =
        joint_column_json(groups[i], a.fit, a.test ? &*a.test : nullptr, a.bootstrap ? &*a.bootstrap : nullptr, set);
    const auto& figures = study.groups[i].figures;
    add_physical_fields(col, a.fit.joint, group_info(groups[i], set, units, i), kalman_rate(set, filter_rate),
                        figures ? &*figures : nullptr, Json(nullptr), "continuous", "kalman");
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

Json joint_select_document(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                           const pipeline::JointSelectStudy& study, const std::vector<std::string>& units,
                           double filter_rate) {
  Json doc = json_document("select");
  doc["input"] = set.path;
  doc["model_spec"] = study.model_spec;
  doc["seed"] = study.seed;
  doc["joint"] = true;
  // The ranking is the cross-validated one; "all" adds the joint fit's bootstrap WVIC.
  doc["optimism"] = study.all_optimisms ? "all" : "replicates";
  doc["estimator"] = study.robust ? "robust" : "classical";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const selection::ReplicateSelection& r = study.results[i];
    Json col;
    col["name"] = groups[i].axis;
    col["freq"] = set.freq;
    col["replicates"] = groups[i].sources;
    col["full_model"] = r.full_model;
    col["training"] = r.training;
    col["chosen"] = r.chosen;
    col["recommended"] = r.recommended;
    col["chosen_analytic"] = r.chosen_analytic;
    col["chosen_bootstrap"] = r.chosen_bootstrap.empty() ? Json(nullptr) : Json(r.chosen_bootstrap);
    col["all_rejected"] = r.all_rejected;
    Json rows = Json::array();
    for (const auto& c : r.ranking)
      rows.push_back({{"rank", c.rank},
                      {"model", c.model},
                      {"effective", c.effective},
                      {"parameters", c.parameters},
                      {"cv_wvic", json_number(c.cv_wvic)},
                      {"split_loss", c.split_loss},
                      {"objective", json_number(c.objective)},
                      {"analytic_wvic", json_number(c.analytic_wvic)},
                      {"rank_analytic", c.rank_analytic},
                      {"bootstrap_wvic", json_number(c.bootstrap_wvic)},
                      {"bootstrap_se", json_number(c.bootstrap_se)},
                      {"rank_bootstrap", c.rank_bootstrap ? Json(c.rank_bootstrap) : Json(nullptr)},
                      {"p_not_worse", json_number(c.p_not_worse)},
                      {"equivalent", c.equivalent}});
    col["ranking"] = rows;
    // The recommended model fitted jointly on all replicates: the values a consumer takes.
    if (i < study.recommended.size()) {
      const FitResult& b = study.recommended[i].fit.joint;
      const bool usable =
          b.status != FitStatus::kFailed && b.theta.size() == b.model.num_parameters() && b.theta.allFinite();
      col["best_model"] = usable ? Json(b.model.to_string(b.theta)) : Json(nullptr);
      col["best_fit"] = {{"model", r.recommended},
                         {"status", to_string(b.status)},
                         {"objective", json_number(b.objective)},
                         {"gof",
                          {{"statistic", json_number(b.gof.statistic)},
                           {"df", b.gof.df},
                           {"p_value", json_number(b.gof.p_value)},
                           {"method", b.gof.method}}}};
      const auto& figures = study.figures[i];
      add_physical_fields(col, b, group_info(groups[i], set, units, i), kalman_rate(set, filter_rate),
                          figures ? &*figures : nullptr, Json(nullptr), "best_continuous", "best_kalman");
    }
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

}  // namespace gmwm::report
