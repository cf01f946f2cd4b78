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
  bool no_unit_check = false;  ///< --no-unit-check
  std::string corrected;       ///< --corrected PATH
};

std::string seconds_text(double tau, const io::SignalSet& set) {
  return set.freq_known ? fmt(tau / set.freq, 3) + " s" : fmt(tau, 6) + " samples";
}

std::string summary_line(const std::string& name, const gap::GapResult& g) { return name + ": " + g.headline; }

// The first added effect's parameters with their bootstrap intervals, discrete and in
// the continuous units a navigation engineer uses.
std::string effect_table(const gap::GapResult& g, const io::SignalSet& set, const std::string& unit) {
  const FitResult& f = g.final_fit;
  if (f.status == FitStatus::kFailed || f.theta.size() != f.model.num_parameters() || f.theta.size() == 0) return {};
  Table t({"effect parameter", "value", "95% interval (bootstrap)", "unit"}, 1);
  for (const auto& r : report::parameter_rows(f))
    t.add({r.process + " " + r.name, fmt(r.value, 5), fmt(r.ci_low, 4) + " - " + fmt(r.ci_high, 4), "discrete"});
  if (set.freq_known && f.ci_low.size() == f.theta.size())
    for (int k = 0; k < f.model.num_components(); ++k) {
      const Process& p = *f.model.components()[static_cast<std::size_t>(k)].process;
      const std::span<const double> th(f.theta.data() + f.model.offset(k), static_cast<std::size_t>(p.size()));
      const auto q = p.physical(th, set.freq);
      const auto iv = physical_interval(
          p, th, std::span<const double>(f.ci_low.data() + f.model.offset(k), static_cast<std::size_t>(p.size())),
          std::span<const double>(f.ci_high.data() + f.model.offset(k), static_cast<std::size_t>(p.size())), set.freq);
      for (std::size_t i = 0; i < q.size(); ++i)
        if (!q[i].unit_pattern.empty())
          t.add({p.name() + " " + q[i].name, fmt(q[i].value, 5),
                 i < iv.size() ? fmt(iv[i].low, 4) + " - " + fmt(iv[i].high, 4) : "",
                 render_unit(q[i].unit_pattern, unit.empty() ? "U" : unit)});
    }
  return t.str();
}

std::string terminal_report(const std::string& name, const gap::GapResult& g, const io::SignalSet& set,
                            const std::vector<std::string>& conversions, const std::string& unit) {
  std::ostringstream os;
  os << summary_line(name, g) << '\n';
  os << "  baseline: " << g.baseline.to_string(g.baseline_theta) << '\n';
  for (const auto& c : conversions) os << "  conversion: " << c << '\n';
  Table levels({"tau", "ratio", "z", "reference band", "outside"});
  for (const auto& l : g.levels)
    levels.add({seconds_text(l.tau, set), fmt(l.ratio, 4), fmt(l.z, 3), fmt(l.ref_low, 3) + " - " + fmt(l.ref_high, 3),
                l.outside ? "yes" : ""});
  os << levels.str();
  if (!g.candidates.empty()) {
    Table cand({"candidate", "improvement", "threshold", "2 x optimism (WVIC)", "cleared", "fit"}, 1);
    for (const auto& c : g.candidates)
      cand.add({gap::to_string(c.effect), fmt(c.improvement, 5), fmt(c.threshold, 4), fmt(2.0 * c.optimism, 4),
                c.cleared ? "yes" : "", c.model});
    os << cand.str();
  }
  const auto& s = g.shrinkage;
  os << "  objective " << fmt(s.objective_before) << " -> " << fmt(s.objective_after) << " (null mean "
     << fmt(s.null_mean, 4) << " -> " << fmt(s.null_mean_after, 4) << "), levels outside " << s.levels_outside_before
     << " -> " << s.levels_outside_after << ", global p " << fmt(s.p_value_before, 3) << " -> "
     << fmt(s.p_value_after, 3) << '\n';
  int disjoint = 0;
  for (const auto& h : g.split_half) disjoint += h.disjoint;
  if (!g.split_half.empty())
    os << "  split halves: " << disjoint << " of " << g.split_half.size() << " levels disagree (95% CIs disjoint)"
       << (disjoint ? ": the record is not stationary" : "") << '\n';
  os << effect_table(g, set, unit);
  if (std::isfinite(g.navigation.rms_without))
    os << "  integrated error after " << fmt(g.navigation.horizon_seconds, 3)
       << " s (attitude for a gyro, velocity for an accelerometer): " << fmt(g.navigation.rms_without, 3) << " -> "
       << fmt(g.navigation.rms_with, 3) << " " << render_unit("U*s", unit.empty() ? "U" : unit)
       << " RMS (baseline -> with the effects)\n";
  if (g.contamination_screened) {
    os << "  contamination screen: ";
    if (g.contaminated_levels.empty()) os << "no level flagged";
    for (std::size_t i = 0; i < g.contaminated_levels.size(); ++i)
      os << (i ? ", " : "levels flagged at ")
         << seconds_text(g.levels[static_cast<std::size_t>(g.contaminated_levels[i] - 1)].tau, set);
    os << " (robust WV below the classical one beyond the data's rounding, with far outliers)\n";
  }
  for (const auto& r : g.refused) os << "  refused (does not lower the objective's excess): " << r << '\n';
  for (const auto& n : g.notes) os << "  note: " << n << '\n';
  return os.str();
}

