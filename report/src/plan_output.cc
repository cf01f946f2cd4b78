// The record-length plan's JSON and terminal table (plan_output.h).
#include "gmwm/report/plan_output.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "gmwm/engine/error.h"

namespace gmwm::report {

namespace {

std::string g(double x, int digits = 4) {
  if (std::isnan(x)) return "-";
  if (std::isinf(x)) return "none";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

// A duration as a person reads it: "38 min", "2.6 h", "11 d".
std::string duration(double s) {
  if (!std::isfinite(s)) return "-";
  if (s < 120.0) return g(s, 3) + " s";
  if (s < 7200.0) return g(s / 60.0, 3) + " min";
  if (s < 172800.0) return g(s / 3600.0, 3) + " h";
  return g(s / 86400.0, 3) + " d";
}

// The unit of a target's value: N U/sqrt(Hz), K U/s/sqrt(Hz), B U; a parameter's: none.
std::string unit_of(const std::string& target, const std::string& unit) {
  const std::string u = unit.empty() ? "U" : unit;
  if (target == "N") return u + "/sqrt(Hz)";
  if (target == "K") return u + "/s/sqrt(Hz)";
  if (target == "B") return u;
  return "";
}

// The terminal's width (every line fits it).
constexpr std::size_t kWidth = 100;

std::string trimmed(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

}  // namespace

Json plan_document(const pipeline::PlanStudy& study, const RecordPlanOptions& options) {
  Json doc = json_document("plan");
  doc["source"] = study.source;
  doc["precision"] = json_number(options.precision);
  doc["confidence"] = json_number(options.confidence);
  doc["record_seconds"] = options.record_seconds > 0.0 ? json_number(options.record_seconds) : Json(nullptr);
  for (const pipeline::PlanColumn& c : study.columns) {
    Json targets = Json::array();
    for (const RecordTarget& t : c.plan.targets)
      targets.push_back(
          {{"name", t.name},
           {"value", json_number(t.value)},
           {"unit", unit_of(t.name, c.unit)},
           {"reachable", t.reachable},
           {"samples", t.samples},
           {"seconds", json_number(t.seconds)},
           {"own_samples", t.own_samples},
           {"relative_se", json_number(t.relative_se)},
           {"precision_at_record", options.record_seconds > 0.0 ? json_number(t.precision_at_record) : Json(nullptr)},
           {"basis", t.basis}});
    doc["columns"].push_back({{"name", c.name},
                              {"unit", c.unit.empty() ? Json(nullptr) : Json(c.unit)},
                              {"model", c.model},
                              {"freq", json_number(c.plan.freq)},
                              {"resolved",
                               {{"samples", c.plan.resolved_samples},
                                {"seconds", json_number(c.plan.resolved_seconds)},
                                {"by", c.plan.resolved_by}}},
                              {"targets", std::move(targets)}});
  }
  return doc;
}

std::string plan_terminal(const pipeline::PlanStudy& study, const RecordPlanOptions& options) {
  std::ostringstream os;
  const bool have = options.record_seconds > 0.0;
  os << "record length for +-" << g(100.0 * options.precision, 3) << "% at " << g(100.0 * options.confidence, 3)
     << "% confidence (" << printable_line(study.source).substr(0, 50) << ")\n";
  char line[200];
  std::snprintf(line, sizeof line, "%-12s %-13s %-22s %10s %10s %8s %s", "column", "target", "value", "samples",
                "duration", "rel. se", have ? ("+-% with " + duration(options.record_seconds)).c_str() : "");
  os << trimmed(line) << '\n';
  std::vector<std::string> notes;
  for (const pipeline::PlanColumn& c : study.columns) {
    for (const RecordTarget& t : c.plan.targets) {
      const std::string printable = printable_line(c.name);
      const std::string name = printable.size() > 12 ? printable.substr(0, 11) + "~" : printable;
      const std::string u = unit_of(t.name, c.unit);
      std::snprintf(
          line, sizeof line, "%-12s %-13s %-22s %10s %10s %8s %s", name.c_str(), t.name.substr(0, 13).c_str(),
          (g(t.value, 4) + (u.empty() ? "" : " " + u)).substr(0, 22).c_str(),
          t.reachable ? std::to_string(t.samples).c_str() : "unreachable",
          t.reachable ? duration(t.seconds).c_str() : "-", g(t.relative_se, 3).c_str(),
          have ? (g(100.0 * t.precision_at_record, 3) + (std::isfinite(t.precision_at_record) ? "%" : "")).c_str()
               : "");
      os << trimmed(line) << '\n';
    }
    notes.push_back(c.name + ": model " + c.model);
    notes.push_back(c.name + ": resolved from " + std::to_string(c.plan.resolved_samples) + " samples (" +
                    duration(c.plan.resolved_seconds) + "; last " + c.plan.resolved_by + ")");
  }
  os << "samples and duration: the record needed; rel. se: the estimate's relative standard error there\n";
  for (const std::string& raw : notes) {
    const std::string n = printable_line(raw);
    // Notes wrap at 100 columns, continuation lines indented by two.
    os << n.substr(0, kWidth) << '\n';
    for (std::size_t at = kWidth; at < n.size(); at += kWidth - 2) os << "  " << n.substr(at, kWidth - 2) << '\n';
  }
  return os.str();
}

}  // namespace gmwm::report
