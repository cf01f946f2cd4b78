// A fit's parameters in continuous units and its Kalman-filter terms (issue 6, items 2
// and 4), for the "fit" and "select" columns.
#include <span>

#include "gmwm/engine/kalman.h"
#include "gmwm/engine/physical.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {
namespace {

std::string unit_of(const ColumnInfo& c) { return c.unit.empty() ? "U" : c.unit; }

bool usable(const FitResult& fit, const ColumnInfo& c) {
  return fit.status != FitStatus::kFailed && fit.theta.size() == fit.model.num_parameters() && fit.theta.size() > 0 &&
         fit.theta.allFinite() && c.freq_known && c.freq > 0.0;
}

// Kalman units: "U^2..." as "(unit)^2..." (variances read best that way), else render_unit.
Json kalman_unit(const std::string& pattern, const ColumnInfo& c) {
  if (pattern.empty()) return nullptr;
  if (pattern.rfind("U^2", 0) == 0) return "(" + unit_of(c) + ")^2" + pattern.substr(3);
  return render_unit(pattern, unit_of(c));
}

std::span<const double> part(const Eigen::VectorXd& v, const Model& m, int k) {
  return {v.data() + m.offset(k),
          static_cast<std::size_t>(m.components()[static_cast<std::size_t>(k)].process->size())};
}

}  // namespace

Json continuous_json(const FitResult& fit, const ColumnInfo& c) {
  Json out = Json::array();
  if (!usable(fit, c)) return out;
  const bool with_ci = fit.ci_low.size() == fit.theta.size() && fit.ci_high.size() == fit.theta.size();
  for (int k = 0; k < fit.model.num_components(); ++k) {
    const Process& p = *fit.model.components()[static_cast<std::size_t>(k)].process;
    const auto th = part(fit.theta, fit.model, k);
    const auto q = p.physical(th, c.freq);
    std::vector<PhysicalInterval> iv;
    if (with_ci) iv = physical_interval(p, th, part(fit.ci_low, fit.model, k), part(fit.ci_high, fit.model, k), c.freq);
    for (std::size_t i = 0; i < q.size(); ++i)
      out.push_back({{"process", p.name()},
                     {"component", k + 1},
                     {"name", q[i].name},
                     {"value", json_number(q[i].value)},
                     {"ci_low", i < iv.size() ? json_number(iv[i].low) : Json(nullptr)},
                     {"ci_high", i < iv.size() ? json_number(iv[i].high) : Json(nullptr)},
                     {"unit", render_unit(q[i].unit_pattern, unit_of(c))},
                     {"convention", q[i].convention}});
  }
  return out;
}

Json kalman_json(const FitResult& fit, const ColumnInfo& c, double filter_rate, const ChosenFigures* figures) {
  Json out = {{"filter_rate", json_number(filter_rate)}, {"terms", Json::array()}};
  if (!usable(fit, c) || !(filter_rate > 0.0)) return out;
  auto row = [&](const KalmanTerm& t, const std::string& process, Json component) {
    out["terms"].push_back({{"process", process},
                            {"component", std::move(component)},
                            {"role", t.role},
                            {"q", json_number(t.q)},
                            {"q_unit", kalman_unit(t.q_unit, c)},
                            {"transition", json_number(t.transition)},
                            {"discrete", json_number(t.discrete)},
                            {"discrete_unit", kalman_unit(t.discrete_unit, c)},
                            {"note", t.note}});
  };
  if (figures)
    for (const KalmanTerm& t : kalman_terms(*figures, filter_rate))
      row(t, t.role.ends_with("(from Q)") ? "Q" : "N, K, B", nullptr);
  for (int k = 0; k < fit.model.num_components(); ++k) {
    const Process& p = *fit.model.components()[static_cast<std::size_t>(k)].process;
    for (const KalmanTerm& t : p.kalman(part(fit.theta, fit.model, k), c.freq, filter_rate)) row(t, p.name(), k + 1);
  }
  return out;
}

}  // namespace gmwm::report
