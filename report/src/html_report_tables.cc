// The report's HTML tables: parameters (discrete and continuous), the selection ranking,
// the gap diagnosis and the WV levels. Every user string goes through html_escape.

#include <cmath>
#include <exception>
#include <span>
#include <sstream>

#include "gmwm/engine/physical.h"
#include "html_report_detail.h"
#include "replicate_rows.h"

namespace gmwm::report::detail {

std::string td(const std::string& text, const char* cls) {
  return std::string("<td") + (cls ? std::string(" class=\"") + cls + "\"" : "") + ">" + html_escape(text) + "</td>";
}

std::string th_row(const std::vector<std::string>& head) {
  std::string s = "<tr>";
  for (const auto& h : head) s += "<th>" + html_escape(h) + "</th>";
  return s + "</tr>\n";
}

namespace {

std::string interval(double lo, double hi, int digits = 4) {
  if (!std::isfinite(lo) && !std::isfinite(hi)) return "-";
  return num(lo, digits) + " to " + num(hi, digits);
}

}  // namespace

std::string parameter_tables(const FitResult& fit, const ReportColumn& c, const std::string& caption) {
  if (!has_theta(fit)) return {};
  std::ostringstream os;
  os << "<div class=\"params\">\n<h4>" << html_escape(caption) << "</h4>\n";
  os << "<p class=\"model\">" << html_escape(fit.model.to_string(fit.theta)) << "</p>\n";
  os << "<table class=\"discrete\">\n<caption>discrete (per sample) parameters, as estimated</caption>\n"
     << th_row({"component", "process", "parameter", "value", "se",
                c.wvs.empty() ? std::string("interval")
                              : "interval (" + num(100.0 * (1.0 - c.wvs.front().alpha), 3) + "%)",
                "meaning"});
  for (const ParameterRow& r : parameter_rows(fit)) {
    std::string meaning;
    for (int k = 0; k < fit.model.num_parameters(); ++k)
      if (fit.model.component_of(k) + 1 == r.component && fit.model.spec_of(k).name == r.name)
        meaning = fit.model.spec_of(k).meaning;
    os << "<tr>" << td(std::to_string(r.component)) << td(r.process) << td(r.name) << td(num(r.value, 6), "num")
       << td(num(r.se, 3), "num") << td(interval(r.ci_low, r.ci_high), "num") << td(meaning, "note") << "</tr>\n";
  }
  os << "</table>\n";
  if (c.freq_known && c.freq > 0.0) {
    os << "<table class=\"continuous\">\n<caption>continuous (physical) quantities at " << html_escape(num(c.freq, 6))
       << " Hz, data unit " << html_escape(data_unit(c)) << "</caption>\n"
       << th_row({"component", "process", "quantity", "value", "interval", "unit", "convention"});
    const bool ci = fit.ci_low.size() == fit.theta.size() && fit.ci_high.size() == fit.theta.size();
    for (int k = 0; k < fit.model.num_components(); ++k) {
      const Process& p = *fit.model.components()[static_cast<std::size_t>(k)].process;
      const auto off = static_cast<std::size_t>(fit.model.offset(k));
      const auto size = static_cast<std::size_t>(p.size());
      const std::span<const double> th(fit.theta.data() + off, size);
      std::vector<PhysicalQuantity> q;
      std::vector<PhysicalInterval> iv;
      try {
        q = p.physical(th, c.freq);
        if (ci)
          iv = physical_interval(p, th, std::span<const double>(fit.ci_low.data() + off, size),
                                 std::span<const double>(fit.ci_high.data() + off, size), c.freq);
      } catch (const std::exception&) {
        // An interval that cannot be mapped (e.g. crossing bounds) is shown as "-".
      }
      for (std::size_t i = 0; i < q.size(); ++i)
        os << "<tr>" << td(std::to_string(k + 1)) << td(p.name()) << td(q[i].name) << td(num(q[i].value, 6), "num")
           << td(i < iv.size() ? interval(iv[i].low, iv[i].high) : "-", "num")
           << td(q[i].unit_pattern.empty() ? "(discrete)" : render_unit(q[i].unit_pattern, data_unit(c)))
           << td(q[i].convention, "note") << "</tr>\n";
    }
    os << "</table>\n";
    // The Kalman-filter terms (engine/kalman.h) at the filter's rate.
    ColumnInfo info{c.name, c.n, c.freq, c.freq_known, c.unit};
    const double rate = c.filter_rate > 0.0 ? c.filter_rate : c.freq;
    const Json k = kalman_json(fit, info, rate, c.allan ? &c.allan->chosen : nullptr);
    if (!k.at("terms").empty()) {
      os << "<table class=\"kalman\">\n<caption>Kalman filter at " << html_escape(num(rate, 6))
         << " Hz: continuous q, transition F and the discrete R or Q_d</caption>\n"
         << th_row({"component", "process", "role", "q", "F", "R or Q_d", "note"});
      auto cell = [](const Json& v, const Json& unit) {
        if (!v.is_number()) return std::string("-");
        return num(v.get<double>(), 5) + (unit.is_string() ? " " + unit.get<std::string>() : std::string());
      };
      for (const auto& t : k.at("terms"))
        os << "<tr>" << td(t.at("component").is_number() ? std::to_string(t.at("component").get<int>()) : "-")
           << td(t.at("process").get<std::string>()) << td(t.at("role").get<std::string>())
           << td(cell(t.at("q"), t.at("q_unit")), "num") << td(cell(t.at("transition"), nullptr), "num")
           << td(cell(t.at("discrete"), t.at("discrete_unit")), "num") << td(t.at("note").get<std::string>(), "note")
           << "</tr>\n";
      os << "</table>\n";
    }
  }
  os << "</div>\n";
  return os.str();
}

std::string ranking_table(const selection::Selection& sel) {
  std::ostringstream os;
  const bool boot = !sel.ranking.empty() && sel.ranking.front().optimism_bootstrap.has_value();
  os << "<div class=\"ranking\">\n<h4>model ranking: " << sel.models << " models (" << html_escape(sel.full_model)
     << "), representation violations " << sel.representation_violations << "</h4>\n"
     << "<table class=\"ranking\">\n";
  std::vector<std::string> head = {"rank", "model (effective)", "parameters", "objective", "optimism", "criterion"};
  if (boot) head.insert(head.end(), {"bootstrap optimism (se)", "rank a/b"});
  head.push_back("GoF p (shared Omega)");
  head.push_back("candidates that fell onto it (their own objective)");
  os << th_row(head);
  for (std::size_t i = 0; i < sel.ranking.size(); ++i) {
    const auto& r = sel.ranking[i];
    const bool chosen = i == 0;
    os << "<tr" << (chosen ? " class=\"chosen\"" : "") << ">" << td(std::to_string(r.rank), "num") << "<td>"
       << html_escape(r.model) << (chosen ? " <span class=\"badge\">chosen</span>" : "") << "</td>"
       << td(std::to_string(r.parameters), "num") << td(num(r.objective, 6), "num") << td(num(r.optimism, 4), "num")
       << td(num(r.criterion, 6), "num");
    if (boot)
      os << td(r.optimism_bootstrap
                   ? num(*r.optimism_bootstrap, 4) + " (" + num(r.optimism_bootstrap_se.value_or(NAN), 2) + ")"
                   : "-",
               "num")
         << td((r.rank_analytic ? std::to_string(*r.rank_analytic) : "-") + "/" +
                   (r.rank_bootstrap ? std::to_string(*r.rank_bootstrap) : "-"),
               "num");
    std::string others;
    for (std::size_t k = 0; k < r.members.size(); ++k)
      if (r.members[k] != r.model)
        others += (others.empty() ? "" : ", ") + r.members[k] + " (" +
                  (k < r.member_objectives.size() ? num(r.member_objectives[k], 4) : std::string("-")) + ")";
    os << td(num(r.gof.p_value, 3), "num") << td(others) << "</tr>\n";
  }
  os << "</table>\n<p class=\"facts\">GoF p (shared Omega): each candidate's test under the selection's shared "
        "weights and covariance, comparable across rows; the chosen model's own test (refitted with its own Omega) "
        "is the one in its parameter table.</p>\n</div>\n";
  return os.str();
}

std::string noise_figures_table(const ReportColumn& c) {
  const ChosenFigures& f = c.allan->chosen;
  const FigureUnits units = figure_units(c.unit);
  std::ostringstream os;
  os << "<div class=\"figures\">\n<table class=\"figures\">\n"
     << th_row({"noise figure (IEEE 952)", "value", "CI low", "CI high", "unit", "source", "model's read-off",
                "data's read-off", "read"});
  auto shown = [](const Readoff& r) {
    if (!r.available()) return std::string("-");
    return num(r.value, 4) + (r.status == ReadoffStatus::kBound ? " (bound)" : "");
  };
  std::string notes;
  auto row = [&](const char* name, const ChosenFigure& x, const std::string& u) {
    os << "<tr>" << td(name) << td(num(x.figure.value, 5), "num") << td(num(x.figure.low, 4), "num")
       << td(num(x.figure.high, 4), "num") << td(u) << td(to_string(x.source)) << td(shown(x.model), "num")
       << td(shown(x.data), "num") << td(x.figure.how) << "</tr>\n";
    std::string comps;
    for (const auto& [component, share] : x.model.sources)
      comps += (comps.empty() ? "" : ", ") + component + " " + num(100.0 * share, 3) + "%";
    notes +=
        "<p class=\"facts\">" +
        html_escape(std::string(name) + ": " + x.note + (comps.empty() ? "" : "; the model's curve there: " + comps)) +
        "</p>\n";
  };
  row("N white noise", f.white, units.white);
  row("K random walk", f.walk, units.walk);
  row("B bias instability", f.instability, units.instability);
  row("Q quantization", f.quantization, units.quantization);
  row("R rate ramp", f.ramp, units.ramp);
  os << "</table>\n" << notes << "</div>\n";
  return os.str();
}

std::string gap_tables(const ReportColumn& c) {
  const gap::GapResult& g = *c.gap;
  const double scale = tau_scale(c);
  const std::string unit = tau_unit(c);
  std::ostringstream os;
  os << "<div class=\"gap\">\n<p class=\"summary\"><b>" << (g.detected ? "gap detected" : "no gap")
     << "</b>: " << html_escape(g.headline) << " (global test statistic " << html_escape(num(g.statistic, 4)) << ")";
  os << "</p>\n<ul class=\"facts\">\n<li>baseline: <code>" << html_escape(g.baseline.to_string(g.baseline_theta))
     << "</code></li>\n";
  if (!g.steps.empty())
    os << "<li>final model: <code>" << html_escape(g.final_model.to_string(g.final_theta)) << "</code></li>\n";
  for (const auto& conv : c.conversions) os << "<li>conversion: " << html_escape(conv) << "</li>\n";
  for (const auto& r : g.refused) os << "<li>refused (does not make the fit better): " << html_escape(r) << "</li>\n";
  if (g.contamination_screened) {
    os << "<li>contamination screen: ";
    if (g.contaminated_levels.empty()) os << "no level flagged";
    for (std::size_t i = 0; i < g.contaminated_levels.size(); ++i)
      os << (i ? ", " : "levels flagged at ")
         << html_escape(
                num(g.levels[static_cast<std::size_t>(g.contaminated_levels[i] - g.first_level)].tau * scale, 4))
         << " " << unit;
    os << " (robust WV below the classical one beyond the data's rounding, with far outliers)</li>\n";
  }
  const auto& s = g.shrinkage;
  os << "<li>objective " << num(s.objective_before) << " &rarr; " << num(s.objective_after) << " (null mean "
     << num(s.null_mean, 4) << " &rarr; " << num(s.null_mean_after, 4) << "), levels outside the band "
     << s.levels_outside_before << " &rarr; " << s.levels_outside_after << ", global p " << num(s.p_value_before, 3)
     << " &rarr; " << num(s.p_value_after, 3) << "</li>\n";
  if (std::isfinite(g.navigation.rms_without))
    os << "<li>integrated error after " << num(g.navigation.horizon_seconds, 3)
       << " s: " << num(g.navigation.rms_without, 3) << " &rarr; " << num(g.navigation.rms_with, 3) << " "
       << html_escape(render_unit("U*s", data_unit(c))) << " RMS (baseline &rarr; with the effects)</li>\n";
  // Times and rates in seconds when the sampling rate is known (issue 14, item 6).
  const bool seconds = c.freq_known && c.freq > 0.0;
  const double rate = seconds ? c.freq : 1.0;
  const char* per = seconds ? " per s" : " per sample";
  if (g.event) {
    const auto& e = *g.event;
    os << "<li>" << gap::to_string(e.effect);
    if (e.effect == gap::GapEffect::kOutliers) os << " (a burst of " << e.length << " samples)";
    os << " at "
       << (seconds ? num(static_cast<double>(e.sample) / rate, 6) + " s" : "sample " + std::to_string(e.sample)) << ", "
       << (e.effect == gap::GapEffect::kOutliers ? "peak departure " : "size ") << num(e.size, 4);
    if (e.effect == gap::GapEffect::kTransient)
      os << ", time constant " << num(e.time_constant / rate, 4) << (seconds ? " s" : " samples");
    os << "</li>\n";
  }
  if (g.trend && g.trend->significant)
    os << "<li>drift (end-segment trend): " << num(g.trend->omega * rate, 4) << per << "</li>\n";
  if (g.temperature)
    os << "<li>temperature coupling " << num(g.temperature->k, 4) << " ("
       << interval(g.temperature->ci_low, g.temperature->ci_high) << ")"
       << (g.temperature->significant ? ", significant" : "") << "</li>\n";
  for (const auto& n : g.notes) os << "<li>note: " << html_escape(n) << "</li>\n";
  os << "</ul>\n";
  if (!g.candidates.empty()) {
    os << "<table class=\"candidates\">\n<caption>candidate effects (first step)</caption>\n"
       << th_row({"effect", "improvement", "threshold", "2 x optimism (WVIC)", "cleared", "fit"});
    for (const auto& cand : g.candidates)
      os << "<tr" << (cand.cleared ? " class=\"chosen\"" : "") << ">" << td(gap::to_string(cand.effect))
         << td(num(cand.improvement, 5), "num") << td(num(cand.threshold, 4), "num")
         << td(num(2.0 * cand.optimism, 4), "num") << td(cand.cleared ? "yes" : "") << td(cand.model, "note")
         << "</tr>\n";
    os << "</table>\n";
  }
  os << "<details><summary>levels against the baseline's reference</summary>\n<table class=\"levels\">\n"
     << th_row(
            {"level", "tau [" + unit + "]", "ratio", "z", "reference band (bootstrap)", "closed-form band", "outside"});
  int level = 0;
  for (const auto& l : g.levels)
    os << "<tr" << (l.outside ? " class=\"outside\"" : "") << ">" << td(std::to_string(++level), "num")
       << td(num(l.tau * scale, 5), "num") << td(num(l.ratio, 4), "num") << td(num(l.z, 3), "num")
       << td(interval(l.ref_low, l.ref_high), "num") << td(interval(l.analytic_low, l.analytic_high), "num")
       << td(l.outside ? "yes" : "") << "</tr>\n";
  os << "</table>\n</details>\n";
  os << parameter_tables(g.final_fit, c, "first added effect's parameters (bootstrap intervals)");
  os << "</div>\n";
  return os.str();
}

std::string wv_table(const ReportColumn& c) {
  std::ostringstream os;
  const double scale = tau_scale(c);
  for (std::size_t k = 0; k < c.wvs.size(); ++k) {
    const WaveletVariance& w = c.wvs[k];
    const std::string label =
        c.replicates && k < c.replicates->sources.size()
            ? "replicate " + std::to_string(k + 1) + " (" + c.replicates->sources[k] + "): " + wv_label(w)
            : wv_label(w);
    // A record with missing samples: the windows read that miss some (partial_windows).
    const bool gaps = !w.partial.empty();
    std::vector<std::string> head = {"level", "tau [samples]", "tau [" + tau_unit(c) + "]", "WV", "CI low", "CI high",
                                     "M_j"};
    if (gaps) head.emplace_back("partial");
    os << "<details><summary>" << html_escape(label) << " by level</summary>\n<table class=\"levels\">\n"
       << th_row(head);
    for (std::size_t j = 0; j < w.wv.size(); ++j) {
      os << "<tr>" << td(std::to_string(j + 1), "num") << td(num(w.tau[j], 10), "num")
         << td(num(w.tau[j] * scale, 5), "num") << td(num(w.wv[j]), "num")
         << td(num(j < w.ci_low.size() ? w.ci_low[j] : NAN), "num")
         << td(num(j < w.ci_high.size() ? w.ci_high[j] : NAN), "num")
         << td(j < w.coefficients.size() ? std::to_string(w.coefficients[j]) : "-", "num");
      if (gaps) os << td(j < w.partial.size() ? std::to_string(w.partial[j]) : "-", "num");
      os << "</tr>\n";
    }
    os << "</table>\n";
    if (gaps)
      os << "<p>M_j: the windows read; partial: those of them missing some samples (each half at most a tenth, "
            "averaged over its observed ones)</p>\n";
    os << "</details>\n";
  }
  return os.str();
}

}  // namespace gmwm::report::detail

