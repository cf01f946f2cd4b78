// gmwm fit INPUT --model SPEC [--robust [--eff E] [--estimator NAME]] [--omega model|diag|full|bootstrap]
//              [--replicates B] ...
// The GMWM fit of one model to the (classical or robust) WV of every selected column.

#include <cmath>
#include <iostream>
#include <sstream>

#include "common.h"
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
};

OmegaKind omega_kind(const std::string& s) { return parse_omega_kind(s).value_or(OmegaKind::kModel); }

std::string terminal_report(const io::SignalSet& set, std::size_t k, const WaveletVariance& w, const FitResult& r,
                            OmegaKind omega) {
  std::ostringstream os;
  const auto& s = set.signals[k];
  os << s.name << ": N = " << s.values.size() << ", " << fmt(set.freq) << " Hz, Omega " << to_string(omega);
  if (w.estimator != "classical")
    os << ", " << w.estimator << " WV (efficiency " << fmt(w.efficiency.value_or(1.0)) << ")";
  os << '\n';
  const bool has_theta = r.theta.size() == r.model.num_parameters() && r.theta.size() > 0 && r.theta.allFinite();
  os << "model: " << (has_theta ? r.model.to_string(r.theta) : r.model.to_string()) << '\n';
  if (has_theta) {
    Table t({"process", "component", "name", "value", "se", "CI low", "CI high", "interval"}, 1);
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
  if (const std::string why = rejection_summary(r, set.freq, set.freq_known); !why.empty())
    os << "fit quality: " << r.model.to_string() << " is " << why << '\n';
  if (const std::string why = degeneracy_summary(r); !why.empty()) os << "fit quality: " << why << '\n';
  return os.str();
}

std::string joint_report(const ReplicateGroup& g, const JointFitResult& r, const ReplicateTest* test,
                         const ReplicateBootstrap* boot, OmegaKind omega, const std::string& estimator) {
  std::ostringstream os;
  os << g.axis << ": joint fit of " << g.sources.size() << " replicates, Omega " << to_string(omega) << ", "
     << estimator << '\n';
  for (std::size_t k = 0; k < g.sources.size(); ++k)
    os << "  replicate " << k + 1 << ": " << g.sources[k] << ", N = " << g.series[k].size() << ", " << r.levels[k]
       << " levels"
       << (k < r.objective_share.size() ? ", its share of the objective " + fmt(r.objective_share[k], 4) : "")
       << ", own fit " << to_string(r.singles[k].status) << '\n';
  const FitResult& j = r.joint;
  const bool ok = j.theta.size() == j.model.num_parameters() && j.theta.size() > 0 && j.theta.allFinite();
  os << "model: " << (ok ? j.model.to_string(j.theta) : j.model.to_string()) << '\n';
  if (ok) {
    std::vector<std::string> header = {"process", "component", "name",      "joint", "se",      "CI low",
                                       "CI high", "boot low",  "boot high", "AGMWM", "AGMWM se"};
    for (std::size_t k = 0; k < r.singles.size(); ++k) header.push_back("replicate " + std::to_string(k + 1));
    Table t(header, 1);
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
  const std::string estimator = replicate_estimator_text(robust);
  std::string report = report::axis_summary(doc) + "\n";
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const JointAnalysis& a = study.groups[i].analysis;
    report += (i ? "\n" : "") +
              joint_report(groups[i], a.fit, a.test ? &*a.test : nullptr, a.bootstrap ? &*a.bootstrap : nullptr,
                           options.omega, estimator) +
              joint_physical_tables(groups[i], set, a.fit.joint, study.groups[i].figures, args.units, filter);
  }
  write_json(common, doc, {.threads = 0, .seconds = {{"total", total.seconds()}}, .argv = {}});
  if (!common.report.empty()) {
    report::ReportData rep = report_data("fit", set, args.model);
    for (std::size_t i = 0; i < groups.size(); ++i)
      fill_joint_report_column(rep.columns[i], groups[i], study.groups[i].wvs, study.groups[i].analysis, estimator);
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) print_text(report);
  for (std::size_t i = 0; i < groups.size(); ++i)
    if (const FitResult& j = study.groups[i].analysis.fit.joint; j.status == FitStatus::kFailed) {
      std::cerr << "gmwm: error: " << printable_line("the joint fit of '" + groups[i].axis + "' failed: " + j.message)
                << '\n';
      return 1;
    }
  return 0;
}

int run_fit(const FitArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const WvOptions wv_opts = wv_options(args.input);
  const auto robust_options = robust_wv_options(args.robust, wv_opts);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_report_option(common);

  FitOptions options;
  options.omega = omega_kind(args.omega);
  options.alpha = args.input.alpha;
  options.bootstrap_replicates = args.replicates;
  options.seed = common.seed;
  options.max_evaluations = args.max_evaluations;
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  if (!args.joint.empty()) {
    if (options.omega == OmegaKind::kBootstrap)
      throw InputError(
          "--joint with --omega bootstrap: the joint fit takes --omega model (or diag, the same there) or full");
    return run_joint_fit(args, common, options, robust_options ? &*robust_options : nullptr);
  }

  // With --freq the model can be checked before reading a long file.
  if (args.input.freq) {
    if (const std::string why = io::sampling_rate_problem(*args.input.freq, "--freq"); !why.empty())
      throw InputError(why);
    parse_model(args.model, ProcessContext{*args.input.freq, true});
  }

  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  pipeline::FitStudyOptions study_options;
  study_options.model = args.model;
  study_options.fit = options;
  study_options.wv = wv_opts;
  study_options.robust = robust_options;
  const pipeline::FitStudy study = pipeline::study_fit(set, study_options);
  std::vector<std::string> units;
  for (const auto& s : set.signals) units.push_back(column_unit(args.units, s.name));

  // Everything is computed: build the outputs, then write them.
  report::Json doc = report::fit_document(set, study, units, filter_rate(args.units, set));
  const double filter = filter_rate(args.units, set);
  std::string report;
  if (common.show_table()) {
    if (set.timing) report += set.timing->summary() + "\n";
    report += report::axis_summary(doc);
    for (std::size_t k = 0; common.verbose && k < study.columns.size(); ++k) {
      const pipeline::FitColumnStudy& c = study.columns[k];
      const report::ColumnInfo info = with_unit(column_info(set, k), args.units);
      const ChosenFigures* chosen = c.figures ? &c.figures->chosen : nullptr;
      report += "\n" + terminal_report(set, k, c.wv, c.fit, options.omega) + continuous_table(c.fit, info) +
                (chosen ? noise_figures_table(*chosen, units[k]) : "") + kalman_table(c.fit, info, filter, chosen);
    }
    if (!common.verbose) report += kDetailsHint;
  }

  warn_about_timing(set);
  int usable = 0;
  for (const pipeline::FitColumnStudy& c : study.columns) {
    const FitResult& r = c.fit;
    if (r.status == FitStatus::kNotConverged)
      warn("column '" + c.name + "': the fit did not converge" + (r.message.empty() ? "" : ": " + r.message));
    else if (r.status == FitStatus::kFailed)
      warn("column '" + c.name + "': the fit failed" + (r.message.empty() ? "" : ": " + r.message));
    if (r.status != FitStatus::kFailed) ++usable;
  }
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds},
                          {"wv", study.wv_seconds},
                          {"allan", study.allan_seconds},
                          {"fit", study.fit_seconds},
                          {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty() && usable > 0) {
    report::ReportData rep = report_data("fit", set, args.model);
    for (std::size_t k = 0; k < study.columns.size(); ++k) {
      const pipeline::FitColumnStudy& c = study.columns[k];
      rep.columns[k].wvs =
          c.classical ? std::vector<WaveletVariance>{c.wv, *c.classical} : std::vector<WaveletVariance>{c.wv};
      rep.columns[k].fit = c.fit;
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
  if (usable == 0) {
    std::cerr << "gmwm: error: no usable fit (every column failed)\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command add_fit_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<FitArgs>();
  CLI::App* sub = app.add_subcommand("fit", "GMWM fit of a latent model (e.g. AR1+WN+RW) to the WV of each column");
  add_input_options(*sub, args->input);
  sub->add_option("--model", args->model,
                  "Model, e.g. '2*AR1+WN+RW' or 'AR1(phi=0.99)+WN' (values are starting values)")
      ->type_name("SPEC")
      ->required();
  sub->add_option("--omega", args->omega,
                  "Weighting matrix: model (1 / Var(nuhat_j) of the model at a pilot fit; the data-only weights "
                  "bias long-memory terms low), diag (data only), full (the model's V^-1) or bootstrap")
      ->check(CLI::IsMember({"model", "diag", "full", "bootstrap"}))
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
  add_max_evaluations_option(*sub, args->max_evaluations);
  add_units_options(*sub, args->units);
  add_robust_options(*sub, args->robust);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_fit(*args, common); }};
}

}  // namespace gmwm::cli
