// JSON of the Allan deviation and the noise figures (json_output.h).
#include <string>

#include "gmwm/engine/physical.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

namespace {

Json numbers(const std::vector<double>& v) {
  Json a = Json::array();
  for (double x : v) a.push_back(json_number(x));
  return a;
}

}  // namespace

FigureUnits figure_units(const std::string& unit) {
  const std::string u = unit.empty() ? "U" : unit;
  auto in = [&](int k) { return render_unit(kFigureNames[k].unit_pattern, u); };  // N, K, B, Q, R
  return {in(0), in(1), in(2), in(3), in(4)};
}

Json allan_json(const AllanDeviation& adev, const std::vector<double>& model_adev) {
  Json j;
  j["alpha"] = json_number(adev.alpha);
  j["m"] = adev.m;
  j["tau"] = numbers(adev.tau);
  j["adev"] = numbers(adev.adev);
  j["ci_low"] = numbers(adev.ci_low);
  j["ci_high"] = numbers(adev.ci_high);
  j["edf"] = numbers(adev.edf);
  j["model"] = model_adev.size() == adev.size() ? numbers(model_adev) : Json(nullptr);
  if (!adev.complete.empty()) {  // a record with missing samples: the windows each point read
    j["complete"] = adev.complete;
    j["partial"] = adev.partial;
  }
  return j;
}

Json readoff_json(const Readoff& r) {
  Json j;
  j["value"] = json_number(r.value);
  j["low"] = json_number(r.low);
  j["high"] = json_number(r.high);
  j["status"] = r.available() ? Json(to_string(r.status)) : Json(nullptr);
  j["tau"] = json_number(r.tau);
  j["region_from"] = json_number(r.region_from);
  j["region_to"] = json_number(r.region_to);
  j["how"] = r.how;
  Json comps = Json::array();
  for (const auto& [name, share] : r.sources) comps.push_back({{"component", name}, {"share", json_number(share)}});
  j["components"] = std::move(comps);
  return j;
}

Json noise_figures_json(const ChosenFigures& figures, const std::string& unit) {
  const FigureUnits units = figure_units(unit);
  Json j;
  auto one = [](const ChosenFigure& c, const std::string& u) {
    Json f = readoff_json(c.figure);
    f["unit"] = u;
    f["source"] = to_string(c.source);
    f["note"] = c.note;
    f["model"] = readoff_json(c.model);
    f["data"] = readoff_json(c.data);
    return f;
  };
  j["white"] = one(figures.white, units.white);
  j["walk"] = one(figures.walk, units.walk);
  j["instability"] = one(figures.instability, units.instability);
  j["quantization"] = one(figures.quantization, units.quantization);
  j["ramp"] = one(figures.ramp, units.ramp);
  return j;
}

}  // namespace gmwm::report
