// The terminal text of `gmwm gap` and `gmwm gap-check` (study_text.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "gmwm/engine/physical.h"
#include "gmwm/report/study_text.h"

namespace gmwm::report {
namespace {

std::string seconds_text(double tau, const io::SignalSet& set) {
  return set.freq_known ? fmt(tau / set.freq, 3) + " s" : fmt(tau, 6) + " samples";
}

// The first added effect's parameters with their bootstrap intervals, discrete and in
// the continuous units a navigation engineer uses.
std::string effect_table(const gap::GapResult& g, const io::SignalSet& set, const std::string& unit) {
  const FitResult& f = g.final_fit;
  if (f.status == FitStatus::kFailed || f.theta.size() != f.model.num_parameters() || f.theta.size() == 0) return {};
  TextTable t({"effect parameter", "value", "95% interval (bootstrap)", "unit"}, 1);
  for (const auto& r : report::parameter_rows(f))
    t.add({r.process + " " + r.name, fmt(r.value, 5), fmt(r.ci_low, 4) + " - " + fmt(r.ci_high, 4), "discrete"});
  if (set.freq_known && f.ci_low.size() == f.theta.size())
    for (int k = 0; k < f.model.num_components(); ++k) {
      const Process& p = *f.model.components()[static_cast<std::size_t>(k)].process;
      const std::span<const double> th(f.theta.data() + f.model.offset(k), static_cast<std::size_t>(p.size()));
      const auto q = p.physical(th, set.freq);
      const auto iv = physical_interval(
          p, th, std::span<const double>(f.ci_low.data() + f.model.offset(k), static_cast<std::size_t>(p.size())),
          std::span<const double>(f.ci_high.data() + f.model.offset(k), static_cast<std::size_t>(p.size())), set.freq);
      for (std::size_t i = 0; i < q.size(); ++i)
        if (!q[i].unit_pattern.empty())
          t.add({p.name() + " " + q[i].name, fmt(q[i].value, 5),
                 i < iv.size() ? fmt(iv[i].low, 4) + " - " + fmt(iv[i].high, 4) : "",
                 render_unit(q[i].unit_pattern, unit.empty() ? "U" : unit)});
    }
  return t.str();
}

std::string gap_column_text(const std::string& name, const gap::GapResult& g, const io::SignalSet& set,
                            const std::string& unit) {
  std::ostringstream os;
  os << name << ": " << g.headline << '\n';
  os << "  baseline: " << g.baseline.to_string(g.baseline_theta) << '\n';
  TextTable levels({"tau", "ratio", "z", "reference band", "outside"});
  for (const auto& l : g.levels)
    levels.add({seconds_text(l.tau, set), fmt(l.ratio, 4), fmt(l.z, 3), fmt(l.ref_low, 3) + " - " + fmt(l.ref_high, 3),
                l.outside ? "yes" : ""});
  os << levels.str();
  if (!g.candidates.empty()) {
    TextTable cand({"candidate", "improvement", "threshold", "2 x optimism (WVIC)", "cleared", "fit"}, 1);
    for (const auto& c : g.candidates)
      cand.add({gap::to_string(c.effect), fmt(c.improvement, 5), fmt(c.threshold, 4), fmt(2.0 * c.optimism, 4),
                c.cleared ? "yes" : "", c.model});
    os << cand.str();
  }
  const auto& s = g.shrinkage;
  os << "  objective " << fmt(s.objective_before) << " -> " << fmt(s.objective_after) << " (null mean "
     << fmt(s.null_mean, 4) << " -> " << fmt(s.null_mean_after, 4) << "), levels outside " << s.levels_outside_before
     << " -> " << s.levels_outside_after << ", global p " << fmt(s.p_value_before, 3) << " -> "
     << fmt(s.p_value_after, 3) << '\n';
  int disjoint = 0;
  for (const auto& h : g.split_half) disjoint += h.disjoint;
  if (!g.split_half.empty())
    os << "  split halves: " << disjoint << " of " << g.split_half.size() << " levels disagree (95% CIs disjoint)"
       << (disjoint ? ": the record is not stationary" : "") << '\n';
  os << effect_table(g, set, unit);
  if (std::isfinite(g.navigation.rms_without))
    os << "  integrated error after " << fmt(g.navigation.horizon_seconds, 3)
       << " s (attitude for a gyro, velocity for an accelerometer): " << fmt(g.navigation.rms_without, 3) << " -> "
       << fmt(g.navigation.rms_with, 3) << " " << render_unit("U*s", unit.empty() ? "U" : unit)
       << " RMS (baseline -> with the effects)\n";
  if (g.contamination_screened) {
    os << "  contamination screen: ";
    if (g.contaminated_levels.empty()) os << "no level flagged";
    for (std::size_t i = 0; i < g.contaminated_levels.size(); ++i)
      os << (i ? ", " : "levels flagged at ")
         << seconds_text(g.levels[static_cast<std::size_t>(g.contaminated_levels[i] - g.first_level)].tau, set);
    os << " (robust WV below the classical one beyond the data's rounding, with far outliers)\n";
  }
  for (const auto& r : g.refused) os << "  refused (does not lower the objective's excess): " << r << '\n';
  for (const auto& n : g.notes) os << "  note: " << n << '\n';
  return os.str();
}

// What to change: the corrected configuration's fields (input -> corrected) and, per
// column, the gap left with the input, with the corrected file and with the full model.
std::string changes_text(const pipeline::CorrectedConfig& c, const io::SignalSet& set,
                         const pipeline::GapStudy& study) {
  std::ostringstream os;
  os << "\nwhat to change (" << c.format << ", --corrected writes it):\n";
  if (c.format != "model") {
    TextTable t({"field", "input", "corrected", "unit", "changed"}, 1);
    for (const auto& ch : c.changes)
      t.add({ch.field, std::isfinite(ch.input) ? fmt(ch.input, 4) : "-",
             std::isfinite(ch.corrected) ? fmt(ch.corrected, 4) : "-", ch.unit, ch.changed ? "yes" : ""});
    os << t.str();
  }
  const bool nav = set.freq_known;
  std::vector<std::string> head{"column", "levels outside (input -> file -> full)",
                                "objective (input -> file -> full)"};
  if (nav) head.push_back("integrated error after 60 s (input -> file -> full)");
  TextTable g(head, 1);
  for (const auto& col : c.columns) {
    std::string unit = "U";
    for (const auto& sc : study.columns)
      if (sc.name == col.name && !sc.unit.empty()) unit = sc.unit;
    std::vector<std::string> row{col.name,
                                 std::to_string(col.before.levels_outside) + " -> " +
                                     std::to_string(col.with_config.levels_outside) + " -> " +
                                     std::to_string(col.with_full.levels_outside),
                                 fmt(col.before.objective, 3) + " -> " + fmt(col.with_config.objective, 3) + " -> " +
                                     fmt(col.with_full.objective, 3)};
    if (nav)
      row.push_back(fmt(col.before.navigation_rms, 3) + " -> " + fmt(col.with_config.navigation_rms, 3) + " -> " +
                    fmt(col.with_full.navigation_rms, 3) + " " + render_unit("U*s", unit) + " RMS");
    g.add(row);
  }
  os << g.str();
  for (const auto& col : c.columns)
    if (!col.why.empty()) os << "  kept, " << col.name << ": " << col.why << '\n';
  for (const auto& col : c.columns)
    for (const auto& x : col.warnings) os << "  warning, " << col.name << ": " << x << '\n';
  for (const auto& col : c.columns)
    for (const auto& x : col.not_expressible) os << "  cannot express, " << col.name << ": " << x << '\n';
  return os.str();
}

// One line per correlated pair: the scales where its cross-axis correlation is significant.
std::string cross_axis_text(const std::vector<gap::CrossAxisPair>& pairs, const io::SignalSet& set) {
  std::map<std::pair<int, int>, std::vector<const gap::CrossAxisPair*>> by_pair;
  for (const auto& p : pairs)
    if (p.significant) by_pair[{p.a, p.b}].push_back(&p);
  std::string out;
  for (const auto& [ab, v] : by_pair) {
    double peak = 0.0;
    for (const auto* p : v)
      if (std::abs(p->rho) > std::abs(peak)) peak = p->rho;
    out += "  cross-axis: " + set.signals[static_cast<std::size_t>(ab.first)].name + " & " +
           set.signals[static_cast<std::size_t>(ab.second)].name + " correlated at " +
           seconds_text(v.front()->tau, set) + (v.size() > 1 ? " - " + seconds_text(v.back()->tau, set) : "") + " (" +
           std::to_string(v.size()) + (v.size() > 1 ? " levels" : " level") + ", rho up to " + fmt(peak, 3) +
           "): a shared effect\n";
  }
  return out;
}

}  // namespace

std::string gap_text(const io::SignalSet& set, const pipeline::GapStudy& study,
                     const std::optional<pipeline::CorrectedConfig>& corrected, bool verbose) {
  std::string text = set.timing ? set.timing->summary() + "\n" : std::string();
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::GapColumnStudy& c = study.columns[k];
    text += c.name + ": " + c.result.headline + "\n";
    // A baseline converted as an earlier column's (one gyro model for every axis) is said once.
    const auto same = std::find_if(study.columns.begin(), study.columns.begin() + static_cast<std::ptrdiff_t>(k),
                                   [&](const pipeline::GapColumnStudy& o) { return o.conversions == c.conversions; });
    if (!c.conversions.empty() && same != study.columns.begin() + static_cast<std::ptrdiff_t>(k))
      text += "  conversion: as " + same->name + "'s\n";
    else
      for (const auto& conversion : c.conversions) text += "  conversion: " + conversion + "\n";
  }
  text += cross_axis_text(study.cross_axis, set);
  if (corrected) text += changes_text(*corrected, set, study);
  if (!verbose) return text + kGapDetailsHint;
  for (const pipeline::GapColumnStudy& c : study.columns) text += "\n" + gap_column_text(c.name, c.result, set, c.unit);
  return text;
}

