// Long gaps: one record's windows pooled, or its segments as replicates? (issue 47, item 1).
// A record of AR1+WN+RW whose long gaps split it into segments, fitted two ways with the true
// structure and gmwm fit's defaults: (a) the WV from the complete windows of the whole record
// (classical_wv_with_gaps: every segment's windows pooled, each window weighted alike), the
// single fit; (b) each segment's own classical WV, the joint fit over them as replicates
// (fit_gmwm_joint: each segment weighted by its own model-based covariance). The truth is the
// oracle: per parameter the relative RMSE of the estimates and the coverage of their 95%
// intervals, over S series per layout.
//
//   build/bench_segments [series, default 200] [log2 N, default 18]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench_common.h"
#include "bench_gap_patterns.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/simulate.h"

using namespace gmwm;

namespace {

// bench_gaps' gyroscope-like truth (white noise first, a Gauss-Markov bias, a random walk).
constexpr const char* kTruth = "AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=2)+RW(gamma2=1e-4)";
constexpr double kGapShare = 0.01;  // each long gap removes 1% of the grid

// A layout: where the long gaps start, as shares of the grid.
struct Layout {
  const char* name;
  std::vector<double> at;
};

struct Estimate {
  std::vector<double> relative_error;  // per parameter, estimate / truth - 1 (NaN: failed)
  std::vector<bool> covered;
};

Estimate estimate_of(const FitResult& f, const Eigen::VectorXd& truth) {
  Estimate e;
  const bool ok = f.status != FitStatus::kFailed && f.theta.size() == truth.size() && f.theta.allFinite() &&
                  f.ci_low.size() == truth.size();
  for (Eigen::Index k = 0; k < truth.size(); ++k) {
    e.relative_error.push_back(ok ? f.theta(k) / truth(k) - 1.0 : NAN);
    e.covered.push_back(ok && f.ci_low(k) <= truth(k) && truth(k) <= f.ci_high(k));
  }
  return e;
}

// "rmse% (coverage%)" per parameter, over the finite estimates.
std::string summary(const std::vector<Estimate>& es, Eigen::Index p) {
  std::string out;
  for (Eigen::Index k = 0; k < p; ++k) {
    double ss = 0.0, covered = 0.0;
    int n = 0;
    for (const Estimate& e : es) {
      const double r = e.relative_error[static_cast<std::size_t>(k)];
      covered += e.covered[static_cast<std::size_t>(k)];
      if (!std::isfinite(r)) continue;
      ss += r * r;
      ++n;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%.1f (%.0f)", out.empty() ? "" : " / ", 100.0 * std::sqrt(ss / std::max(n, 1)),
                  100.0 * covered / static_cast<double>(es.size()));
    out += buf;
  }
  return out;
}

void study(const Layout& layout, int series, std::int64_t n, std::uint64_t seed) {
  const Model truth = parse_model(kTruth);
  const Eigen::VectorXd given = truth.given_values();
  const Model structure = parse_model(truth.to_string());
  std::vector<MissingRun> runs;
  for (const double a : layout.at)
    runs.push_back({static_cast<std::int64_t>(a * static_cast<double>(n)),
                    static_cast<std::int64_t>(kGapShare * static_cast<double>(n))});
  std::vector<Estimate> pooled(static_cast<std::size_t>(series)), joint(pooled.size());
  bench::Stopwatch clock;
  double pooled_seconds = 0.0, joint_seconds = 0.0;
  for (int s = 0; s < series; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::vector<double> x = simulate(truth, given, n, seed, static_cast<std::uint64_t>(s));
    clock.reset();
    WaveletVariance windows = classical_wv_with_gaps(bench::observed_of(x, runs), runs);
    drop_incomplete_levels(windows);
    pooled[i] = estimate_of(fit_gmwm(windows, structure), given);
    pooled_seconds += clock.seconds();
    clock.reset();
    std::vector<WaveletVariance> parts;
    std::int64_t from = 0;
    for (std::size_t g = 0; g <= runs.size(); ++g) {
      const std::int64_t to = g < runs.size() ? runs[g].start : n;
      parts.push_back(classical_wv(x.data() + from, to - from));
      if (g < runs.size()) from = runs[g].start + runs[g].length;
    }
    joint[i] = estimate_of(fit_gmwm_joint(parts, structure).joint, given);
    joint_seconds += clock.seconds();
  }
  std::printf("| %s | %s | %s | %.2f s / %.2f s |\n", layout.name, summary(pooled, given.size()).c_str(),
              summary(joint, given.size()).c_str(), pooled_seconds / series, joint_seconds / series);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  const int series = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  const int log2n = argc > 2 ? std::clamp(std::atoi(argv[2]), 14, 22) : 18;
  const std::int64_t n = std::int64_t{1} << log2n;
  std::printf(
      "%s, %d series at N = 2^%d per row, each long gap 1%% of the grid. Per parameter (phi, sigma2 of AR1, sigma2 "
      "of WN, gamma2 of RW): relative RMSE %% (coverage of the 95%% interval %%).\n\n"
      "| segments | pooled windows, single fit | segments as replicates, joint fit | s per series |\n"
      "|---|---|---|---|\n",
      kTruth, series, log2n);
  const std::vector<Layout> layouts = {{"2 halves", {0.5}},
                                       {"4 unequal (gaps at 10%, 40%, 85%)", {0.10, 0.40, 0.85}},
                                       {"8 equal", {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875}}};
  std::uint64_t seed = 4750;
  for (const Layout& l : layouts) study(l, series, n, seed++);
  return 0;
}
