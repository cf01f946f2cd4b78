// Which models represent which (model_relations.h), the warm starts that follow, and the
// effective form of a fit (effective_model.h). Seeds are fixed here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/effective_model.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_relations.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

WaveletVariance wv_of(const std::string& spec, std::int64_t n, std::uint64_t seed) {
  const Model m = parse_model(spec);
  const auto x = simulate(m, m.given_values(), n, seed, 0);
  return classical_wv(x.data(), n);
}

std::vector<double> dyadic_tau(int levels) {
  std::vector<double> tau;
  for (int j = 1; j <= levels; ++j) tau.push_back(std::ldexp(1.0, j));
  return tau;
}

TEST(ModelRelations, AnAr1SlotRepresentsWhiteNoiseAndRandomWalkButNotTheReverse) {
  EXPECT_TRUE(represents(parse_model("2*AR1"), parse_model("WN+RW")));
  EXPECT_TRUE(represents(parse_model("3*AR1"), parse_model("2*AR1+WN")));
  EXPECT_TRUE(represents(parse_model("AR1+WN"), parse_model("AR1"))) << "nesting is representation";
  EXPECT_FALSE(represents(parse_model("WN+RW"), parse_model("AR1")));
  EXPECT_FALSE(represents(parse_model("AR1"), parse_model("WN+RW"))) << "one slot takes one component";
  EXPECT_FALSE(represents(parse_model("3*AR1"), parse_model("AR1+QN"))) << "an AR1 is no quantisation noise";
  EXPECT_FALSE(represents(parse_model("2*AR1"), parse_model("AR1+DR")));
}

TEST(ModelRelations, MovingAverageAndArma11RepresentWhiteAndQuantisationNoise) {
  EXPECT_TRUE(represents(parse_model("MA1"), parse_model("WN")));
  EXPECT_TRUE(represents(parse_model("MA1"), parse_model("QN")));
  EXPECT_TRUE(represents(parse_model("ARMA11"), parse_model("AR1")));
  EXPECT_TRUE(represents(parse_model("ARMA11"), parse_model("MA1")));
  EXPECT_TRUE(represents(parse_model("ARMA11+MA1"), parse_model("AR1+QN")));
  EXPECT_FALSE(represents(parse_model("ARMA11+WN"), parse_model("AR1+QN"))) << "one slot for two roles";
  EXPECT_FALSE(represents(parse_model("MA1"), parse_model("AR1")));
}

TEST(ModelRelations, AMappedStartReproducesTheRepresentedWaveletVariance) {
  const auto tau = dyadic_tau(19);
  // WN exactly (phi = 0); RW in the limit phi -> 1 - 1e-15, to 1e-9 relative up to tau = 2^19.
  const Model sub = parse_model("WN(sigma2=0.7)+RW(gamma2=3e-9)");
  const Model super = parse_model("2*AR1");
  const WaveletVariance w = wv_of("WN(sigma2=0.7)+RW(gamma2=3e-9)", 1 << 12, 1);
  const auto start = represent_start(super, sub, sub.given_values(), w);
  ASSERT_TRUE(start.has_value());
  const Eigen::VectorXd a = super.wv(*start, tau), b = sub.wv(sub.given_values(), tau);
  for (Eigen::Index j = 0; j < a.size(); ++j) EXPECT_NEAR(a(j) / b(j), 1.0, 1e-9) << "level " << j + 1;
  // QN through MA1 with theta -> -1.
  const Model q = parse_model("QN(Q2=0.3)");
  const auto qs = represent_start(parse_model("MA1"), q, q.given_values(), w);
  ASSERT_TRUE(qs.has_value());
  const Eigen::VectorXd qa = parse_model("MA1").wv(*qs, tau), qb = q.wv(q.given_values(), tau);
  for (Eigen::Index j = 0; j < qa.size(); ++j) EXPECT_NEAR(qa(j) / qb(j), 1.0, 1e-9) << "level " << j + 1;
  EXPECT_FALSE(represent_start(parse_model("AR1"), sub, sub.given_values(), w).has_value());
}

TEST(ModelRelations, NeighboursAreOneComponentRemovedOrReplacedBySomethingItContains) {
  std::set<std::string> names;
  for (const Model& m : representation_neighbours(parse_model("3*AR1"))) names.insert(m.to_string());
  EXPECT_EQ(names, (std::set<std::string>{"2*AR1", "2*AR1+WN", "2*AR1+RW"}));
  names.clear();
  for (const Model& m : representation_neighbours(parse_model("AR1+WN+RW"))) names.insert(m.to_string());
  // AR1 -> WN or RW would repeat a linear process already there: the same as removing it.
  EXPECT_EQ(names, (std::set<std::string>{"WN+RW", "AR1+RW", "AR1+WN"}));
}

TEST(ModelRelations, CoversLinkEachModelToWhatItRepresentsDirectly) {
  const std::vector<Model> models = {parse_model("AR1"), parse_model("WN"), parse_model("AR1+WN"), parse_model("2*AR1"),
                                     parse_model("WN+RW")};
  const auto rep = representation_matrix(models);
  EXPECT_TRUE(rep[3][4]);  // 2*AR1 represents WN+RW
  EXPECT_TRUE(rep[3][2]);  // and AR1+WN
  EXPECT_TRUE(rep[3][0]);  // and AR1, through AR1+WN
  EXPECT_FALSE(rep[4][3]);
  EXPECT_TRUE(rep[2][4]) << "AR1+WN represents WN+RW too (its AR1 as the random walk)";
  const auto covers = representation_covers(rep);
  EXPECT_EQ(covers[3], (std::vector<int>{2})) << "everything else is reached through AR1+WN";
  EXPECT_EQ(covers[2], (std::vector<int>{0, 4})) << "WN is reached through AR1 or WN+RW";
  EXPECT_TRUE(covers[0].size() == 1 && covers[0][0] == 1) << "AR1 represents WN";
  // A model listed twice orders nothing (no cycle).
  const auto twice = representation_matrix({parse_model("AR1+WN"), parse_model("WN+AR1")});
  EXPECT_FALSE(twice[0][1]);
  EXPECT_FALSE(twice[1][0]);
}

