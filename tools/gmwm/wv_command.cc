// gmwm wv INPUT [--columns ..] [--freq HZ] [--alpha A] [--levels J] [--csv PATH] [--json PATH]
// The classical Haar wavelet variance of every selected column with its CIs.

#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include "common.h"
#include "gmwm/io/atomic_file.h"

namespace gmwm::cli {

namespace {

struct WvArgs {
  InputOptions input;
  RobustOptions robust;
  std::string csv;
};

std::string csv_table(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs) {
  std::ostringstream os;
  os << "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients\n";
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
      os << w.coefficients[l] << '\n';
    }
  }
  return os.str();
}

std::string terminal_table(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs) {
  std::ostringstream os;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const auto& w = wvs[k];
    const auto& s = set.signals[k];
    if (k) os << '\n';
    os << s.name << ": N = " << s.values.size() << ", " << fmt(set.freq) << " Hz, classical WV, "
       << fmt(100.0 * (1.0 - w.alpha)) << "% CI" << (s.unit.empty() ? "" : ", WV in (" + s.unit + ")^2")
       << '\n';
    Table t({"level", "tau", "tau [s]", "WV", "CI low", "CI high", "M_j"});
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      t.add({std::to_string(j + 1), fmt(w.tau[l], 10), fmt(w.tau[l] / set.freq), fmt(w.wv[l]),
             fmt(w.ci_low[l]), fmt(w.ci_high[l]), std::to_string(w.coefficients[l])});
    }
    os << t.str();
  }
  return os.str();
}

int run_wv(const WvArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  refuse_robust(args.robust);
  const WvOptions options = wv_options(args.input);
  check_output_path("--json", common.json);
  check_output_path("--csv", args.csv);

  Stopwatch read_clock;
  const io::SignalSet set = read_input(args.input);
  const double read_seconds = read_clock.seconds();
  Stopwatch wv_clock;
  const std::vector<WaveletVariance> wvs = compute_wv(set, options);
  const double wv_seconds = wv_clock.seconds();

  // Everything is computed: build the outputs, then write them.
  io::Json doc = io::json_document("wv");
  doc["input"] = set.path;
  if (set.timing) doc["timing"] = io::timing_json(*set.timing);
  for (std::size_t k = 0; k < wvs.size(); ++k)
    doc["columns"].push_back(io::wv_column_json(column_info(set, k), wvs[k]));
  const std::string csv = args.csv.empty() ? std::string() : csv_table(set, wvs);
  const std::string table = common.show_table() ? terminal_table(set, wvs) : std::string();

  warn_about_timing(set);
  if (!args.csv.empty()) io::write_file_atomically(args.csv, csv);
  write_json(common, doc,
             {.threads = 0,
              .seconds = {{"read", read_seconds}, {"wv", wv_seconds}, {"total", total.seconds()}},
              .argv = {}});
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
      "wv", "Classical Haar wavelet variance of each column, with confidence intervals");
  add_input_options(*sub, args->input);
  add_robust_options(*sub, args->robust);
  sub->add_option("--csv", args->csv, "Also write the WV as a CSV table to PATH")
      ->type_name("PATH");
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_wv(*args, common); }};
}

}  // namespace gmwm::cli
