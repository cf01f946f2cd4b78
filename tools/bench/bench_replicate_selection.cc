// Selection accuracy with replicates against one signal of the same total length (issue
// 15). For four truths of bench_selection_accuracy, 50 data sets each: K = 3 replicates of
// 2^15 samples, ranked by the cross-validated WVIC (chosen and recommended) and by the
// joint fit's analytic WVIC; and one series of 3 x 2^15 samples ranked by the
// single-signal analytic WVIC. Maximal model 3*AR1+WN+RW+QN+DR (63 sub-models), Omega
// model. Scored: the truth (its canonical string) first.
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <oneapi/tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/selection/select.h"

namespace {

constexpr int kSets = 50;
constexpr int kLog2n = 15;
constexpr int kK = 3;
constexpr const char* kMaximal = "3*AR1+WN+RW+QN+DR";
constexpr int kBootstrapSets = 20;
constexpr int kBootstrapDraws = 20;

}  // namespace

// Arguments: optional 1-based truth numbers to run (default: all four), and "--bootstrap"
// to add the joint fit's parametric-bootstrap WVIC (kBootstrapDraws per candidate) on
// kBootstrapSets data sets per truth.
int main(int argc, char** argv) {
  using namespace gmwm;
  const char* truths[] = {"WN(sigma2=1)+QN(Q2=1)+RW(gamma2=3e-6)",
                          "AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=2)+RW(gamma2=1e-4)",
                          "AR1(phi=0.95,sigma2=0.05)+AR1(phi=0.998,sigma2=3e-4)+WN(sigma2=1)",
                          "AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)+QN(Q2=0.3)+DR(omega=1e-4)"};
  const Model maximal = parse_model(kMaximal);
  bool bootstrap = false;
  for (int a = 1; a < argc; ++a) bootstrap = bootstrap || std::string(argv[a]) == "--bootstrap";
  const int sets = bootstrap ? kBootstrapSets : kSets;
  std::printf("## Selection with replicates against one signal of the same length (bench_replicate_selection)\n\n");
  std::printf("%d data sets per truth: %d replicates of 2^%d samples, or one series of %d x 2^%d; maximal %s.\n\n",
              sets, kK, kLog2n, kK, kLog2n, kMaximal);
  if (bootstrap) std::printf("Bootstrap WVIC: %d draws of every replicate per candidate.\n\n", kBootstrapDraws);
  std::printf(
      "| truth | replicates: CV-WVIC chosen | replicates: recommended | replicates: joint analytic WVIC | %s"
      "one series: WVIC |\n|---|---|---|---|%s---|\n",
      bootstrap ? "replicates: joint bootstrap WVIC | " : "", bootstrap ? "---|" : "");
  bench::Stopwatch clock;
  std::vector<bool> run(4, argc <= 1 + static_cast<int>(bootstrap));
  for (int a = 1; a < argc; ++a) {
    if (std::string(argv[a]) == "--bootstrap") continue;
    const int t = std::atoi(argv[a]);
    if (t < 1 || t > 4) {
      std::fprintf(stderr, "bench_replicate_selection: truth numbers are 1..4, got '%s'\n", argv[a]);
      return 2;
    }
    run[static_cast<std::size_t>(t - 1)] = true;
  }
  std::uint64_t seed = 7100;
  for (std::size_t t = 0; t < 4; ++t) {
    const char* spec = truths[t];
    if (!run[t]) {
      seed += 1000;  // each truth keeps its own seeds
      continue;
    }
    const Model m = parse_model(spec);
    const std::string truth = m.canonical().to_string();
    std::atomic<int> cv{0}, rec{0}, ana{0}, boot{0}, single{0};
    oneapi::tbb::parallel_for(0, sets, [&](int i) {
      const std::int64_t n = std::int64_t{1} << kLog2n;
      std::vector<WaveletVariance> wvs;
      for (int k = 0; k < kK; ++k) {
        const auto x =
            simulate(m, m.given_values(), n, seed + static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(k));
        wvs.push_back(classical_wv(x.data(), n));
      }
      const auto long_x = simulate(m, m.given_values(), kK * n, seed + 100000 + static_cast<std::uint64_t>(i), 0);
      const WaveletVariance long_wv = classical_wv(long_x.data(), kK * n);
      selection::ReplicateSelectOptions ro;
      ro.seed = static_cast<std::uint64_t>(i);
      if (bootstrap) {
        ro.select.optimism = selection::OptimismMethod::kBoth;
        ro.select.bootstrap_replicates = kBootstrapDraws;
      }
      const auto r = selection::select_by_replicates(wvs, maximal, ro);
      cv += r.chosen == truth;
      rec += r.recommended == truth;
      ana += r.chosen_analytic == truth;
      boot += r.chosen_bootstrap == truth;
      const auto s = selection::select_models({long_wv}, maximal).front();
      single += !s.ranking.empty() && s.ranking.front().model == truth;
    });
    seed += 1000;
    const std::string boot_cell = bootstrap ? std::to_string(100 * boot / sets) + "% | " : "";
    std::printf("| %s | %d%% | %d%% | %d%% | %s%d%% |\n", spec, 100 * cv / sets, 100 * rec / sets, 100 * ana / sets,
                boot_cell.c_str(), 100 * single / sets);
    std::fflush(stdout);
  }
  std::printf("\n(%.0f s)\n", clock.seconds());
  return 0;
}
