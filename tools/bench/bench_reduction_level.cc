// Level and power of the effective-form reduction (issue 27, engine/include/gmwm/engine/
// effective_model.h), each measured on series of N = 2^17 fitted exactly as `select`
// fits a candidate (select_among on the one model: the model-based Omega of its pilot,
// the exact Cov(nuhat) for the test):
//
//  - level, per kind of reduction: a spurious AR1 dropped (truth AR1(0.9, 0.1) + WN(1)
//    fitted as 2*AR1+WN), an AR1 that stands for a random walk (WN + RW fitted as AR1+WN),
//    an AR1 that stands for a white noise (AR1 + WN fitted as 2*AR1). The reduced model
//    is true, so the share of fits NOT reduced to it is the test's rejection rate under
//    its null; nominal alpha = 5%. A fit whose extra term collapsed (no share) is reduced
//    for free and tests nothing: those are counted apart.
//  - power: truth AR1(0.9, 0.1) + AR1(0.999, 1e-5) + WN(1) fitted as itself. The share of
//    fits whose slow AR1 is kept (the effective model is the truth's structure), against
//    the oracle that knows the slow component's form: the chi-square test (1 df, 5%) with
//    non-centrality the V0^-1 distance of the truth's exact WV from the best model without
//    it (bench_common.h, refit_noncentrality), power Phi-type upper bound for any
//    WV-based test.
//
//   build/bench_reduction_level [series]      (default 400; seeds fixed below)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "bench_detectability.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/selection/select.h"

using namespace gmwm;

namespace {

constexpr std::int64_t kN = 1 << 17;
constexpr std::uint64_t kLevelSeed = 27001, kPowerSeed = 27002;  // fixed before looking at results
constexpr double kAlpha = 0.05;

struct Outcome {
  std::string effective;
  double statistic = 0.0, threshold = 0.0;
  int tested = 0;
  std::string reductions;
};

Outcome reduce_one(const Model& truth, const Model& fitted, std::uint64_t seed, int r) {
  const auto x = simulate(truth, truth.given_values(), kN, seed, static_cast<std::uint64_t>(r));
  const std::vector<WaveletVariance> wv = {classical_wv(x.data(), kN)};
  selection::SelectOptions o;
  const selection::Selection sel = selection::select_among(wv, {fitted}, o).front();
  const EffectiveModel& e = sel.candidates.front().effective;
  Outcome out{e.model.to_string(), e.statistic, e.threshold, e.tested_parameters, ""};
  for (const auto& s : e.reductions) out.reductions += (out.reductions.empty() ? "" : "; ") + s;
  return out;
}

std::vector<Outcome> run(const char* truth_spec, const char* fitted_spec, std::uint64_t seed, int series) {
  const Model truth = parse_model(truth_spec), fitted = parse_model(fitted_spec);
  std::vector<Outcome> out(static_cast<std::size_t>(series));
  tbb::parallel_for(0, series, [&](int r) { out[static_cast<std::size_t>(r)] = reduce_one(truth, fitted, seed, r); });
  return out;
}

void print_outcomes(const std::vector<Outcome>& v) {
  std::map<std::string, int> by;
  for (const auto& o : v) ++by[o.effective];
  for (const auto& [k, n] : by) std::printf("  - effective %s: %d\n", k.c_str(), n);
}

// Monte-Carlo standard error of a proportion p over n series.
double mc_se(double p, int n) { return std::sqrt(p * (1.0 - p) / n); }

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  const int series = argc > 1 ? std::atoi(argv[1]) : 400;
  bench::Stopwatch clock;

  // Level, one case per kind of reduction, each under its own null (the reduced model true):
  struct LevelCase {
    const char* kind;
    const char* truth;
    const char* fitted;
    std::uint64_t seed;
  };
  const LevelCase cases[] = {
      // a spurious AR1 beside a real one: dropped
      {"drop", "AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)", "2*AR1+WN", kLevelSeed},
      // an AR1 standing for a random walk (phi -> 1): RW-like (the truth's RW detectable, nc 51)
      {"RW-like", "WN(sigma2=1)+RW(gamma2=1e-5)", "AR1+WN", kLevelSeed + 10},
      // an AR1 standing for a white noise (phi -> 0) beside a real AR1: WN-like
      {"WN-like", "AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)", "2*AR1", kLevelSeed + 20},
  };
  std::printf(
      "Level of each kind of reduction: the reduced model is true, so the share of fits NOT reduced to it "
      "is the test's rejection rate under its null; %d series of N = 2^17 each, nominal %.0f%%.\n\n",
      series, 100 * kAlpha);
  std::printf(
      "| reduction | truth | fitted as | reduced for free (nothing tested) | tested | not reduced | "
      "rejection rate under the null |\n|---|---|---|---|---|---|---|\n");
  for (const LevelCase& c : cases) {
    const auto lv = run(c.truth, c.fitted, c.seed, series);
    const std::string reduced = parse_model(c.truth).to_string();
    int tested = 0, rejected = 0, free_reduced = 0;
    for (const auto& o : lv) {
      if (o.effective == reduced) {
        if (o.tested > 0)
          ++tested;
        else
          ++free_reduced;
      } else {
        ++tested;
        ++rejected;
      }
    }
    const double level = tested ? static_cast<double>(rejected) / tested : 0.0;
    std::printf("| %s | %s | %s | %d | %d | %d | %.1f%% +- %.1f%% |\n", c.kind, c.truth, c.fitted, free_reduced, tested,
                rejected, 100 * level, 100 * mc_se(level, std::max(tested, 1)));
    if (std::getenv("GMWM_BENCH_VERBOSE")) {
      print_outcomes(lv);
      for (const auto& o : lv)
        std::printf("    %s S %.3g (threshold %.3g, %d df): %s\n", o.effective.c_str(), o.statistic, o.threshold,
                    o.tested, o.reductions.c_str());
    }
    std::fflush(stdout);
  }

  const char* slow_truth = "AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=1e-5)+WN(sigma2=1)";
  const Model st = parse_model(slow_truth);
  const auto pw = run(slow_truth, "2*AR1+WN", kPowerSeed, series);
  int kept = 0;
  for (const auto& o : pw) kept += o.effective == st.to_string();
  const auto refit = bench::refit_noncentrality(st, kN);
  // The slow AR1 is the truth's second component in canonical order (the larger phi).
  double nc_slow = 0.0;
  for (int c = 0; c < st.num_components(); ++c)
    if (st.components()[static_cast<std::size_t>(c)].process->name() == "AR1" && st.given_values()(st.offset(c)) > 0.99)
      nc_slow = refit[static_cast<std::size_t>(c)];
  const double power = static_cast<double>(kept) / series;
  std::printf("\nPower: truth %s fitted as itself, %d series (seed %llu).\n", slow_truth, series,
              static_cast<unsigned long long>(kPowerSeed));
  print_outcomes(pw);
  std::printf("  slow AR1 kept %.1f%% +- %.1f%%; oracle (its form known, the others re-estimated: nc %.3g) %.1f%%\n",
              100 * power, 100 * mc_se(power, series), nc_slow, 100 * bench::oracle_power(nc_slow));
  std::printf("\n(%.0f s)\n", clock.seconds());
  return 0;
}
