// The fleet study's JSON, CSV and terminal table (fleet_output.h).
#include "gmwm/report/fleet_output.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>

#include "gmwm/engine/physical.h"
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

const ChosenFigure* figure_of(const fleet::FleetRow& r, int k) { return r.figures_known ? &r.figures[k] : nullptr; }

std::string symbol(int k) { return std::string(1, kFigureNames[k].symbol); }

bool read_off(const ChosenFigure& c) {
  return c.source != FigureSource::kBound && c.figure.available() && c.figure.status != ReadoffStatus::kBound;
}

Json spec_json(const fleet::FleetRow& r) {
  Json checks = Json::array();
  for (const fleet::SpecCheck& c : r.spec)
    checks.push_back({{"figure", std::string(1, c.figure)},
                      {"limit", c.limit.value},
                      {"limit_unit", c.limit.unit},
                      {"limit_key", c.limit.key},
                      {"limit_where", c.limit.where},
                      {"value", json_number(c.value)},
                      {"low", json_number(c.low)},
                      {"high", json_number(c.high)},
                      {"verdict", to_string(c.verdict)},
                      {"note", c.note}});
  return checks;
}

// A row's spec verdict in one word: "fail (N, B)", "pass", "unknown (K)", "" without checks.
std::string spec_word(const fleet::FleetRow& r) {
  if (r.spec.empty()) return {};
  std::string fail, unknown;
  for (const fleet::SpecCheck& c : r.spec) {
    std::string& list = c.verdict == fleet::SpecVerdict::kFail ? fail : unknown;
    if (c.verdict != fleet::SpecVerdict::kPass) list += (list.empty() ? "" : ", ") + std::string(1, c.figure);
  }
  if (!fail.empty()) return "fail (" + fail + ")";
  return unknown.empty() ? "pass" : "unknown (" + unknown + ")";
}

Json replicate_test_json(const ReplicateTest& t) {
  return {{"heterogeneity", json_number(t.heterogeneity)},
          {"heterogeneity_p_value", json_number(t.heterogeneity_p)},
          {"statistic", json_number(t.statistic)},
          {"p_value", json_number(t.p_value)},
          {"calibration", to_string(t.calibration)},
          {"df_heterogeneity", json_number(t.df_heterogeneity)},
          {"df_statistic", json_number(t.df_statistic)},
          {"draws", t.draws},
          {"shared", !t.rejects()}};
}

Json joint_json(const fleet::FleetJointModel& m) {
  Json j = {{"group", m.group},
            {"axis", m.axis},
            {"units", m.units},
            {"left_out", m.left_out},
            {"status", m.status},
            {"unit", m.unit},
            {"freq", json_number(m.freq)},
            {"n", m.n},
            {"seconds", json_number(m.seconds)}};
  if (m.status != "ok") return j;
  const FitResult& f = m.fit.joint;
  j["recommended"] = m.recommended;
  j["chosen"] = m.chosen;
  j["model"] = f.model.to_string(f.theta);
  j["parameters"] = parameters_json(f);
  if (m.intervals) {
    Json lo = Json::array(), hi = Json::array();
    for (const auto& p : parameter_rows(replicate_bootstrap_as_fit(m.fit, *m.intervals))) {
      lo.push_back(json_number(p.ci_low));
      hi.push_back(json_number(p.ci_high));
    }
    j["replicate_bootstrap"] = {
        {"method", "replicate-t"}, {"ci_low", lo}, {"ci_high", hi}, {"draws", m.intervals->draws}};
  }
  j["gof"] = {{"statistic", json_number(f.gof.statistic)},
              {"df", f.gof.df},
              {"p_value", json_number(f.gof.p_value)},
              {"method", f.gof.method}};
  j["replicate_test"] = m.test ? replicate_test_json(*m.test) : Json(nullptr);
  for (int k = 0; k < kFigureCount; ++k) j[symbol(k)] = m.figures ? figure_json((*m.figures)[k]) : Json(nullptr);
  return j;
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
  doc["cache_problems"] = study.cache_problems;
  doc["spec"] = study.spec_path.empty() ? Json(nullptr) : Json(study.spec_path);
  doc["gap_baseline"] = study.gap_baseline.empty() ? Json(nullptr) : Json(study.gap_baseline);
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
                {"n", r.n},
                {"first_level", r.first_level}};
    for (int k = 0; k < kFigureCount; ++k)
      row[symbol(k)] = figure_of(r, k) ? figure_json(*figure_of(r, k)) : Json(nullptr);
    row["seconds"] = json_number(r.seconds);
    row["cached"] = r.cached;
    row["flags"] = r.flags;
    if (!study.gap_baseline.empty())
      row["gap"] =
          r.gap_verdict.empty()
              ? Json(nullptr)
              : Json{{"verdict", r.gap_verdict}, {"headline", r.gap_headline}, {"p_value", json_number(r.gap_p)}};
    if (!study.spec_path.empty()) {
      row["spec"] = spec_json(r);
      row["spec_verdict"] = spec_word(r);
      row["spec_note"] = r.spec_note;
    }
    rows.push_back(std::move(row));
  }
  doc["rows"] = std::move(rows);
  Json summary = Json::array();
  for (const fleet::FleetFigureSummary& s : study.summary)
    summary.push_back({{"group", s.group},
                       {"axis", s.axis},
                       {"figure", std::string(1, s.figure)},
                       {"units", s.units},
                       {"unit", s.unit},
                       {"median", json_number(s.median)},
                       {"spread", json_number(s.spread)},
                       {"unit_spread", json_number(s.unit_spread)},
                       {"flagged", s.flagged},
                       {"out_of_spec", s.out_of_spec}});
  doc["summary"] = std::move(summary);
  Json joint = Json::array();
  for (const fleet::FleetJointModel& m : study.joint) joint.push_back(joint_json(m));
  doc["joint"] = std::move(joint);
  doc["outlier_rule"] = {{"robust_z", fleet::kFleetOutlierZ}, {"min_units", fleet::kMinUnitsForFlags}};
  return doc;
}

