// Does the goodness-of-fit test hold its level? (issue 43, item 4)
//
// For each true model (WN+QN+RW, AR1+WN+RW, 2*AR1+WN) at N = 2^17: series simulated from
// it, and the rejection rate at 5% of the true model by
//   - own:    `gmwm fit --model TRUTH` (fit_gmwm with its defaults),
//   - shared: the true model's row of a selection over 3*AR1+WN+RW+QN+DR (select_models,
//             its shared Omega and V),
//   - oracle: the statistic at the true parameters, (nuhat - nu)' V^-1 (nuhat - nu) with
//             V at the truth, against chi-square(J): what the normal approximation of
//             nuhat alone costs, no estimation involved.
// A calibrated test rejects 5% +- 2 Monte-Carlo s.e. (sqrt(0.05 * 0.95 / series)).
//
// Usage: bench_gof_level [series per model = 200] [which: all | own | shared | oracle]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/selection/select.h"

using namespace gmwm;

namespace {

constexpr std::int64_t kN = std::int64_t{1} << 17;
constexpr double kLevel = 0.05;
constexpr std::uint64_t kSeed = 43004;

struct Truth {
  const char* spec;
};

// IMU-like: a white floor, and the slow component the WN+QN+RW case carried.
const Truth kTruths[] = {
    {"WN(sigma2=1)+QN(Q2=2)+RW(gamma2=1e-6)"},
    {"AR1(phi=0.995,sigma2=1e-3)+WN(sigma2=1)+RW(gamma2=1e-6)"},
    {"AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=1e-3)+WN(sigma2=1)"},
};

struct Column {
  std::vector<double> p;
  int missing = 0;  // no p-value (no row of that model, or a degenerate test)
};

void print_row(const char* truth, const char* column, const Column& c) {
  std::vector<double> p;
  for (double v : c.p)
    if (std::isfinite(v)) p.push_back(v);
  std::sort(p.begin(), p.end());
  const double m = static_cast<double>(p.size());
  int rejected = 0;
  for (double v : p) rejected += v < kLevel;
  const double rate = m > 0 ? rejected / m : NAN;
  const double se = std::sqrt(kLevel * (1.0 - kLevel) / std::max(m, 1.0));
  std::printf("| %s | %s | %zu | %d | %.1f%% | %s |", truth, column, p.size(), c.missing, 100.0 * rate,
              std::abs(rate - kLevel) <= 2.0 * se ? "yes" : "no");
  for (int d = 1; d <= 9; ++d) std::printf(" %.2f", p.empty() ? NAN : p[p.size() * static_cast<std::size_t>(d) / 10]);
  std::printf(" |\n");
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  const int series = argc > 1 ? std::atoi(argv[1]) : 200;
  const std::string which = argc > 2 ? argv[2] : "all";
  const bool do_own = which == "all" || which == "own", do_shared = which == "all" || which == "shared",
             do_oracle = which == "all" || which == "oracle";
  const Model maximal = parse_model("3*AR1+WN+RW+QN+DR");
  std::printf("N = %lld, %d series per model, level %.0f%%; a calibrated test: within %.1f%% +- %.1f%% (2 s.e.)\n\n",
              static_cast<long long>(kN), series, 100 * kLevel, 100 * kLevel,
              200 * std::sqrt(kLevel * (1 - kLevel) / series));
  std::printf(
      "| true model | test | p-values | none | rejected at 5%% | within 2 s.e. | p deciles 10%%..90%% |\n"
      "|---|---|---|---|---|---|---|\n");
  for (const Truth& t : kTruths) {
    const Model given = parse_model(t.spec);
    Eigen::VectorXd theta = given.given_values();
    const Model truth = given.canonical(&theta);
    const std::string name = truth.to_string();
    const Model bare = parse_model(name);  // as a user writes it: no values
    Column own, shared, oracle, own_full, own_before, own_full_before, shared_before;
    for (Column* c : {&own_full, &own_before, &own_full_before, &shared_before})
      c->p.assign(static_cast<std::size_t>(series), NAN);
    own.p.assign(static_cast<std::size_t>(series), NAN);
    shared.p.assign(static_cast<std::size_t>(series), NAN);
    oracle.p.assign(static_cast<std::size_t>(series), NAN);
    std::vector<char> no_row(static_cast<std::size_t>(series), 0);
    const bench::Stopwatch clock;
    tbb::parallel_for(0, series, [&](int s) {
      const auto i = static_cast<std::size_t>(s);
      const std::vector<double> x = simulate(truth, theta, kN, kSeed, static_cast<std::uint64_t>(s));
      const WaveletVariance wv = classical_wv(x.data(), kN);
      if (do_oracle) {
        const Eigen::MatrixXd V = model_wv_covariance(truth, theta, wv.n, wv.levels());
        const Eigen::VectorXd e = wv.values() - truth.wv(theta, wv.tau);
        const double q = e.dot(V.ldlt().solve(e));
        oracle.p[i] =
            boost::math::cdf(boost::math::complement(boost::math::chi_squared(static_cast<double>(wv.levels())), q));
      }
      // The test as it was before issue 43 (item 4): measured with the V that formed Omega
      // (the pilot's), chi-square when Omega is that V's inverse.
      auto with_v = [&](const FitResult& f, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v, bool inverse) {
        return goodness_of_fit(f.model.jacobian(f.theta, wv.tau), f.objective, wv.levels() - f.model.num_parameters(),
                               omega, v, inverse)
            .p_value;
      };
      if (do_own) {
        const FitResult f = fit_gmwm(wv, bare);
        own.p[i] = f.gof.p_value;
        own_before.p[i] = with_v(f, f.omega, f.wv_covariance, false);
        FitOptions full;
        full.omega = OmegaKind::kFull;
        const FitResult g = fit_gmwm(wv, bare, full);
        own_full.p[i] = g.gof.p_value;
        own_full_before.p[i] = with_v(g, g.omega, g.wv_covariance, true);
      }
      if (do_shared) {
        const auto sel = selection::select_models({wv}, maximal).front();
        for (const auto& row : sel.ranking)
          if (row.model == name) {
            shared.p[i] = row.gof.p_value;
            shared_before.p[i] = with_v(row.fit, sel.omega, sel.v, false);
          }
        if (!std::isfinite(shared.p[i])) no_row[i] = 1;
      }
    });
    for (char c : no_row) shared.missing += c;
    shared_before.missing = shared.missing;
    if (do_oracle) print_row(name.c_str(), "oracle: true parameters, V^-1, chi-square(J)", oracle);
    if (do_own) {
      print_row(name.c_str(), "own (fit), before: the pilot's V", own_before);
      print_row(name.c_str(), "own (fit)", own);
      print_row(name.c_str(), "own, --omega full, before: chi-square with the pilot's V", own_full_before);
      print_row(name.c_str(), "own, --omega full", own_full);
    }
    if (do_shared) {
      print_row(name.c_str(), "shared, before: the maximal pilot's V", shared_before);
      print_row(name.c_str(), "shared (select over 3*AR1+WN+RW+QN+DR)", shared);
    }
    std::fprintf(stderr, "%s: %.1f s\n", name.c_str(), clock.seconds());
  }
  return 0;
}
