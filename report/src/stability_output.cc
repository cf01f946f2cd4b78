// The frequency-stability study's JSON document and terminal tables (stability_output.h).
#include "gmwm/report/stability_output.h"

#include <cmath>
#include <sstream>

#include "gmwm/engine/number_text.h"
#include "gmwm/report/terminal.h"
#include "stability_detail.h"

namespace gmwm::report {

namespace detail {

std::string deviation_unit(stability::DeviationKind kind, const std::string& data_unit) {
  if (data_unit.empty()) return {};
  return stability::in_time_units(kind) ? "(" + data_unit + ")*s" : data_unit;
}

std::string hat_unit(const std::vector<std::string>& units) {
  if (units.size() < stability::kHatSensors || units[0] != units[1] || units[1] != units[2]) return {};
  return units[0];
}

std::string hat_heading(const pipeline::StabilityHat& hat) {
  return "three-cornered hat of " + hat.sensors[0] + ", " + hat.sensors[1] + ", " + hat.sensors[2] +
         ": each column's own deviation, separated from what the three share";
}

std::string hat_value_text(const stability::HatSensor& s, std::size_t i) {
  return s.negative[i] ? "[var " + significant(s.variance[i], 5) + "]" : significant(s.value[i], 5);
}

bool hat_has_negative(const pipeline::StabilityHat& hat) {
  for (const stability::ThreeCorneredHat& k : hat.kinds)
    for (const stability::HatSensor& s : k.sensors)
      for (const bool b : s.negative)
        if (b) return true;
  return false;
}

std::string hat_negative_note() {
  return "[var V]: the separated variance V (in the unit squared) is negative: no deviation (records too short for "
         "it, or sensors not independent); kept, not clamped";
}

std::string hat_interval_words(double confidence) {
  return "the " + significant(100.0 * confidence, 4) +
         "% score interval of each separated variance from edf, the smallest of the three pairs' degrees of freedom";
}

}  // namespace detail

namespace {

using detail::deviation_unit;
using detail::hat_unit;

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

Json hat_sensor_json(const std::string& name, const stability::HatSensor& s) {
  Json negative = Json::array();
  for (const bool b : s.negative) negative.push_back(b);
  return {{"name", name},
          {"value", numbers(s.value)},
          {"variance", numbers(s.variance)},
          {"negative", std::move(negative)},
          {"ci_low", numbers(s.low)},
          {"ci_high", numbers(s.high)}};
}

// One kind's separation: the factors, the pairs' smallest edf, each column's deviation.
Json hat_kind_json(const pipeline::StabilityHat& hat, const stability::ThreeCorneredHat& k,
                   const std::string& data_unit) {
  const std::string unit = deviation_unit(k.kind, data_unit);
  Json sensors = Json::array();
  for (std::size_t s = 0; s < stability::kHatSensors; ++s)
    sensors.push_back(hat_sensor_json(hat.sensors[s], k.sensors[s]));
  return {{"m", k.m},
          {"tau", k.tau},
          {"edf", numbers(k.edf)},
          {"unit", unit.empty() ? Json(nullptr) : Json(unit)},
          {"sensors", std::move(sensors)}};
}

// The document's "hat": the columns, the pairs' deviations (as a column's), each kind's separation.
Json hat_json(const pipeline::StabilityHat& hat, const std::string& unit) {
  Json pairs = Json::array();
  for (const pipeline::StabilityColumn& p : hat.pairs) {
    Json deviations = Json::object();
    for (std::size_t d = 0; d < p.deviations.size(); ++d)
      deviations[std::string(stability::deviation_name(p.deviations[d].kind))] =
          curve_json(p.deviations[d], p.intervals[d], unit);
    pairs.push_back({{"name", p.name}, {"deviations", std::move(deviations)}});
  }
  Json kinds = Json::object();
  for (const stability::ThreeCorneredHat& k : hat.kinds)
    kinds[std::string(stability::deviation_name(k.kind))] = hat_kind_json(hat, k, unit);
  return {{"sensors", hat.sensors}, {"pairs", std::move(pairs)}, {"deviations", std::move(kinds)}};
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
  if (study.hat) doc["hat"] = hat_json(*study.hat, hat_unit(units));
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

// One kind's separation: each averaging time's three rows (a column's deviation, its
// interval and the pairs' edf); a negative variance as "[var V]".
std::string hat_kind_table(const pipeline::StabilityHat& hat, const stability::ThreeCorneredHat& k,
                           const std::string& unit) {
  const std::string u = unit.empty() ? (stability::in_time_units(k.kind) ? "U*s" : "U") : unit;
  TextTable t(
      {"tau [s]", "column", std::string(stability::deviation_name(k.kind)) + " [" + u + "]", "low", "high", "edf"}, 0);
  for (std::size_t i = 0; i < k.m.size(); ++i)
    for (std::size_t s = 0; s < stability::kHatSensors; ++s) {
      const stability::HatSensor& h = k.sensors[s];
      t.add({s == 0 ? significant(k.tau[i], 6) : std::string(), hat.sensors[s], detail::hat_value_text(h, i),
             significant(h.low[i], 5, NonFinite::kDash), significant(h.high[i], 5, NonFinite::kDash),
             s == 0 ? significant(k.edf[i], 4, NonFinite::kDash) : std::string()});
    }
  return t.str();
}

// The hat's tables and what they read.
std::string hat_text(const pipeline::StabilityHat& hat, const std::string& unit, double confidence) {
  std::ostringstream os;
  os << detail::hat_heading(hat) << "\n";
  for (const stability::ThreeCorneredHat& k : hat.kinds) os << hat_kind_table(hat, k, deviation_unit(k.kind, unit));
  if (detail::hat_has_negative(hat)) os << "  " << detail::hat_negative_note() << "\n";
  os << "  low, high: " << detail::hat_interval_words(confidence)
     << "; - where none fits (docs/stability.md, \"Three-cornered hat\"); the pairs' deviations are in the JSON "
        "(hat.pairs)\n";
  return os.str();
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
  if (study.hat) os << hat_text(*study.hat, hat_unit(units), study.hat->kinds.front().confidence);
  return os.str();
}

}  // namespace gmwm::report
