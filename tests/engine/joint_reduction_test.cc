// The joint fit's reduction of the stacked problem (K replicates' WVs stacked under a
// block-diagonal Omega) to one WV on the common levels: the identities behind it, checked
// at arbitrary theta against the stacked computation, and the joint fit, its inference
// and the shared-theta test against the stacked problem solved as the joint fit solved it
// before the reduction (the oracle), for K = 2..12 replicates of different lengths.
// Seeds are fixed here.
//
// Tolerances. The identities hold exactly: sums of the same O(K J^2) products in another
// order, so they agree to a few hundred roundings of the largest term (1e-12 relative).
// The estimates come from two minimisations of the same function that stop where the
// optimiser stops: within about 1e-9 of the objective on these fits (select.cc: ~1e-8
// relative on real data; we allow 1e-8). Near the minimum the objective rises by
// (delta / se)^2 (its Hessian is about twice the inverse covariance under model-based
// weights), so an objective within 1e-8 Q of the minimum (Q ~ 100-300 here) puts theta
// within sqrt(1e-8 x 300) = 1.7e-3 se of it: we allow 0.01 se; standard errors move with
// theta by delta / theta, below 0.01 se / theta, < 1e-3 here: we allow 1e-3 relative; a
// goodness-of-fit p moves by its density times the objective's 1e-8 relative: 1e-6.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm {
namespace {

// A random walk these lengths resolve, so no parameter sits on the boundary.
constexpr const char* kTruth = "AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=1e-2)+RW(gamma2=1e-6)";
constexpr double kIdentity = 1e-12;  // round-off of the reordered sums
// The fits' agreement, relative: the Newton polish settles when no coordinate moves by 1e-11
// (fit.cc, kPolishStepSettled); the worst over K = 2..12 was 2.5e-13 (issue 44; 9e-10 before
// the polish converged on the gradient).
constexpr double kObjective = 1e-10;
constexpr double kTheta = 0.01;   // in standard errors
constexpr double kSe = 1e-3;      // relative
constexpr double kPValue = 1e-6;  // absolute

// K replicates of 2^12, 2^13, 2^14, 2^12, ... samples.
std::vector<WaveletVariance> replicates(int K, std::uint64_t seed) {
  const Model m = parse_model(kTruth);
  std::vector<WaveletVariance> out;
  for (int k = 0; k < K; ++k) {
    const std::int64_t n = std::int64_t{1} << (12 + k % 3);
    const auto x = simulate(m, m.given_values(), n, seed, static_cast<std::uint64_t>(k));
    out.push_back(classical_wv(x.data(), n));
  }
  return out;
}

std::vector<Eigen::MatrixXd> covariances(std::span<const WaveletVariance> wvs, const Model& m,
                                         const Eigen::VectorXd& theta) {
  std::vector<Eigen::MatrixXd> v;
  for (const auto& w : wvs) v.push_back(model_wv_covariance(m, theta, w.n, w.levels()));
  return v;
}

std::vector<Eigen::MatrixXd> inverses(const std::vector<Eigen::MatrixXd>& v) {
  std::vector<Eigen::MatrixXd> out;
  for (const auto& x : v) {
    Eigen::MatrixXd w = x.completeOrthogonalDecomposition().pseudoInverse();
    out.push_back(0.5 * (w + w.transpose()));
  }
  return out;
}

std::vector<Eigen::MatrixXd> diagonal_inverses(const std::vector<Eigen::MatrixXd>& v) {
  std::vector<Eigen::MatrixXd> out;
  for (const auto& x : v) out.push_back(Eigen::MatrixXd(x.diagonal().cwiseInverse().asDiagonal()));
  return out;
}

// The stacked objective's minimisation as the joint fit ran it on the stacked WV.
FitResult stacked_minimum(const WaveletVariance& stacked, const Model& model, const Eigen::MatrixXd& omega,
                          const std::vector<Eigen::VectorXd>& starts, bool inference) {
  FitOptions o;
  o.omega_matrix = omega;
  o.starts = starts;
  o.nested_starts = false;
  o.multistarts = 1;
  o.inference = inference;
  return fit_gmwm(stacked, model, o);
}

// The oracle: fit_gmwm_joint's algorithm on the stacked WV, as before the reduction.
struct StackedJoint {
  FitResult fit;
  std::vector<Eigen::MatrixXd> omegas;
};
StackedJoint stacked_joint_fit(std::span<const WaveletVariance> wvs, const Model& model_in, OmegaKind kind) {
  const Model model = model_in.canonical();
  FitOptions fo;
  fo.omega = kind;
  std::vector<Eigen::VectorXd> starts;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(model.num_parameters());
  for (const auto& w : wvs) {
    starts.push_back(fit_gmwm(w, model, fo).theta);
    mean += starts.back() / static_cast<double>(wvs.size());
  }
  starts.push_back(mean);
  WaveletVariance stacked = stack_wv(wvs);
  StackedJoint out;
  for (const auto& w : wvs) out.omegas.push_back(diagonal_omega(w));
  const FitResult pilot = stacked_minimum(stacked, model, block_diagonal(out.omegas), starts, false);
  const auto v = covariances(wvs, pilot.model, pilot.theta);
  out.omegas = kind == OmegaKind::kFull ? inverses(v) : diagonal_inverses(v);
  starts.push_back(pilot.theta);
  const FitResult refit = stacked_minimum(stacked, model, block_diagonal(out.omegas), starts, false);
  // Inference with V = blockdiag(V_k) at the estimate, from the estimate.
  stacked.covariance = block_diagonal(covariances(wvs, refit.model, refit.theta));
  out.fit = stacked_minimum(stacked, model, block_diagonal(out.omegas), {refit.theta}, true);
  if (kind == OmegaKind::kFull) {  // chi-square under V^-1 weights (the pilot's V formed them)
    out.fit.gof.p_value = boost::math::cdf(
        boost::math::complement(boost::math::chi_squared(out.fit.gof.df), std::max(out.fit.objective, 0.0)));
    out.fit.gof.method = "chi-square";
  }
  return out;
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(a.norm(), b.norm());
}

TEST(JointReduction, TheReducedObjectiveIsTheStackedOneLessAConstantAtAnyTheta) {
  const auto wvs = replicates(5, 7001);  // lengths 2^12..2^14: padded levels
  const Model m = parse_model(kTruth);
  const auto v = covariances(wvs, m, m.given_values());
  for (const auto& omegas : {diagonal_inverses(v), inverses(v)}) {
    const ReducedReplicates r = reduce_replicates(wvs, omegas);
    ASSERT_EQ(r.wv.levels(), 14);
    EXPECT_EQ(r.stacked_levels, 12 + 13 + 14 + 12 + 13);
    const WaveletVariance stacked = stack_wv(wvs);
    const Eigen::MatrixXd omega = block_diagonal(omegas);
    double scale = 0.0;  // the terms the two sides cancel: sum_k nuhat_k' Omega_k nuhat_k
    for (std::size_t k = 0; k < wvs.size(); ++k) scale += wvs[k].values().dot(omegas[k] * wvs[k].values());
    for (const double factor : {1.0, 0.5, 2.0, 10.0}) {
      const Eigen::VectorXd theta = m.given_values() * factor;
      const double s = gmwm_objective(stacked, m, theta, omega);
      const double q = gmwm_objective(r.wv, m, theta, r.weight) + r.within;
      // Round-off of reordered sums is relative to their largest terms: the data's (scale)
      // or, at a theta far off (factor 10: phi = 9.5, objective ~1e170), the model's.
      EXPECT_NEAR(q, s, kIdentity * std::max(scale, std::abs(s))) << factor;
    }
  }
}

TEST(JointReduction, TheReducedSandwichAndGoodnessOfFitTermsAreTheStackedOnes) {
  const auto wvs = replicates(7, 7002);
  const Model m = parse_model(kTruth);
  const Eigen::VectorXd theta = m.given_values();
  const auto v = covariances(wvs, m, theta);
  const WaveletVariance stacked = stack_wv(wvs);
  const Eigen::MatrixXd A_s = m.jacobian(theta, stacked.tau);
  const Eigen::MatrixXd V_s = block_diagonal(v);
  for (const bool full : {false, true}) {
    const auto omegas = full ? inverses(v) : diagonal_inverses(v);
    const ReducedReplicates r = reduce_replicates(wvs, omegas, v);
    const Eigen::MatrixXd O_s = block_diagonal(omegas);
    const Eigen::MatrixXd A = m.jacobian(theta, r.wv.tau);
    // A_s' Omega_s A_s = A' W A;  A_s' Omega_s V_s Omega_s A_s = A' U A = A' W Var(nutilde) W A.
    EXPECT_LT(relative_difference(A.transpose() * r.weight * A, A_s.transpose() * O_s * A_s), kIdentity) << full;
    const Eigen::MatrixXd meat_s = A_s.transpose() * O_s * V_s * O_s * A_s;
    EXPECT_LT(relative_difference(A.transpose() * r.meat * A, meat_s), kIdentity) << full;
    // Var(nutilde) through W^-1: its condition (~1e3 scaled) costs three more digits.
    EXPECT_LT(relative_difference(A.transpose() * r.weight * *r.wv.covariance * r.weight * A, meat_s), 1e3 * kIdentity)
        << full;
    // The stacked Satterthwaite goodness of fit from the reduced traces.
    const double objective = gmwm_objective(stacked, m, theta, O_s);
    const double df = static_cast<double>(r.stacked_levels - m.num_parameters());
    const GoodnessOfFit a = goodness_of_fit(A_s, objective, df, O_s, V_s, false);
    const GoodnessOfFit b = stacked_goodness_of_fit(r, A, objective, df, false);
    EXPECT_EQ(b.method, "satterthwaite");
    EXPECT_NEAR(b.p_value, a.p_value, 1e-9 * std::max(a.p_value, 1e-3)) << full;
  }
}

TEST(JointReduction, ALevelNoReplicateWeighsIsDroppedAndTheIdentityStillHolds) {
  const auto wvs = replicates(3, 7003);
  const Model m = parse_model(kTruth);
  auto omegas = diagonal_inverses(covariances(wvs, m, m.given_values()));
  for (auto& o : omegas) o(2, 2) = 0.0;  // level 3 weighed by nobody: W singular there
  const ReducedReplicates r = reduce_replicates(wvs, omegas);
  EXPECT_EQ(r.wv.levels(), 13);
  EXPECT_EQ(r.kept[2], 3);
  const double s = gmwm_objective(stack_wv(wvs), m, m.given_values(), block_diagonal(omegas));
  EXPECT_NEAR(gmwm_objective(r.wv, m, m.given_values(), r.weight) + r.within, s, kIdentity * s * 1e3);
}

TEST(JointReduction, RefusesReplicatesWhoseLevelsAreAtOtherScales) {
  auto wvs = replicates(2, 7004);
  wvs[1].tau[3] *= 1.5;
  std::vector<Eigen::MatrixXd> omegas = {diagonal_omega(wvs[0]), diagonal_omega(wvs[1])};
  EXPECT_THROW(reduce_replicates(wvs, omegas), InvalidArgument);
}

// theta, objective, standard errors and GoF p of the reduced joint fit against the oracle.
void expect_same_fit(const JointFitResult& r, const StackedJoint& o, const std::string& what) {
  ASSERT_NE(r.joint.status, FitStatus::kFailed) << what;
  ASSERT_EQ(r.joint.theta.size(), o.fit.theta.size()) << what;
  EXPECT_NEAR(r.joint.objective, o.fit.objective, kObjective * o.fit.objective) << what;
  for (Eigen::Index i = 0; i < r.joint.theta.size(); ++i) {
    ASSERT_TRUE(std::isfinite(o.fit.se(i))) << what << " parameter " << i;
    EXPECT_NEAR(r.joint.theta(i), o.fit.theta(i), kTheta * o.fit.se(i)) << what << " parameter " << i;
    EXPECT_NEAR(r.joint.se(i), o.fit.se(i), kSe * o.fit.se(i)) << what << " parameter " << i;
  }
  EXPECT_LT(relative_difference(r.joint.covariance, o.fit.covariance), 2.0 * kSe) << what;
  EXPECT_EQ(r.joint.gof.df, o.fit.gof.df) << what;
  EXPECT_EQ(r.joint.gof.method, o.fit.gof.method) << what;
  EXPECT_NEAR(r.joint.gof.p_value, o.fit.gof.p_value, kPValue) << what;
  for (std::size_t k = 0; k < r.omegas.size(); ++k)
    EXPECT_LT(relative_difference(r.omegas[k], o.omegas[k]), 2.0 * kSe) << what << " Omega of replicate " << k;
}

TEST(JointReduction, TheReducedJointFitEqualsTheStackedOneForTwoToTwelveReplicates) {
  const Model model = parse_model("AR1+WN+RW");
  for (int K = 2; K <= 12; ++K) {
    const auto wvs = replicates(K, 7100 + static_cast<std::uint64_t>(K));
    for (const OmegaKind kind : {OmegaKind::kModel, OmegaKind::kFull}) {
      FitOptions fo;
      fo.omega = kind;
      const JointFitResult r = fit_gmwm_joint(wvs, model, fo);
      const StackedJoint o = stacked_joint_fit(wvs, model, kind);
      const std::string what = "K = " + std::to_string(K) + ", Omega " + to_string(kind);
      expect_same_fit(r, o, what);
      // The stacked levels' misfits (under model-based diag weights the GoF's V is V at
      // the estimate, as the oracle's): the same z level by level.
      if (kind != OmegaKind::kModel) continue;
      ASSERT_EQ(r.joint.misfits.size(), o.fit.misfits.size()) << what;
      for (std::size_t i = 0; i < r.joint.misfits.size(); ++i)
        EXPECT_NEAR(r.joint.misfits[i].z, o.fit.misfits[i].z, 2.0 * kTheta) << what << " level " << i + 1;
    }
  }
}

// The shared-theta test's statistics on the stacked problem: T, each replicate's own minimum
// and H under Omega_k = V_k^-1 at the fixed point, iterated as replicate_test iterates it.
struct StackedStatistics {
  double t = 0.0, h = 0.0;
  std::vector<double> own;
};
StackedStatistics stacked_statistics(std::span<const WaveletVariance> wvs, const JointFitResult& joint) {
  const Model& m = joint.joint.model;
  const WaveletVariance stacked = stack_wv(wvs);
  Eigen::VectorXd theta = joint.joint.theta;
  for (int it = 0; it < 4; ++it) {  // replicate_test's kOmegaUpdates and kOmegaSettled
    const FitResult f = stacked_minimum(stacked, m, block_diagonal(inverses(covariances(wvs, m, theta))),
                                        {theta, joint.joint.theta}, false);
    const bool settled = ((f.theta - theta).array().abs() <= 1e-3 * theta.array().abs()).all();
    theta = f.theta;
    if (settled) break;
  }
  const auto omegas = inverses(covariances(wvs, m, theta));
  StackedStatistics s;
  s.t = stacked_minimum(stacked, m, block_diagonal(omegas), {theta}, false).objective;
  double sum = 0.0;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    s.own.push_back(stacked_minimum(wvs[k], m, omegas[k], {theta}, false).objective);
    sum += s.own.back();
  }
  s.h = std::max(0.0, s.t - sum);
  return s;
}

