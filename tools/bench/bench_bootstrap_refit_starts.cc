// Do bootstrap refits need a shape-based start beside the fit they are warm-started from?
// (issue 44: the bootstrap optimism's refits)
//
// A bootstrap replicate is simulated from a candidate's fit and refitted under the
// selection's Omega (selection/src/select.cc, bootstrap_optimism). The refit starts from
// the fit it was simulated from; until issue 44 it also started from the best placement of
// the components on the replicate's WV (multistarts = 1), whose search (every placement's
// sizes solved by NNLS) was 11% of a bootstrap's CPU. This compares, replicate by
// replicate, the refit from the fit alone (multistarts = 0, what the selection now does)
// with the refit from both (the oracle: it can only end lower), on every ranked row of a
// selection over 4*AR1+WN+RW on each axis of the three ADIS16405 units:
//   - how often, and by how much, the fit-alone refit ends above the other's objective;
//   - the bootstrap optimism (2 tr(Omega C)) each gives the row, the difference in units of
//     the oracle's Monte-Carlo s.e.
//
// Usage: bench_bootstrap_refit_starts [replicates per row = 20] [units = 3]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/selection/select.h"

using namespace gmwm;

namespace {

constexpr std::uint64_t kSeed = 44044;
// A refit "ends above" the oracle's when its objective is larger by more than this
// (relative): the optimiser's own tolerance (FitOptions::relative_tolerance 1e-12) times
// a margin for the polish's last steps.
constexpr double kSameObjective = 1e-9;

struct Refit {
  bool ok = false;
  double objective = NAN;
  Eigen::VectorXd implied, empirical;
};

// 2 tr(Omega C) of the replicates' (implied, empirical) pairs, and its Monte-Carlo s.e.,
// as selection/src/select.cc's bootstrap_optimism forms them.
std::pair<double, double> optimism(const std::vector<Refit>& r, const Eigen::MatrixXd& omega) {
  Eigen::VectorXd mi, me;
  int n = 0;
  for (const auto& x : r)
    if (x.ok) {
      mi = n == 0 ? x.implied : Eigen::VectorXd(mi + x.implied);
      me = n == 0 ? x.empirical : Eigen::VectorXd(me + x.empirical);
      ++n;
    }
  if (n < 2) return {NAN, NAN};
  mi /= n;
  me /= n;
  std::vector<double> terms;
  for (const auto& x : r)
    if (x.ok) terms.push_back(2.0 * (x.implied - mi).dot(omega * (x.empirical - me)));
  double sum = 0.0, sum2 = 0.0;
  for (double t : terms) sum += t;
  for (double t : terms) sum2 += (t - sum / n) * (t - sum / n);
  return {sum / (n - 1), std::sqrt(sum2 / (n - 1)) / std::sqrt(static_cast<double>(n)) * n / (n - 1)};
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  const int R = argc > 1 ? std::atoi(argv[1]) : 20;
  const int units = argc > 2 ? std::clamp(std::atoi(argv[2]), 1, 3) : 3;
  const Model maximal = parse_model("4*AR1+WN+RW");
  int rows = 0, replicates = 0, above = 0, failed_alone = 0, failed_oracle = 0;
  double worst_gap = 0.0, worst_se = 0.0;
  std::string worst_row;
  std::printf(
      "| unit | column | row | optimism, fit alone | optimism, oracle (MC s.e.) | difference / s.e. | refits above |\n"
      "|---|---|---|---|---|---|---|\n");
  for (int u = 1; u <= units; ++u) {
    const std::string file = bench::shared_data_file("adis_16405_imu" + std::to_string(u) + ".csv.gz");
    io::ReadOptions ro;
    ro.freq = 100.0;
    const io::SignalSet set = io::read_signals(file, ro);
    for (std::size_t c = 0; c < set.signals.size(); ++c) {
      const auto& s = set.signals[c];
      const std::vector<WaveletVariance> wv = {
          classical_wv(s.values.data(), static_cast<std::int64_t>(s.values.size()))};
      const selection::Selection sel = selection::select_models(wv, maximal).front();
      for (std::size_t k = 0; k < sel.ranking.size(); ++k) {
        const FitResult& fit = sel.ranking[k].fit;
        if (fit.status == FitStatus::kFailed) continue;
        std::vector<Refit> alone(static_cast<std::size_t>(R)), oracle(static_cast<std::size_t>(R));
        tbb::parallel_for(0, R, [&](int b) {
          const std::uint64_t stream = (static_cast<std::uint64_t>(u) * 64 + c) * 1024 * 1024 + k * 1024 + b;
          const std::vector<double> x = simulate(fit.model, fit.theta, wv[0].n, kSeed, stream);
          WvOptions wo;
          wo.levels = wv[0].levels();
          const WaveletVariance w = classical_wv(x.data(), wv[0].n, wo);
          if (w.levels() != wv[0].levels() || !w.values().allFinite()) return;
          for (int m = 0; m <= 1; ++m) {
            FitOptions fo;
            fo.omega_matrix = sel.omega;
            fo.nested_starts = false;
            fo.inference = false;
            fo.multistarts = m;
            fo.starts = {fit.theta};
            fo.log_not_converged = false;
            const FitResult r = fit_gmwm(w, fit.model, fo);
            Refit& out = (m == 0 ? alone : oracle)[static_cast<std::size_t>(b)];
            if (r.status == FitStatus::kFailed) continue;
            out = {true, r.objective, r.implied_wv, w.values()};
          }
        });
        int row_above = 0;
        for (int b = 0; b < R; ++b) {
          const Refit &a = alone[static_cast<std::size_t>(b)], &o = oracle[static_cast<std::size_t>(b)];
          failed_alone += !a.ok;
          failed_oracle += !o.ok;
          if (!a.ok || !o.ok) continue;
          ++replicates;
          const double gap = (a.objective - o.objective) / std::max(o.objective, 1e-300);
          if (gap > kSameObjective) ++row_above;
          worst_gap = std::max(worst_gap, gap);
        }
        above += row_above;
        const auto [oa, sa] = optimism(alone, sel.omega);
        const auto [oo, so] = optimism(oracle, sel.omega);
        const double d = so > 0 ? (oa - oo) / so : 0.0;
        if (std::abs(d) > std::abs(worst_se)) {
          worst_se = d;
          worst_row = "imu" + std::to_string(u) + " " + s.name + " " + sel.ranking[k].model;
        }
        ++rows;
        std::printf("| imu%d | %s | %s | %.6g | %.6g (%.2g) | %.2g | %d of %d |\n", u, s.name.c_str(),
                    sel.ranking[k].model.c_str(), oa, oo, so, d, row_above, R);
        std::fflush(stdout);
      }
    }
  }
  std::printf(
      "\n%d rows, %d replicates refitted both ways (failed: fit alone %d, oracle %d). The fit-alone refit ended above "
      "the oracle's objective (by > %.0e relative) in %d; the largest gap %.3g (relative). Largest optimism "
      "difference: %.3g Monte-Carlo s.e. (%s).\n",
      rows, replicates, failed_alone, failed_oracle, kSameObjective, above, worst_gap, worst_se, worst_row.c_str());
  return 0;
}