namespace gmwm::report::detail {

namespace {

// The shared-theta test in one sentence, highlighted when it rejects.
std::string replicate_test_line(const ReplicateTest& t) {
  const bool rejects = t.rejects();
  std::ostringstream os;
  os << "<p class=\"" << (rejects ? "quality" : "facts")
     << "\">shared theta? heterogeneity H = " << html_escape(num(t.heterogeneity, 4)) << ", bootstrap p "
     << html_escape(num(t.heterogeneity_p, 3)) << ": "
     << (rejects ? "<b>the replicates do not share one theta</b> (compare their own estimates below)"
                 : "one theta fits them all")
     << "; joint misfit T = " << html_escape(num(t.statistic, 4)) << ", bootstrap p " << html_escape(num(t.p_value, 3))
     << " (" << t.draws << " parametric-bootstrap draws, Omega_k = V_k^-1 at the fixed-point estimate)</p>\n";
  return os.str();
}

// Parameters side by side: joint (sandwich and replicate-t intervals), AGMWM, each replicate's own.
std::string side_by_side(const ReplicateReport& r, const ReportColumn& c) {
  const JointFitResult& j = *r.joint;
  const FitResult& f = j.joint;
  if (!has_theta(f)) return {};
  const std::string level = c.wvs.empty() ? std::string() : " (" + num(100.0 * (1.0 - c.wvs.front().alpha), 3) + "%)";
  std::vector<std::string> head = {"component", "process", "parameter", "joint", "sandwich interval" + level};
  if (r.bootstrap) head.push_back("replicate-t interval" + level);
  head.insert(head.end(), {"AGMWM", "AGMWM se"});
  for (std::size_t k = 0; k < j.singles.size(); ++k) head.push_back("replicate " + std::to_string(k + 1) + " alone");
  std::ostringstream os;
  os << "<div class=\"params\">\n<table class=\"discrete\">\n<caption>discrete (per sample) parameters: the joint "
        "estimate beside the average of the replicates' own estimates (AGMWM) and each of them</caption>\n"
     << th_row(head);
  const bool sandwich = f.ci_low.size() == f.theta.size() && f.ci_high.size() == f.theta.size();
  const bool boot = r.bootstrap && r.bootstrap->ci_low.size() == f.theta.size();
  for (int i = 0; i < f.model.num_parameters(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const int comp = f.model.component_of(i);
    os << "<tr>" << td(std::to_string(comp + 1))
       << td(f.model.components()[static_cast<std::size_t>(comp)].process->name()) << td(f.model.spec_of(i).name)
       << td(num(f.theta(k), 6), "num") << td(sandwich ? interval(f.ci_low(k), f.ci_high(k)) : "-", "num");
    if (r.bootstrap) os << td(boot ? interval(r.bootstrap->ci_low(k), r.bootstrap->ci_high(k)) : "-", "num");
    os << td(k < j.agmwm.size() ? num(j.agmwm(k), 6) : "-", "num")
       << td(k < j.agmwm_se.size() ? num(j.agmwm_se(k), 3) : "-", "num");
    for (const auto& s : j.singles) os << td(has_theta(s) && k < s.theta.size() ? num(s.theta(k), 6) : "-", "num");
    os << "</tr>\n";
  }
  os << "</table>\n</div>\n";
  return os.str();
}

// The selection over replicates: CV-WVIC, analytic and bootstrap WVIC side by side.
std::string replicate_ranking(const selection::ReplicateSelection& s) {
  const bool boot = !s.chosen_bootstrap.empty();
  std::ostringstream os;
  os << "<div class=\"ranking\">\n<h4>model selection over the replicates: " << s.ranking.size() << " sub-models of "
     << html_escape(s.full_model) << " (" << detail::fold_by_effective(s).size() << " distinct effective models), "
     << s.training.size() << " training splits of " << (s.training.empty() ? 0 : s.training.front().size())
     << "</h4>\n<table class=\"ranking\">\n";
  std::vector<std::string> head = {"rank (CV)", "effective model", "parameters",
                                   "CV-WVIC",   "analytic WVIC",   "rank (analytic)"};
  if (boot) head.insert(head.end(), {"bootstrap WVIC (s.e.)", "rank (bootstrap)"});
  head.insert(head.end(), {"P(not worse)", "equivalent", "other candidates that fell onto it (CV-WVIC)"});
  os << th_row(head);
  for (const detail::FoldedRow& f : detail::fold_by_effective(s)) {
    const selection::CvCandidate& r = *f.best;
    std::string badges;
    if (f.chosen) badges += " <span class=\"badge\">chosen</span>";
    if (f.recommended) badges += " <span class=\"badge\">recommended</span>";
    std::string others;
    for (const selection::CvCandidate* o : f.others)
      others += (others.empty() ? "" : ", ") + o->model + " (" + num(o->cv_wvic, 4) + ")";
    os << "<tr" << (f.chosen ? " class=\"chosen\"" : "") << ">" << td(std::to_string(r.rank), "num") << "<td>"
       << html_escape(detail::folded_name(f)) << badges << "</td>" << td(std::to_string(r.parameters), "num")
       << td(num(r.cv_wvic, 6), "num") << td(num(r.analytic_wvic, 6), "num")
       << td(std::to_string(r.rank_analytic), "num");
    if (boot)
      os << td(num(r.bootstrap_wvic, 6) + " (" + num(r.bootstrap_se, 2) + ")", "num")
         << td(r.rank_bootstrap ? std::to_string(r.rank_bootstrap) : "-", "num");
    os << td(num(r.p_not_worse, 3), "num") << td(r.equivalent ? "yes" : "") << td(others, "note") << "</tr>\n";
  }
  os << "</table>\n<p class=\"facts\">chosen (smallest CV-WVIC): " << html_escape(s.chosen)
     << "; recommended (smallest equivalent model): " << html_escape(s.recommended)
     << "; smallest analytic WVIC of the joint fit: " << html_escape(s.chosen_analytic);
  if (boot) os << "; smallest bootstrap WVIC: " << html_escape(s.chosen_bootstrap);
  os << ". A model is equivalent to the chosen one unless its held-out loss is larger in more than 95% of "
        "bootstrap resamples of the splits.</p>\n";
  if (s.all_rejected)
    os << "<p class=\"quality\"><b>every candidate's joint fit is rejected at 5%</b>: no sub-model of "
       << html_escape(s.full_model) << " describes these recordings, and the ranking compares misfits</p>\n";
  os << "</div>\n";
  return os.str();
}

}  // namespace

std::string replicate_tables(const ReportColumn& c) {
  if (!c.replicates) return {};
  const ReplicateReport& r = *c.replicates;
  std::ostringstream os;
  os << "<div class=\"params\">\n<table class=\"replicates\">\n<caption>replicates (" << html_escape(r.estimator)
     << ")</caption>\n"
     << th_row({"replicate", "source", "N", "levels", "share of the joint objective", "own fit"});
  for (std::size_t k = 0; k < r.sources.size(); ++k) {
    const bool fitted = r.joint && k < r.joint->singles.size();
    os << "<tr>" << td(std::to_string(k + 1)) << td(r.sources[k])
       << td(k >= r.n.size() ? "-"
             : k < r.missing.size() && r.missing[k] > 0
                 ? std::to_string(r.n[k]) + " (+" + std::to_string(r.missing[k]) + " missing)"
                 : std::to_string(r.n[k]),
             "num")
       << td(k < c.wvs.size() ? std::to_string(c.wvs[k].levels()) : "-", "num")
       << td(r.joint && k < r.joint->objective_share.size() ? num(r.joint->objective_share[k], 4) : "-", "num")
       << td(fitted ? gmwm::to_string(r.joint->singles[k].status) : "-") << "</tr>\n";
  }
  os << "</table>\n</div>\n";
  if (r.test) os << replicate_test_line(*r.test);
  if (r.joint) os << side_by_side(r, c);
  if (r.selection) os << replicate_ranking(*r.selection);
  return os.str();
}

}  // namespace gmwm::report::detail