TEST(JointReduction, TheSharedThetaTestsStatisticsEqualTheStackedOnesForTwoToTwelveReplicates) {
  // The fixed point stops once no parameter moves by more than 1e-3 (relative): Omega_k,
  // and the minima under it, are known to about that precision, which bounds T and H.
  constexpr double kFixedPoint = 1e-3;
  const Model model = parse_model("AR1+WN+RW");
  ReplicateTestOptions o;
  o.calibration = ReplicateCalibration::kChiSquare;
  o.fit.inference = false;
  for (int K = 2; K <= 12; ++K) {
    const auto wvs = replicates(K, 7200 + static_cast<std::uint64_t>(K));
    const JointFitResult r = fit_gmwm_joint(wvs, model);
    const ReplicateTest t = replicate_test(wvs, r, o);
    const StackedStatistics s = stacked_statistics(wvs, r);
    const std::string what = "K = " + std::to_string(K);
    EXPECT_NEAR(t.statistic, s.t, kFixedPoint * s.t) << what;
    EXPECT_NEAR(t.heterogeneity, s.h, kFixedPoint * s.t) << what;
    ASSERT_EQ(t.own_minimum.size(), s.own.size());
    for (std::size_t k = 0; k < s.own.size(); ++k) EXPECT_NEAR(t.own_minimum[k], s.own[k], kFixedPoint * s.own[k]);
    // The chi-square's degrees of freedom: (K - 1) p and sum_k J_k - p (p = 4, all identified).
    EXPECT_EQ(t.calibration, ReplicateCalibration::kChiSquare);
    EXPECT_EQ(t.draws, 0);
    EXPECT_EQ(t.df_heterogeneity, 4.0 * (K - 1)) << what;
    int levels = 0;
    for (const auto& w : wvs) levels += w.levels();
    EXPECT_EQ(t.df_statistic, levels - 4.0) << what;
    EXPECT_NEAR(t.heterogeneity_p,
                boost::math::cdf(boost::math::complement(boost::math::chi_squared(4.0 * (K - 1)), t.heterogeneity)),
                1e-12);
  }
}

