// The terminal text of fit and select (and their joint forms): the per-axis summary read
// from the JSON document, then the detail tables (study_text.h).
#include <cmath>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/report/study_text.h"
#include "replicate_rows.h"

namespace gmwm::report {
namespace {

// The ranking's goodness of fit is each candidate's test under the selection's shared
// Omega and V (comparable across rows), not the chosen model's own refitted test.
constexpr const char* kSharedGofNote =
    "GoF p (shared): each candidate's test under the selection's shared Omega and V; the chosen model's own "
    "test (refitted, its own Omega) is the summary's\n";

// The candidates of a ranking row other than its model itself, each with its own
// objective: "3*AR1 (7.78), 2*AR1+WN (8.1) (+3 more)"; "" when the only member is the model.
std::string members_text(const selection::RankedModel& r) {
  constexpr std::size_t kShown = 3;
  std::vector<std::string> others;
  for (std::size_t k = 0; k < r.members.size(); ++k)
    if (r.members[k] != r.model)
      others.push_back(r.members[k] + " (" +
                       (k < r.member_objectives.size() ? fmt(r.member_objectives[k], 4) : std::string("-")) + ")");
  std::string out;
  for (std::size_t i = 0; i < others.size() && i < kShown; ++i) out += (i ? ", " : "") + others[i];
  if (others.size() > kShown) out += " (+" + std::to_string(others.size() - kShown) + " more)";
  return out;
}

// " (+M missing in G gaps: each scale reads the windows without one)" for a replicate with
// gaps; "" otherwise.
std::string missing_text(const pipeline::ReplicateGroup& g, std::size_t k) {
  if (g.gaps(k) == 0) return {};
  return " (+" + std::to_string(g.missing_samples(k)) + " missing in " + std::to_string(g.gaps(k)) +
         " gaps: each scale reads the windows without one)";
}

std::string joint_fit_detail(const pipeline::ReplicateGroup& g, const JointFitResult& r, const ReplicateTest* test,
                             const ReplicateBootstrap* boot, OmegaKind omega, const std::string& estimator) {
  std::ostringstream os;
  os << g.axis << ": joint fit of " << g.sources.size() << " replicates, Omega " << to_string(omega) << ", "
     << estimator << '\n';
  for (std::size_t k = 0; k < g.sources.size(); ++k)
    os << "  replicate " << k + 1 << ": " << g.sources[k] << ", N = " << g.series[k].size() << missing_text(g, k)
       << ", " << r.levels[k] << " levels"
       << (k < r.objective_share.size() ? ", its share of the objective " + fmt(r.objective_share[k], 4) : "")
       << ", own fit " << to_string(r.singles[k].status) << '\n';
  const FitResult& j = r.joint;
  const bool ok = j.theta.size() == j.model.num_parameters() && j.theta.size() > 0 && j.theta.allFinite();
  os << "model: " << (ok ? j.model.to_string(j.theta) : j.model.to_string()) << '\n';
  if (ok) {
    std::vector<std::string> header = {"process", "component", "name",      "joint", "se",      "CI low",
                                       "CI high", "boot low",  "boot high", "AGMWM", "AGMWM se"};
    for (std::size_t k = 0; k < r.singles.size(); ++k) header.push_back("replicate " + std::to_string(k + 1));
    TextTable t(header, 1);
    // Every column in display units (SIN f in Hz ...), as parameter_rows gives them.
    const auto rows = report::parameter_rows(j);
    const auto agmwm = report::parameter_rows(report::agmwm_as_fit(r));
    const auto boot_rows = boot ? report::parameter_rows(report::replicate_bootstrap_as_fit(r, *boot))
                                : std::vector<report::ParameterRow>{};
    std::vector<std::vector<report::ParameterRow>> own;
    for (const auto& s : r.singles) own.push_back(report::parameter_rows(s));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& p = rows[i];
      std::vector<std::string> row = {p.process,
                                      std::to_string(p.component),
                                      p.name,
                                      fmt(p.value, 8),
                                      fmt(p.se, 3),
                                      fmt(p.ci_low),
                                      fmt(p.ci_high),
                                      i < boot_rows.size() ? fmt(boot_rows[i].ci_low) : "-",
                                      i < boot_rows.size() ? fmt(boot_rows[i].ci_high) : "-",
                                      fmt(agmwm[i].value),
                                      fmt(agmwm[i].se, 3)};
      for (const auto& o : own) row.push_back(i < o.size() ? fmt(o[i].value) : "-");
      t.add(row);
    }
    os << t.str();
  }
  os << "objective: " << fmt(j.objective, 8) << " (the sum over the replicates)\n";
  os << "goodness of fit: statistic " << fmt(j.gof.statistic) << ", df " << fmt(j.gof.df) << ", p-value "
     << fmt(j.gof.p_value, 4) << (j.gof.method.empty() ? "" : " (" + j.gof.method + ")") << '\n';
  os << "status: " << (j.message.empty() ? to_string(j.status) : j.message) << '\n';
  for (const auto& note : j.notes) os << "note: " << note << '\n';
  if (boot)
    os << "boot low / high: replicate-t interval (t at K - 1 df, bootstrap sd x sqrt(K / (K - 1)), log scale for "
          "variances) from the joint fit redone on "
       << boot->draws
       << (boot->exhaustive ? " distinct resamples (all, weighted by their bootstrap probability)" : " resamples")
       << " of the replicates drawn with replacement\n";
  if (test)
    os << "shared theta? heterogeneity H = " << fmt(test->heterogeneity, 4) << ", bootstrap p "
       << fmt(test->heterogeneity_p, 3)
       << (test->rejects() ? " (the replicates do not share one theta)" : " (one theta fits them all)")
       << "; joint misfit T = " << fmt(test->statistic, 4) << ", bootstrap p " << fmt(test->p_value, 3) << " ("
       << test->draws << " draws, Omega_k = V_k^-1 at the fixed-point estimate)\n";
  return os.str();
}

// The other candidates of a folded row: "2*AR1+WN (12.3), 3*AR1 (12.4) (+3 more)".
std::string members_of(const detail::FoldedRow& f) {
  constexpr std::size_t kShown = 3;
  std::string out;
  for (std::size_t i = 0; i < f.others.size() && i < kShown; ++i)
    out += (i ? ", " : "") + f.others[i]->model + " (" + fmt(f.others[i]->cv_wvic, 4) + ")";
  if (f.others.size() > kShown) out += " (+" + std::to_string(f.others.size() - kShown) + " more)";
  return out;
}

std::string joint_select_detail(const pipeline::ReplicateGroup& g, const selection::ReplicateSelection& r,
                                const std::string& estimator) {
  std::ostringstream os;
  const bool boot = !r.chosen_bootstrap.empty();
  os << g.axis << ": selection over " << g.sources.size() << " replicates (" << r.training.size()
     << " training splits of " << r.training.front().size() << "), maximal model " << r.full_model << ", " << estimator
     << '\n';
  for (std::size_t k = 0; k < g.sources.size(); ++k)
    os << "  replicate " << k + 1 << ": " << g.sources[k] << ", N = " << g.series[k].size() << missing_text(g, k)
       << '\n';
  const std::vector<detail::FoldedRow> folded = detail::fold_by_effective(r);
  os << "  " << r.ranking.size() << " candidates, " << folded.size()
     << " distinct effective models (each listed once with the numbers of its best candidate; p: that candidate's "
        "parameters)\n";
  // The model first: a table too wide for the terminal moves its widest columns below it
  // as notes, never the first.
  std::vector<std::string> head = {"effective model", "rank", "p", "CV-WVIC", "analytic WVIC", "rank (analytic)"};
  if (boot) head.insert(head.end(), {"bootstrap WVIC (s.e.)", "rank (bootstrap)"});
  head.insert(head.end(), {"P(not worse)", "equivalent", "its best candidate", "candidates that fell onto it"});
  TextTable t(head, 1);
  for (const detail::FoldedRow& f : folded) {
    const selection::CvCandidate& c = *f.best;
    const std::string& effective = c.effective.empty() ? c.model : c.effective;
    std::vector<std::string> row = {effective,         std::to_string(c.rank),  std::to_string(c.parameters),
                                    fmt(c.cv_wvic, 6), fmt(c.analytic_wvic, 6), std::to_string(c.rank_analytic)};
    if (boot)
      row.insert(row.end(),
                 {fmt(c.bootstrap_wvic, 6) + " (" + fmt(c.bootstrap_se, 2) + ")", std::to_string(c.rank_bootstrap)});
    row.insert(row.end(),
               {fmt(c.p_not_worse, 3), c.equivalent ? "yes" : "", effective == c.model ? "" : c.model, members_of(f)});
    t.add(row);
  }
  os << t.str();
  os << "chosen (smallest CV-WVIC): " << r.chosen << "; recommended (smallest equivalent model): " << r.recommended
     << "; smallest analytic WVIC of the joint fit: " << r.chosen_analytic;
  if (boot) os << "; smallest bootstrap WVIC: " << r.chosen_bootstrap;
  os << '\n';
  if (r.all_rejected)
    os << "warning: every candidate's joint fit is rejected by its goodness-of-fit test at 5%: no sub-model of "
       << r.full_model << " describes these recordings, and the ranking compares misfits\n";
  return os.str();
}

// The joint model's tables in the data's units, as a single fit shows them: continuous
// parameters, noise figures (when given) and the Kalman terms at `filter_rate` Hz.
std::string joint_physical_tables(const pipeline::ReplicateGroup& group, const io::SignalSet& set,
                                  const FitResult& joint, const std::optional<ChosenFigures>& figures,
                                  const std::string& unit, double filter_rate) {
  const ColumnInfo info{group.axis, group.series.empty() ? 0 : static_cast<std::int64_t>(group.series.front().size()),
                        set.freq, set.freq_known, unit};
  return continuous_table(joint, info) + (figures ? noise_figures_table(*figures, info.unit) : "") +
         kalman_table(joint, info, filter_rate, figures ? &*figures : nullptr);
}

// A column's facts with its unit.
ColumnInfo column_of(const io::SignalSet& set, std::size_t k, const TextOptions& options) {
  const auto& s = set.signals[k];
  return {s.name, static_cast<std::int64_t>(s.values.size()), set.freq, set.freq_known,
          k < options.units.size() ? options.units[k] : std::string()};
}

// The text's head: the timing summary (gaps, disorder) and the per-axis summary.
std::string text_head(const Json& doc, const io::SignalSet& set) {
  return (set.timing ? set.timing->summary() + "\n" : std::string()) + axis_summary(doc);
}

// A column's tables of a fitted model in the data's units.
std::string physical_tables(const FitResult& fit, const ColumnInfo& info, const std::optional<FigureReport>& figures,
                            double filter_rate) {
  const ChosenFigures* chosen = figures ? &figures->chosen : nullptr;
  return continuous_table(fit, info) + (chosen ? noise_figures_table(*chosen, info.unit) : "") +
         kalman_table(fit, info, filter_rate, chosen);
}

}  // namespace