std::string fleet_csv(const fleet::FleetStudy& study) {
  std::ostringstream os;
  os << "unit,model,group,path,axis,unit_of_data,status,chosen,gof_p_value,freq,n,first_level,"
        "N,N_low,N_high,K,K_low,K_high,B,B_low,B_high,Q,Q_low,Q_high,R,R_low,R_high,seconds,cached,spec,gap,flags\n";
  for (const fleet::FleetRow& r : study.rows) {
    os << io::csv_field(r.unit) << ',' << io::csv_field(r.model) << ',' << io::csv_field(r.group) << ','
       << io::csv_field(r.path) << ',' << io::csv_field(r.axis) << ',' << io::csv_field(r.data_unit) << ','
       << io::csv_field(r.status) << ',' << io::csv_field(r.chosen) << ',' << exact(r.gof_p) << ',' << exact(r.freq)
       << ',' << (r.n ? std::to_string(r.n) : std::string()) << ','
       << (r.n ? std::to_string(r.first_level) : std::string());
    for (int k = 0; k < kFigureCount; ++k) {
      const ChosenFigure* f = figure_of(r, k);
      os << ',' << (f ? exact(f->figure.value) : "") << ',' << (f ? exact(f->figure.low) : "") << ','
         << (f ? exact(f->figure.high) : "");
    }
    std::string flags;
    for (const std::string& f : r.flags) flags += (flags.empty() ? "" : "; ") + f;
    os << ',' << exact(r.seconds) << ',' << (r.cached ? "true" : "false") << ',' << io::csv_field(spec_word(r)) << ','
       << io::csv_field(r.gap_verdict) << ',' << io::csv_field(flags) << '\n';
  }
  return os.str();
}