// What to change: the corrected configuration's fields (input -> corrected) and, per
// column, the gap left with the input, with the corrected file and with the full model.
std::string changes_text(const pipeline::CorrectedConfig& c, const io::SignalSet& set,
                         const pipeline::GapStudy& study) {
  std::ostringstream os;
  os << "\nwhat to change (" << c.format << ", --corrected writes it):\n";
  if (c.format != "model") {
    Table t({"field", "input", "corrected", "unit", "changed"}, 1);
    for (const auto& ch : c.changes)
      t.add({ch.field, std::isfinite(ch.input) ? fmt(ch.input, 4) : "-",
             std::isfinite(ch.corrected) ? fmt(ch.corrected, 4) : "-", ch.unit, ch.changed ? "yes" : ""});
    os << t.str();
  }
  const bool nav = set.freq_known;
  std::vector<std::string> head{"column", "levels outside (input -> file -> full)",
                                "objective (input -> file -> full)"};
  if (nav) head.push_back("integrated error after 60 s (input -> file -> full)");
  Table g(head, 1);
  for (const auto& col : c.columns) {
    std::string unit = "U";
    for (const auto& sc : study.columns)
      if (sc.name == col.name && !sc.unit.empty()) unit = sc.unit;
    std::vector<std::string> row{col.name,
                                 std::to_string(col.before.levels_outside) + " -> " +
                                     std::to_string(col.with_config.levels_outside) + " -> " +
                                     std::to_string(col.with_full.levels_outside),
                                 fmt(col.before.objective, 3) + " -> " + fmt(col.with_config.objective, 3) + " -> " +
                                     fmt(col.with_full.objective, 3)};
    if (nav)
      row.push_back(fmt(col.before.navigation_rms, 3) + " -> " + fmt(col.with_config.navigation_rms, 3) + " -> " +
                    fmt(col.with_full.navigation_rms, 3) + " " + render_unit("U*s", unit) + " RMS");
    g.add(row);
  }
  os << g.str();
  for (const auto& col : c.columns)
    for (const auto& x : col.not_expressible) os << "  cannot express, " << col.name << ": " << x << '\n';
  return os.str();
}

// One line per correlated pair: the scales where its cross-axis correlation is significant.
std::string cross_axis_text(const std::vector<gap::CrossAxisPair>& pairs, const io::SignalSet& set) {
  std::map<std::pair<int, int>, std::vector<const gap::CrossAxisPair*>> by_pair;
  for (const auto& p : pairs)
    if (p.significant) by_pair[{p.a, p.b}].push_back(&p);
  std::string out;
  for (const auto& [ab, v] : by_pair) {
    double peak = 0.0;
    for (const auto* p : v)
      if (std::abs(p->rho) > std::abs(peak)) peak = p->rho;
    out += "  cross-axis: " + set.signals[static_cast<std::size_t>(ab.first)].name + " & " +
           set.signals[static_cast<std::size_t>(ab.second)].name + " correlated at " +
           seconds_text(v.front()->tau, set) + (v.size() > 1 ? " - " + seconds_text(v.back()->tau, set) : "") + " (" +
           std::to_string(v.size()) + (v.size() > 1 ? " levels" : " level") + ", rho up to " + fmt(peak, 3) +
           "): a shared effect\n";
  }
  return out;
}

// --kalibr FILE[:imuN]: the file, and the IMU of a chain (empty: the file is one IMU).
// Split at the last ':' only when the whole text is not a file, its head is, and its
// tail names an IMU (a file name may contain ':').
std::pair<std::string, std::string> kalibr_source(const std::string& text) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || fs::exists(text, ec)) return {text, ""};
  const std::string imu = text.substr(colon + 1);
  const bool names_imu =
      imu.size() > 3 && imu.rfind("imu", 0) == 0 && imu.find_first_not_of("0123456789", 3) == std::string::npos;
  if (names_imu) return {text.substr(0, colon), imu};  // a missing FILE is then reported by its own name
  if (!fs::exists(text.substr(0, colon), ec)) return {text, ""};
  throw InputError("--kalibr " + text + ": expected FILE or FILE:imuN (e.g. imu_chain.yaml:imu1), got '" + imu + "'");
}

