// The curve fit's document and terminal text (curve_output.h).
#include "gmwm/report/curve_output.h"

#include <algorithm>
#include <sstream>

#include "gmwm/engine/number_text.h"

namespace gmwm::report {
namespace {

using json = Json;

ColumnInfo curve_column(const pipeline::CurveFitColumn& c, const std::string& unit) {
  return {c.curve.name, c.wv.n, c.freq, true, unit};
}

// The column's "curve": what was given and how it was read.
json curve_json(const pipeline::CurveFitStudy& study, const pipeline::CurveFitColumn& c) {
  json tau = json::array(), fitted = json::array();
  for (std::size_t k = 0; k < c.curve.size(); ++k) {
    tau.push_back(json_number(c.curve.tau[k]));
    fitted.push_back(static_cast<bool>(c.fitted[k]));
  }
  const bool intervals = c.weights == CurveWeights::kIntervals;
  const bool record = c.weights == CurveWeights::kRecord;
  return {{"source", c.curve.source},
          {"value", to_string(c.curve.quantity)},
          {"tau", std::move(tau)},
          {"fitted", std::move(fitted)},
          {"excluded", study.exclude.empty() ? json(nullptr) : json(pipeline::tau_ranges_text(study.exclude))},
          {"weights", to_string(c.weights)},
          {"confidence", intervals ? json_number(study.confidence) : json(nullptr)},
          {"record_seconds", record ? json_number(study.record_seconds) : json(nullptr)},
          {"rate", study.freq_given ? "given" : "curve"},
          {"whole_samples", c.whole_samples}};
}

// One line saying what the curve is and how it was read.
std::string curve_head(const pipeline::CurveFitStudy& study, const pipeline::CurveFitColumn& c) {
  std::ostringstream os;
  const auto fitted = std::count(c.fitted.begin(), c.fitted.end(), true);
  os << c.curve.name << ": a curve of " << c.curve.size() << " points (" << to_string(c.curve.quantity) << ", "
     << c.curve.source << ")";
  if (static_cast<std::size_t>(fitted) < c.curve.size()) os << ", " << fitted << " fitted";
  const double m0 = c.wv.tau.empty() ? 1.0 : 0.5 * c.wv.tau.front();  // the finest averaging time, samples
  os << "; " << fmt(c.freq) << " Hz ("
     << (study.freq_given ? std::string("given")
         : m0 == 1.0      ? std::string("its finest tau one sample")
                          : "its finest tau " + fmt(m0) + " samples, the others no multiples of it")
     << "), weights from " << to_string(c.weights) << ", Omega " << to_string(study.omega) << '\n';
  return os.str();
}

}  // namespace

Json curve_fit_column_json(const pipeline::CurveFitStudy& study, std::size_t k, const std::string& unit,
                           double filter_rate) {
  const pipeline::CurveFitColumn& c = study.columns.at(k);
  const ColumnInfo info = curve_column(c, unit);
  json col = fit_column_json(info, c.wv, c.fit, study.omega);
  col["first_level"] = 1;
  add_physical_fields(
      col, c.fit, info, filter_rate > 0.0 ? filter_rate : c.freq, c.figures ? &c.figures->chosen : nullptr,
      c.figures ? allan_json(c.figures->adev, c.figures->model_adev) : json(nullptr), "continuous", "kalman");
  col["curve"] = curve_json(study, c);
  return col;
}

Json curve_fit_document(const std::string& input, const pipeline::CurveFitStudy& study,
                        const std::vector<std::string>& units, double filter_rate) {
  json doc = json_document("fit");
  doc["input"] = input;
  doc["model_spec"] = study.model_spec;
  doc["seed"] = study.seed;
  for (std::size_t k = 0; k < study.columns.size(); ++k)
    doc["columns"].push_back(curve_fit_column_json(study, k, k < units.size() ? units[k] : "", filter_rate));
  return doc;
}

std::string curve_fit_text(const Json& doc, const pipeline::CurveFitStudy& study, const TextOptions& options) {
  std::string text = axis_summary(doc);
  for (std::size_t k = 0; options.verbose && k < study.columns.size(); ++k) {
    const pipeline::CurveFitColumn& c = study.columns[k];
    const ColumnInfo info = curve_column(c, k < options.units.size() ? options.units[k] : "");
    const std::string detail = fit_detail(info, c.wv, c.fit, study.omega);
    const ChosenFigures* chosen = c.figures ? &c.figures->chosen : nullptr;
    text += "\n" + curve_head(study, c) + detail.substr(detail.find('\n') + 1) + continuous_table(c.fit, info) +
            (chosen ? noise_figures_table(*chosen, info.unit) : "") +
            kalman_table(c.fit, info, options.filter_rate > 0.0 ? options.filter_rate : c.freq, chosen);
  }
  return options.verbose ? text : text + kDetailsHint;
}

}  // namespace gmwm::report
