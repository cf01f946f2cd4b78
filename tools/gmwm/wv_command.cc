// gmwm wv INPUT [--robust [--eff E] [--estimator huber|bisquare]] [--columns ..] [--freq HZ]
//             [--alpha A] [--levels J] [--csv PATH] [--json PATH]
// The Haar wavelet variance of every selected column with its CIs: classical, or robust
// side by side with the classical one and a per-level contamination diagnostic.

#include <cmath>
#include <iostream>
#include <sstream>

#include "common.h"
#include "units_tables.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/signal_writer.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/wv_study.h"
#include "gmwm/robust/contamination.h"

namespace gmwm::cli {

namespace {

struct WvArgs {
  InputOptions input;
  RobustOptions robust;
  std::string csv;
  bool adev = false;     ///< --adev: the Allan deviation and its IEEE 952 read-offs
  std::string adev_csv;  ///< --adev-csv PATH
  int adev_points = AllanOptions{}.points_per_octave;
  UnitsOptions units;
};

// Parse: the study's options from the arguments, every input and output declared first.
pipeline::WvStudyOptions wv_study_options(const WvArgs& args, const CommonOptions& common) {
  pipeline::WvStudyOptions o;
  o.wv = wv_options(args.input);
  o.robust = robust_wv_options(args.robust, o.wv);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_report_option(common);
  declare_output(common, "--csv", args.csv);
  declare_output(common, "--adev-csv", args.adev_csv);
  if (!args.adev_csv.empty() && !args.adev)
    throw InputError("--adev-csv " + args.adev_csv + ": only meaningful with --adev");
  if (!args.units.units.empty()) io::parse_units(args.units.units);  // a bad --units fails before any work
  AllanOptions allan_options;
  allan_options.points_per_octave = args.adev_points;
  allan_options.alpha = args.input.alpha;
  if (const std::string why = allan_options.Validate(); !why.empty()) throw InputError("--adev-points: " + why);
  if (args.adev) o.allan = allan_options;
  return o;
}

// One part's WV (the record, or a topic of --topic A,B): its study, warnings and rendering.
struct WvPart {
  Outcome outcome;
  std::string csv, adev_csv;
};

WvPart wv_part(const WvArgs& args, const pipeline::WvStudyOptions& options, const io::SignalSet& set,
               double read_seconds) {
  auto study = std::make_shared<const pipeline::WvStudy>(pipeline::study_wv(set, options));
  const std::vector<std::string> units = column_units(args.units, set);
  warn_about_timing(set);
  WvPart part;
  if (!args.csv.empty()) part.csv = report::wv_csv(set, *study);
  if (!args.adev_csv.empty()) part.adev_csv = report::adev_csv(set, *study);
  part.outcome = {report::wv_document(set, *study, units),
                  {{"read", read_seconds}, {"wv", study->wv_seconds}, {"allan", study->allan_seconds}},
                  [&set, study, units] { return report::wv_report_data(set, *study, units); },
                  [&set, study, units](const report::Json&) {
                    return (set.timing ? set.timing->summary() + "\n" : std::string()) + report::wv_text(set, *study) +
                           report::adev_text(set, *study, units);
                  }};
  return part;
}

int run_wv(const WvArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const pipeline::WvStudyOptions study_options = wv_study_options(args, common);

  Stopwatch read_clock;
  const std::vector<io::RecordPart> parts = read_parts(args.input);
  const double read_seconds = read_clock.seconds();
  std::vector<Outcome> outcomes;
  std::vector<std::string> csvs, adev_csvs;
  for (const io::RecordPart& p : parts) {
    WvPart part = wv_part(args, study_options, p.set, read_seconds / static_cast<double>(parts.size()));
    outcomes.push_back(std::move(part.outcome));
    csvs.push_back(std::move(part.csv));
    adev_csvs.push_back(std::move(part.adev_csv));
  }
  // Everything is computed: render, then emit.
  if (!args.csv.empty()) common.outputs->stage(args.csv, merge_csv_tables(csvs));
  if (!args.adev_csv.empty()) common.outputs->stage(args.adev_csv, merge_csv_tables(adev_csvs));
  Outcome outcome = merge_parts(parts, std::move(outcomes));
  outcome.seconds["total"] = total.seconds();
  return emit(common, std::move(outcome));
}

}  // namespace

Command add_wv_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<WvArgs>();
  CLI::App* sub = app.add_subcommand(
      "wv", "Haar wavelet variance of each column (classical, or robust with --robust), with confidence intervals");
  add_input_options(*sub, args->input);
  add_robust_options(*sub, args->robust);
  sub->add_option("--csv", args->csv, "Also write the WV as a CSV table to PATH")->type_name("PATH");
  sub->add_flag("--adev", args->adev,
                "Also the overlapping Allan deviation with its CI and the IEEE 952 read-offs N (-1/2 slope at 1 s), "
                "K (+1/2 slope at 3 s) and B (flat minimum / 0.664)");
  sub->add_option("--adev-csv", args->adev_csv, "With --adev: write the Allan deviation as a CSV table to PATH")
      ->type_name("PATH");
  sub->add_option("--adev-points", args->adev_points, "With --adev: averaging times per octave (1: octaves only)")
      ->type_name("K")
      ->transform(whole_number(1, 64))
      ->capture_default_str();
  add_units_option(*sub, args->units);
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_wv(*args, common); }};
}

}  // namespace gmwm::cli