std::string gap_check_text(const gap::GapCheckResult& r) {
  std::ostringstream os;
  std::vector<std::string> reported;
  for (const auto& [t, row] : r.confusion)
    for (const auto& [rep, n] : row)
      if (std::find(reported.begin(), reported.end(), rep) == reported.end()) reported.push_back(rep);
  std::vector<std::string> head = {"truth \\ reported"};
  head.insert(head.end(), reported.begin(), reported.end());
  TextTable conf(head, 1);
  for (const auto& [t, row] : r.confusion) {
    std::vector<std::string> line = {t};
    for (const auto& rep : reported) {
      const auto it = row.find(rep);
      line.push_back(it == row.end() ? "" : std::to_string(it->second));
    }
    conf.add(line);
  }
  os << "confusion matrix (rows: withheld effect; none = base only, REPARAMETERISE = base off by +-20%)\n"
     << conf.str();
  TextTable fam({"truth", "cases", "top-1 correct", "detected", "band located", "median S", "power by strength",
                 "90% power at", "oracle's", "ratio"},
                1);
  for (const auto& [t, f] : r.families) {
    std::string power;
    for (const auto& [s, p] : f.power) power += (power.empty() ? "" : ", ") + fmt(s, 3) + ": " + fmt(100 * p, 3) + "%";
    const bool effect = !f.power.empty();
    const std::string prefix = f.crossing == gap::Crossing::kAtMost   ? "<= "
                               : f.crossing == gap::Crossing::kBeyond ? "> "
                                                                      : "";
    fam.add({t, std::to_string(f.cases), fmt(100.0 * f.correct / f.cases, 3) + "%",
             fmt(100.0 * f.detected / f.cases, 3) + "%", fmt(100.0 * f.located / f.cases, 3) + "%",
             fmt(f.median_excess_removed, 3), power.empty() ? "-" : power,
             effect ? prefix + fmt(f.strength_90, 3) : "-", effect ? fmt(f.oracle_strength_90, 3) : "-",
             effect ? prefix + fmt(f.oracle_ratio, 3) : "-"});
  }
  os << fam.str();
  os << "90% power at: the strength where the share correctly attributed reaches 90% (\"<=\": already at the "
        "grid's smallest, \">\": not within the grid); oracle's: where a one-sided test that knows the base, the "
        "effect's form and everything but its amplitude reaches 90% on average over the same cases (exact "
        "Cov(nuhat) of the base, Gaussian WV; DR: the GLS test on the series itself, its most powerful test); ratio: "
        "ours / oracle's (goal <= 1.5)\n";
  os << "correct " << r.correct << " of " << r.cases.size() << ", false alarms on the null side " << r.false_alarms
     << '\n';
  return os.str();
}

}  // namespace gmwm::report
