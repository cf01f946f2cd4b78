// gmwm fit INPUT --model SPEC [--robust [--eff E] [--estimator NAME]] [--omega model|diag|full|bootstrap]
//              [--replicates B] ...
// The GMWM fit of one model to the (classical or robust) WV of every selected column.

#include <cmath>
#include <iostream>
#include <sstream>

#include "common.h"
#include "curve_fit.h"
#include "replicates.h"
#include "units_tables.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/pipeline/fit_study.h"

namespace gmwm::cli {

namespace {

struct FitArgs {
  InputOptions input;
  RobustOptions robust;
  std::string model;
  std::string omega = "model";
  int replicates = FitOptions{}.bootstrap_replicates;
  int max_evaluations = FitOptions{}.max_evaluations;
  UnitsOptions units;
  std::vector<std::string> joint;  ///< --joint FILE[:COLUMN] ...: replicates of INPUT's columns
  std::string first_level = "1";   ///< --first-level L|auto (pipeline::parse_first_level)
  CurveArgs curve;                 ///< --curve FILE and its options: a given curve instead of INPUT
  const CLI::App* command = nullptr;
};

OmegaKind omega_kind(const std::string& s) { return parse_omega_kind(s).value_or(OmegaKind::kModel); }

int run_joint_fit(const FitArgs& args, const CommonOptions& common, const FitOptions& options,
                  const robust::RobustWvOptions* robust) {
  Stopwatch total;
  for (const auto& e : args.joint) declare_input(common, replicate_path(e));
  const WvOptions wv_opts = wv_options(args.input);
  const io::SignalSet set = read_input(args.input);
  const std::vector<ReplicateGroup> groups = read_replicates(set, args.joint, args.input);
  // The declared units (a bad --units fails here, before any work) and the Kalman rate.
  std::vector<std::string> units;
  for (const ReplicateGroup& g : groups) units.push_back(column_unit(args.units, g.axis));
  const double filter = filter_rate(args.units, set);
  pipeline::JointFitStudyOptions o;
  o.model = args.model;
  o.fit = options;
  o.wv = wv_opts;
  if (robust) o.robust = *robust;
  o.test_draws = args.replicates;
  o.seed = common.seed;
  // Progress on a terminal: the shared-theta test's bootstrap draws (each a joint refit).
  ProgressBar bar("fit --joint: bootstrap draws", common);
  if (bar.enabled()) o.progress = [&](int done, int draws) { bar.update(done, draws); };
  const pipeline::JointFitStudy study = pipeline::study_joint_fit(groups, ProcessContext{set.freq, set.freq_known}, o);
  bar.finish();

  report::Json doc = report::joint_fit_document(set, groups, study, units, filter);
  const std::string estimator = report::replicate_estimator_text(o.robust);
  write_json(common, doc, {.threads = 0, .seconds = {{"total", total.seconds()}}, .argv = {}});
  if (!common.report.empty()) write_report(common, report::joint_fit_report_data(set, groups, study, estimator));
  commit_outputs(common);
  if (common.show_table())
    print_text(report::joint_fit_text(doc, set, groups, study, estimator, {units, filter, common.verbose}));
  for (std::size_t i = 0; i < groups.size(); ++i)
    if (const FitResult& j = study.groups[i].analysis.fit.joint; j.status == FitStatus::kFailed) {
      std::cerr << "gmwm: error: " << printable_line("the joint fit of '" + groups[i].axis + "' failed: " + j.message)
                << '\n';
      return 1;
    }
  return 0;
}

// The fit's settings from the options (InputError naming the option when invalid).
FitOptions fit_options(const FitArgs& args, const CommonOptions& common) {
  FitOptions options;
  options.omega = omega_kind(args.omega);
  options.alpha = args.input.alpha;
  options.bootstrap_replicates = args.replicates;
  options.seed = common.seed;
  options.max_evaluations = args.max_evaluations;
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  return options;
}

// Warns about every column whose fit did not converge or failed; the number usable.
int warn_about_fits(const pipeline::FitStudy& study) {
  int usable = 0;
  for (const pipeline::FitColumnStudy& c : study.columns) {
    const FitResult& r = c.fit;
    if (r.status == FitStatus::kNotConverged)
      warn("column '" + c.name + "': the fit did not converge" + (r.message.empty() ? "" : ": " + r.message));
    else if (r.status == FitStatus::kFailed)
      warn("column '" + c.name + "': the fit failed" + (r.message.empty() ? "" : ": " + r.message));
    if (r.status != FitStatus::kFailed) ++usable;
  }
  return usable;
}

// Parse: the study's options from the arguments, every input and output declared first.
pipeline::FitStudyOptions fit_study_options(const FitArgs& args, const CommonOptions& common) {
  pipeline::FitStudyOptions o;
  o.model = args.model;
  o.wv = wv_options(args.input);
  o.robust = robust_wv_options(args.robust, o.wv);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  o.fit = fit_options(args, common);
  o.first_level = first_level_of(args.first_level);
  if (!args.joint.empty() && o.first_level != 1)
    throw InputError("--joint with --first-level: the joint fit takes every level of each replicate");
  if (!args.joint.empty() && o.fit.omega == OmegaKind::kBootstrap)
    throw InputError(
        "--joint with --omega bootstrap: the joint fit takes --omega model (or diag, the same there) or full");
  return o;
}

// One part's fit (the record, or a topic of --topic A,B): its study, warnings and rendering.
struct FitPart {
  Outcome outcome;
  int usable = 0;  ///< the columns whose fit did not fail
};

FitPart fit_part(const FitArgs& args, const CommonOptions& common, const pipeline::FitStudyOptions& options,
                 const io::SignalSet& set, double read_seconds) {
  auto study = std::make_shared<const pipeline::FitStudy>(pipeline::study_fit(set, options));
  const std::vector<std::string> units = column_units(args.units, set);
  const double filter = filter_rate(args.units, set);
  warn_about_timing(set);
  FitPart part;
  part.usable = warn_about_fits(*study);
  std::function<report::ReportData()> report_data;  // none when every fit failed
  if (part.usable > 0)
    report_data = [&set, study, model = args.model, units, filter] {
      return report::fit_report_data(set, *study, model, units, filter);
    };
  part.outcome = {
      report::fit_document(set, *study, units, filter),
      {{"read", read_seconds}, {"wv", study->wv_seconds}, {"allan", study->allan_seconds}, {"fit", study->fit_seconds}},
      report_data,
      [&set, study, units, filter, verbose = common.verbose](const report::Json& doc) {
        return report::fit_text(doc, set, *study, {units, filter, verbose});
      }};
  return part;
}

int run_fit(const FitArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  if (!args.curve.curve.empty())
    return run_curve_fit(*args.command, args.curve,
                         {args.model, args.omega, args.input.alpha, args.max_evaluations, args.input.freq,
                          args.input.columns, args.units},
                         common);
  if (args.input.input.empty()) throw InputError("INPUT is required (a record to fit, or --curve FILE)");
  const pipeline::FitStudyOptions study_options = fit_study_options(args, common);
  if (!args.joint.empty())
    return run_joint_fit(args, common, study_options.fit, study_options.robust ? &*study_options.robust : nullptr);
  check_models_before_reading(args.input, {study_options.model});

  Stopwatch read_clock;
  const std::vector<io::RecordPart> parts = read_parts(args.input);
  const double read_seconds = read_clock.seconds() / static_cast<double>(parts.size());
  std::vector<Outcome> outcomes;
  int failed_parts = 0;
  for (const io::RecordPart& p : parts) {
    FitPart part = fit_part(args, common, study_options, p.set, read_seconds);
    outcomes.push_back(std::move(part.outcome));
    failed_parts += part.usable == 0;
  }
  Outcome outcome = merge_parts(parts, std::move(outcomes));
  outcome.seconds["total"] = total.seconds();
  emit(common, std::move(outcome));
  if (failed_parts > 0) {
    std::cerr << "gmwm: error: no usable fit (every column" << (parts.size() > 1 ? " of a topic" : "") << " failed)\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command add_fit_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<FitArgs>();
  CLI::App* sub = app.add_subcommand("fit", "GMWM fit of a latent model (e.g. AR1+WN+RW) to the WV of each column");
  add_input_options(*sub, args->input);
  sub->get_option("INPUT")->required(false);  // not with --curve: run_fit asks for one of the two
  args->command = sub;
  sub->add_option("--model", args->model,
                  "Model, e.g. '2*AR1+WN+RW' or 'AR1(phi=0.99)+WN' (values are starting values)")
      ->type_name("SPEC")
      ->required();
  sub->add_option("--omega", args->omega,
                  "Weighting matrix: model (1 / Var(nuhat_j) of the model at a pilot fit; the data-only weights "
                  "bias long-memory terms low), diag (data only), full (the model's V^-1) or bootstrap")
      ->check(choice_of(omega_kind_names()))
      ->capture_default_str();
  sub->add_option("--replicates", args->replicates,
                  "Bootstrap replicates for --omega bootstrap, and for the shared-theta test with --joint")
      ->type_name("B")
      ->transform(whole_number(2, 1000000))
      ->capture_default_str();
  sub->add_option("--joint", args->joint,
                  "Replicates of INPUT's sensor, fitted jointly with it (multi-signal GMWM): FILE adds that "
                  "file's columns of the same names (one joint model per axis), FILE:COLUMN one column as a "
                  "replicate of INPUT's single selected column")
      ->type_name("FILE[:COLUMN] ...")
      ->expected(1, -1);
  add_fitting_options(*sub, args->first_level, args->max_evaluations);
  add_units_options(*sub, args->units);
  add_robust_options(*sub, args->robust);
  add_curve_options(*sub, args->curve);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_fit(*args, common); }};
}

}  // namespace gmwm::cli