int run_gap(const GapArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const WvOptions wv_opts = wv_options(args.input);
  declare_input(common, args.input.input);
  const auto [kalibr_path, kalibr_imu] = kalibr_source(args.kalibr);
  declare_input(common, kalibr_path);
  declare_input(common, args.gazebo);
  declare_input(common, args.datasheet);
  declare_output(common, "--json", common.json);
  declare_output(common, "--corrected", args.corrected);
  check_report_option(common);
  const int given =
      !args.model.empty() + !args.kalibr.empty() + !args.gazebo.empty() + !args.fit.empty() + !args.datasheet.empty();
  if (given != 1)
    throw InputError(
        "gap: give exactly one baseline: --model SPEC_WITH_VALUES, --kalibr imu.yaml, --gazebo FILE.sdf, "
        "--datasheet FILE.yaml or --fit SPEC");
  pipeline::GapStudyOptions options;
  options.wv = wv_opts;
  options.units = io::parse_units(args.units);
  options.units_declared = !args.units.empty();
  if (!args.sensor.empty()) options.sensor = args.sensor == "gyro" ? io::SensorKind::kGyro : io::SensorKind::kAccel;
  options.temperature_column = args.temperature;
  options.unit_check = !args.no_unit_check;
  options.replicates = args.replicates;
  options.seed = common.seed;
  options.alpha = args.input.alpha;
  if (!args.model.empty()) options.baseline = pipeline::ModelBaseline{args.model};
  if (!args.fit.empty()) options.baseline = pipeline::FitBaseline{args.fit};

  Stopwatch read_clock;
  io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  // A side file's refusal names its option too: "--kalibr imu.yaml:3: ...".
  auto named = [](const char* option, const auto& read) {
    try {
      return read();
    } catch (const InputError& e) {
      throw InputError(std::string(option) + " " + e.what());
    }
  };
  if (!args.kalibr.empty())
    options.baseline = pipeline::ConfigBaseline{
        named("--kalibr", [&] { return io::read_kalibr_imu_yaml(kalibr_path, set.freq, options.units, kalibr_imu); }),
        kalibr_path};
  if (!args.gazebo.empty())
    options.baseline = pipeline::ConfigBaseline{
        named("--gazebo", [&] { return io::read_gazebo_sdf(args.gazebo, set.freq, options.units); }), args.gazebo};
  if (!args.datasheet.empty())
    options.baseline = pipeline::ConfigBaseline{
        named("--datasheet", [&] { return io::read_datasheet_yaml(args.datasheet, set.freq, options.units); }),
        args.datasheet};
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
  std::optional<pipeline::CorrectedConfig> corrected =
      pipeline::corrected_config(set, study, options, {options.units, options.sensor, baseline_file});
  if (!args.corrected.empty()) common.outputs->stage(args.corrected, corrected->content);
  report::Json doc = report::gap_document(set, study);
  if (corrected) doc["corrected"] = report::corrected_config_json(*corrected, set.freq_known ? set.freq : 0.0);
  std::string report;
  if (common.show_table()) {
    if (set.timing) report += set.timing->summary() + "\n";
    for (std::size_t k = 0; k < study.columns.size(); ++k) {
      const pipeline::GapColumnStudy& c = study.columns[k];
      report += (k ? "\n" : "") + terminal_report(c.name, c.result, set, c.conversions, c.unit);
    }
    report += "\nsummary:\n";
    for (const pipeline::GapColumnStudy& c : study.columns) report += "  " + summary_line(c.name, c.result) + "\n";
    report += cross_axis_text(study.cross_axis, set);
    if (corrected) report += changes_text(*corrected, set, study);
  }
  warn_about_timing(set);
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds},
                          {"wv", study.wv_seconds},
                          {"gap", study.gap_seconds},
                          {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty()) {
    report::ReportData rep = report_data("gap", set,
                                         !args.model.empty() ? args.model
                                         : !args.fit.empty() ? "fit " + args.fit
                                                             : baseline_file);
    for (std::size_t k = 0; k < study.columns.size(); ++k) {
      const pipeline::GapColumnStudy& c = study.columns[k];
      rep.columns[k].wvs = {c.wv, c.robust_wv};
      rep.columns[k].gap = c.result;
      rep.columns[k].conversions = c.conversions;
      if (!c.unit.empty()) rep.columns[k].unit = c.unit;
    }
    rep.corrected = corrected;
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) {
    print_text(report);
  }
  return 0;
}

}  // namespace

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
      ->check(CLI::IsMember({"gyro", "accel"}));
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
  sub->add_flag("--no-unit-check", args->no_unit_check,
                "Diagnose even when a column's finest scales sit at a unit factor ((180/pi)^2, 9.80665^2, ...) "
                "from the baseline");
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_gap(*args, common); }};
}

}  // namespace gmwm::cli