std::string continuous_table(const FitResult& fit, const report::ColumnInfo& column) {
  const report::Json rows = report::continuous_json(fit, column);
  if (rows.empty()) return {};
  TextTable t({"continuous", "value", "CI low", "CI high", "unit"}, 1);
  for (const auto& r : rows) {
    if (r.at("unit").get<std::string>().empty()) continue;  // no physical counterpart (MA1, ARMA)
    auto num = [](const report::Json& v) { return v.is_number() ? fmt(v.get<double>(), 5) : std::string("-"); };
    t.add({r.at("process").get<std::string>() + " " + r.at("name").get<std::string>(), num(r.at("value")),
           num(r.at("ci_low")), num(r.at("ci_high")), r.at("unit").get<std::string>()});
  }
  return t.str();
}

std::string kalman_table(const FitResult& fit, const report::ColumnInfo& column, double filter_rate,
                         const ChosenFigures* figures) {
  const report::Json k = report::kalman_json(fit, column, filter_rate, figures);
  if (k.at("terms").empty()) return {};
  TextTable t({"Kalman filter at " + fmt(filter_rate, 6) + " Hz", "role", "q (continuous)", "F", "R or Q_d", "note"},
              2);
  auto num = [](const report::Json& v, const report::Json& unit) {
    if (!v.is_number()) return std::string("-");
    return fmt(v.get<double>(), 5) + (unit.is_string() ? " " + unit.get<std::string>() : "");
  };
  for (const auto& r : k.at("terms"))
    t.add({r.at("process").get<std::string>(), r.at("role").get<std::string>(), num(r.at("q"), r.at("q_unit")),
           num(r.at("transition"), nullptr), num(r.at("discrete"), r.at("discrete_unit")),
           r.at("note").get<std::string>()});
  return t.str();
}

