// gmwm select INPUT (--model SPEC | --models "SPEC1;SPEC2;...") [--penalty wvic|bic] [--optimism analytic|bootstrap|both]
//              [--omega model|full|data]
//              [--replicates B] [--robust ...]
// Every sub-model of SPEC fitted on every selected column and ranked (selection/).

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <iostream>
#include <mutex>
#include <sstream>

#include "common.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/select_study.h"
#include "units_tables.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/selection/select.h"
#include "gmwm/selection/submodels.h"
#include "replicates.h"

namespace gmwm::cli {

namespace {

struct SelectArgs {
  InputOptions input;
  RobustOptions robust;
  std::string model;
  std::string models;  ///< --models "SPEC1;SPEC2;..."
  std::string penalty = "wvic";
  std::string optimism = "analytic";
  std::string omega = "model";
  int replicates = selection::SelectOptions{}.bootstrap_replicates;
  int max_evaluations = FitOptions{}.max_evaluations;
  UnitsOptions units;
  std::vector<std::string> joint;  ///< --joint FILE[:COLUMN] ...: replicates of INPUT's columns
};

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

std::string terminal_report(const io::SignalSet& set, std::size_t k, const selection::Selection& sel) {
  std::ostringstream os;
  const auto& s = set.signals[k];
  os << s.name << ": N = " << s.values.size() << ", " << sel.models << " sub-models of " << sel.full_model
     << ", representation violations " << sel.representation_violations << '\n';
  const bool both =
      !sel.ranking.empty() && sel.ranking.front().optimism_bootstrap && sel.ranking.front().optimism_analytic;
  std::vector<std::string> head = {
      "rank",     "model (effective)", "p",           "objective",
      "optimism", "criterion",         "GoF p-value", "candidates that fell onto it (their own objective)"};
  if (both) head.insert(head.end(), {"analytic", "bootstrap (se)", "rank a/b"});
  Table t(head, 2);
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
  os << t.str();
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
    const std::string why = rejection_summary(b, set.freq, set.freq_known);
    os << "fit quality: every candidate is rejected at 5%: no sub-model of " << sel.full_model
       << " describes these data" << (why.empty() ? "" : "; the chosen " + b.model.to_string() + " is " + why) << '\n';
  } else if (const std::string why = rejection_summary(b, set.freq, set.freq_known); !why.empty()) {
    os << "fit quality: the chosen " << b.model.to_string() << " is " << why << '\n';
  }
  if (const std::string why = degeneracy_summary(b); !why.empty()) os << "fit quality: " << why << '\n';
  return os.str();
}

// Selection over replicates: per axis, every sub-model of the maximal model ranked by its
// cross-validated WVIC over the replicates, the analytic WVIC of the joint fit beside it,
// the equivalent models and the recommended one.
// The shared-theta test in a report needs at least this many draws (ReplicateTestOptions).
constexpr int kMinReportTestDraws = 19;

std::string joint_select_report(const ReplicateGroup& g, const selection::ReplicateSelection& r,
                                const std::string& estimator) {
  std::ostringstream os;
  const bool boot = !r.chosen_bootstrap.empty();
  os << g.axis << ": selection over " << g.sources.size() << " replicates (" << r.training.size()
     << " training splits of " << r.training.front().size() << "), maximal model " << r.full_model << ", " << estimator
     << '\n';
  for (std::size_t k = 0; k < g.sources.size(); ++k)
    os << "  replicate " << k + 1 << ": " << g.sources[k] << ", N = " << g.series[k].size() << '\n';
  std::vector<std::string> head = {"rank", "model", "p", "CV-WVIC", "analytic WVIC", "rank (analytic)"};
  if (boot) head.insert(head.end(), {"bootstrap WVIC (s.e.)", "rank (bootstrap)"});
  head.insert(head.end(), {"P(not worse)", "equivalent"});
  Table t(head, 1);
  for (const auto& c : r.ranking) {
    std::vector<std::string> row = {std::to_string(c.rank),       c.model,
                                    std::to_string(c.parameters), fmt(c.cv_wvic, 6),
                                    fmt(c.analytic_wvic, 6),      std::to_string(c.rank_analytic)};
    if (boot)
      row.insert(row.end(),
                 {fmt(c.bootstrap_wvic, 6) + " (" + fmt(c.bootstrap_se, 2) + ")", std::to_string(c.rank_bootstrap)});
    row.insert(row.end(), {fmt(c.p_not_worse, 3), c.equivalent ? "yes" : ""});
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

int run_joint_select(const SelectArgs& args, const CommonOptions& common, const selection::SelectOptions& options,
                     const robust::RobustWvOptions* robust) {
  Stopwatch total;
  if (args.model.empty() || !args.models.empty())
    throw InputError("--joint: give the maximal model with --model SPEC (not --models)");
  if (args.penalty == "bic")
    throw InputError("--joint with --penalty bic: the selection over replicates ranks by the cross-validated WVIC");
  if (args.optimism == "bootstrap" || args.optimism == "both")
    throw InputError("--joint with --optimism " + args.optimism +
                     ": the selection over replicates ranks by the cross-validated WVIC; --optimism all gives the "
                     "analytic and bootstrap WVIC of the joint fit beside it");
  for (const auto& e : args.joint) declare_input(common, replicate_path(e));
  const WvOptions wv_opts = wv_options(args.input);
  const io::SignalSet set = read_input(args.input);
  const std::vector<ReplicateGroup> groups = read_replicates(set, args.joint, args.input);
  // The declared units (a bad --units fails here, before any work) and the Kalman rate.
  std::vector<std::string> units;
  for (const ReplicateGroup& g : groups) units.push_back(column_unit(args.units, g.axis));
  const double filter = filter_rate(args.units, set);
  pipeline::JointSelectStudyOptions o;
  o.model = args.model;
  o.select.select = options;
  o.select.select.estimator = nullptr;  // the study sets it
  o.select.select.optimism =
      args.optimism == "all" ? selection::OptimismMethod::kBoth : selection::OptimismMethod::kAnalytic;
  o.select.seed = common.seed;
  o.wv = wv_opts;
  if (robust) o.robust = *robust;
  // A report draws the recommended model of each axis fitted jointly, with its test.
  if (!common.report.empty()) o.recommended_test_draws = std::max(args.replicates, kMinReportTestDraws);
  // Progress on a terminal: the selections (all replicates, then every training split) done.
  ProgressBar bar("select --joint: selections", common);
  if (bar.enabled()) o.select.select.progress = [&](int done, int count) { bar.update(done, count); };
  const pipeline::JointSelectStudy study =
      pipeline::study_joint_select(groups, ProcessContext{set.freq, set.freq_known}, o);
  bar.finish();
  const std::string estimator = replicate_estimator_text(robust);
  report::Json doc = report::joint_select_document(set, groups, study, units, filter);
  std::string report = report::axis_summary(doc) + "\n";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const FitResult& best = study.recommended[i].fit.joint;
    report += (i ? "\n" : "") + joint_select_report(groups[i], study.results[i], estimator);
    if (best.theta.size() == best.model.num_parameters() && best.theta.allFinite())
      report += "recommended, fitted jointly: " + best.model.to_string(best.theta) + "\n" +
                joint_physical_tables(groups[i], set, best, study.figures[i], args.units, filter);
  }
  write_json(common, doc, {.threads = 0, .seconds = {{"total", total.seconds()}}, .argv = {}});
  if (!common.report.empty()) {
    report::ReportData rep = report_data("select", set, args.model);
    for (std::size_t i = 0; i < groups.size(); ++i) {
      fill_joint_report_column(rep.columns[i], groups[i], study.wvs[i], study.recommended[i], estimator);
      rep.columns[i].replicates->selection = study.results[i];
    }
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) print_text(report);
  return 0;
}

int run_select(const SelectArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const WvOptions wv_opts = wv_options(args.input);
  const auto robust_options = robust_wv_options(args.robust, wv_opts);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  selection::SelectOptions options;
  const bool by_replicates = args.optimism == "replicates" || args.optimism == "all";
  if (by_replicates && args.joint.empty())
    throw InputError("--optimism " + args.optimism +
                     ": the replicate-based optimism needs replicates; give them with --joint FILE[:COLUMN] ...");
  // CLI11 checked the names against the same spellings.
  options.optimism = selection::parse_optimism_method(args.optimism).value_or(selection::OptimismMethod::kAnalytic);
  options.omega = selection::parse_omega_source(args.omega).value_or(selection::OmegaSource::kModel);
  options.bootstrap_replicates = args.replicates;
  options.seed = common.seed;
  options.penalty = selection::parse_penalty(args.penalty).value_or(selection::Penalty::kWvic);
  options.fit.alpha = args.input.alpha;
  options.fit.seed = common.seed;
  options.fit.max_evaluations = args.max_evaluations;
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  if (!args.joint.empty()) {
    return run_joint_select(args, common, options, robust_options ? &*robust_options : nullptr);
  }
  if (args.model.empty() == args.models.empty())
    throw InputError("select: give either --model SPEC (every sub-model) or --models \"SPEC1;SPEC2;...\"");
  // The listed models of --models, split at ';' (empty entries are an error).
  std::vector<std::string> specs;
  if (!args.models.empty()) {
    std::string cur;
    for (char ch : args.models + ";") {
      if (ch != ';') {
        cur += ch;
        continue;
      }
      if (cur.find_first_not_of(" \t") == std::string::npos)
        throw InputError("--models \"" + args.models + "\": empty model in the list");
      specs.push_back(cur);
      cur.clear();
    }
  }
  pipeline::SelectStudyOptions study_options;
  study_options.models = specs.empty() ? std::vector<std::string>{args.model} : specs;
  study_options.listed = !specs.empty();
  study_options.select = options;
  study_options.wv = wv_opts;
  study_options.robust = robust_options;
  if (args.input.freq) {
    if (const std::string why = io::sampling_rate_problem(*args.input.freq, "--freq"); !why.empty())
      throw InputError(why);
    for (const std::string& m : study_options.models) parse_model(m, ProcessContext{*args.input.freq, true});
  }

  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  // Progress on a terminal: models done / total (bootstrap refits included), time left.
  ProgressBar bar("select: models", common);
  if (bar.enabled())
    study_options.select.progress = [&](int done, int total_models) { bar.update(done, total_models); };
  const pipeline::SelectStudy study = pipeline::study_select(set, study_options);

  std::vector<std::string> units;
  for (const auto& s : set.signals) units.push_back(column_unit(args.units, s.name));
  const double filter = filter_rate(args.units, set);
  report::Json doc = report::select_document(set, study, units, filter);
  std::string report;
  if (common.show_table()) {
    if (set.timing) report += set.timing->summary() + "\n";
    report += report::axis_summary(doc);
    for (std::size_t k = 0; common.verbose && k < study.columns.size(); ++k) {
      const pipeline::SelectColumnStudy& c = study.columns[k];
      const report::ColumnInfo info = with_unit(column_info(set, k), args.units);
      const ChosenFigures* chosen = c.figures ? &c.figures->chosen : nullptr;
      report += "\n" + terminal_report(set, k, c.selection) + continuous_table(c.selection.best_fit, info) +
                (chosen ? noise_figures_table(*chosen, info.unit) : "") +
                kalman_table(c.selection.best_fit, info, filter, chosen);
    }
    if (!common.verbose) report += kDetailsHint;
  }
  warn_about_timing(set);
  for (const pipeline::SelectColumnStudy& c : study.columns)
    if (c.selection.best_fit.status == FitStatus::kFailed)
      warn("column '" + c.name + "': the best model's fit with inference failed");
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds},
                          {"wv", study.wv_seconds},
                          {"allan", study.allan_seconds},
                          {"select", study.select_seconds},
                          {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty()) {
    report::ReportData rep = report_data("select", set, specs.empty() ? args.model : args.models);
    for (std::size_t k = 0; k < study.columns.size(); ++k) {
      const pipeline::SelectColumnStudy& c = study.columns[k];
      rep.columns[k].wvs =
          c.classical ? std::vector<WaveletVariance>{c.wv, *c.classical} : std::vector<WaveletVariance>{c.wv};
      rep.columns[k].selection = c.selection;
      rep.columns[k].allan = c.figures;
      rep.columns[k].filter_rate = filter;
      if (!units[k].empty()) rep.columns[k].unit = units[k];
    }
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) {
    print_text(report);
  }
  return 0;
}

}  // namespace

