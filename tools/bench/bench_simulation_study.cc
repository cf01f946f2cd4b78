// The published GMWM simulation study (Guerrier et al. 2013, JASA, WN + GM + DR):
// 100 series of length 6000 at 1 Hz from WN(sigma2 = 4) + GM(beta = 0.05,
// sigma2_gm = 16) + DR(omega = 0.005); fit WN+GM+DR; RMSE and relative RMSE per
// parameter. Published GMWM relative RMSEs: 0.03 (sigma2), 0.06 (sigma2_gm),
// 0.09 (beta), 0.06 (omega); the acceptance bar is 1.2 times those.
#include <cmath>
#include <cstdio>
#include <vector>

#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

using namespace gmwm;

int run(OmegaKind omega_kind) {
  constexpr int kSeries = 100;
  constexpr std::int64_t kLength = 6000;
  constexpr std::uint64_t kSeed = 2013;  // fixed before looking at results
  ProcessContext ctx;
  ctx.freq = 1.0;
  ctx.freq_known = true;
  const Model truth_model = parse_model("GM(beta=0.05,sigma2_gm=16)+WN(sigma2=4)+DR(omega=0.005)", ctx);
  const Eigen::VectorXd truth = truth_model.given_values();
  const Model fit_model = parse_model("GM+WN+DR", ctx);
  std::vector<Eigen::VectorXd> est(kSeries);
  std::vector<int> converged(kSeries);
  bench::Stopwatch sw;
  tbb::parallel_for(0, kSeries, [&](int r) {
    const auto x = simulate(truth_model, truth, kLength, kSeed, static_cast<std::uint64_t>(r));
    FitOptions o;
    o.omega = omega_kind;
    const FitResult f = fit_gmwm(classical_wv(x.data(), kLength), fit_model, o);
    est[static_cast<std::size_t>(r)] = f.theta;
    converged[static_cast<std::size_t>(r)] = f.status == FitStatus::kConverged;
  });
  const double secs = sw.seconds();
  const char* names[] = {"beta", "sigma2_gm", "sigma2", "omega"};
  const double published[] = {0.09, 0.06, 0.03, 0.06};
  int ok = 0, conv = 0;
  for (int c : converged) conv += c;
  std::printf("\nOmega = %s\n\n", to_string(omega_kind));
  std::printf("| parameter | truth | mean estimate | RMSE | relative RMSE | published GMWM | bar (1.2x) | verdict |\n|---|---|---|---|---|---|---|---|\n");
  for (int k = 0; k < 4; ++k) {
    double se2 = 0, mean = 0;
    for (const auto& e : est) {
      const double v = (k == 3) ? std::abs(e(k)) : e(k);
      se2 += (v - truth(k)) * (v - truth(k)) / kSeries;
      mean += v / kSeries;
    }
    const double rmse = std::sqrt(se2), rel = rmse / std::abs(truth(k));
    const bool pass = rel <= 1.2 * published[k];
    ok += pass;
    std::printf("| %s | %g | %.5g | %.4g | %.4f | %.2f | %.3f | %s |\n", names[k], truth(k), mean, rmse, rel,
                published[k], 1.2 * published[k], pass ? "pass" : "FAIL");
  }
  std::printf("\n%d series of length %lld, %d converged, %.2f s wall (%.1f ms per fit on 2 threads).\n", kSeries,
              static_cast<long long>(kLength), conv, secs, 1000 * secs / kSeries * 2);
  return ok == 4 ? 0 : 1;
}

int main() {
  const int diag = run(OmegaKind::kDiag);
  const int full = run(OmegaKind::kFull);
  return (diag == 0 || full == 0) ? 0 : 1;
}