std::string noise_figures_table(const ChosenFigures& figures, const std::string& unit) {
  const report::FigureUnits units = report::figure_units(unit);
  TextTable t({"noise figure (IEEE 952)", "value", "CI low", "CI high", "unit", "source", "model's", "data's", "read"},
              1);
  auto status = [](const Readoff& r) {
    if (!r.available()) return std::string("-");
    return fmt(r.value, 4) + (r.status == ReadoffStatus::kBound ? " (bound)" : "");
  };
  std::string notes;
  auto row = [&](const char* name, const ChosenFigure& c, const std::string& u) {
    const Readoff& f = c.figure;
    t.add({name, fmt(f.value, 5), fmt(f.low, 4), fmt(f.high, 4), u, to_string(c.source), status(c.model),
           status(c.data), f.how});
    std::string comps;
    for (const auto& [component, share] : c.model.sources)
      comps += (comps.empty() ? "" : ", ") + component + " " + fmt(100.0 * share, 3) + "%";
    notes += std::string("  ") + name + ": " + c.note + (comps.empty() ? "" : "; model's curve there: " + comps) + "\n";
  };
  row("N white noise", figures.white, units.white);
  row("K random walk", figures.walk, units.walk);
  row("B bias instability", figures.instability, units.instability);
  row("Q quantization", figures.quantization, units.quantization);
  row("R rate ramp", figures.ramp, units.ramp);
  return t.str() + notes;
}

