// gmwm wv INPUT [--robust [--eff E] [--estimator huber|bisquare]] [--columns ..] [--freq HZ]
//             [--alpha A] [--levels J] [--csv PATH] [--json PATH]
// The Haar wavelet variance of every selected column with its CIs: classical, or robust
// side by side with the classical one and a per-level contamination diagnostic.

#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include "common.h"
#include "gmwm/robust/contamination.h"

namespace gmwm::cli {

namespace {

struct WvArgs {
  InputOptions input;
  RobustOptions robust;
  std::string csv;
};

// The robust WV's companions, per column (empty for a classical run).
struct RobustView {
  std::vector<WaveletVariance> classical;
  std::vector<robust::Quantization> quantization;
  std::vector<std::vector<robust::LevelDiagnostic>> diagnostic;
  bool active() const { return !classical.empty(); }
};

std::string csv_table(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs,
                      const RobustView& rv) {
  std::ostringstream os;
  os << "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients";
  if (rv.active()) os << ",classical_wv,robust_to_classical,ci_disjoint,contaminated";
  os << "\n";
  // Shortest text that reads back to the same double.
  auto num = [](std::ostream& o, double x) -> std::ostream& {
    if (!std::isfinite(x)) return o << "nan";
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return o.write(buf, r.ptr - buf);
  };
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const auto& w = wvs[k];
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      os << set.signals[k].name << ',' << (j + 1) << ',';
      num(os, w.tau[l]) << ',';
      num(os, w.tau[l] / set.freq) << ',';
      num(os, w.wv[l]) << ',';
      num(os, w.ci_low[l]) << ',';
      num(os, w.ci_high[l]) << ',';
      os << w.coefficients[l];
      if (rv.active()) {
        const auto& d = rv.diagnostic[k][l];
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

std::string terminal_table(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs,
                           const RobustView& rv) {
  std::ostringstream os;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const auto& w = wvs[k];
    const auto& s = set.signals[k];
    if (k) os << '\n';
    os << s.name << ": N = " << s.values.size() << ", " << fmt(set.freq) << " Hz, ";
    if (rv.active())
      os << w.estimator << " WV (efficiency " << fmt(w.efficiency.value_or(1.0)) << ")";
    else
      os << "classical WV";
    os << ", " << fmt(100.0 * (1.0 - w.alpha)) << "% CI" << (s.unit.empty() ? "" : ", WV in (" + s.unit + ")^2")
       << '\n';
    std::vector<std::string> head = {"level", "tau", "tau [s]", "WV", "CI low", "CI high", "M_j"};
    if (rv.active()) head.insert(head.end(), {"classical", "ratio", "flag"});
    Table t(head);
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      std::vector<std::string> row = {std::to_string(j + 1), fmt(w.tau[l], 10), fmt(w.tau[l] / set.freq),
                                      std::isfinite(w.wv[l]) ? fmt(w.wv[l]) : "no root",
                                      fmt(w.ci_low[l]), fmt(w.ci_high[l]), std::to_string(w.coefficients[l])};
      if (rv.active()) {
        const auto& d = rv.diagnostic[k][l];
        row.insert(row.end(), {fmt(d.classical_wv), fmt(d.robust_to_classical, 4),
                               d.contaminated ? "contaminated" : (d.ci_disjoint ? "CIs disjoint" : "")});
      }
      t.add(row);
    }
    os << t.str();
    if (rv.active()) {
      const auto& q = rv.quantization[k];
      if (q.detected) os << "rounding step " << fmt(q.quantum) << " detected; flags are calibrated against it\n";
      int flagged = 0;
      for (const auto& d : rv.diagnostic[k]) flagged += d.contaminated;
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

  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  Stopwatch wv_clock;
  RobustView rv;
  std::vector<WaveletVariance> wvs;
  if (robust_options) {
    wvs = compute_robust_wv(set, *robust_options);
    rv.classical = compute_wv(set, options);
    const robust::Tuning tuning = robust::tune(robust_options->estimator, robust_options->efficiency);
    rv.quantization.resize(wvs.size());
    rv.diagnostic.resize(wvs.size());
    for (std::size_t k = 0; k < wvs.size(); ++k) {
      const auto& x = set.signals[k].values;
      rv.quantization[k] = robust::detect_quantization(x.data(), static_cast<std::int64_t>(x.size()));
      rv.diagnostic[k] = robust::contamination_diagnostic(x.data(), static_cast<std::int64_t>(x.size()), wvs[k],
                                                          rv.classical[k], rv.quantization[k], tuning);
    }
  } else {
    wvs = compute_wv(set, options);
  }
  const double wv_seconds = wv_clock.seconds();

  // Everything is computed: build the outputs, then write them.
  io::Json doc = io::json_document("wv");
  doc["input"] = set.path;
  if (set.timing) doc["timing"] = io::timing_json(*set.timing);
  for (std::size_t k = 0; k < wvs.size(); ++k)
    doc["columns"].push_back(rv.active() ? io::robust_wv_column_json(column_info(set, k), wvs[k], rv.diagnostic[k],
                                                                     rv.quantization[k])
                                         : io::wv_column_json(column_info(set, k), wvs[k]));
  const std::string csv = args.csv.empty() ? std::string() : csv_table(set, wvs, rv);
  const std::string table = common.show_table() ? terminal_table(set, wvs, rv) : std::string();

  warn_about_timing(set);
  if (!args.csv.empty()) common.outputs->stage(args.csv, csv);
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds}, {"wv", wv_seconds}, {"total", total.seconds()}},
              .argv = {}});
  if (!common.report.empty()) {
    io::ReportData rep = report_data("wv", set);
    for (std::size_t k = 0; k < wvs.size(); ++k)
      rep.columns[k].wvs =
          rv.active() ? std::vector<WaveletVariance>{rv.classical[k], wvs[k]} : std::vector<WaveletVariance>{wvs[k]};
    write_report(common, rep);
  }
  commit_outputs(common);
  if (common.show_table()) {
    if (set.timing) std::cout << set.timing->summary() << '\n';
    std::cout << table;
    std::cout.flush();
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
  sub->add_option("--csv", args->csv, "Also write the WV as a CSV table to PATH")
      ->type_name("PATH");
  add_common_options(*sub, common);
  add_report_option(*sub, common);
  return {sub, [args, &common] { return run_wv(*args, common); }};
}

}  // namespace gmwm::cli
