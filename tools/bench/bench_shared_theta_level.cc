// The shared-theta test's level under its null (issue 30): data sets of K replicates that
// share one theta, each tested with the asymptotic chi-square calibration and (B > 0) with
// the parametric bootstrap of B draws. The rejection rate of each at 5% is its level (the
// data sets are the oracle: simulated from the null itself); the mean of H / ((K - 1) q)
// and of T / (sum_k J_k - q) says how far the statistics' means are from the chi-square's
// (a relative excess d of the mean moves H by d (K - 1) q, against a chi-square standard
// deviation of sqrt(2 (K - 1) q): the larger K, the more a small d costs the chi-square).
//
//   build-joint/bench_shared_theta_level TRUTH K log2n SETS [B] [MISSING]
//
// MISSING > 0 (a share, e.g. 0.2; issue 47): each replicate misses that share of its grid in
// random bursts of 1-200 samples, its own pattern; its WV reads the windows without a gap, and
// the bootstrap draws each replicate through its own gaps (what gmwm does), beside draws of
// whole grids read by the classical WV (what the fleet's joint model did before): the last
// two columns are those draws' level of H and of T.
//
// TRUTH: 1 = WN(sigma2=1e-2)+RW(gamma2=1e-8) (the issue-15 level study's), 2 =
// AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=1e-2)+RW(gamma2=1e-6) (resolved at 2^12), 3 = the
// fleet's unit AR1(phi=exp(-1/200),sigma2=1e-5)+WN(sigma2=1e-2)+RW(gamma2=1e-9). Every
// replicate has 2^log2n samples. Prints one markdown table row.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_common.h"
#include "bench_gap_patterns.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

constexpr std::uint64_t kSeed = 30100;

std::string truth(int t) {
  if (t == 1) return "WN(sigma2=1e-2)+RW(gamma2=1e-8)";
  if (t == 2) return "AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=1e-2)+RW(gamma2=1e-6)";
  char buf[160];
  std::snprintf(buf, sizeof buf, "AR1(phi=%.17g,sigma2=1e-5)+WN(sigma2=1e-2)+RW(gamma2=1e-9)", std::exp(-1.0 / 200.0));
  return buf;
}

struct Tally {
  int sets = 0, chi_h = 0, chi_t = 0, boot_h = 0, boot_t = 0, whole_h = 0, whole_t = 0;
  double h_ratio = 0.0, t_ratio = 0.0, seconds_chi = 0.0, seconds_boot = 0.0;
};

void one_set(const Model& m, const Model& fitted, int K, int log2n, int draws, double missing, std::uint64_t seed,
             Tally& tally) {
  std::vector<WaveletVariance> wvs(static_cast<std::size_t>(K));
  const std::int64_t n = std::int64_t{1} << log2n;
  // Each replicate's own gaps (none without MISSING), its WV from the windows without one.
  std::vector<std::unique_ptr<GappyWvEstimator>> own;
  for (int k = 0; k < K && missing > 0.0; ++k)
    own.push_back(std::make_unique<GappyWvEstimator>(
        bench::pattern_runs(bench::Pattern::kBursts, n, missing, seed * 131 + static_cast<std::uint64_t>(k))));
  gmwm::parallel_for(0, K, [&](int k) {
    const auto x = simulate(m, m.given_values(), n, seed, static_cast<std::uint64_t>(k));
    WaveletVariance& w = wvs[static_cast<std::size_t>(k)];
    if (own.empty()) {
      w = classical_wv(x.data(), n);
      return;
    }
    w = own[static_cast<std::size_t>(k)]->compute(x.data(), n, 0, 0.05);
    drop_incomplete_levels(w);
  });
  FitOptions fo;
  fo.log_not_converged = false;
  const JointFitResult r = fit_gmwm_joint(wvs, fitted, fo);
  if (r.joint.status == FitStatus::kFailed) return;
  ReplicateTestOptions o;
  o.fit.inference = false;
  o.fit.log_not_converged = false;
  o.calibration = ReplicateCalibration::kChiSquare;
  bench::Stopwatch clock;
  const ReplicateTest c = replicate_test(wvs, r, o);
  tally.seconds_chi += clock.seconds();
  ++tally.sets;
  tally.chi_h += c.heterogeneity_p <= kReplicateTestLevel;
  tally.chi_t += c.p_value <= kReplicateTestLevel;
  tally.h_ratio += c.heterogeneity / c.df_heterogeneity;
  tally.t_ratio += c.statistic / c.df_statistic;
  if (draws == 0) return;
  o.calibration = ReplicateCalibration::kBootstrap;
  o.bootstrap = draws;
  o.seed = seed;
  for (const auto& e : own) o.estimators.push_back(e.get());
  clock.reset();
  const ReplicateTest b = replicate_test(wvs, r, o);
  tally.seconds_boot += clock.seconds();
  tally.boot_h += b.heterogeneity_p <= kReplicateTestLevel;
  tally.boot_t += b.p_value <= kReplicateTestLevel;
  if (own.empty()) return;
  o.estimators.clear();  // whole grids, the classical WV
  const ReplicateTest w = replicate_test(wvs, r, o);
  tally.whole_h += w.heterogeneity_p <= kReplicateTestLevel;
  tally.whole_t += w.p_value <= kReplicateTestLevel;
}

