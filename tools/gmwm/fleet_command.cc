// gmwm fleet MANIFEST --model SPEC [--csv PATH] [--json PATH] [--report PATH]
// Every recording of a manifest analysed the same way (the selection over SPEC with its
// noise figures, as gmwm select), one results table (docs/cli.md, "fleet"). Parses, checks
// every row of the manifest before any work, runs fleet::study_fleet, renders with
// report/fleet_output.h, commits.
#include <iostream>
#include <optional>
#include <utility>

#include "common.h"
#include "fleet_dask.h"
#include "gmwm/engine/error.h"
#include "gmwm/fleet/fleet_cache.h"
#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/fleet_manifest.h"
#include "gmwm/io/fleet_spec.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/report/fleet_output.h"
#include "gmwm/report/fleet_page.h"

namespace gmwm::cli {
namespace {

struct FleetArgs {
  std::string manifest;
  std::string model;
  std::string csv;
  double alpha = 0.05;
  int max_evaluations = FitOptions{}.max_evaluations;
  std::optional<double> memory_mb;
  std::optional<std::string> cache;  ///< --cache DIR; default: default_fleet_cache_dir
  bool no_cache = false;
  std::string scheduler;                              ///< --scheduler ADDRESS: a Dask cluster; empty: this machine
  std::string spec;                                   ///< --spec FILE: the datasheet limits per sensor model
  std::string gap_kalibr, gap_gazebo, gap_datasheet;  ///< --gap-kalibr FILE[:imuN], --gap-gazebo, --gap-datasheet
  int gap_replicates = fleet::FleetGapBaseline{}.replicates;
  bool joint = false;  ///< --joint: each group's axis's joint model
  int joint_draws = fleet::FleetStudyOptions::Joint{}.test_draws;
  std::string first_level = "auto";  ///< --first-level L|auto: the selection's and the gap diagnosis'
};

// The rate a gap baseline is checked at before any work when the manifest's first row gives
// none (the recordings' own rates are known only once read): any rate parses the same file.
constexpr double kNominalGapCheckRate = 100.0;

// The gap baseline of --gap-kalibr / --gap-gazebo / --gap-datasheet (at most one), read
// whole before any work and checked at the first recording's rate (or 100 Hz).
std::optional<fleet::FleetGapBaseline> gap_baseline(const FleetArgs& a, const io::FleetManifest& manifest,
                                                    const CommonOptions& common) {
  const int given = !a.gap_kalibr.empty() + !a.gap_gazebo.empty() + !a.gap_datasheet.empty();
  if (given == 0) return std::nullopt;
  if (given > 1) throw InputError("fleet: give one gap baseline: --gap-kalibr, --gap-gazebo or --gap-datasheet");
  const auto [option, format] = !a.gap_kalibr.empty()   ? std::pair{"--gap-kalibr", io::SimFormat::kKalibr}
                                : !a.gap_gazebo.empty() ? std::pair{"--gap-gazebo", io::SimFormat::kGzSensors}
                                                        : std::pair{"--gap-datasheet", io::SimFormat::kDatasheet};
  const auto [path, imu] = !a.gap_kalibr.empty()
                               ? kalibr_source(option, a.gap_kalibr)
                               : std::pair{!a.gap_gazebo.empty() ? a.gap_gazebo : a.gap_datasheet, std::string()};
  declare_input(common, path);
  const double freq = manifest.recordings.empty() || !manifest.recordings.front().rate
                          ? kNominalGapCheckRate
                          : *manifest.recordings.front().rate;
  try {
    return fleet::read_gap_baseline(format, path, imu, a.gap_replicates, freq);
  } catch (const InputError& e) {
    throw InputError(std::string(option) + " " + e.what());
  }
}

// The bad rows said at most (a manifest of a hundred thousand copied rows would otherwise
// bury the terminal); the count of all of them follows.
constexpr std::size_t kMaxRowsSaid = 100;

// The manifest's bad rows, one line each on stderr, before any work (exit 2); one bad row
// is one line, as every refusal (it was followed by a line counting it).
int refuse_rows(const std::vector<std::string>& problems) {
  if (problems.size() == 1) throw InputError(problems.front() + "; nothing analysed");
  for (std::size_t i = 0; i < problems.size() && i < kMaxRowsSaid; ++i)
    std::cerr << "gmwm: error: " << capped_line(printable_line(problems[i])) << '\n';
  if (problems.size() > kMaxRowsSaid)
    std::cerr << "gmwm: error: ... and " << problems.size() - kMaxRowsSaid << " more bad row(s)\n";
  std::cerr << "gmwm: error: " << problems.size() << " row(s) of the manifest refused; nothing analysed\n";
  return 2;
}

// Parse: the study's options from the arguments (the cache and the scheduler checked before
// any work; InputError naming the option).
fleet::FleetStudyOptions fleet_study_options(const FleetArgs& a, const CommonOptions& common) {
  fleet::FleetStudyOptions o;
  o.model = a.model;
  o.wv.alpha = a.alpha;
  o.select.fit.alpha = a.alpha;
  o.select.fit.seed = common.seed;
  o.select.fit.max_evaluations = a.max_evaluations;
  o.select.seed = common.seed;
  o.first_level = first_level_of(a.first_level);
  if (a.memory_mb) o.memory_budget = *a.memory_mb * 1e6;
  o.joint.enabled = a.joint;
  o.joint.test_draws = a.joint_draws;
  if (!a.no_cache) o.cache_dir = a.cache ? *a.cache : fleet::default_fleet_cache_dir(a.manifest);
  // A cache that cannot be one is refused before any work (a run that would have lost its
  // resumability in silence: the study's warning was below the default log level).
  try {
    fleet::check_fleet_cache_dir(o.cache_dir);
  } catch (const InputError& e) {
    throw InputError(std::string(a.cache ? "--cache " : "the default cache ") + e.what() +
                     (a.cache ? "" : "; give --cache DIR or --no-cache"));
  }
  if (!a.scheduler.empty()) {
    check_scheduler_address(a.scheduler);
    o.runner = dask_runner(a.scheduler);
  }
  if (const std::string why = o.Validate(); !why.empty()) throw InputError("fleet: " + why);
  return o;
}

// The rows that did not fit and the cache's entries not used, as many as the bad rows said at most.
void warn_about_fleet(const fleet::FleetStudy& study) {
  for (const fleet::FleetRow& r : study.rows)
    if (r.status != "ok")
      warn("unit '" + r.unit + "'" + (r.axis.empty() ? "" : ", axis '" + r.axis + "'") + ": " + r.status);
  for (std::size_t i = 0; i < study.cache_problems.size() && i < kMaxRowsSaid; ++i)
    warn("fleet cache: " + capped_line(study.cache_problems[i]));
  if (study.cache_problems.size() > kMaxRowsSaid)
    warn("fleet cache: ... and " + std::to_string(study.cache_problems.size() - kMaxRowsSaid) +
         " more entries not used (the JSON's \"cache_problems\" lists them)");
}

int run_fleet(const FleetArgs& a, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  fleet::FleetStudyOptions o = fleet_study_options(a, common);
  declare_input(common, a.manifest);
  declare_output(common, "--csv", a.csv);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  if (!a.spec.empty()) {
    declare_input(common, a.spec);
    o.spec = io::read_fleet_spec(a.spec);
  }
  const io::FleetManifest manifest = io::read_fleet_manifest(a.manifest);
  for (const io::FleetRecording& r : manifest.recordings) declare_input(common, r.path);
  o.gap = gap_baseline(a, manifest, common);
  if (const std::vector<std::string> problems = io::fleet_manifest_problems(manifest); !problems.empty())
    return refuse_rows(problems);

  ProgressBar bar("fleet: recordings", common);
  if (bar.enabled()) o.progress = [&bar](int done, int all) { bar.update(done, all); };
  const fleet::FleetStudy study = fleet::study_fleet(manifest, o);
  bar.finish();

  if (!a.csv.empty()) common.outputs->stage(a.csv, report::fleet_csv(study));
  emit(common, {report::fleet_document(study),
                {{"total", total.seconds()}},
                {},
                [&](const report::Json&) { return report::fleet_text(study, common.verbose); },
                [&] { report::stage_fleet_report(*common.outputs, common.report, study); }});
  warn_about_fleet(study);
  return 0;
}

}  // namespace

Command add_fleet_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<FleetArgs>();
  CLI::App* sub = app.add_subcommand(
      "fleet",
      "Every recording of a manifest (one row per unit) analysed the same way: one table of N, K, B and models");
  sub->add_option("MANIFEST", args->manifest,
                  "CSV (header path,unit,model[,topic,columns,units,rate,group]) or YAML list of the recordings")
      ->required();
  sub->add_option("--model", args->model, "The maximal model each axis's selection ranks the sub-models of")
      ->type_name("SPEC")
      ->required();
  sub->add_option("--csv", args->csv, "The results table: one row per unit x axis")->type_name("PATH");
  sub->add_option("--alpha", args->alpha, "1 - the intervals' level")
      ->transform(decimal_number([](double x) { return x > 0.0 && x < 1.0; }, "a number in (0, 1)"))
      ->capture_default_str();
  sub->add_option_function<double>(
         "--memory", [a = args.get()](const double& mb) { a->memory_mb = mb; },
         "Memory for one recording's samples, MB (beyond it they go on in temporary files)")
      ->type_name("MB")
      ->transform(memory_megabytes());
  sub->add_option_function<std::string>(
         "--cache", [a = args.get()](const std::string& dir) { a->cache = dir; },
         "Folder of the records already computed, by content and options (default: .gmwm-cache beside the "
         "manifest): a re-run computes only what is missing or changed")
      ->type_name("DIR");
  sub->add_option("--spec", args->spec,
                  "Datasheet limits per sensor model (a datasheet yaml per model, or one for all): each unit's N, K, B "
                  "checked against them (docs/fleet.md)")
      ->type_name("FILE");
  sub->add_option("--gap-kalibr", args->gap_kalibr,
                  "Diagnose each recording's gap against a simulator's Kalibr imu.yaml (FILE or FILE:imuN), as gmwm "
                  "gap does")
      ->type_name("FILE");
  sub->add_option("--gap-gazebo", args->gap_gazebo, "Diagnose each recording's gap against a Gazebo SDF's IMU noise")
      ->type_name("FILE");
  sub->add_option("--gap-datasheet", args->gap_datasheet, "Diagnose each recording's gap against a datasheet yaml")
      ->type_name("FILE");
  sub->add_option("--gap-replicates", args->gap_replicates,
                  "Reference replicates of each column's gap diagnosis (fewer: faster, coarser)")
      ->transform(whole_number(20, 100000))
      ->capture_default_str();
  sub->add_flag("--joint", args->joint,
                "Also each group's joint model per axis (its units as replicates): the selection over them, the "
                "shared-theta test, the typical unit's N, K, B");
  sub->add_option("--joint-draws", args->joint_draws,
                  "Bootstrap draws of the shared-theta test for groups of up to 12 units (beyond: chi-square)")
      ->transform(whole_number(19, 100000))
      ->capture_default_str();
  sub->add_flag("--no-cache", args->no_cache, "Neither read nor write cached records")->excludes("--cache");
  sub->add_option("--scheduler", args->scheduler,
                  "A Dask scheduler's address (tcp://HOST:8786): the recordings run as tasks on its workers, "
                  "through the gmwm Python module (docs/cli.md, \"fleet\")")
      ->type_name("ADDRESS");
  add_fitting_options(*sub, args->first_level, args->max_evaluations);  // the gap diagnosis' first level too
  add_report_option(*sub, common);
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_fleet(*args, common); }};
}

}  // namespace gmwm::cli
