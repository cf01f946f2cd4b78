// Speed of the foundation on the shared recording adis_16405_imu1.csv.gz ($GMWM_SHARED_DATA) (6 x 1,000,000, gzip):
// parsing, the classical WV of all six columns, and one fit of 3*AR1+WN+RW+QN+DR.
// Reference (R GMWM 3.0.0 timed on this machine kind):
// WV one column 0.53 s, six columns 3.46 s; one fit of AR1+WN+RW+QN 2.89 s.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/signal_reader.h"

using namespace gmwm;

int main() {
  const std::string path = bench::shared_data_file("adis_16405_imu1.csv.gz");
  constexpr int kRepeats = 5;  // best of 5 for the sub-second parts
  double parse = 1e9, wv_all = 1e9;
  io::SignalSet set;
  for (int r = 0; r < kRepeats; ++r) {
    bench::Stopwatch sw;
    io::ReadOptions ro;
    ro.freq = 100.0;
    set = io::read_signals(path, ro);
    parse = std::min(parse, sw.seconds());
  }
  std::vector<std::span<const double>> cols;
  for (const auto& s : set.signals) cols.emplace_back(s.values);
  std::vector<WaveletVariance> wv;
  for (int r = 0; r < kRepeats; ++r) {
    bench::Stopwatch sw;
    wv = classical_wv(cols);
    wv_all = std::min(wv_all, sw.seconds());
  }
  double fit_best = 1e9, fit_ar1wnrwqn = 1e9;
  FitResult fr;
  for (int r = 0; r < 3; ++r) {
    bench::Stopwatch sw;
    fr = fit_gmwm(wv[0], parse_model("3*AR1+WN+RW+QN+DR"));
    fit_best = std::min(fit_best, sw.seconds());
    sw.reset();
    fit_gmwm(wv[0], parse_model("AR1+WN+RW+QN"));
    fit_ar1wnrwqn = std::min(fit_ar1wnrwqn, sw.seconds());
  }
  std::printf("| task | gmwm | reference R | ratio |\n|---|---|---|---|\n");
  std::printf("| parse 6 x 1e6 gzip CSV | %.3f s | - | - |\n", parse);
  std::printf("| classical WV, six columns (19 levels) | %.4f s | 3.46 s | %.0fx faster |\n", wv_all, 3.46 / wv_all);
  std::printf("| wv total (parse + WV) | %.3f s | - | - |\n", parse + wv_all);
  std::printf("| fit AR1+WN+RW+QN, one column (with inference) | %.4f s | 2.89 s | %.0fx faster |\n", fit_ar1wnrwqn,
              2.89 / fit_ar1wnrwqn);
  std::printf("| fit 3*AR1+WN+RW+QN+DR, one column (with inference) | %.4f s | - | - |\n", fit_best);
  std::printf("\nfit 3*AR1+WN+RW+QN+DR on %s: status %s, objective %.6g, optimisation %.4f s, inference %.4f s\n",
              set.signals[0].name.c_str(), to_string(fr.status), fr.objective, fr.seconds_optimise,
              fr.seconds_inference);
  return 0;
}
