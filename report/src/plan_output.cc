// The record-length plan's JSON and terminal table (plan_output.h).
#include "gmwm/report/plan_output.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::report {

namespace {

// An infinite figure is a bound that does not exist ("none").
std::string g(double x, int digits = 4) { return std::isinf(x) ? "none" : significant(x, digits, NonFinite::kDash); }

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
           {"precision_at_record_basis", t.record_basis.empty() ? Json(nullptr) : Json(t.record_basis)},
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

// A note wrapped at kWidth columns, continuation lines indented by two, broken after a '+',
// ',' or ' ' where one is near (a model's text is broken between its components, not inside
// a number).
void wrap_note(std::ostringstream& os, const std::string& note) {
  std::string rest = note;
  std::size_t width = kWidth;
  std::string indent;
  while (rest.size() > width) {
    std::size_t cut = rest.find_last_of("+, ", width - 1);
    cut = cut == std::string::npos || cut < width / 2 ? width : cut + 1;
    os << indent << trimmed(rest.substr(0, cut)) << '\n';
    rest = rest.substr(cut);
    indent = "  ";
    width = kWidth - indent.size();
  }
  os << indent << rest << '\n';
}

std::string plan_terminal(const pipeline::PlanStudy& study, const RecordPlanOptions& options) {
  std::ostringstream os;
  const bool have = options.record_seconds > 0.0;
  std::ostringstream head;
  head << "record length for +-" << g(100.0 * options.precision, 3) << "% at " << g(100.0 * options.confidence, 3)
       << "% confidence (" << study.source << ")";
  wrap_note(os, printable_line(head.str()));
  char line[240];
  // Value and unit in columns of their own: a figure's unit is never cut (the longest,
  // deg/s/s/sqrt(Hz), deg/h/s/sqrt(Hz), m/s^2/s/sqrt(Hz), is 16).
  std::snprintf(line, sizeof line, "%-12s %-13s %-10s %-16s %10s %8s %8s %s", "column", "target", "value", "unit",
                "samples", "duration", "rel. se", have ? ("+-% with " + duration(options.record_seconds)).c_str() : "");
  os << trimmed(line) << '\n';
  std::vector<std::string> notes;
  for (const pipeline::PlanColumn& c : study.columns) {
    for (const RecordTarget& t : c.plan.targets) {
      const std::string printable = printable_line(c.name);
      const std::string name = printable.size() > 12 ? printable.substr(0, 11) + "~" : printable;
      const std::string u = printable_line(unit_of(t.name, c.unit));
      std::snprintf(line, sizeof line, "%-12s %-13s %-10s %-16s %10s %8s %8s %s", name.c_str(),
                    t.name.substr(0, 13).c_str(), g(t.value, 4).c_str(),
                    (u.size() > 16 ? u.substr(0, 15) + "~" : u).c_str(),
                    t.reachable ? std::to_string(t.samples).c_str() : "unreachable",
                    t.reachable ? duration(t.seconds).c_str() : "-", g(t.relative_se, 3).c_str(),
                    have ? (std::isfinite(t.precision_at_record) ? g(100.0 * t.precision_at_record, 3) + "%"
                            : std::isinf(t.precision_at_record)  ? std::string("n/a (note)")
                                                                 : std::string("-"))
                               .c_str()
                         : "");
      os << trimmed(line) << '\n';
      if (have && !t.record_basis.empty())
        notes.push_back(c.name + " " + t.name + ": no precision with " + duration(options.record_seconds) + ": " +
                        t.record_basis);
    }
    notes.push_back(c.name + ": model " + c.display_model);
    if (c.plan.resolved_samples < options.max_samples)
      notes.push_back(c.name + ": resolved from " + std::to_string(c.plan.resolved_samples) + " samples (" +
                      duration(c.plan.resolved_seconds) + "; last " + c.plan.resolved_by + ")");
    else
      notes.push_back(c.name + ": not resolved within " + std::to_string(options.max_samples) + " samples (" +
                      duration(static_cast<double>(options.max_samples) / c.plan.freq) + ")" +
                      (c.plan.resolved_by.empty() ? std::string() : "; least resolved " + c.plan.resolved_by));
  }
  os << "samples and duration: the record needed; rel. se: the estimate's relative standard error there\n";
  for (const std::string& raw : notes) wrap_note(os, printable_line(raw));
  return os.str();
}

}  // namespace gmwm::report
