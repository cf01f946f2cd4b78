// The export's JSON document and terminal summary (export_output.h).
#include "gmwm/report/export_output.h"

#include <sstream>

#include "gmwm/report/terminal.h"

namespace gmwm::report {
namespace {

Json written_json(const io::WrittenNoise& w) {
  return {{"noise_density", json_number(w.noise_density)},
          {"random_walk", json_number(w.random_walk)},
          {"bias_drive", json_number(w.bias_drive)},
          {"bias_correlation_time", json_number(w.bias_correlation_time)},
          {"bias_from_random_walk", w.bias_from_random_walk}};
}

}  // namespace

Json export_document(const pipeline::ExportStudy& study, const std::string& output) {
  const io::ExportOptions& o = study.options;
  const io::ExportResult& r = study.result;
  Json doc = json_document("export");
  doc["format"] = io::to_string(o.format);
  doc["output"] = output;
  doc["sidecar"] = r.sidecar ? Json(output + ".txt") : Json(nullptr);
  doc["source"] = study.source;
  doc["aggregation"] = io::to_string(o.aggregation);
  doc["inflate"] = json_number(o.inflate);
  doc["inflate_walk"] = json_number(o.inflate_walk.value_or(o.inflate));
  doc["rate"] = json_number(r.rate);
  for (const auto& a : r.columns) {
    Json c = {{"name", a.column},
              {"freq", json_number(a.freq)},
              {"kind", io::to_string(a.kind)},
              {"unit", a.unit.name},
              {"model", a.model},
              {"noise_density", json_number(a.white)},
              {"random_walk", json_number(a.walk)}};
    Json gm = Json::array();
    for (const auto& g : a.gauss_markov)
      gm.push_back({{"correlation_time", json_number(g.correlation_time)},
                    {"sigma", json_number(g.sigma)},
                    {"drive", json_number(g.drive)}});
    c["gauss_markov"] = std::move(gm);
    c["others"] = a.others;
    doc["columns"].push_back(std::move(c));
  }
  Json kinds = Json::object();
  for (const auto& k : r.kinds) {
    if (k.columns.empty()) continue;
    Json e = {{"columns", k.columns}, {"per_axis", k.per_axis}, {"combined", written_json(k.combined)}};
    if (k.per_axis)
      e["axes"] = {{"x", written_json(k.axes[0])}, {"y", written_json(k.axes[1])}, {"z", written_json(k.axes[2])}};
    kinds[io::to_string(k.kind)] = std::move(e);
  }
  doc["written"] = std::move(kinds);
  doc["warnings"] = r.warnings;
  doc["consistent_for"] = nullptr;
  if (study.consistent) {
    const pipeline::ConsistentInflation& c = *study.consistent;
    doc["consistent_for"] = {
        {"update_rate", json_number(study.consistency->update_rate)},
        {"horizon", json_number(study.consistency->horizon)},
        {"fix_sigma", json_number(study.consistency->fix_sigma)},
        {"white_factor", json_number(c.white)},
        {"walk_factor", json_number(c.factor)},
        {"verdict", nav::to_string(c.verdict)},
        {"nees_inside", json_number(c.nees_inside)},
        {"smaller_factor", json_number(c.smaller)},
        {"smaller_factor_above_band", json_number(c.smaller_above)},
        {"smaller_factor_verdict", c.smaller == 0.0 ? Json(nullptr) : Json(nav::to_string(c.smaller_verdict))},
        {"reason", c.reason}};
  }
  return doc;
}

std::string export_text(const pipeline::ExportStudy& study, const std::string& output) {
  const io::ExportOptions& o = study.options;
  const io::ExportResult& r = study.result;
  std::ostringstream os;
  os << "wrote " << io::to_string(o.format) << " noise parameters to " << output;
  if (r.sidecar) os << " (header in " << output << ".txt)";
  os << " at " << fmt(r.rate) << " Hz, " << io::to_string(o.aggregation) << ", inflation x" << fmt(o.inflate);
  if (o.inflate_walk && *o.inflate_walk != o.inflate) os << " (random walks x" << fmt(*o.inflate_walk) << ")";
  os << '\n';
  TextTable t({"sensor", "axis", "noise density", "random walk", "bias drive", "bias T (s)"}, 2);
  for (const auto& k : r.kinds) {
    if (k.columns.empty()) continue;
    const char* si_density = k.kind == io::SensorKind::kGyro ? "rad/s/sqrt(Hz)" : "m/s^2/sqrt(Hz)";
    auto row = [&](const std::string& axis, const io::WrittenNoise& w) {
      t.add({std::string(io::to_string(k.kind)) + " [" + si_density + "]", axis, fmt(w.noise_density, 5),
             fmt(w.random_walk, 5), w.bias_drive > 0 ? fmt(w.bias_drive, 5) : "-",
             w.bias_drive > 0 ? fmt(w.bias_correlation_time, 5) : "-"});
    };
    if (k.per_axis) {
      row("x", k.axes[0]);
      row("y", k.axes[1]);
      row("z", k.axes[2]);
    } else {
      row(io::to_string(o.aggregation), k.combined);
    }
  }
  os << t.str();
  if (const auto& c = study.consistent)
    os << "inflation N x" << fmt(c->white, 3) << ", K x" << fmt(c->factor, 3)
       << ": the smallest with which the filter is not optimistic (" << fmt(study.consistency->update_rate)
       << " Hz updates, " << fmt(study.consistency->horizon) << " s on the IMU alone); NEES in band "
       << fmt(100.0 * c->nees_inside, 3) << "% (" << nav::to_string(c->verdict) << ")\n";
  return os.str();
}

}  // namespace gmwm::report
