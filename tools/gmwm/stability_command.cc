// gmwm stability INPUT [--kind oadev,mdev,...] [--taus octave|decade|all|T1,T2,...]
//                      [--confidence P] [--intervals stable32|exact] [--noise-alpha A] [--report PATH]
//                      [--hat] [--data rate|increment|phase] [--columns ..] [--freq HZ] [--units ..]
// The frequency-stability deviations of every selected column (docs/stability.md), with --hat
// the three-cornered hat of three columns recorded together: parses, runs
// pipeline::study_stability, renders with report/stability_output.h, commits.
#include <cmath>
#include <optional>

#include "common.h"
#include "units_tables.h"
#include "gmwm/engine/error.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/report/html_report.h"
#include "gmwm/report/stability_output.h"

namespace gmwm::cli {
namespace {

struct StabilityArgs {
  InputOptions input;
  std::string kinds = "oadev";
  std::string taus = "octave";
  double confidence = stability::kStable32Confidence;
  std::string intervals = "stable32";
  std::optional<int> noise_alpha;
  bool hat = false;
  UnitsOptions units;
};

// --taus: a set's name, or averaging times in seconds (InputError naming the entry).
void parse_taus(const std::string& text, pipeline::StabilityStudyOptions& o) {
  if (const auto set = stability::tau_set_from_name(text)) {
    o.taus = *set;
    return;
  }
  const std::vector<std::string> entries = io::comma_list(text);
  if (entries.empty())
    throw InputError("--taus: found '" + text +
                     "', expected all, octave, decade or averaging times in seconds (1,10,100)");
  for (const std::string& entry : entries) {
    char* end = nullptr;
    const double tau = std::strtod(entry.c_str(), &end);
    if (entry.empty() || end != entry.c_str() + entry.size() || !std::isfinite(tau))
      throw InputError("--taus: found '" + entry +
                       "', expected all, octave, decade or averaging times in seconds (1,10,100)");
    o.tau_list.push_back(tau);
  }
}

pipeline::StabilityStudyOptions stability_options(const StabilityArgs& args, const CommonOptions& common) {
  pipeline::StabilityStudyOptions o;
  o.kinds.clear();
  for (const std::string& k : io::comma_list(args.kinds)) o.kinds.push_back(stability::deviation_of(k));
  parse_taus(args.taus, o);
  o.intervals.confidence = args.confidence;
  const auto method = stability::interval_method_from_name(args.intervals);
  if (!method) throw InputError("--intervals: found '" + args.intervals + "', expected stable32 or exact");
  o.intervals.method = *method;
  o.intervals.noise_alpha = args.noise_alpha;
  o.three_cornered_hat = args.hat;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(why);
  declare_input(common, args.input.input);
  declare_output(common, "--json", common.json);
  check_page_report_option(common);
  if (!args.units.units.empty()) io::parse_units(args.units.units);  // a bad --units fails before any work
  return o;
}

int run_stability(const StabilityArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const pipeline::StabilityStudyOptions options = stability_options(args, common);
  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  // The study first: a record it refuses is one line, without the reading's warnings.
  const pipeline::StabilityStudy study = pipeline::study_stability(set, options);
  warn_about_timing(set);
  const std::vector<std::string> units = column_units(args.units, set);
  report::Json doc = report::stability_document(set, study, options, units);
  write_json(common, doc,
             {.threads = active_threads(),
              .seconds = {{"read", read_seconds},
                          {"deviations", study.seconds},
                          {"intervals", study.interval_seconds},
                          {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty())
    common.outputs->stage(common.report, report::render_stability_html(set, study, options, units));
  commit_outputs(common);
  if (common.show_table())
    print_text((set.timing ? set.timing->summary() + "\n" : std::string()) + report::stability_text(study, units));
  return 0;
}

}  // namespace

Command add_stability_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<StabilityArgs>();
  CLI::App* sub = app.add_subcommand(
      "stability",
      "Frequency-stability deviations of each column with their intervals (Allan, modified, time, Hadamard, "
      "total, Theo1, MTIE, TIE rms; NIST SP 1065)");
  add_record_options(*sub, args->input);
  std::string kinds;
  for (const stability::DeviationKind k : stability::deviation_kinds())
    kinds += (kinds.empty() ? "" : ", ") + std::string(stability::deviation_name(k));
  sub->add_option("--kind", args->kinds, "Deviations, comma-separated: " + kinds + " (docs/stability.md)")
      ->type_name("K1,K2")
      ->capture_default_str();
  sub->add_option("--taus", args->taus,
                  "Averaging times: octave (1, 2, 4, ... periods), decade (1, 2, 4, 10, 20, 40, ...), all, or "
                  "a list in seconds (each a whole number of sampling periods)")
      ->type_name("SET|T1,T2")
      ->capture_default_str();
  sub->add_option("--confidence", args->confidence,
                  "Confidence of each deviation's chi-square interval (default: Stable32's one sigma, "
                  "0.6827)")
      ->type_name("P");
  sub->add_option("--intervals", args->intervals,
                  "Chi-square quantiles: stable32 (exact up to 100 degrees of freedom, as Stable32 prints them) "
                  "or exact")
      ->type_name("stable32|exact")
      ->capture_default_str();
  sub->add_option("--noise-alpha", args->noise_alpha,
                  "The noise exponent for every tau's degrees of freedom (2 white PM, 1 flicker PM, 0 white FM, "
                  "-1 flicker FM, -2 random-walk FM, ...), instead of identifying it at each tau")
      ->type_name("A");
  sub->add_flag("--hat,--three-cornered-hat", args->hat,
                "The three-cornered hat of three columns recorded together (--columns A,B,C: three co-located "
                "sensors' same axis, three clocks): each column's own deviation separated from what the three "
                "share, from the pairs' differences, with its interval (docs/stability.md)");
  add_units_option(*sub, args->units);
  sub->add_option("--report", common.report,
                  "Write a self-contained HTML report: the deviations with their interval bands, and the table");
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_stability(*args, common); }};
}

}  // namespace gmwm::cli
