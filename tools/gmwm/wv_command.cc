// gmwm wv INPUT [--robust [--eff E] [--estimator huber|bisquare]] [--columns ..] [--freq HZ]
//             [--alpha A] [--levels J] [--csv PATH] [--json PATH]
// The Haar wavelet variance of every selected column with its CIs: classical, or robust
// side by side with the classical one and a per-level contamination diagnostic.

#include <charconv>
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

// Shortest text that reads back to the same double ("nan" when not finite).
std::ostream& num(std::ostream& o, double x) {
  if (!std::isfinite(x)) return o << "nan";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return o.write(buf, r.ptr - buf);
}

struct WvArgs {
  InputOptions input;
  RobustOptions robust;
  std::string csv;
  bool adev = false;     ///< --adev: the Allan deviation and its IEEE 952 read-offs
  std::string adev_csv;  ///< --adev-csv PATH
  int adev_points = AllanOptions{}.points_per_octave;
  UnitsOptions units;
};

// The Allan deviation table and its read-offs, per column.
std::string adev_terminal(const io::SignalSet& set, const pipeline::WvStudy& study, const UnitsOptions& units) {
  std::ostringstream os;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    if (!study.columns[k].allan) continue;
    const FigureReport& r = *study.columns[k].allan;
    const std::string unit = column_unit(units, set.signals[k].name);
    os << '\n'
       << set.signals[k].name << ": overlapping Allan deviation, " << fmt(100.0 * (1.0 - r.adev.alpha))
       << "% CI (chi-square, edf = (N - 2m + 1) / 2m)" << (unit.empty() ? "" : ", in " + unit) << '\n';
    Table t({"m", "tau [s]", "ADEV", "CI low", "CI high", "edf"});
    for (std::size_t i = 0; i < r.adev.size(); ++i)
      t.add({std::to_string(r.adev.m[i]), fmt(r.adev.tau[i]), fmt(r.adev.adev[i]), fmt(r.adev.ci_low[i]),
             fmt(r.adev.ci_high[i]), fmt(r.adev.edf[i], 4)});
    os << t.str() << noise_figures_table(r.chosen, unit);
  }
  return os.str();
}

std::string adev_csv(const io::SignalSet& set, const pipeline::WvStudy& study) {
  std::ostringstream os;
  os << "column,m,tau_seconds,adev,ci_low,ci_high,edf\n";
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    if (!study.columns[k].allan) continue;
    const AllanDeviation& a = study.columns[k].allan->adev;
    for (std::size_t i = 0; i < a.size(); ++i) {
      os << io::csv_field(set.signals[k].name) << ',' << a.m[i] << ',';
      num(os, a.tau[i]) << ',';
      num(os, a.adev[i]) << ',';
      num(os, a.ci_low[i]) << ',';
      num(os, a.ci_high[i]) << ',';
      num(os, a.edf[i]) << '\n';
    }
  }
  return os.str();
}

std::string csv_table(const io::SignalSet& set, const pipeline::WvStudy& study) {
  const bool robust = !study.columns.empty() && study.columns.front().robust.has_value();
  std::ostringstream os;
  os << "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients";
  if (robust) os << ",classical_wv,robust_to_classical,ci_disjoint,contaminated";
  os << "\n";
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const auto& w = study.columns[k].wv;
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      os << io::csv_field(set.signals[k].name) << ',' << (j + 1) << ',';
      num(os, w.tau[l]) << ',';
      num(os, w.tau[l] / set.freq) << ',';
      num(os, w.wv[l]) << ',';
      num(os, w.ci_low[l]) << ',';
      num(os, w.ci_high[l]) << ',';
      os << w.coefficients[l];
      if (robust) {
        const auto& d = study.columns[k].robust->diagnostic[l];
        os << ',';
        num(os, d.classical_wv) << ',';
        num(os, d.robust_to_classical) << ',' << (d.ci_disjoint ? "true" : "false") << ','
                                       << (d.contaminated ? "true" : "false");
      }
      os << '\n';
    }
  }
  return os.str();
}