Command add_select_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<SelectArgs>();
  CLI::App* sub = app.add_subcommand(
      "select", "Fit every sub-model of a maximal model (e.g. 3*AR1+WN+RW+QN+DR) on each column and rank them");
  add_input_options(*sub, args->input);
  auto* one =
      sub->add_option("--model", args->model, "Maximal model, e.g. '3*AR1+WN+RW+QN+DR': every sub-model is ranked")
          ->type_name("SPEC");
  sub->add_option("--models", args->models,
                  "Non-nested mode: only these models, e.g. 'AR1+WN;2*AR1;WN+RW' (their common super-model gives V)")
      ->type_name("SPEC1;SPEC2;...")
      ->excludes(one);
  sub->add_option("--penalty", args->penalty, "wvic (objective + analytic optimism) or bic (+ p log N)")
      ->check(CLI::IsMember({"wvic", "bic"}))
      ->capture_default_str();
  sub->add_option("--optimism", args->optimism,
                  "Optimism of the WVIC: analytic (delta method), bootstrap (parametric, --replicates per model) "
                  "or both side by side (the criterion uses the analytic one); with --joint: replicates "
                  "(cross-validated over the replicates, the joint fit's analytic WVIC beside it) or all (and the "
                  "joint fit's parametric-bootstrap WVIC, --replicates draws of every replicate per model)")
      ->check(CLI::IsMember({"analytic", "bootstrap", "both", "replicates", "all"}))
      ->capture_default_str();
  sub->add_option("--omega", args->omega,
                  "Omega shared by all models: model (diag 1 / V_jj, V model-based at a pilot fit of the maximal "
                  "model), full (V^-1, same V: chi-square scaled objective) or data (diag 1 / Var(nuhat_j) from the "
                  "data's WV alone)")
      ->check(CLI::IsMember({"model", "full", "data"}))
      ->capture_default_str();
  sub->add_option("--replicates", args->replicates, "Bootstrap replicates per model")
      ->type_name("B")
      ->transform(whole_number(2, 100000))
      ->capture_default_str();
  sub->add_option("--joint", args->joint,
                  "Replicates of INPUT's sensor (FILE: its columns of the same names; FILE:COLUMN: one column for "
                  "INPUT's single selected one): every sub-model ranked by its WVIC cross-validated over them")
      ->type_name("FILE[:COLUMN] ...")
      ->expected(1, -1);
  add_max_evaluations_option(*sub, args->max_evaluations);
  add_units_options(*sub, args->units);
  add_robust_options(*sub, args->robust);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_select(*args, common); }};
}

}  // namespace gmwm::cli
