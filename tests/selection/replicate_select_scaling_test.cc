// Selection over replicates at any K: every split's selection runs on the reduction of
// its stacked WV (joint_fit.h), which must score the candidates as the stacked problem did
// (checked against that computation for K = 2..12, the exhaustive splits); beyond 12
// replicates the splits are random halves drawn from the seed (Monte Carlo
// cross-validation), and the result does not depend on the thread count. Seeds are fixed.
//
// Tolerances, from the optimiser's stopping precision as in tests/engine/
// joint_reduction_test.cc: each fit's objective within 1e-8 of its minimum (relative), so
// theta within 0.01 standard errors of it. A held-out loss L is not minimised at the
// training fit: it moves to first order, by at most 2 sqrt(L) x 0.01 (the step in its own
// metric, 0.01 se, times its gradient's length there); an analytic WVIC moves with its
// objective (1e-8) and its optimism (2 tr(...), smooth in theta: 1e-2 of it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/selection/replicate_select.h"
#include "gmwm/selection/select.h"

namespace gmwm::selection {
namespace {

constexpr double kObjective = 1e-8;
constexpr double kLossStep = 0.02;  // 2 x 0.01 se
constexpr double kOptimism = 1e-2;

// K replicates of `spec`, of 2^(base), 2^(base+1), 2^(base+2), 2^(base), ... samples.
std::vector<WaveletVariance> replicates(const std::string& spec, int K, int base, std::uint64_t seed) {
  const Model m = parse_model(spec);
  std::vector<WaveletVariance> out;
  for (int k = 0; k < K; ++k) {
    const std::int64_t n = std::int64_t{1} << (base + k % 3);
    const auto x = simulate(m, m.given_values(), n, seed, static_cast<std::uint64_t>(k));
    out.push_back(classical_wv(x.data(), n));
  }
  return out;
}

// The oracle: select_by_replicates's numbers as it computed them on the stacked WV of every
// split before the reduction (pilot weights as it forms them; Omega model).
struct StackedNumbers {
  std::map<std::string, double> objective, analytic_wvic, cv_wvic;
  std::map<std::string, std::vector<double>> split_loss;
};

Selection stacked_selection(std::span<const WaveletVariance> wvs, const std::vector<int>& members,
                            const std::vector<Eigen::MatrixXd>& v, const std::vector<Eigen::MatrixXd>& omega,
                            const Model& maximal) {
  std::vector<WaveletVariance> part;
  std::vector<Eigen::MatrixXd> pv, po;
  for (int k : members) {
    part.push_back(wvs[static_cast<std::size_t>(k)]);
    pv.push_back(v[static_cast<std::size_t>(k)]);
    po.push_back(omega[static_cast<std::size_t>(k)]);
  }
  WaveletVariance stacked = stack_wv(part);
  stacked.covariance = block_diagonal(pv);
  SelectOptions so;
  so.fit.omega_matrix = block_diagonal(po);
  return select_models({stacked}, maximal, so).front();
}

StackedNumbers stacked_cv(std::span<const WaveletVariance> wvs, const Model& maximal,
                          const std::vector<std::vector<int>>& training) {
  FitOptions fo;
  fo.omega = OmegaKind::kDiag;
  fo.inference = false;
  const JointFitResult pilot = fit_gmwm_joint(wvs, maximal, fo);
  std::vector<Eigen::MatrixXd> v, omega;
  for (const auto& w : wvs) {
    v.push_back(model_wv_covariance(pilot.joint.model, pilot.joint.theta, w.n, w.levels()));
    omega.push_back(Eigen::MatrixXd(v.back().diagonal().cwiseInverse().asDiagonal()));
  }
  StackedNumbers out;
  std::vector<int> all(wvs.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  const Selection whole = stacked_selection(wvs, all, v, omega, maximal);
  for (const auto& c : whole.candidates) out.objective[c.model] = c.fit.objective;
  for (const auto& row : whole.ranking)
    for (const auto& m : row.members) out.analytic_wvic[m] = row.objective + row.optimism_analytic.value_or(NAN);
  for (const auto& split : training) {
    const Selection s = stacked_selection(wvs, split, v, omega, maximal);
    for (const auto& c : s.candidates) {
      double loss = 0.0;
      for (std::size_t k = 0; k < wvs.size(); ++k) {
        if (std::find(split.begin(), split.end(), static_cast<int>(k)) != split.end()) continue;
        const Eigen::VectorXd r = wvs[k].values() - c.fit.model.wv(c.fit.theta, wvs[k].tau);
        loss += r.dot(omega[k] * r);
      }
      out.split_loss[c.model].push_back(loss);
    }
  }
  for (const auto& [m, l] : out.split_loss) {
    double sum = 0.0;
    for (double x : l) sum += x;
    out.cv_wvic[m] = sum / static_cast<double>(l.size());
  }
  return out;
}

TEST(ReplicateSelectScaling, TheReducedSelectionScoresTheCandidatesAsTheStackedOneForTwoToTwelveReplicates) {
  const Model maximal = parse_model("AR1+WN");
  for (int K = 2; K <= 12; ++K) {
    const auto wvs =
        replicates("AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=1e-2)", K, 11, 8100 + static_cast<std::uint64_t>(K));
    const ReplicateSelection r = select_by_replicates(wvs, maximal);
    const std::string what = "K = " + std::to_string(K);
    // Up to 12 replicates: every subset of ceil(K/2), in lexicographic order.
    std::set<std::vector<int>> distinct(r.training.begin(), r.training.end());
    ASSERT_EQ(distinct.size(), r.training.size()) << what;
    ASSERT_EQ(r.training.front().size(), static_cast<std::size_t>((K + 1) / 2)) << what;
    EXPECT_TRUE(std::is_sorted(r.training.begin(), r.training.end())) << what;
    const StackedNumbers o = stacked_cv(wvs, maximal, r.training);
    ASSERT_EQ(r.ranking.size(), o.objective.size()) << what;
    for (const auto& c : r.ranking) {
      const std::string at = what + ", " + c.model;
      ASSERT_TRUE(o.objective.count(c.model)) << at;
      EXPECT_NEAR(c.objective, o.objective.at(c.model), kObjective * o.objective.at(c.model)) << at;
      const double optimism = o.analytic_wvic.at(c.model) - o.objective.at(c.model);
      EXPECT_NEAR(c.analytic_wvic, o.analytic_wvic.at(c.model),
                  kObjective * o.objective.at(c.model) + kOptimism * std::abs(optimism))
          << at;
      ASSERT_EQ(c.split_loss.size(), o.split_loss.at(c.model).size()) << at;
      for (std::size_t s = 0; s < c.split_loss.size(); ++s) {
        const double l = o.split_loss.at(c.model)[s];
        EXPECT_NEAR(c.split_loss[s], l, kLossStep * std::sqrt(l) + kObjective * l) << at << ", split " << s;
      }
      const double cv = o.cv_wvic.at(c.model);
      EXPECT_NEAR(c.cv_wvic, cv, kLossStep * std::sqrt(cv) + kObjective * cv) << at;
    }
  }
}

constexpr const char* kFleetTruth = "AR1(phi=0.95,sigma2=1e-3)+WN(sigma2=1e-2)+RW(gamma2=1e-6)";

TEST(ReplicateSelectScaling, SelectsOverFortyReplicatesByRandomHalfSplitsAndRecoversTheTruth) {
  const auto wvs = replicates(kFleetTruth, 40, 12, 8201);
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("AR1+WN+RW"));
  // 924 distinct random halves of 20, each sorted, drawn from the seed.
  ASSERT_EQ(r.training.size(), 924u);
  std::set<std::vector<int>> distinct(r.training.begin(), r.training.end());
  EXPECT_EQ(distinct.size(), 924u);
  std::vector<int> times_in_training(40, 0);
  for (const auto& s : r.training) {
    ASSERT_EQ(s.size(), 20u);
    EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));
    for (int k : s) ++times_in_training[static_cast<std::size_t>(k)];
  }
  // Every replicate trains in about half the splits (binomial(924, 1/2): sd 15).
  for (int t : times_in_training) EXPECT_NEAR(t, 462, 5 * 15.2);
  EXPECT_EQ(r.recommended, parse_model(kFleetTruth).canonical().to_string());
  EXPECT_EQ(r.chosen, r.recommended);
  for (const auto& c : r.ranking) EXPECT_EQ(c.split_loss.size(), 924u) << c.model;
  // Another seed draws other splits.
  ReplicateSelectOptions o;
  o.seed = 1;
  EXPECT_NE(select_by_replicates(wvs, parse_model("WN+RW"), o).training,
            select_by_replicates(wvs, parse_model("WN+RW")).training);
}

