// The fleet study's JSON, CSV and terminal table (fleet_output.h).
#include "gmwm/report/fleet_output.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "gmwm/io/signal_writer.h"
#include "gmwm/report/terminal.h"

namespace gmwm::report {
namespace {

Json figure_json(const ChosenFigure& f) {
  return {{"value", json_number(f.figure.value)},
          {"low", json_number(f.figure.low)},
          {"high", json_number(f.figure.high)},
          {"source", to_string(f.source)}};
}

// Shortest text that reads back to the same double; empty when not finite.
std::string exact(double x) {
  if (!std::isfinite(x)) return {};
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

const ChosenFigure* figure_of(const fleet::FleetRow& r, int k) {
  if (!r.figures_known) return nullptr;
  return k == 0 ? &r.figures.white : k == 1 ? &r.figures.walk : &r.figures.instability;
}

}  // namespace

Json fleet_document(const fleet::FleetStudy& study) {
  Json doc = json_document("fleet");
  doc["manifest"] = study.manifest;
  doc["model_spec"] = study.model_spec;
  doc["recordings"] = study.recordings;
  doc["failed"] = study.failed;
  doc["cached"] = study.cached;
  doc["cache"] = study.cache_dir.empty() ? Json(nullptr) : Json(study.cache_dir);
  Json rows = Json::array();
  for (const fleet::FleetRow& r : study.rows) {
    Json row = {{"unit", r.unit},
                {"model", r.model},
                {"group", r.group},
                {"path", r.path},
                {"axis", r.axis},
                {"unit_of_data", r.data_unit},
                {"status", r.status},
                {"chosen", r.chosen.empty() ? Json(nullptr) : Json(r.chosen)},
                {"chosen_structure", r.chosen_structure.empty() ? Json(nullptr) : Json(r.chosen_structure)},
                {"gof_p_value", json_number(r.gof_p)},
                {"freq", json_number(r.freq)},
                {"n", r.n}};
    const char* names[] = {"N", "K", "B"};
    for (int k = 0; k < 3; ++k) row[names[k]] = figure_of(r, k) ? figure_json(*figure_of(r, k)) : Json(nullptr);
    row["seconds"] = json_number(r.seconds);
    row["cached"] = r.cached;
    row["flags"] = r.flags;
    rows.push_back(std::move(row));
  }
  doc["rows"] = std::move(rows);
  Json summary = Json::array();
  for (const fleet::FleetFigureSummary& s : study.summary)
    summary.push_back({{"group", s.group},
                       {"axis", s.axis},
                       {"figure", std::string(1, s.figure)},
                       {"units", s.units},
                       {"median", json_number(s.median)},
                       {"spread", json_number(s.spread)},
                       {"flagged", s.flagged}});
  doc["summary"] = std::move(summary);
  doc["outlier_rule"] = {{"robust_z", fleet::kFleetOutlierZ}, {"min_units", fleet::kMinUnitsForFlags}};
  return doc;
}

std::string fleet_csv(const fleet::FleetStudy& study) {
  std::ostringstream os;
  os << "unit,model,group,path,axis,unit_of_data,status,chosen,gof_p_value,freq,n,"
        "N,N_low,N_high,K,K_low,K_high,B,B_low,B_high,seconds,cached,flags\n";
  for (const fleet::FleetRow& r : study.rows) {
    os << io::csv_field(r.unit) << ',' << io::csv_field(r.model) << ',' << io::csv_field(r.group) << ','
       << io::csv_field(r.path) << ',' << io::csv_field(r.axis) << ',' << io::csv_field(r.data_unit) << ','
       << io::csv_field(r.status) << ',' << io::csv_field(r.chosen) << ',' << exact(r.gof_p) << ',' << exact(r.freq)
       << ',' << (r.n ? std::to_string(r.n) : std::string());
    for (int k = 0; k < 3; ++k) {
      const ChosenFigure* f = figure_of(r, k);
      os << ',' << (f ? exact(f->figure.value) : "") << ',' << (f ? exact(f->figure.low) : "") << ','
         << (f ? exact(f->figure.high) : "");
    }
    std::string flags;
    for (const std::string& f : r.flags) flags += (flags.empty() ? "" : "; ") + f;
    os << ',' << exact(r.seconds) << ',' << (r.cached ? "true" : "false") << ',' << io::csv_field(flags) << '\n';
  }
  return os.str();
}

std::string fleet_text(const fleet::FleetStudy& study) {
  TextTable t({"unit", "axis", "N", "K", "B", "unit of data", "GoF p", "chosen"}, 2);
  std::string failures;
  for (const fleet::FleetRow& r : study.rows) {
    if (r.axis.empty()) {
      failures += "  " + r.unit + ": " + r.status + "\n";
      continue;
    }
    auto fig = [&](int k) {
      const ChosenFigure* f = figure_of(r, k);
      if (!f) return std::string("-");
      return (f->figure.status == ReadoffStatus::kBound ? "< " : "") + fmt(f->figure.value, 4);
    };
    t.add({r.unit, r.axis, fig(0), fig(1), fig(2), r.data_unit.empty() ? "U" : r.data_unit, fmt(r.gof_p, 2),
           r.status == "ok" ? r.chosen_structure : r.status});
  }
  std::ostringstream os;
  os << study.recordings << " recordings of " << study.manifest << ", each selected over " << study.model_spec
     << " (N in U/sqrt(Hz), K in U/s/sqrt(Hz), B in U; U the data's unit): " << study.failed << " failed"
     << (study.cache_dir.empty() ? std::string()
                                 : ", " + std::to_string(study.cached) + " from the cache " + study.cache_dir)
     << "\n"
     << t.str();
  if (!failures.empty()) os << "failed:\n" << failures;
  // Each group's axes: the median of each figure, its spread, the units that stand out.
  TextTable s({"group", "axis", "units", "N median (spread)", "K median (spread)", "B median (spread)"}, 2);
  std::string flagged;
  for (std::size_t i = 0; i + 2 < study.summary.size(); i += 3) {
    std::vector<std::string> row = {study.summary[i].group, study.summary[i].axis,
                                    std::to_string(study.summary[i].units)};
    for (std::size_t k = 0; k < 3; ++k) {
      const fleet::FleetFigureSummary& f = study.summary[i + k];
      row.push_back(f.units ? fmt(f.median, 4) + " (x" + fmt(f.spread, 3) + ")" : "-");
    }
    s.add(row);
  }
  for (const fleet::FleetRow& r : study.rows)
    for (const std::string& f : r.flags) flagged += "  " + r.unit + ", " + r.axis + ": " + f + "\n";
  os << "\nper group and axis (median of the units' read-offs; spread: exp(MAD of the logs / 0.6745)):\n" << s.str();
  os << (flagged.empty() ? "no unit stands out from its group (robust z beyond 3.5; groups of 5 units or more)\n"
                         : "stand out from their group (robust z beyond 3.5):\n" + flagged);
  return os.str();
}

}  // namespace gmwm::report
