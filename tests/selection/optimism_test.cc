// Analytic WVIC optimism (selection/src/optimism.cc) against a high-precision reference
// value ("Analytic optimism", computed independently of this code), the exact 2p of linear
// models, boundary components, and the error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "gmwm/engine/check.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/selection/optimism.h"

namespace gmwm::selection {
namespace {

std::vector<double> dyadic_tau(int J) {
  std::vector<double> tau;
  for (int j = 1; j <= J; ++j) tau.push_back(std::ldexp(1.0, j));
  return tau;
}

// docs/statistics.md section 6, the formula check: theta = AR1(0.9, 0.1) + WN(1), j = 1..9,
// nuhat_j = nu_j (1 + 0.1 sin j), Omega = diag(1 / (0.1 nu_j)^2), V = Omega^-1, natural parameters.
struct ReferenceCase {
  Model model = parse_model("AR1+WN");
  Eigen::VectorXd theta = (Eigen::VectorXd(3) << 0.9, 0.1, 1.0).finished();
  std::vector<double> tau = dyadic_tau(9);
  Eigen::VectorXd nu, nuhat;
  Eigen::MatrixXd omega, v;
  ReferenceCase() {
    nu = model.wv(theta, tau);
    nuhat = nu;
    Eigen::VectorXd w(9);
    for (int j = 0; j < 9; ++j) {
      nuhat(j) = nu(j) * (1.0 + 0.1 * std::sin(j + 1.0));
      w(j) = 1.0 / std::pow(0.1 * nu(j), 2);
    }
    omega = w.asDiagonal();
    v = w.cwiseInverse().asDiagonal();
  }
};

TEST(AnalyticOptimism, ReproducesTheReferenceValueOfTheTestVectors) {
  const ReferenceCase c;
  const Optimism o = analytic_optimism(c.model, c.theta, c.tau, c.nuhat, c.omega, c.v);
  EXPECT_EQ(o.status, OptimismStatus::kOk) << o.message;
  // 6 significant digits given; a flipped sign of D would give 5.88654.
  EXPECT_NEAR(o.value, 6.29072, 5e-6);
  EXPECT_TRUE(o.boundary_components.empty());
  EXPECT_TRUE(o.message.empty()) << o.message;
}

TEST(AnalyticOptimism, IsExactlyTwicePForALinearModelWithVTheInverseOfOmega) {
  const Model m = parse_model("WN+RW");
  const Eigen::VectorXd theta = (Eigen::VectorXd(2) << 1.0, 1e-3).finished();
  const auto tau = dyadic_tau(12);
  const Eigen::VectorXd nu = m.wv(theta, tau);
  Eigen::VectorXd nuhat = nu, w(12);
  for (int j = 0; j < 12; ++j) {
    nuhat(j) *= 1.0 + 0.2 * std::cos(3.0 * j);  // any nuhat: D = 0 for a linear model
    w(j) = 1.0 / (nu(j) * nu(j));
  }
  const Eigen::MatrixXd omega = w.asDiagonal();
  const Optimism o = analytic_optimism(m, theta, tau, nuhat, omega, omega.inverse());
  EXPECT_EQ(o.status, OptimismStatus::kOk);
  EXPECT_NEAR(o.value, 4.0, 1e-10);
}

TEST(AnalyticOptimism, DropsComponentsAtTheBoundaryAndSaysSo) {
  // QN with Q2 = 0 on top of WN + RW: its parameter is dropped, 2p = 4 remains.
  const Model m = parse_model("WN+QN+RW");
  const Eigen::VectorXd theta = (Eigen::VectorXd(3) << 1.0, 0.0, 1e-3).finished();
  const auto tau = dyadic_tau(12);
  const Eigen::VectorXd nu = m.wv(theta, tau);
  const Eigen::MatrixXd omega = nu.array().square().inverse().matrix().asDiagonal();
  const Optimism o = analytic_optimism(m, theta, tau, nu, omega, omega.inverse());
  EXPECT_EQ(o.status, OptimismStatus::kOk);
  EXPECT_NEAR(o.value, 4.0, 1e-10);
  EXPECT_EQ(o.boundary_components, std::vector<int>{1});
  EXPECT_NE(o.message.find("component 2 at the boundary"), std::string::npos) << o.message;
}

TEST(AnalyticOptimism, RejectsInconsistentSizesNamingTheArgument) {
  const ReferenceCase c;
  auto message = [&](auto&& call) {
    try {
      call();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_NE(message([&] { analytic_optimism(c.model, c.theta.head(2), c.tau, c.nuhat, c.omega, c.v); }).find("theta"),
            std::string::npos);
  EXPECT_NE(message([&] { analytic_optimism(c.model, c.theta, c.tau, c.nuhat.head(8), c.omega, c.v); }).find("nuhat"),
            std::string::npos);
  EXPECT_NE(message([&] {
              analytic_optimism(c.model, c.theta, c.tau, c.nuhat, Eigen::MatrixXd::Identity(8, 8), c.v);
            }).find("Omega"),
            std::string::npos);
  EXPECT_NE(
      message([&] { analytic_optimism(c.model, c.theta, c.tau, c.nuhat, c.omega, Eigen::MatrixXd()); }).find("V "),
      std::string::npos);
}

}  // namespace
}  // namespace gmwm::selection

namespace gmwm::selection {
namespace {

TEST(AnalyticOptimism, LeavesOutDirectionsOfNegativeCurvatureAndSaysSo) {
  // Data far above the model's WV (a fit stopped at the edge of the parameter space,
  // where the first-order condition fails): the AR1's phi direction has negative
  // curvature, which the plain inverse turned into a large negative optimism.
  const ReferenceCase c;
  for (double f : {0.2, 2.0}) {
    const Optimism o = analytic_optimism(c.model, c.theta, c.tau, Eigen::VectorXd(f * c.nu), c.omega, c.v);
    EXPECT_EQ(o.status, OptimismStatus::kPseudoInverse) << f;
    EXPECT_NE(o.message.find("1 direction of negative curvature"), std::string::npos) << o.message;
    EXPECT_NE(o.message.find("pseudo-inverse over its 2 positive directions"), std::string::npos) << o.message;
    // Two directions kept, V = Omega^-1: a positive optimism of the order of 2 x 2.
    EXPECT_GT(o.value, 1.0) << f;
    EXPECT_LT(o.value, 6.0) << f;
  }
}

}  // namespace
}  // namespace gmwm::selection
