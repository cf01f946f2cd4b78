// The published GMWM simulation study (Guerrier et al. 2013, JASA, WN + GM + DR):
// 100 series of length 6000 at 1 Hz from WN(sigma2 = 4) + GM(beta = 0.05,
// sigma2_gm = 16) + DR(omega = 0.005); fit WN+GM+DR; RMSE and relative RMSE per
// parameter. Published GMWM relative RMSEs: 0.03 (sigma2), 0.06 (sigma2_gm),
// 0.09 (beta), 0.06 (omega); the acceptance bar is 1.2 times those.
//
// Besides the published design (100 series, whose relative RMSEs carry a Monte-Carlo
// relative error of about 1/sqrt(2 x 100) = 7%), the study is repeated with 2000 series
// (1.6%), and the asymptotic relative standard errors are printed: the sandwich
// sqrt(diag((A' V^-1 A)^-1)) / |theta| at the truth with the exact model-based V of all
// floor(log2 6000) = 12 levels. V^-1 is the efficient weighting, so no GMWM on the Haar
// WV of these levels can have a smaller asymptotic variance, whatever its Omega.
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Dense>
#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

using namespace gmwm;

namespace {

constexpr std::int64_t kLength = 6000;
constexpr std::uint64_t kSeed = 2013;  // fixed before looking at results
constexpr int kPublishedSeries = 100;
constexpr int kPreciseSeries = 2000;
const char* const kNames[] = {"beta", "sigma2_gm", "sigma2", "omega"};
constexpr double kPublished[] = {0.09, 0.06, 0.03, 0.06};
constexpr double kBarFactor = 1.2;

ProcessContext one_hz() {
  ProcessContext ctx;
  ctx.freq = 1.0;
  ctx.freq_known = true;
  return ctx;
}

const Model& truth_model() {
  static const Model m = parse_model("GM(beta=0.05,sigma2_gm=16)+WN(sigma2=4)+DR(omega=0.005)", one_hz());
  return m;
}

// Relative asymptotic standard errors at the truth: efficient (V^-1) and the diag
// weighting 1/V_jj (what the data-based diag Omega estimates).
void asymptotic_floor(Eigen::VectorXd& efficient, Eigen::VectorXd& diag) {
  const Model& m = truth_model();
  const Eigen::VectorXd th = m.given_values();
  const int J = static_cast<int>(std::floor(std::log2(static_cast<double>(kLength))));
  std::vector<double> tau;
  for (int j = 1; j <= J; ++j) tau.push_back(std::ldexp(1.0, j));
  const Eigen::MatrixXd V = model_wv_covariance(m, th, kLength, J);
  const Eigen::MatrixXd A = m.jacobian(th, tau);
  const Eigen::MatrixXd C = (A.transpose() * V.inverse() * A).inverse();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(J, J);
  for (int j = 0; j < J; ++j) W(j, j) = 1.0 / V(j, j);
  const Eigen::MatrixXd B = (A.transpose() * W * A).inverse();
  const Eigen::MatrixXd Cd = B * A.transpose() * W * V * W * A * B;
  efficient.resize(th.size());
  diag.resize(th.size());
  for (int k = 0; k < th.size(); ++k) {
    efficient(k) = std::sqrt(C(k, k)) / std::abs(th(k));
    diag(k) = std::sqrt(Cd(k, k)) / std::abs(th(k));
  }
}

// Relative RMSE per parameter over `series` replicates; prints the table.
Eigen::VectorXd run(OmegaKind omega_kind, int series, const Eigen::VectorXd& floor_rel) {
  const Model& truth = truth_model();
  const Eigen::VectorXd theta0 = truth.given_values();
  const Model fit_model = parse_model("GM+WN+DR", one_hz());
  std::vector<Eigen::VectorXd> est(static_cast<std::size_t>(series));
  std::vector<int> converged(static_cast<std::size_t>(series));
  bench::Stopwatch sw;
  tbb::parallel_for(0, series, [&](int r) {
    const auto x = simulate(truth, theta0, kLength, kSeed, static_cast<std::uint64_t>(r));
    FitOptions o;
    o.omega = omega_kind;
    o.inference = false;
    const FitResult f = fit_gmwm(classical_wv(x.data(), kLength), fit_model, o);
    est[static_cast<std::size_t>(r)] = f.theta;
    converged[static_cast<std::size_t>(r)] = f.status == FitStatus::kConverged;
  });
  const double secs = sw.seconds();
  int conv = 0;
  for (int c : converged) conv += c;
  std::printf("\nOmega = %s, %d series\n\n", to_string(omega_kind), series);
  std::printf(
      "| parameter | truth | mean estimate | RMSE | relative RMSE | asymptotic floor (V^-1) | published GMWM | bar "
      "(1.2x) | verdict |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  Eigen::VectorXd rel(4);
  for (int k = 0; k < 4; ++k) {
    double se2 = 0, mean = 0;
    for (const auto& e : est) {
      se2 += (e(k) - theta0(k)) * (e(k) - theta0(k)) / series;
      mean += e(k) / series;
    }
    const double rmse = std::sqrt(se2);
    rel(k) = rmse / std::abs(theta0(k));
    const bool pass = rel(k) <= kBarFactor * kPublished[k];
    std::printf("| %s | %g | %.5g | %.4g | %.4f | %.4f | %.2f | %.3f | %s |\n", kNames[k], theta0(k), mean, rmse,
                rel(k), floor_rel(k), kPublished[k], kBarFactor * kPublished[k], pass ? "pass" : "FAIL");
  }
  std::printf("\n%d series of length %lld, %d converged, %.2f s wall (%.1f ms per fit on 2 threads).\n", series,
              static_cast<long long>(kLength), conv, secs, 1000 * secs / series * 2);
  return rel;
}

}  // namespace

int main() {
  Eigen::VectorXd efficient, diag;
  asymptotic_floor(efficient, diag);
  std::printf(
      "Asymptotic relative standard errors at the truth (all 12 levels):\n\n"
      "| parameter | Omega = V^-1 (efficient, the floor) | Omega = diag(1/V_jj) | bar (1.2 x published) "
      "|\n|---|---|---|---|\n");
  for (int k = 0; k < 4; ++k)
    std::printf("| %s | %.4f | %.4f | %.3f%s |\n", kNames[k], efficient(k), diag(k), kBarFactor * kPublished[k],
                efficient(k) > kBarFactor * kPublished[k] ? " (below the floor: unattainable)" : "");
  int passes = 0;
  for (OmegaKind kind : {OmegaKind::kDiag, OmegaKind::kFull}) {
    const Eigen::VectorXd rel = run(kind, kPublishedSeries, efficient);
    run(kind, kPreciseSeries, efficient);
    int ok = 0;
    for (int k = 0; k < 4; ++k) ok += rel(k) <= kBarFactor * kPublished[k];
    passes += ok == 4;
  }
  return passes > 0 ? 0 : 1;
}