std::string fit_detail(const ColumnInfo& column, const WaveletVariance& w, const FitResult& r, OmegaKind omega) {
  std::ostringstream os;
  os << column.name << ": N = " << column.n << ", " << fmt(column.freq) << " Hz, Omega " << to_string(omega);
  if (w.estimator != "classical")
    os << ", " << w.estimator << " WV (efficiency " << fmt(w.efficiency.value_or(1.0)) << ")";
  os << '\n';
  const bool has_theta = r.theta.size() == r.model.num_parameters() && r.theta.size() > 0 && r.theta.allFinite();
  os << "model: " << (has_theta ? r.model.to_string(r.theta) : r.model.to_string()) << '\n';
  if (has_theta) {
    TextTable t({"process", "component", "name", "value", "se", "CI low", "CI high", "interval"}, 1);
    for (const report::ParameterRow& p : report::parameter_rows(r))
      t.add({p.process, std::to_string(p.component), p.name, fmt(p.value, 8), fmt(p.se, 3), fmt(p.ci_low),
             fmt(p.ci_high), p.interval == "two-sided" ? "" : p.interval});
    os << t.str();
  }
  os << "objective: " << fmt(r.objective, 8) << '\n';
  os << "goodness of fit: statistic " << fmt(r.gof.statistic) << ", df " << fmt(r.gof.df) << ", p-value "
     << fmt(r.gof.p_value, 4) << (r.gof.method.empty() ? "" : " (" + r.gof.method + ")") << '\n';
  const std::string status = to_string(r.status);
  const bool repeats =
      r.message.rfind(status, 0) == 0 || (r.status == FitStatus::kConverged && r.message.rfind("converged", 0) == 0);
  os << "status: " << (r.message.empty() ? status : repeats ? r.message : status + " (" + r.message + ")") << '\n';
  for (const auto& note : r.notes) os << "note: " << note << '\n';
  if (const std::string why = rejection_summary(r, column.freq, column.freq_known); !why.empty())
    os << "fit quality: " << r.model.to_string() << " is " << why << '\n';
  if (const std::string why = degeneracy_summary(r); !why.empty()) os << "fit quality: " << why << '\n';
  return os.str();
}