// "x.x% +- y.y" with the binomial Monte-Carlo standard error.
std::string rate(int hits, int sets) {
  const double p = static_cast<double>(hits) / sets;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.1f%% +- %.1f", 100.0 * p, 100.0 * std::sqrt(0.05 * 0.95 / sets));
  return buf;
}

}  // namespace
}  // namespace gmwm

int main(int argc, char** argv) {
  using namespace gmwm;
  if (argc < 5) {
    std::fprintf(stderr, "usage: bench_shared_theta_level TRUTH(1-3) K log2n SETS [B]\n");
    return 2;
  }
  const int t = std::atoi(argv[1]), K = std::atoi(argv[2]), log2n = std::atoi(argv[3]), sets = std::atoi(argv[4]);
  const int draws = argc > 5 ? std::atoi(argv[5]) : 0;
  const double missing = argc > 6 ? std::atof(argv[6]) : 0.0;
  if (t < 1 || t > 3 || K < 2 || log2n < 8 || sets < 1 || draws < 0 || (draws > 0 && draws < 19) ||
      !(missing >= 0.0 && missing < 0.5) || (missing > 0.0 && draws == 0)) {
    std::fprintf(stderr,
                 "bench_shared_theta_level: TRUTH 1-3, K >= 2, log2n >= 8, SETS >= 1, B = 0 or >= 19, MISSING in "
                 "[0, 0.5) (with B > 0)\n");
    return 2;
  }
  const Model m = parse_model(truth(t));
  const Model fitted = m.canonical();  // the truth's structure, values free
  Tally tally;
  bench::Stopwatch clock;
  for (int s = 0; s < sets; ++s)
    one_set(m, parse_model(fitted.to_string()), K, log2n, draws, missing,
            kSeed + 1000 * static_cast<std::uint64_t>(t) + s, tally);
  if (missing > 0.0)
    std::printf("| %s | %d | 2^%d | %.0f%% | %d | %s | %s | %s | %s | %s | %s | %.0f s |\n", truth(t).c_str(), K, log2n,
                100.0 * missing, tally.sets, rate(tally.chi_h, tally.sets).c_str(),
                rate(tally.chi_t, tally.sets).c_str(), rate(tally.boot_h, tally.sets).c_str(),
                rate(tally.boot_t, tally.sets).c_str(), rate(tally.whole_h, tally.sets).c_str(),
                rate(tally.whole_t, tally.sets).c_str(), clock.seconds());
  else
    std::printf("| %s | %d | 2^%d | %d | %s | %s | %.3f | %.3f | %s | %s | %.2f s / %.1f s | %.0f s |\n",
                truth(t).c_str(), K, log2n, tally.sets, rate(tally.chi_h, tally.sets).c_str(),
                rate(tally.chi_t, tally.sets).c_str(), tally.h_ratio / tally.sets, tally.t_ratio / tally.sets,
                draws ? rate(tally.boot_h, tally.sets).c_str() : "-",
                draws ? rate(tally.boot_t, tally.sets).c_str() : "-", tally.seconds_chi / tally.sets,
                draws ? tally.seconds_boot / tally.sets : 0.0, clock.seconds());
  return 0;
}
