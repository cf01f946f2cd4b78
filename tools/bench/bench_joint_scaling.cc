// The joint (MGMWM) model of a fleet and its shared-theta test at fleet size (issue 30):
// K units of one sensor model, each WN + RW + AR1 with unit-to-unit spread (every unit's
// white-noise and AR1 variances, random-walk rate and AR1 correlation time multiplied by
// exp(SPREAD Z), Z standard normal: a lognormal spread of 15% sd by default), 2^log2n samples per
// unit. Timed, each on its own: the units' WVs; fit_gmwm_joint (with inference);
// replicate_test with the asymptotic chi-square and with the parametric bootstrap
// (B draws); replicate_bootstrap (the replicate-t intervals); select_by_replicates over
// the maximal model WN+RW+AR1 (random half-splits beyond 12 units). Peak RSS from
// getrusage.
//
//   build-joint/bench_joint_scaling [K [log2n [B [SPREAD]]]]
//
// (defaults 495, 18, 100, 0.15; B = 0: no bootstrap test; SPREAD = 0: units that share theta)
//
// Prints a markdown section for tools/bench/results/.
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <boost/random/normal_distribution.hpp>
#include <oneapi/tbb/info.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/selection/replicate_select.h"

namespace gmwm {
namespace {

// The fleet's typical unit: a random walk the coarsest levels of one unit's 2^18 samples
// barely see (its WV crosses the AR1's near tau = 2^16), resolved jointly.
constexpr double kWn = 1e-2, kAr1Sigma2 = 1e-5, kAr1Time = 200.0, kRw = 1e-9;
// The sd of the log of each unit's factor on each parameter: 15%, in the 10-20% of a
// datasheet's unit-to-unit spread.
constexpr double kDefaultSpread = 0.15;
constexpr std::uint64_t kSeed = 30495;

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

std::string spec(double wn, double ar, double time, double rw) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "AR1(phi=%.17g,sigma2=%.17g)+WN(sigma2=%.17g)+RW(gamma2=%.17g)", std::exp(-1.0 / time),
                ar, wn, rw);
  return buf;
}

// Unit k's model with its own factors (stream k of kSeed).
std::string unit_spec(int k, double spread) {
  Rng rng = make_stream(kSeed, {0x756eu, static_cast<std::uint64_t>(k)});
  boost::random::normal_distribution<double> z(0.0, 1.0);
  const double wn = kWn * std::exp(spread * z(rng)), ar = kAr1Sigma2 * std::exp(spread * z(rng));
  const double time = kAr1Time * std::exp(spread * z(rng)), rw = kRw * std::exp(spread * z(rng));
  return spec(wn, ar, time, rw);
}

// The K units' classical WVs (in parallel; each unit's series is dropped once its WV is made).
std::vector<WaveletVariance> fleet(int K, int log2n, double spread) {
  std::vector<WaveletVariance> wvs(static_cast<std::size_t>(K));
  const std::int64_t n = std::int64_t{1} << log2n;
  gmwm::parallel_for(0, K, [&](int k) {
    const Model m = parse_model(unit_spec(k, spread));
    const std::vector<double> x = simulate(m, m.given_values(), n, kSeed, static_cast<std::uint64_t>(k));
    wvs[static_cast<std::size_t>(k)] = classical_wv(x.data(), n);
  });
  return wvs;
}

void print_fit(const JointFitResult& r, double seconds) {
  const FitResult& j = r.joint;
  std::printf("| fit_gmwm_joint (with inference) | %.1f s | %s; objective %.6g, GoF df %.0f, p %.3g |\n", seconds,
              j.model.to_string(j.theta).c_str(), j.objective, j.gof.df, j.gof.p_value);
}

void print_test(const char* what, const ReplicateTest& t, double seconds) {
  std::printf("| replicate_test, %s | %.1f s | H = %.6g (p %.3g), T = %.6g (p %.3g)", what, seconds, t.heterogeneity,
              t.heterogeneity_p, t.statistic, t.p_value);
  if (t.calibration == ReplicateCalibration::kChiSquare)
    std::printf(", df %.0f and %.0f", t.df_heterogeneity, t.df_statistic);
  else
    std::printf(", %d draws", t.draws);
  std::printf(" |\n");
}

int run(int K, int log2n, int draws, double spread) {
  std::printf("## Joint model and shared-theta test of a fleet (bench_joint_scaling %d %d %d %g)\n\n", K, log2n, draws,
              spread);
  std::printf(
      "%d units of 2^%d samples, each %s with every parameter (the AR1 by its correlation time) times "
      "exp(%.2f Z); %d threads.\n\n",
      K, log2n, spec(kWn, kAr1Sigma2, kAr1Time, kRw).c_str(), spread, tbb::info::default_concurrency());
  std::printf("| step | wall time | result |\n|---|---|---|\n");
  bench::Stopwatch clock;
  const std::vector<WaveletVariance> wvs = fleet(K, log2n, spread);
  std::printf("| simulate the units and their WVs | %.1f s | %d levels each |\n", clock.seconds(),
              wvs.front().levels());
  const Model maximal = parse_model("AR1+WN+RW");
  clock.reset();
  const JointFitResult fit = fit_gmwm_joint(wvs, maximal);
  print_fit(fit, clock.seconds());
  ReplicateTestOptions to;
  to.fit.inference = false;
  to.calibration = ReplicateCalibration::kChiSquare;
  clock.reset();
  const ReplicateTest chi = replicate_test(wvs, fit, to);
  print_test("chi-square", chi, clock.seconds());
  if (draws > 0) {
    to.calibration = ReplicateCalibration::kBootstrap;
    to.bootstrap = draws;
    clock.reset();
    const ReplicateTest boot = replicate_test(wvs, fit, to);
    print_test("bootstrap", boot, clock.seconds());
  }
  clock.reset();
  const ReplicateBootstrap boot = replicate_bootstrap(wvs, fit, 0.05, 200, 0, to.fit);
  std::printf("| replicate_bootstrap (replicate-t, 200 resamples) | %.1f s | %d fits; RW gamma2 in [%.3g, %.3g] |\n",
              clock.seconds(), boot.draws, boot.ci_low(3), boot.ci_high(3));
  clock.reset();
  const selection::ReplicateSelection sel = selection::select_by_replicates(wvs, maximal);
  std::printf("| select_by_replicates over %s | %.1f s | %zu splits; chosen %s, recommended %s |\n",
              maximal.to_string().c_str(), clock.seconds(), sel.training.size(), sel.chosen.c_str(),
              sel.recommended.c_str());
  std::printf("\nPeak resident memory: %.0f MB.\n", peak_rss_mb());
  return 0;
}

}  // namespace
}  // namespace gmwm

int main(int argc, char** argv) {
  const int K = argc > 1 ? std::atoi(argv[1]) : 495;
  const int log2n = argc > 2 ? std::atoi(argv[2]) : 18;
  const int draws = argc > 3 ? std::atoi(argv[3]) : 100;
  const double spread = argc > 4 ? std::atof(argv[4]) : gmwm::kDefaultSpread;
  if (K < 2 || log2n < 8 || log2n > 26 || draws < 0 || (draws > 0 && draws < 19) || !(spread >= 0.0)) {
    std::fprintf(stderr, "bench_joint_scaling: K >= 2, 8 <= log2n <= 26, B = 0 or >= 19, SPREAD >= 0\n");
    return 2;
  }
  return gmwm::run(K, log2n, draws, spread);
}
