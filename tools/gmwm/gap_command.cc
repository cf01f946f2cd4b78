// gmwm gap INPUT (--model SPEC_WITH_VALUES | --kalibr imu.yaml | --gazebo FILE.sdf | --datasheet FILE.yaml | --fit SPEC)
//              [--units gyro=deg/s,accel=g] [--sensor gyro|accel] [--replicates B]
// Where a simulator's (or a fitted) noise model departs from each column's WV, which
// unmodelled effect explains it, and how much of the gap it removes (docs/gap.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <iostream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include "common.h"
#include "units_tables.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/pipeline/corrected_config.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/engine/physical.h"
#include "gmwm/gap/cross_axis.h"
#include "gmwm/gap/gap.h"
#include "gmwm/pipeline/gap_study.h"

namespace gmwm::cli {
namespace {

struct GapArgs {
  InputOptions input;
  std::string model;        ///< --model SPEC_WITH_VALUES
  std::string kalibr;       ///< --kalibr imu.yaml
  std::string gazebo;       ///< --gazebo FILE.sdf (gz-sensors <noise> blocks or a RotorS/PX4 IMU plugin)
  std::string fit;          ///< --fit SPEC
  std::string datasheet;    ///< --datasheet FILE.yaml (figures in the datasheet's units)
  std::string units;        ///< --units gyro=deg/s,accel=g
  std::string sensor;       ///< --sensor gyro|accel (all columns)
  std::string temperature;  ///< --temperature COLUMN
  int replicates = gap::GapOptions{}.replicates;
  std::string effects;  ///< --effects WN,DR,...: the candidates tried (empty: all)
  double min_effect = gap::GapOptions{}.min_effect;
  int max_steps = gap::GapOptions{}.max_steps;
  bool no_unit_check = false;        ///< --no-unit-check
  std::string corrected;             ///< --corrected PATH
  std::string first_level = "auto";  ///< --first-level L|auto (pipeline::parse_first_level)
};

// The study's settings but the baseline (InputError naming the option when invalid).
pipeline::GapStudyOptions gap_study_options(const GapArgs& args, const CommonOptions& common) {
  const int given =
      !args.model.empty() + !args.kalibr.empty() + !args.gazebo.empty() + !args.fit.empty() + !args.datasheet.empty();
  if (given != 1)
    throw InputError(
        "gap: give exactly one baseline: --model SPEC_WITH_VALUES, --kalibr imu.yaml, --gazebo FILE.sdf, "
        "--datasheet FILE.yaml or --fit SPEC");
  pipeline::GapStudyOptions options;
  options.wv = wv_options(args.input);
  options.units = io::parse_units(args.units);
  options.units_declared = !args.units.empty();
  if (!args.sensor.empty()) options.sensor = args.sensor == "gyro" ? io::SensorKind::kGyro : io::SensorKind::kAccel;
  options.temperature_column = args.temperature;
  options.unit_check = !args.no_unit_check;
  options.first_level = first_level_of(args.first_level);
  options.gap.replicates = args.replicates;
  options.gap.seed = common.seed;
  options.gap.alpha = args.input.alpha;
  options.gap.min_effect = args.min_effect;
  options.gap.max_steps = args.max_steps;
  if (!args.effects.empty()) options.gap.candidates = gap::parse_gap_candidates(args.effects, "--effects");
  if (!args.model.empty()) options.baseline = pipeline::ModelBaseline{args.model};
  if (!args.fit.empty()) options.baseline = pipeline::FitBaseline{args.fit};
  return options;
}

// The baseline of --kalibr, --gazebo or --datasheet, read at the data's rate; a side file's
// refusal names its option too ("--kalibr imu.yaml:3: ..."). Nothing for --model and --fit.
void read_baseline_file(const GapArgs& args, const io::SignalSet& set, pipeline::GapStudyOptions& options) {
  auto named = [](const char* option, const auto& read) {
    try {
      return read();
    } catch (const InputError& e) {
      throw InputError(std::string(option) + " " + e.what());
    }
  };
  if (!args.kalibr.empty()) {
    const auto [path, imu] = kalibr_source("--kalibr", args.kalibr);
    options.baseline = pipeline::ConfigBaseline{
        named("--kalibr", [&] { return io::read_kalibr_imu_yaml(path, set.freq, options.units, imu); }), path};
  }
  if (!args.gazebo.empty())
    options.baseline = pipeline::ConfigBaseline{
        named("--gazebo", [&] { return io::read_gazebo_sdf(args.gazebo, set.freq, options.units); }), args.gazebo};
  if (!args.datasheet.empty())
    options.baseline = pipeline::ConfigBaseline{
        named("--datasheet", [&] { return io::read_datasheet_yaml(args.datasheet, set.freq, options.units); }),
        args.datasheet};
}

// Every file gap reads and writes, declared before any work; the Kalibr file's path.
std::string declare_gap_files(const GapArgs& args, const CommonOptions& common) {
  declare_input(common, args.input.input);
  const std::string kalibr_path = kalibr_source("--kalibr", args.kalibr).first;
  declare_input(common, kalibr_path);
  declare_input(common, args.gazebo);
  declare_input(common, args.datasheet);
  declare_output(common, "--json", common.json);
  declare_output(common, "--corrected", args.corrected);
  check_report_option(common);
  return kalibr_path;
}

int run_gap(const GapArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const std::string kalibr_path = declare_gap_files(args, common);
  pipeline::GapStudyOptions options = gap_study_options(args, common);

  Stopwatch read_clock;
  io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  read_baseline_file(args, set, options);
  // The file a baseline came from ("" for --model and --fit).
  const std::string baseline_file = !args.kalibr.empty()   ? kalibr_path
                                    : !args.gazebo.empty() ? args.gazebo
                                                           : args.datasheet;
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("gap: " + why);
  // Progress on a terminal: per column, its reference replicates and then its attribution.
  ProgressBar bar("gap: columns x steps", common);
  if (bar.enabled()) options.progress = [&bar](double done, double all) { bar.update(done, all); };
  const pipeline::GapStudy study = pipeline::study_gap(set, options);

  // The corrected configuration (docs/gap.md): in the JSON and the table always, in a file with --corrected.
  const std::optional<pipeline::CorrectedConfig> corrected = pipeline::corrected_config(
      set, study, options, {options.units, options.sensor, baseline_file, args.input.columns.has_value()});
  if (!args.corrected.empty()) common.outputs->stage(args.corrected, corrected->content);
  report::Json doc = report::gap_document(set, study);
  if (corrected) doc["corrected"] = report::corrected_config_json(*corrected, set.freq_known ? set.freq : 0.0);
  warn_about_timing(set);
  const std::string baseline = !args.model.empty() ? args.model : !args.fit.empty() ? "fit " + args.fit : baseline_file;
  return emit(
      common,
      {std::move(doc),
       {{"read", read_seconds}, {"wv", study.wv_seconds}, {"gap", study.gap_seconds}, {"total", total.seconds()}},
       [&] { return report::gap_report_data(set, study, baseline, corrected); },
       [&](const report::Json&) { return report::gap_text(set, study, corrected, common.verbose); }});
}

}  // namespace

// What the comparison with the baseline takes: the effect size, the stepwise limit, the unit
// check and the first level compared.
void add_comparison_options(CLI::App& sub, GapArgs& a) {
  sub.add_option("--min-effect", a.min_effect,
                 "Practical effect size of a gap band: a level departs only when its WV is off by more than this "
                 "fraction (docs/gap.md)")
      ->type_name("X")
      ->transform(decimal_number([](double x) { return x >= 0.0 && x < 10.0; }, "a fraction from 0 to 10"))
      ->capture_default_str();
  sub.add_option("--max-steps", a.max_steps, "The most effects the forward-stepwise attribution adds")
      ->type_name("N")
      ->transform(whole_number(0, 20))
      ->capture_default_str();
  sub.add_flag("--no-unit-check", a.no_unit_check,
               "Diagnose even when a column's finest scales sit at a unit factor ((180/pi)^2, 9.80665^2, ...) "
               "from the baseline");
  add_first_level_option(sub, a.first_level,
                         "Compare the WV with the baseline from this level on (tau = 2^L samples), the finer levels "
                         "shown, not compared");
}

Command add_gap_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<GapArgs>();
  CLI::App* sub = app.add_subcommand(
      "gap",
      "Where a simulator's or fitted noise model departs from each column, which effect explains it, and by how much");
  add_input_options(*sub, args->input);
  auto* m =
      sub->add_option("--model", args->model, "Baseline with every value, e.g. 'WN(sigma2=2.5e-5)+RW(gamma2=1e-12)'")
          ->type_name("SPEC_WITH_VALUES");
  auto* k = sub->add_option("--kalibr", args->kalibr,
                            "Baseline from a Kalibr imu.yaml (noise densities and random walks); "
                            "FILE:imuN takes one IMU of a chain (imu0, imu1, ...)")
                ->type_name("imu.yaml[:imuN]");
  auto* z = sub->add_option("--gazebo", args->gazebo,
                            "Baseline from a Gazebo SDF: gz-sensors IMU <noise> blocks or RotorS/PX4 IMU plugin "
                            "parameters")
                ->type_name("FILE.sdf");
  auto* d = sub->add_option("--datasheet", args->datasheet,
                            "Baseline from a datasheet's figures in its own units (YAML: gyroscope/accelerometer "
                            "noise_density or angle/velocity random walk, bias_instability or in_run_bias_stability "
                            "with an optional bias_correlation_time, rate/acceleration random walk; docs/gap.md)")
                ->type_name("FILE.yaml");
  auto* f = sub->add_option("--fit", args->fit, "Fit this family on each column first, then diagnose what it lacks")
                ->type_name("SPEC");
  m->excludes(k)->excludes(z)->excludes(d)->excludes(f);
  k->excludes(z)->excludes(d)->excludes(f);
  z->excludes(d)->excludes(f);
  d->excludes(f);
  sub->add_option("--units", args->units, "Units of the columns, e.g. gyro=deg/s,accel=g (SI by default)")
      ->type_name("KIND=UNIT,...");
  sub->add_option("--sensor", args->sensor, "Treat every column as this sensor (else told by its name)")
      ->check(choice_of(io::sensor_kind_names()));
  sub->add_option(
         "--temperature", args->temperature,
         "A temperature column: each signal's coupling to it is tested (TEMPERATURE); it is not diagnosed itself")
      ->type_name("COLUMN");
  sub->add_option("--replicates", args->replicates, "Reference replicates (parametric bootstrap of the baseline)")
      ->type_name("B")
      ->transform(whole_number(20, 100000))
      ->capture_default_str();
  sub->add_option("--corrected", args->corrected,
                  "Write the corrected simulator configuration to PATH in the baseline's own format (Kalibr yaml, "
                  "gz-sensors SDF, RotorS plugin, or one model string per column), with a header of what changed, "
                  "why, and what the format cannot express")
      ->type_name("PATH");
  sub->add_option(
         "--effects", args->effects,
         "The effects the attribution may add, e.g. DR,AR1 (default: all of WN, QN, RW, DR, AR1, FLICKER, SIN, "
         "REPARAMETERISE; OUTLIERS, STEP, TRANSIENT and TEMPERATURE are tested on the series itself)")
      ->type_name("LIST");
  add_comparison_options(*sub, *args);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_gap(*args, common); }};
}

}  // namespace gmwm::cli