TEST(GmwmFitRepresentation, AModelNeverEndsAboveAModelItCanRepresent) {
  // The case of the issue: 3*AR1 ended at 34.96 where 2*AR1+WN reached 21.04.
  const WaveletVariance w =
      wv_of("AR1(phi=0.9,sigma2=0.01)+AR1(phi=0.999,sigma2=1e-6)+WN(sigma2=1)+RW(gamma2=1e-9)", 1 << 17, 4211);
  const FitResult small = fit_gmwm(w, parse_model("2*AR1+WN"));
  FitOptions o;
  o.omega_matrix = small.omega;
  const FitResult big = fit_gmwm(w, parse_model("3*AR1"), o);
  ASSERT_NE(big.status, FitStatus::kFailed) << big.message;
  EXPECT_LE(big.objective, small.objective * (1.0 + 1e-9));
  const FitResult walk = fit_gmwm(w, parse_model("2*AR1+RW"), o);
  EXPECT_LE(big.objective, walk.objective * (1.0 + 1e-9));
}

TEST(EffectiveModel, AnAr1AtPhiZeroIsWhiteNoiseLike) {
  const WaveletVariance w = wv_of("AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=1)", 1 << 16, 5);
  const Model m = parse_model("2*AR1");
  Eigen::VectorXd theta(4);
  theta << 0.001, 1.0, 0.99, 1e-3;
  const EffectiveModel e = effective_model(w, m, theta);
  EXPECT_EQ(e.model.to_string(), "AR1+WN");
  ASSERT_EQ(e.reductions.size(), 1u);
  EXPECT_NE(e.reductions[0].find("is WN-like"), std::string::npos) << e.reductions[0];
  EXPECT_EQ(e.labels, (std::vector<std::string>{"", "WN-like"}));
  EXPECT_EQ(e.parameters(), 3);
  EXPECT_LE(e.statistic, e.threshold);
  // Its size keeps the long-run variance: sigma2 / (1 - phi)^2.
  EXPECT_NEAR(e.theta(2), 1.0 / (0.999 * 0.999), 0.01);
}

TEST(EffectiveModel, AnAr1BeyondTheRecordIsRandomWalkLikeAndACollapsedTermIsDropped) {
  const WaveletVariance w = wv_of("WN(sigma2=1)+RW(gamma2=1e-6)", 1 << 16, 6);
  const Model m = parse_model("AR1+WN+QN");
  Eigen::VectorXd theta(4);
  theta << 1.0 - 1e-12, 1e-6, 1.0, 1e-18;
  const EffectiveModel e = effective_model(w, m, theta);
  EXPECT_EQ(e.model.to_string(), "WN+RW");
  EXPECT_EQ(e.reductions.size(), 2u);
  bool walk = false, dropped = false;
  for (const auto& r : e.reductions) {
    walk = walk || r.find("is RW-like") != std::string::npos;
    dropped = dropped || r.find("QN(") == 0;
  }
  EXPECT_TRUE(walk && dropped);
}

TEST(EffectiveModel, TwoAr1AtOnePhiMergeAndVisibleComponentsStay) {
  const WaveletVariance w = wv_of("AR1(phi=0.95,sigma2=0.1)+WN(sigma2=1)", 1 << 16, 7);
  Eigen::VectorXd theta(5);
  theta << 0.95, 0.04, 0.95, 0.06, 1.0;
  const EffectiveModel merged = effective_model(w, parse_model("2*AR1+WN"), theta);
  EXPECT_EQ(merged.model.to_string(), "AR1+WN");
  EXPECT_NEAR(merged.theta(1), 0.1, 1e-6);
  // A fast but clearly visible AR1 (phi = 0.16, the ADIS gyros' own filter) stays an AR1.
  Eigen::VectorXd fast(3);
  fast << 0.16, 1.0, 1e-3;
  const WaveletVariance wf = wv_of("AR1(phi=0.16,sigma2=1)+WN(sigma2=1e-3)", 1 << 16, 8);
  const EffectiveModel kept = effective_model(wf, parse_model("AR1+WN"), fast);
  EXPECT_NE(kept.model.to_string().find("AR1"), std::string::npos) << kept.model.to_string();
}

TEST(EffectiveModel, RejectsABadLevelAndAThetaOfTheWrongSize) {
  const WaveletVariance w = wv_of("WN(sigma2=1)", 1 << 10, 9);
  EffectiveOptions o;
  o.alpha = 1.5;
  EXPECT_NE(o.Validate().find("alpha"), std::string::npos);
  EXPECT_THROW(effective_model(w, parse_model("WN"), Eigen::VectorXd::Ones(1), o), InputError);
  EXPECT_THROW(effective_model(w, parse_model("WN"), Eigen::VectorXd::Ones(2)), InvalidArgument);
}

}  // namespace
}  // namespace gmwm