std::string select_detail(const ColumnInfo& column, const selection::Selection& sel) {
  std::ostringstream os;
  os << column.name << ": N = " << column.n << ", " << sel.models << " sub-models of " << sel.full_model
     << ", representation violations " << sel.representation_violations << '\n';
  const bool both =
      !sel.ranking.empty() && sel.ranking.front().optimism_bootstrap && sel.ranking.front().optimism_analytic;
  std::vector<std::string> head = {"rank",
                                   "model (effective)",
                                   "p",
                                   "objective",
                                   "optimism",
                                   "criterion",
                                   "GoF p (shared)",
                                   "candidates that fell onto it (their own objective)"};
  if (both) head.insert(head.end(), {"analytic", "bootstrap (se)", "rank a/b"});
  TextTable t(head, 2);
  auto opt = [](const std::optional<double>& v, int digits) { return v ? fmt(*v, digits) : std::string("-"); };
  for (const auto& r : sel.ranking) {
    std::vector<std::string> row = {std::to_string(r.rank),       r.model,
                                    std::to_string(r.parameters), fmt(r.objective, 6),
                                    fmt(r.optimism, 4),           fmt(r.criterion, 6),
                                    fmt(r.gof.p_value, 3),        members_text(r)};
    if (both)
      row.insert(row.end(), {opt(r.optimism_analytic, 4),
                             opt(r.optimism_bootstrap, 4) + " (" + opt(r.optimism_bootstrap_se, 2) + ")",
                             (r.rank_analytic ? std::to_string(*r.rank_analytic) : "-") + "/" +
                                 (r.rank_bootstrap ? std::to_string(*r.rank_bootstrap) : "-")});
    t.add(row);
  }
  os << t.str() << kSharedGofNote;
  const FitResult& b = sel.best_fit;
  if (b.theta.size() == b.model.num_parameters() && b.theta.allFinite())
    os << "best: " << b.model.to_string(b.theta) << '\n';
  for (const auto& r : sel.ranking)
    if (r.rank == 1)
      for (const auto& line : r.effective.reductions) os << "  " << r.reduced_member << ": " << line << '\n';
  if (sel.not_converged > 0 || sel.failed > 0)
    os << "candidates: " << sel.candidates.size() << " fitted, " << sel.not_converged << " stopped before converging, "
       << sel.failed << " failed (their fits are in the JSON \"candidates\")\n";
  if (sel.all_rejected) {
    const std::string why = rejection_summary(b, column.freq, column.freq_known);
    os << "fit quality: every candidate is rejected at 5%: no sub-model of " << sel.full_model
       << " describes these data" << (why.empty() ? "" : "; the chosen " + b.model.to_string() + " is " + why) << '\n';
  } else if (const std::string why = rejection_summary(b, column.freq, column.freq_known); !why.empty()) {
    os << "fit quality: the chosen " << b.model.to_string() << " is " << why << '\n';
  }
  if (const std::string why = degeneracy_summary(b); !why.empty()) os << "fit quality: " << why << '\n';
  return os.str();
}