std::string terminal_table(const io::SignalSet& set, const pipeline::WvStudy& study) {
  std::ostringstream os;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const auto& w = study.columns[k].wv;
    const std::optional<pipeline::RobustWvView>& rv = study.columns[k].robust;
    const auto& s = set.signals[k];
    if (k) os << '\n';
    os << s.name << ": N = " << s.values.size() << ", " << fmt(set.freq) << " Hz, ";
    if (rv)
      os << w.estimator << " WV (efficiency " << fmt(w.efficiency.value_or(1.0)) << ")";
    else
      os << "classical WV";
    os << ", " << fmt(100.0 * (1.0 - w.alpha)) << "% CI" << (s.unit.empty() ? "" : ", WV in (" + s.unit + ")^2")
       << '\n';
    std::vector<std::string> head = {"level", "tau", "tau [s]", "WV", "CI low", "CI high", "M_j"};
    if (rv) head.insert(head.end(), {"classical", "ratio", "flag"});
    Table t(head);
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      std::vector<std::string> row = {std::to_string(j + 1),
                                      fmt(w.tau[l], 10),
                                      fmt(w.tau[l] / set.freq),
                                      std::isfinite(w.wv[l]) ? fmt(w.wv[l]) : "no root",
                                      fmt(w.ci_low[l]),
                                      fmt(w.ci_high[l]),
                                      std::to_string(w.coefficients[l])};
      if (rv) {
        const auto& d = rv->diagnostic[l];
        row.insert(row.end(), {fmt(d.classical_wv), fmt(d.robust_to_classical, 4),
                               d.contaminated ? "contaminated" : (d.ci_disjoint ? "CIs disjoint" : "")});
      }
      t.add(row);
    }
    os << t.str();
    if (rv) {
      const auto& q = rv->quantization;
      if (q.detected) os << "rounding step " << fmt(q.quantum) << " detected; flags are calibrated against it\n";
      int flagged = 0;
      for (const auto& d : rv->diagnostic) flagged += d.contaminated;
      if (flagged) os << flagged << " level(s) flagged as contaminated: there the robust WV is the one to trust\n";
      for (int j = 0; j < w.levels(); ++j)
        if (!w.notes[static_cast<std::size_t>(j)].empty() && !std::isfinite(w.wv[static_cast<std::size_t>(j)]))
          os << "level " << j + 1 << ": " << w.notes[static_cast<std::size_t>(j)] << '\n';
    }
  }
  return os.str();
}

int run_wv(const WvArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  const WvOptions options = wv_options(args.input);
  const auto robust_options = robust_wv_options(args.robust, options);
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

  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  pipeline::WvStudyOptions study_options;
  study_options.wv = options;
  study_options.robust = robust_options;
  if (args.adev) study_options.allan = allan_options;
  const pipeline::WvStudy study = pipeline::study_wv(set, study_options);

  // Everything is computed: build the outputs, then write them.
  std::vector<std::string> units;
  for (const auto& s : set.signals) units.push_back(column_unit(args.units, s.name));
  report::Json doc = report::wv_document(set, study, units);
  const std::string csv = args.csv.empty() ? std::string() : csv_table(set, study);
  const std::string table = common.show_table() ? terminal_table(set, study) : std::string();

  warn_about_timing(set);
  if (!args.csv.empty()) common.outputs->stage(args.csv, csv);
  if (!args.adev_csv.empty()) common.outputs->stage(args.adev_csv, adev_csv(set, study));
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds},
                          {"wv", study.wv_seconds},
                          {"allan", study.allan_seconds},
                          {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty()) {
    report::ReportData rep = report_data("wv", set);
    for (std::size_t k = 0; k < study.columns.size(); ++k) {
      const pipeline::WvColumnStudy& c = study.columns[k];
      rep.columns[k].wvs =
          c.robust ? std::vector<WaveletVariance>{c.robust->classical, c.wv} : std::vector<WaveletVariance>{c.wv};
      rep.columns[k].allan = c.allan;
      if (!units[k].empty()) rep.columns[k].unit = units[k];
    }
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) {
    print_text((set.timing ? set.timing->summary() + "\n" : std::string()) + table +
               adev_terminal(set, study, args.units));
  }
  return 0;
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