TEST(ReplicateSelectScaling, GivesTheSameResultWhateverTheThreadCountWithFortyReplicates) {
  const auto wvs = replicates(kFleetTruth, 40, 11, 8202);
  const Model maximal = parse_model("AR1+WN+RW");
  const ReplicateSelection many = select_by_replicates(wvs, maximal);
  ReplicateSelection one;
  {
    oneapi::tbb::global_control single(oneapi::tbb::global_control::max_allowed_parallelism, 1);
    one = select_by_replicates(wvs, maximal);
  }
  EXPECT_EQ(many.training, one.training);
  EXPECT_EQ(many.chosen, one.chosen);
  EXPECT_EQ(many.recommended, one.recommended);
  ASSERT_EQ(many.ranking.size(), one.ranking.size());
  for (std::size_t i = 0; i < one.ranking.size(); ++i) {
    EXPECT_EQ(many.ranking[i].model, one.ranking[i].model);
    EXPECT_EQ(many.ranking[i].split_loss, one.ranking[i].split_loss);  // bit for bit
    EXPECT_EQ(many.ranking[i].analytic_wvic, one.ranking[i].analytic_wvic);
    EXPECT_EQ(many.ranking[i].p_not_worse, one.ranking[i].p_not_worse);
  }
}

TEST(ReplicateSelectScaling, PutsTheBootstrapWvicBesideTheAnalyticOneForSeventeenReplicates) {
  // Beyond 16 replicates each draw takes K streams (stream x K + k; stream x 16 + k up to
  // 16, as always), and the draw is the reduction of the K simulated WVs under the same
  // Omega_k: at the truth the bootstrap optimism estimates the analytic one.
  const auto wvs = replicates("WN(sigma2=1e-2)+RW(gamma2=1e-6)", 17, 10, 8203);
  ReplicateSelectOptions o;
  o.select.optimism = OptimismMethod::kBoth;
  o.select.bootstrap_replicates = 40;
  const ReplicateSelection r = select_by_replicates(wvs, parse_model("WN+RW"), o);
  for (const auto& c : r.ranking)
    if (c.model == "WN+RW") {
      ASSERT_TRUE(std::isfinite(c.bootstrap_wvic));
      const double analytic = c.analytic_wvic - c.objective, boot = c.bootstrap_wvic - c.objective;
      EXPECT_NEAR(boot, analytic, 4.0 * c.bootstrap_se + 0.25 * analytic) << c.bootstrap_se;
    }
}

}  // namespace
}  // namespace gmwm::selection
