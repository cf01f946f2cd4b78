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
  std::string first_level = "1";   ///< --first-level L|auto
};

// Selection over replicates: per axis, every sub-model of the maximal model ranked by its
// cross-validated WVIC over the replicates, the analytic WVIC of the joint fit beside it,
// the equivalent models and the recommended one.
// The shared-theta test in a report needs at least this many draws (ReplicateTestOptions).
constexpr int kMinReportTestDraws = 19;

// What a selection over replicates does not take (InputError naming the option).
void check_joint_select_options(const SelectArgs& args) {
  if (args.model.empty() || !args.models.empty())
    throw InputError("--joint: give the maximal model with --model SPEC (not --models)");
  if (args.penalty == "bic")
    throw InputError("--joint with --penalty bic: the selection over replicates ranks by the cross-validated WVIC");
  if (args.optimism == "bootstrap" || args.optimism == "both")
    throw InputError("--joint with --optimism " + args.optimism +
                     ": the selection over replicates ranks by the cross-validated WVIC; --optimism all gives the "
                     "analytic and bootstrap WVIC of the joint fit beside it");
}

int run_joint_select(const SelectArgs& args, const CommonOptions& common, const selection::SelectOptions& options,
                     const robust::RobustWvOptions* robust) {
  Stopwatch total;
  check_joint_select_options(args);
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
  const std::string estimator = report::replicate_estimator_text(o.robust);
  return emit(common,
              {report::joint_select_document(set, groups, study, units, filter),
               {{"total", total.seconds()}},
               [&] { return report::joint_select_report_data(set, groups, study, estimator); },
               [&](const report::Json& doc) {
                 return report::joint_select_text(doc, set, groups, study, estimator, {units, filter, common.verbose});
               }});
}

// The study's warnings: repeated entries of --models (one line), failed best fits.
void warn_about_selection(const pipeline::SelectStudy& study) {
  if (!study.duplicates.empty()) {
    // One line: a list of thousands of copies would otherwise bury the terminal.
    constexpr std::size_t kSaid = 3;  // the entries named; the count says the rest
    std::string which;
    for (std::size_t i = 0; i < study.duplicates.size() && i < kSaid; ++i)
      which += (i ? "; " : "") + study.duplicates[i];
    if (study.duplicates.size() > kSaid) which += "; and " + std::to_string(study.duplicates.size() - kSaid) + " more";
    warn(capped_line("--models: " + std::to_string(study.duplicates.size()) + " entr" +
                     (study.duplicates.size() == 1 ? "y repeats" : "ies repeat") + " an earlier entry's model and " +
                     (study.duplicates.size() == 1 ? "was" : "were") +
                     " dropped (each model is ranked once): " + which));
  }
  for (const pipeline::SelectColumnStudy& c : study.columns)
    if (c.selection.best_fit.status == FitStatus::kFailed)
      warn("column '" + c.name + "': the best model's fit with inference failed");
}

// --optimism's names: a single recording's, then the replicates' (with --joint).
std::vector<std::string> select_optimism_names() {
  std::vector<std::string> names = selection::optimism_method_names();
  for (std::string& n : pipeline::replicate_optimism_names()) names.push_back(std::move(n));
  return names;
}

// The selection's settings from the options (InputError naming the option when invalid).
selection::SelectOptions select_options(const SelectArgs& args, const CommonOptions& common) {
  selection::SelectOptions options;
  const std::vector<std::string> joint = pipeline::replicate_optimism_names();
  const bool by_replicates = std::find(joint.begin(), joint.end(), args.optimism) != joint.end();
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
  return options;
}

// Parse: the study's options from the arguments (the models aside), every input and output
// declared first.
pipeline::SelectStudyOptions select_study_options(const SelectArgs& args, const CommonOptions& common) {
  pipeline::SelectStudyOptions o;
  o.wv = wv_options(args.input);
  o.robust = robust_wv_options(args.robust, o.wv);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  o.select = select_options(args, common);
  o.first_level = first_level_of(args.first_level);
  if (!args.joint.empty() && o.first_level != 1)
    throw InputError("--joint with --first-level: the joint selection takes every level of each replicate");
  return o;
}

// One part's selection (the record, or a topic of --topic A,B): its study, warnings and rendering.
Outcome select_part(const SelectArgs& args, const CommonOptions& common, pipeline::SelectStudyOptions options,
                    const io::SignalSet& set, double read_seconds) {
  // Progress on a terminal: models done / total (bootstrap refits included), time left.
  ProgressBar bar("select: models", common);
  if (bar.enabled()) options.select.progress = [&](int done, int total_models) { bar.update(done, total_models); };
  auto study = std::make_shared<const pipeline::SelectStudy>(pipeline::study_select(set, options));
  bar.finish();
  const std::vector<std::string> units = column_units(args.units, set);
  const double filter = filter_rate(args.units, set);
  warn_about_timing(set);
  warn_about_selection(*study);
  const std::string models = args.models.empty() ? args.model : args.models;
  return {
      report::select_document(set, *study, units, filter),
      {{"read", read_seconds},
       {"wv", study->wv_seconds},
       {"allan", study->allan_seconds},
       {"select", study->select_seconds}},
      [&set, study, models, units, filter] { return report::select_report_data(set, *study, models, units, filter); },
      [&set, study, units, filter, verbose = common.verbose](const report::Json& doc) {
        return report::select_text(doc, set, *study, {units, filter, verbose});
      }};
}

int run_select(const SelectArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  pipeline::SelectStudyOptions study_options = select_study_options(args, common);
  if (!args.joint.empty())
    return run_joint_select(args, common, study_options.select,
                            study_options.robust ? &*study_options.robust : nullptr);
  pipeline::set_select_models(study_options, args.model, args.models);
  check_models_before_reading(args.input, study_options.models);

  Stopwatch read_clock;
  const std::vector<io::RecordPart> parts = read_parts(args.input);
  const double read_seconds = read_clock.seconds() / static_cast<double>(parts.size());
  std::vector<Outcome> outcomes;
  for (const io::RecordPart& p : parts)
    outcomes.push_back(select_part(args, common, study_options, p.set, read_seconds));
  Outcome outcome = merge_parts(parts, std::move(outcomes));
  outcome.seconds["total"] = total.seconds();
  return emit(common, std::move(outcome));
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
      ->check(choice_of(selection::penalty_names()))
      ->capture_default_str();
  sub->add_option("--optimism", args->optimism,
                  "Optimism of the WVIC: analytic (delta method), bootstrap (parametric, --replicates per model) "
                  "or both side by side (the criterion uses the analytic one); with --joint: replicates "
                  "(cross-validated over the replicates, the joint fit's analytic WVIC beside it) or all (and the "
                  "joint fit's parametric-bootstrap WVIC, --replicates draws of every replicate per model)")
      ->check(choice_of(select_optimism_names()))
      ->capture_default_str();
  sub->add_option("--omega", args->omega,
                  "Omega shared by all models: model (diag 1 / V_jj, V model-based at a pilot fit of the maximal "
                  "model), full (V^-1, same V: chi-square scaled objective) or data (diag 1 / Var(nuhat_j) from the "
                  "data's WV alone)")
      ->check(choice_of(selection::omega_source_names()))
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
  add_fitting_options(*sub, args->first_level, args->max_evaluations);
  add_units_options(*sub, args->units);
  add_robust_options(*sub, args->robust);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_select(*args, common); }};
}

}  // namespace gmwm::cli