namespace {

// A median in the datasheet's unit when the data's unit is known ("0.297 deg/sqrt(h)"), else
// in the data's unit pattern.
std::string figure_text(char figure, double value, const std::string& unit, double spread) {
  if (!std::isfinite(value)) return "-";
  const std::string x = spread > 0.0 ? " x" + fmt(spread, 3) : std::string();
  if (const std::optional<DatasheetValue> d = datasheet_value(figure, value, unit))
    return fmt(d->value, 3) + " " + d->unit + x;
  // The data's unit unknown: the number alone (the headings say N in U/sqrt(Hz), ...).
  if (unit.empty()) return fmt(value, 3) + x;
  if (figure == 'Q' || figure == 'R') return fmt(value, 3) + " " + render_unit(figure == 'Q' ? "U*s" : "U/s", unit) + x;
  const char* per = figure == 'N' ? "/sqrt(Hz)" : figure == 'K' ? "/s/sqrt(Hz)" : "";
  return fmt(value, 3) + " " + unit + per + x;
}

std::vector<std::string> with_figures(std::vector<std::string> head, const std::vector<int>& shown) {
  for (int k : shown) head.push_back(symbol(k));
  return head;
}

std::string summary_table(const fleet::FleetStudy& study) {
  const std::vector<int> shown = fleet_shown_figures(study);
  TextTable s(with_figures({"group", "axis", "units"}, shown), 2);
  const auto per = static_cast<std::size_t>(kFigureCount);  // fleet_summary: every figure per group and axis
  for (std::size_t i = 0; i + per - 1 < study.summary.size(); i += per) {
    std::vector<std::string> row = {study.summary[i].group, study.summary[i].axis,
                                    std::to_string(study.summary[i].units)};
    for (int k : shown) {
      const fleet::FleetFigureSummary& f = study.summary[i + static_cast<std::size_t>(k)];
      row.push_back(f.units ? figure_text(f.figure, f.median, f.unit, f.spread) : "-");
    }
    s.add(row);
  }
  return s.str();
}

// Per group, axis and figure checked: the limit and how many units are above it (surely:
// their interval wholly above), within it, or undecided.
std::string spec_table(const fleet::FleetStudy& study) {
  struct Count {
    std::string group, axis, limit;
    char figure;
    int above = 0, surely = 0, within = 0, unknown = 0;
  };
  std::vector<Count> counts;
  for (const fleet::FleetRow& r : study.rows)
    for (const fleet::SpecCheck& c : r.spec) {
      auto it = std::find_if(counts.begin(), counts.end(), [&](const Count& x) {
        return x.group == r.group && x.axis == r.axis && x.figure == c.figure && x.limit == c.limit.written;
      });
      if (it == counts.end()) it = counts.insert(counts.end(), Count{r.group, r.axis, c.limit.written, c.figure});
      if (c.verdict == fleet::SpecVerdict::kFail) {
        ++it->above;
        it->surely += c.low > c.limit.value;
      }
      it->within += c.verdict == fleet::SpecVerdict::kPass;
      it->unknown += c.verdict == fleet::SpecVerdict::kUnknown;
    }
  TextTable t({"group", "axis", "figure", "limit", "above", "surely", "within", "undecided"}, 4);
  for (const Count& c : counts)
    t.add({c.group, c.axis, std::string(1, c.figure), c.limit, std::to_string(c.above), std::to_string(c.surely),
           std::to_string(c.within), std::to_string(c.unknown)});
  return t.str();
}

// Per group and axis: how many units have no gap against the baseline, a gap the named
// effects close, a gap that remains, or were not diagnosed.
std::string gap_table(const fleet::FleetStudy& study) {
  struct Count {
    std::string group, axis;
    int none = 0, closed = 0, remains = 0, not_diagnosed = 0;
  };
  std::vector<Count> counts;
  for (const fleet::FleetRow& r : study.rows) {
    if (r.gap_verdict.empty()) continue;
    auto it = std::find_if(counts.begin(), counts.end(),
                           [&](const Count& c) { return c.group == r.group && c.axis == r.axis; });
    if (it == counts.end()) it = counts.insert(counts.end(), Count{r.group, r.axis});
    it->none += r.gap_verdict == "none";
    it->closed += r.gap_verdict == "closed";
    it->remains += r.gap_verdict == "remains";
    it->not_diagnosed += r.gap_verdict == "not diagnosed";
  }
  TextTable t({"group", "axis", "no gap", "closed", "remains", "not diagnosed"}, 2);
  for (const Count& c : counts)
    t.add({c.group, c.axis, std::to_string(c.none), std::to_string(c.closed), std::to_string(c.remains),
           std::to_string(c.not_diagnosed)});
  return t.str();
}

// Each group's axis: the joint model's structure, N, K, B (datasheet units) and whether its
// units share one theta; a model that could not be had says why.
std::string joint_text(const fleet::FleetStudy& study) {
  const std::vector<int> shown = fleet_shown_figures(study);
  std::vector<std::string> head = with_figures({"group", "axis", "units", "joint model"}, shown);
  head.push_back("shared?");
  TextTable t(head, 3);
  std::string why;
  for (const fleet::FleetJointModel& m : study.joint) {
    if (m.status != "ok") {
      why += "  " + m.group + ", " + m.axis + ": " + m.status + "\n";
      continue;
    }
    auto fig = [&](int k) {
      if (!m.figures) return std::string("-");
      const ChosenFigure& c = (*m.figures)[k];
      return (c.figure.status == ReadoffStatus::kBound ? "< " : "") +
             figure_text(kFigureNames[k].symbol, c.figure.value, m.unit, 0.0);
    };
    std::string shared = "-";
    if (m.test)
      shared = std::string(m.test->rejects() ? "no" : "yes") + " p " + fmt(m.test->heterogeneity_p, 2) +
               (m.test->calibration == ReplicateCalibration::kChiSquare ? " chi2" : "");
    std::vector<std::string> row = {
        m.group, m.axis, std::to_string(m.units) + (m.left_out.empty() ? "" : "+" + std::to_string(m.left_out.size())),
        m.recommended};
    for (int k : shown) row.push_back(fig(k));
    row.push_back(shared);
    t.add(std::move(row));
  }
  return "the joint model of each group's axis: its units as replicates (the selection over them; +k: the units that "
         "stand out, left out), the figures of the group's typical unit, and whether the units share one theta (the "
         "shared-theta test's p, chi2 where calibrated by its chi-square beyond 12 units):\n" +
         t.str() + why;
}

std::string unit_table(const fleet::FleetStudy& study) {
  const std::vector<int> shown = fleet_shown_figures(study);
  std::vector<std::string> head = with_figures({"unit", "axis"}, shown);
  head.insert(head.end(), {"GoF p", "chosen"});
  TextTable t(head, 2);
  for (const fleet::FleetRow& r : study.rows) {
    if (r.axis.empty()) continue;
    auto fig = [&](int k) {
      const ChosenFigure* f = figure_of(r, k);
      if (!f) return std::string("-");
      return (f->figure.status == ReadoffStatus::kBound ? "< " : "") +
             figure_text(kFigureNames[k].symbol, f->figure.value, r.data_unit, 0.0);
    };
    std::vector<std::string> row = {r.unit, r.axis};
    for (int k : shown) row.push_back(fig(k));
    row.insert(row.end(), {fmt(r.gof_p, 2), r.status == "ok" ? r.chosen_structure : r.status});
    t.add(std::move(row));
  }
  return t.str();
}

}  // namespace

