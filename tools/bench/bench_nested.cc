// Fit quality on real data: for every column of adis_16405_imu1.csv.gz, the model
// 3*AR1+WN+RW+QN+DR and each sub-model obtained by removing one component are fitted
// under the same Omega (the data's diag Omega); the larger model's objective must never
// be above the smaller one's (relative tolerance 1e-9). Each model is fitted on its own
// with the default options (shape-based starts, multi-starts, revival of collapsed
// components, nested starts from its own one-removed sub-models, Newton polish), and the
// full model additionally warm-started from the sub-models' fits, as model selection does.
#include <cstdio>
#include <string>
#include <vector>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/signal_reader.h"

using namespace gmwm;

int main() {
  io::ReadOptions ro;
  ro.freq = 100.0;
  const io::SignalSet set = io::read_signals(bench::shared_data_file("adis_16405_imu1.csv.gz"), ro);
  const std::string full = "3*AR1+WN+RW+QN+DR";
  const std::vector<std::string> subs = {"2*AR1+WN+RW+QN+DR", "3*AR1+RW+QN+DR", "3*AR1+WN+QN+DR", "3*AR1+WN+RW+DR",
                                         "3*AR1+WN+RW+QN"};
  int violations = 0, independent_violations = 0;
  bench::Stopwatch total;
  std::printf(
      "| column | model | objective | status | objective (independent fit of the full model) "
      "|\n|---|---|---|---|---|\n");
  for (const auto& sig : set.signals) {
    const WaveletVariance w = classical_wv(sig.values.data(), static_cast<std::int64_t>(sig.values.size()));
    FitOptions o;
    o.omega_matrix = diagonal_omega(w);
    const FitResult independent = fit_gmwm(w, parse_model(full), o);
    FitOptions ow = o;
    std::vector<FitResult> sub_fits;
    for (const auto& s : subs) {
      sub_fits.push_back(fit_gmwm(w, parse_model(s), o));
      ow.starts.push_back(embed_start(sub_fits.back().model, sub_fits.back().theta, parse_model(full), w));
    }
    ow.starts.push_back(independent.theta);
    const FitResult warm = fit_gmwm(w, parse_model(full), ow);
    std::printf("| %s | %s | %.10g | %s | %.10g |\n", sig.name.c_str(), full.c_str(), warm.objective,
                to_string(warm.status), independent.objective);
    for (std::size_t k = 0; k < subs.size(); ++k) {
      const bool bad = warm.objective > sub_fits[k].objective * (1 + 1e-9);
      const bool bad_ind = independent.objective > sub_fits[k].objective * (1 + 1e-9);
      violations += bad;
      independent_violations += bad_ind;
      std::printf("| %s | %s | %.10g | %s%s | |\n", sig.name.c_str(), subs[k].c_str(), sub_fits[k].objective,
                  to_string(sub_fits[k].status), bad ? " VIOLATION" : "");
    }
  }
  std::printf(
      "\nnested violations (full model above a sub-model, rel. tol 1e-9): %d of %zu with warm starts; "
      "%d of %zu for independent fits of the full model. Wall time %.2f s.\n",
      violations, set.signals.size() * subs.size(), independent_violations, set.signals.size() * subs.size(),
      total.seconds());
  return (violations == 0 && independent_violations == 0) ? 0 : 1;
}
