// gmwm nav --truth SOURCE [--filter SOURCE]... [--trajectory static|constant-velocity|manoeuvre]
//          [--horizon S] [--fix-rate HZ] [--fix-sigma M] [--outage START:END]... [--imu-rate HZ]
//          [--rate HZ] [--units gyro=deg/s,accel=g] [--monte-carlo RUNS] [--output-interval S]
// What a noise model costs a navigation filter (docs/nav.md): the errors of an INS aided by
// position fixes when the IMU follows the truth model and the filter assumes each filter
// model, by covariance analysis (and Monte Carlo). Parses, runs pipeline::study_nav,
// renders with io/nav_output.h, commits.
#include <iostream>
#include <variant>

#include "common.h"
#include "gmwm/engine/error.h"
#include "gmwm/report/nav_output.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/nav_study.h"
#include "gmwm/engine/choice.h"

namespace gmwm::cli {
namespace {

struct NavArgs {
  std::string truth;
  std::vector<std::string> filters, labels;
  std::string trajectory = "static";
  double horizon = 600.0, fix_rate = 1.0, fix_sigma = 1.0, output_interval = 1.0, judge_from = 0.0;
  std::vector<std::string> outages;
  std::optional<double> imu_rate, rate;
  std::string units;
  int monte_carlo = 0;
};

nav::Outage parse_outage(const std::string& text) {
  const auto colon = text.find(':');
  const auto a = colon == std::string::npos ? std::nullopt : parse_decimal(text.substr(0, colon));
  const auto b = colon == std::string::npos ? std::nullopt : parse_decimal(text.substr(colon + 1));
  if (!a || !b || !(*a >= 0.0) || !(*b > *a))
    throw InputError("--outage '" + text + "': expected START:END in seconds with 0 <= START < END, e.g. 300:360");
  return {*a, *b};
}

// Every file nav reads (the models' sources: no output may be one of them) and writes,
// declared before any work.
void declare_nav_files(const NavArgs& args, const CommonOptions& common) {
  std::vector<std::string> sources = args.filters;
  sources.push_back(args.truth);
  for (const std::string& text : sources) {
    const pipeline::NavSource source = pipeline::parse_nav_source(text);
    if (const auto* file = std::get_if<pipeline::ModelFile>(&source.what)) declare_input(common, file->path);
  }
  declare_output(common, "--json", common.json);
  check_page_report_option(common);
}

// Parse: the study's options from the arguments (InputError naming the option).
pipeline::NavStudyOptions nav_study_options(const NavArgs& args, const CommonOptions& common) {
  pipeline::NavStudyOptions o;
  const auto trajectory = nav::parse_trajectory(args.trajectory);
  if (!trajectory) throw InputError("--trajectory: " + unknown_choice(args.trajectory, nav::trajectory_names()));
  o.scenario.trajectory = *trajectory;
  o.scenario.horizon = args.horizon;
  o.scenario.fix_rate = args.fix_rate;
  o.scenario.fix_sigma = args.fix_sigma;
  o.scenario.output_interval = args.output_interval;
  o.scenario.judge_from = args.judge_from;
  if (args.imu_rate) o.scenario.imu_rate = *args.imu_rate;
  for (const std::string& t : args.outages) o.scenario.outages.push_back(parse_outage(t));
  o.truth = pipeline::parse_nav_source(args.truth);
  for (const std::string& f : args.filters) o.filters.push_back(pipeline::parse_nav_source(f));
  o.labels = args.labels;
  o.rate = args.rate;
  if (!args.units.empty()) o.units = io::parse_declared_units(args.units);
  o.monte_carlo_runs = args.monte_carlo;
  o.seed = common.seed;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError("nav: " + why);
  return o;
}

int run_nav(const NavArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  declare_nav_files(args, common);
  pipeline::NavStudyOptions o = nav_study_options(args, common);
  ProgressBar bar("nav", common);
  if (bar.enabled())
    o.progress = [&](double share) {
      bar.update(share, 1.0);
      return true;
    };
  const pipeline::NavStudy study = pipeline::study_nav(o);
  bar.finish();
  return emit(common,
              {report::nav_document(study),
               {{"analysis", study.seconds_exact}, {"monte_carlo", study.seconds_sampled}, {"total", total.seconds()}},
               {},
               [&](const report::Json&) { return report::nav_terminal(study); },
               [&] { common.outputs->stage(common.report, report::render_nav_html(study)); }});
}

}  // namespace

Command add_nav_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<NavArgs>();
  CLI::App* sub = app.add_subcommand(
      "nav",
      "What a noise model costs a navigation filter: errors and consistency of each filter model against the truth");
  sub->add_option(
         "--truth", args->truth,
         "The IMU's noise: a gmwm fit/select --json result, a Kalibr or datasheet yaml, a gz-sensors/RotorS SDF, "
         "or gyro=SPEC;accel=SPEC with values")
      ->required()
      ->type_name("SOURCE");
  sub->add_option(
         "--filter", args->filters,
         "A model the filter assumes (repeatable): the same kinds, 'truth', 'wnrw' (the truth's white noise and "
         "random walk alone), each optionally '*X' (noise figures times X). Default: truth and wnrw")
      ->type_name("SOURCE");
  sub->add_option("--label", args->labels, "A name for each --filter, in order (repeatable; default: its SOURCE)")
      ->type_name("NAME");
  add_choice(*sub, "--trajectory", args->trajectory, nav::trajectory_names(), "The vehicle's motion");
  sub->add_option("--horizon", args->horizon, "Seconds analysed")
      ->transform(decimal_number([](double x) { return x > 0.0 && x <= 1e7; }, "a duration in seconds up to 1e7"))
      ->capture_default_str();
  sub->add_option("--fix-rate", args->fix_rate, "Position fixes per second (0: free inertial)")
      ->transform(decimal_number([](double x) { return x >= 0.0 && x <= 1e4; }, "a rate in Hz from 0 to 1e4"))
      ->capture_default_str();
  sub->add_option("--fix-sigma", args->fix_sigma, "A fix's error per axis, m (1 sigma)")
      ->transform(decimal_number([](double x) { return x > 0.0 && x <= 1e6; }, "a positive distance in m"))
      ->capture_default_str();
  sub->add_option("--outage", args->outages, "No fix in START:END seconds (repeatable)")->type_name("START:END");
  sub->add_option("--output-interval", args->output_interval, "Seconds between output times")
      ->transform(decimal_number([](double x) { return x > 0.0; }, "a positive duration in seconds"))
      ->capture_default_str();
  sub->add_option("--judge-from", args->judge_from,
                  "The NEES verdict counts the output times from S seconds on (a warm-up before is shown, not judged)")
      ->type_name("S")
      ->transform(decimal_number([](double x) { return x >= 0.0; }, "a time in seconds, 0 or more"))
      ->capture_default_str();
  sub->add_option("--imu-rate", args->imu_rate, "The IMU's rate, Hz (default: the truth's)")
      ->transform(sampling_rate_number());
  sub->add_option("--rate", args->rate,
                  "Hz at which model strings' and configuration files' values are given (default: the truth's rate)")
      ->transform(sampling_rate_number());
  sub->add_option(
      "--units", args->units,
      "Units of model strings and of results that do not say theirs, e.g. gyro=deg/s,accel=g (SI otherwise)");
  sub->add_option("--monte-carlo", args->monte_carlo, "Monte-Carlo runs as the analysis' check (0: none)")
      ->transform(whole_number(0, 100000))
      ->capture_default_str();
  add_common_options(*sub, common);
  sub->add_option("--report", common.report, "Write a self-contained HTML report with the error curves to PATH")
      ->type_name("PATH");
  return {sub, [args, &common] { return run_nav(*args, common); }};
}

}  // namespace gmwm::cli