std::vector<int> fleet_shown_figures(const fleet::FleetStudy& study) {
  std::vector<int> shown;
  for (int k = 0; k < kFigureCount; ++k) {
    bool read = kFigureNames[k].symbol != 'Q' && kFigureNames[k].symbol != 'R';
    for (const fleet::FleetRow& r : study.rows) read = read || (r.figures_known && read_off(r.figures[k]));
    for (const fleet::FleetJointModel& m : study.joint) read = read || (m.figures && read_off((*m.figures)[k]));
    if (read) shown.push_back(k);
  }
  return shown;
}

std::string fleet_text(const fleet::FleetStudy& study, bool verbose) {
  std::ostringstream os;
  os << study.manifest << ": " << study.recordings << " recordings, " << study.failed << " failed"
     << (study.cache_dir.empty() ? std::string()
                                 : ", " + std::to_string(study.cached) + " from the cache " + study.cache_dir)
     << "; each selected over " << study.model_spec
     << " (N in U/sqrt(Hz), K in U/s/sqrt(Hz), B in U, Q in U*s, R in U/s, U the data's unit, unless in datasheet "
        "units; Q and R shown where a unit reads them)\n";
  os << "\nper group and axis: the median of the units' figures, xS their spread (one robust sigma as a factor, "
        "exp(MAD of the logs / 0.6745)):\n"
     << summary_table(study);
  std::string flagged, checks, failures;
  for (const fleet::FleetRow& r : study.rows) {
    if (r.axis.empty()) failures += "  " + r.unit + ": " + r.status + "\n";
    for (const std::string& f : r.flags) flagged += "  " + r.unit + ", " + r.axis + ": " + f + "\n";
    for (const fleet::SpecCheck& c : r.spec)
      if (c.verdict != fleet::SpecVerdict::kPass) checks += "  " + r.unit + ", " + r.axis + ": " + c.note + "\n";
  }
  os << "\n"
     << (flagged.empty() ? "no unit stands out from its group (robust z beyond 3.5; groups of 5 units or more)\n"
                         : "stand out from their group (robust z beyond 3.5):\n" + flagged);
  if (!study.spec_path.empty()) {
    os << "\nagainst the spec " << study.spec_path
       << " (units above each limit; surely: their interval wholly above it; undecided: no read-off, or only a "
          "bound above the limit):\n"
       << spec_table(study);
    if (verbose && !checks.empty()) os << "each figure above its limit or undecided:\n" << checks;
  }
  if (!study.gap_baseline.empty()) {
    os << "\nthe gap against " << study.gap_baseline
       << " (gmwm gap's diagnosis; closed: the effects its headline names close it):\n"
       << gap_table(study);
    std::string headlines;
    for (const fleet::FleetRow& r : study.rows)
      if (!r.gap_verdict.empty() && (verbose || r.gap_verdict == "not diagnosed"))
        headlines += "  " + r.unit + ", " + r.axis + ": " + r.gap_verdict + ": " + r.gap_headline + "\n";
    os << headlines;
  }
  if (!study.joint.empty()) os << "\n" << joint_text(study);
  if (!failures.empty()) os << "failed:\n" << failures;
  const std::size_t axes = study.rows.size() - static_cast<std::size_t>(study.failed);
  if (verbose || axes <= kFleetTerminalRows)
    os << "\nper unit and axis (figures in datasheet units where the data's unit is declared):\n" << unit_table(study);
  else
    os << "\n" << axes << " unit x axis rows: --verbose prints them, --csv and --json write them\n";
  return wrap_to_width(os.str());
}

}  // namespace gmwm::report
