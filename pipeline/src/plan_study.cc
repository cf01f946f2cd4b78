#include "gmwm/pipeline/plan_study.h"

#include <cmath>
#include <cstdio>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"

namespace gmwm::pipeline {

namespace {

// The model with its values at the terminal's precision (component_text, 4 digits).
std::string display_text(const Model& m, const Eigen::VectorXd& theta) {
  std::string out;
  for (int c = 0; c < m.num_components(); ++c) out += (c ? "+" : "") + component_text(m, c, theta);
  return out;
}

}  // namespace

std::string PlanStudyOptions::Validate() const {
  const bool has_result = !result.empty() || !result_text.empty();
  if (has_result == !model.empty()) return "give either a fit/select result or a model with values";
  if (!model.empty() && !freq) return "a model's values need its sampling rate (freq, Hz)";
  if (freq && (!(*freq > 0.0) || !std::isfinite(*freq))) return "freq must be positive (Hz)";
  if (!model.empty() && !columns.empty()) return "columns pick a result's columns, not a model's";
  if (!unit.empty()) try {
      io::parse_any_unit(unit);  // a typo is refused, never taken as a label
    } catch (const InputError& e) {
      return e.what();
    }
  return plan.Validate();
}

PlanStudy study_plan(const PlanStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("plan: " + why);
  PlanStudy out;
  if (!options.model.empty()) {
    const Model m = options.model.bind(ProcessContext{*options.freq, true});
    if (!m.fully_specified())
      throw InputError("model '" + options.model.text() +
                       "': give every parameter's value, e.g. WN(sigma2=1e-6)+RW(gamma2=1e-12)");
    const Eigen::VectorXd theta = m.given_values();
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", *options.freq);
    out.source = "model " + display_text(m, theta) + " at " + rate + " Hz";
    const std::string unit = options.unit.empty() ? std::string() : io::parse_any_unit(options.unit).second.name;
    out.columns.push_back({"model", unit, m.to_string(theta), display_text(m, theta),
                           plan_record_length(m, theta, *options.freq, options.plan)});
    return out;
  }
  io::ResultReadOptions ro;
  ro.columns = options.columns;
  ro.rate = options.freq;
  ro.unit_free = true;  // a plan needs no unit: a column's own (when it says it) labels its figures
  const std::string name = options.result.empty() ? std::string("result") : options.result;
  const io::ResultColumns r = options.result_text.empty() ? io::read_result_columns(options.result, ro)
                                                          : io::read_result_columns(name, options.result_text, ro);
  out.source = "gmwm " + r.command + " result" + (options.result.empty() ? "" : " " + options.result);
  for (const io::ExportColumn& c : r.columns)
    out.columns.push_back({c.name, c.unit.name, c.model.to_string(c.theta), display_text(c.model, c.theta),
                           plan_record_length(c.model, c.theta, c.freq, options.plan)});
  return out;
}

}  // namespace gmwm::pipeline