TEST(JointReduction, TheChiSquareCalibrationOfTheSharedThetaTestHoldsItsLevelUnderTheNull) {
  // The oracle is the null itself: data sets of replicates that share theta. 60 sets of
  // K = 6 replicates (2^11..2^13): at 5% the rejections have a Monte-Carlo sd of 2.8
  // points, so more than 5% + 3 sd = 13.5% (8 of 60) says the chi-square is too liberal;
  // and H's mean over the sets is (K - 1) p = 20 times 1 +- 4 sds of a mean of 60
  // chi2(20) / 20 (0.16). (Measured against the bootstrap on 200 sets of 10 replicates:
  // 4.0% vs 3.0%, tools/bench/results/2026-11-28-joint-scaling.md.)
  constexpr int kSets = 60, K = 6;
  const Model model = parse_model("AR1+WN+RW");
  const Model truth = parse_model(kTruth);
  ReplicateTestOptions o;
  o.calibration = ReplicateCalibration::kChiSquare;
  o.fit.inference = false;
  o.fit.log_not_converged = false;
  int rejected = 0;
  double ratio = 0.0;
  for (int s = 0; s < kSets; ++s) {
    std::vector<WaveletVariance> wvs;
    for (int k = 0; k < K; ++k) {
      const std::int64_t n = std::int64_t{1} << (11 + k % 3);
      const auto x =
          simulate(truth, truth.given_values(), n, 7300 + static_cast<std::uint64_t>(s), static_cast<std::uint64_t>(k));
      wvs.push_back(classical_wv(x.data(), n));
    }
    FitOptions fo;
    fo.log_not_converged = false;
    const ReplicateTest t = replicate_test(wvs, fit_gmwm_joint(wvs, model, fo), o);
    rejected += t.rejects();
    ratio += t.heterogeneity / t.df_heterogeneity / kSets;
  }
  EXPECT_LE(rejected, 8);
  EXPECT_NEAR(ratio, 1.0, 0.16);
}

TEST(JointReduction, TheChiSquareCalibrationRejectsAReplicateWhoseNoiseDiffers) {
  ReplicateTestOptions o;
  o.calibration = ReplicateCalibration::kChiSquare;
  auto wvs = replicates(4, 7400);
  const Model model = parse_model("AR1+WN+RW");
  EXPECT_FALSE(replicate_test(wvs, fit_gmwm_joint(wvs, model), o).rejects());
  const Model louder = parse_model("AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=2e-2)+RW(gamma2=1e-6)");
  const auto x = simulate(louder, louder.given_values(), 1 << 13, 7401, 0);
  wvs[1] = classical_wv(x.data(), 1 << 13);  // twice the white noise
  const ReplicateTest t = replicate_test(wvs, fit_gmwm_joint(wvs, model), o);
  EXPECT_TRUE(t.rejects());
  EXPECT_LT(t.heterogeneity_p, 1e-6);
  // No draw, and no minimum number of them: the bootstrap's B is not asked for.
  o.bootstrap = 1;
  EXPECT_TRUE(o.Validate().empty());
  EXPECT_EQ(t.draws, 0);
}

}  // namespace
}  // namespace gmwm