// Each robust column's spike screen, named by its column (screening_summary).
template <class Columns>
std::string screening_lines(const io::SignalSet& set, const Columns& columns) {
  std::string out;
  for (std::size_t k = 0; k < columns.size() && k < set.signals.size(); ++k) {
    const std::string s = screening_summary(columns[k].wv, columns[k].wv.n, set.freq, set.freq_known);
    if (!s.empty()) out += printable_line(set.signals[k].name) + ": " + s;
  }
  return out;
}

std::string fit_text(const Json& doc, const io::SignalSet& set, const pipeline::FitStudy& study,
                     const TextOptions& options) {
  std::string text = text_head(doc, set) + screening_lines(set, study.columns);
  for (std::size_t k = 0; options.verbose && k < study.columns.size(); ++k) {
    const pipeline::FitColumnStudy& c = study.columns[k];
    const ColumnInfo info = column_of(set, k, options);
    text += "\n" + fit_detail(info, c.wv, c.fit, study.omega) +
            physical_tables(c.fit, info, c.figures, options.filter_rate);
  }
  return options.verbose ? text : text + kDetailsHint;
}

std::string select_text(const Json& doc, const io::SignalSet& set, const pipeline::SelectStudy& study,
                        const TextOptions& options) {
  std::string text = text_head(doc, set) + screening_lines(set, study.columns);
  for (std::size_t k = 0; options.verbose && k < study.columns.size(); ++k) {
    const pipeline::SelectColumnStudy& c = study.columns[k];
    const ColumnInfo info = column_of(set, k, options);
    text += "\n" + select_detail(info, c.selection) +
            physical_tables(c.selection.best_fit, info, c.figures, options.filter_rate);
  }
  return options.verbose ? text : text + kDetailsHint;
}

std::string replicate_estimator_text(const std::optional<robust::RobustWvOptions>& robust) {
  return robust ? "robust WV (Gaussian efficiency " + fmt(robust->efficiency) + ")" : std::string("classical WV");
}

std::string joint_fit_text(const Json& doc, const io::SignalSet& set,
                           const std::vector<pipeline::ReplicateGroup>& groups, const pipeline::JointFitStudy& study,
                           const std::string& estimator, const TextOptions& options) {
  std::string text = axis_summary(doc) + "\n";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const JointAnalysis& a = study.groups[i].analysis;
    text += (i ? "\n" : "") +
            joint_fit_detail(groups[i], a.fit, a.test ? &*a.test : nullptr, a.bootstrap ? &*a.bootstrap : nullptr,
                             study.omega, estimator) +
            joint_physical_tables(groups[i], set, a.fit.joint, study.groups[i].figures,
                                  i < options.units.size() ? options.units[i] : std::string(), options.filter_rate);
  }
  return text;
}

std::string joint_select_text(const Json& doc, const io::SignalSet& set,
                              const std::vector<pipeline::ReplicateGroup>& groups,
                              const pipeline::JointSelectStudy& study, const std::string& estimator,
                              const TextOptions& options) {
  std::string text = axis_summary(doc) + "\n";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const FitResult& best = study.recommended[i].fit.joint;
    text += (i ? "\n" : "") + joint_select_detail(groups[i], study.results[i], estimator);
    if (best.theta.size() == best.model.num_parameters() && best.theta.allFinite())
      text += "recommended, fitted jointly: " + best.model.to_string(best.theta) + "\n" +
              joint_physical_tables(groups[i], set, best, study.figures[i],
                                    i < options.units.size() ? options.units[i] : std::string(), options.filter_rate);
  }
  return text;
}

}  // namespace gmwm::report
