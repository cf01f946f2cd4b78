// The frequency-stability study's JSON document and terminal tables (stability_output.h).
#include "gmwm/report/stability_output.h"

#include <cmath>
#include <sstream>

#include "gmwm/engine/number_text.h"
#include "gmwm/report/terminal.h"

namespace gmwm::report {
namespace {

// A deviation's unit: the data's, TDEV's the data's times seconds (the phase's); "" unknown.
std::string deviation_unit(stability::DeviationKind kind, const std::string& data_unit) {
  if (data_unit.empty()) return {};
  return stability::in_time_units(kind) ? "(" + data_unit + ")*s" : data_unit;
}

Json numbers(const std::vector<double>& v) {
  Json out = Json::array();
  for (const double x : v) out.push_back(json_number(x));
  return out;
}

Json curve_json(const stability::DeviationCurve& c, const stability::DeviationIntervals& ci,
                const std::string& data_unit) {
  const std::string unit = deviation_unit(c.kind, data_unit);
  Json alpha = Json::array(), noise = Json::array(), method = Json::array();
  for (const stability::NoiseIdentification& id : ci.noise) {
    alpha.push_back(id.alpha);
    noise.push_back(std::string(stability::noise_name(id.alpha)));
    method.push_back(std::string(stability::noise_id_method_name(id.method)));
  }
  return {{"m", c.m},
          {"tau", c.tau},
          {"value", numbers(c.value)},
          {"ci_low", numbers(ci.low)},
          {"ci_high", numbers(ci.high)},
          {"edf", numbers(ci.edf)},
          {"alpha", std::move(alpha)},
          {"noise", std::move(noise)},
          {"noise_id", std::move(method)},
          {"n", c.terms},
          {"unit", unit.empty() ? Json(nullptr) : Json(unit)}};
}

}  // namespace

Json stability_document(const io::SignalSet& set, const pipeline::StabilityStudy& study,
                        const pipeline::StabilityStudyOptions& options, const std::vector<std::string>& units) {
  Json doc = json_document("stability");
  doc["input"] = set.path;
  doc["data"] = std::string(io::data_kind_name(set.data));
  Json kinds = Json::array();
  for (const stability::DeviationKind k : options.kinds) kinds.push_back(std::string(stability::deviation_name(k)));
  doc["kinds"] = std::move(kinds);
  doc["taus"] =
      options.tau_list.empty() ? Json(std::string(stability::tau_set_name(options.taus))) : Json(options.tau_list);
  doc["confidence"] = options.intervals.confidence;
  doc["interval_method"] = std::string(stability::interval_method_name(options.intervals.method));
  doc["noise_alpha"] = options.intervals.noise_alpha ? Json(*options.intervals.noise_alpha) : Json(nullptr);
  doc["tau0"] = study.tau0;
  doc["phase_points"] = study.phase_points;
  add_record_json(doc, set);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::StabilityColumn& c = study.columns[k];
    const std::string unit = k < units.size() ? units[k] : std::string();
    Json col =
        column_json({c.name, static_cast<std::int64_t>(set.signals[k].values.size()), set.freq, set.freq_known, unit});
    col["unit"] = unit.empty() ? Json(nullptr) : Json(unit);
    Json deviations = Json::object();
    for (std::size_t d = 0; d < c.deviations.size(); ++d)
      deviations[std::string(stability::deviation_name(c.deviations[d].kind))] =
          curve_json(c.deviations[d], c.intervals[d], unit);
    col["deviations"] = std::move(deviations);
    doc["columns"].push_back(std::move(col));
  }
  return doc;
}

namespace {

// One kind's table: each averaging time's value, interval, degrees of freedom and noise.
std::string kind_table(const stability::DeviationCurve& c, const stability::DeviationIntervals& ci,
                       const std::string& unit) {
  const std::string u = unit.empty() ? (stability::in_time_units(c.kind) ? "U*s" : "U") : unit;
  TextTable t(
      {"tau [s]", std::string(stability::deviation_name(c.kind)) + " [" + u + "]", "low", "high", "edf", "noise"}, 0);
  for (std::size_t i = 0; i < c.m.size(); ++i)
    t.add({significant(c.tau[i], 6), significant(c.value[i], 5), significant(ci.low[i], 5, NonFinite::kDash),
           significant(ci.high[i], 5, NonFinite::kDash), significant(ci.edf[i], 4, NonFinite::kDash),
           std::string(stability::noise_name(ci.noise[i].alpha)) + " (" +
               std::string(stability::noise_id_method_name(ci.noise[i].method)) + ")"});
  return t.str();
}

}  // namespace

std::string stability_text(const pipeline::StabilityStudy& study, const std::vector<std::string>& units) {
  std::ostringstream os;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::StabilityColumn& c = study.columns[k];
    const std::string unit = k < units.size() ? units[k] : std::string();
    os << c.name << ": stability deviations, tau0 = " << significant(study.tau0, 6) << " s, " << study.phase_points
       << " phase points\n";
    for (std::size_t d = 0; d < c.deviations.size(); ++d)
      os << kind_table(c.deviations[d], c.intervals[d], deviation_unit(c.deviations[d].kind, unit));
    if (unit.empty()) os << "  U: the data's unit (--units declares it)\n";
    if (!c.intervals.empty()) {
      const stability::IntervalOptions& o = c.intervals.front().options;
      os << "  low, high: the " << significant(100.0 * o.confidence, 4) << "% chi-square interval ("
         << stability::interval_method_name(o.method) << " quantiles) from edf, the equivalent degrees of freedom of "
         << (o.noise_alpha ? "the noise given" : "the noise identified at each tau") << " (docs/stability.md)\n";
    }
  }
  return os.str();
}

}  // namespace gmwm::report
