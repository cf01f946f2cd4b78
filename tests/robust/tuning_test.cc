// Tuning of the robust scale M-estimators (robust/src/tuning.cc): the table of c and
// a(c) for Huber's Proposal 2 in docs/statistics.md section 2, eff(tune(e).c) == e for both
// estimators, a(c) == E[chi_c(Z)] by an independent quadrature, argument checks of
// tune(), and the estimator names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust {
namespace {

struct TableRow {
  double eff, c, a;
};
// docs/statistics.md section 2, "Values": target efficiency, c, a(c) (10 decimals).
const TableRow kSpecTable[] = {
    {0.5, 1.0303349218, 0.5351519938},  {0.6, 1.2245090302, 0.6486092194}, {0.7, 1.4400500526, 0.7535145427},
    {0.8, 1.6995410597, 0.8485514579},  {0.9, 2.0676770356, 0.9320957578}, {0.95, 2.3761316828, 0.9686157802},
    {0.99, 2.9619288304, 0.9943547785},
};

// E[f(Z)], Z ~ N(0, 1), for an even f, by adaptive Gauss-Kronrod on [0, inf) split at
// the kink c (independent of the closed forms and of the module's own quadrature).
template <class F>
double gaussian_expectation(F f, double c) {
  auto g = [&](double z) { return 2.0 * f(z) * std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi); };
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  return GK::integrate(g, 0.0, c, 15, 1e-14) + GK::integrate(g, c, 40.0, 15, 1e-14);
}

TEST(HuberTuning, ReproducesTheSpecTableOfCAndA) {
  // The table has 10 decimals, so 1e-8 leaves two digits for the table's rounding.
  for (const auto& row : kSpecTable) {
    const Tuning t = tune(RobustKind::kHuber, row.eff);
    EXPECT_EQ(t.kind, RobustKind::kHuber);
    EXPECT_EQ(t.efficiency, row.eff);
    EXPECT_NEAR(t.c, row.c, 1e-8) << "eff " << row.eff;
    EXPECT_NEAR(t.a, row.a, 1e-8) << "eff " << row.eff;
  }
}

TEST(RobustTuning, SolvesTheTargetEfficiencyForBothEstimators) {
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double e : {0.05, 0.3, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99, 0.999}) {
      const Tuning t = tune(kind, e);
      EXPECT_NEAR(efficiency(kind, t.c), e, 1e-10) << to_string(kind) << " eff " << e;
      EXPECT_DOUBLE_EQ(t.a, consistency(kind, t.c));
    }
  }
}

TEST(RobustTuning, EfficiencyIncreasesWithTheTuningConstant) {
  // Bisquare needs a larger c than Huber for the same efficiency (it rejects, not clips).
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    double prev = 0.0;
    for (double e = 0.1; e < 0.991; e += 0.1) {
      const double c = tune(kind, e).c;
      EXPECT_GT(c, prev) << to_string(kind) << " eff " << e;
      prev = c;
    }
  }
  EXPECT_GT(tune(RobustKind::kBisquare, 0.6).c, tune(RobustKind::kHuber, 0.6).c);
}

TEST(RobustTuning, ConsistencyConstantIsTheGaussianMeanOfChi) {
  // a(c) = E[chi_c(Z)] (Fisher consistency), checked against an independent quadrature
  // of the chi() the estimator uses; 1e-10 is well above the quadrature's error.
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double e : {0.5, 0.6, 0.9}) {
      const Tuning t = tune(kind, e);
      const double direct = gaussian_expectation([&](double z) { return chi(kind, t.c, z * z); }, t.c);
      EXPECT_NEAR(t.a, direct, 1e-10) << to_string(kind) << " eff " << e;
    }
  }
}

TEST(RobustTuning, EfficiencyMatchesTheGeneralMEstimatorFormula) {
  // eff(c) = (E[Z chi'(Z)])^2 / (2 Var chi(Z)) evaluated by quadrature of the chi() the
  // estimator uses, chi' by second-order one-sided differences (h = 1e-4, error
  // O(h^2) ~ 1e-8) that never step across the kink at |z| = c.
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double e : {0.6, 0.9}) {
      const Tuning t = tune(kind, e);
      auto chi_z = [&](double z) { return chi(kind, t.c, z * z); };
      auto z_dchi = [&](double z) {
        const double h = z < t.c ? -1e-4 : 1e-4;  // stay on z's side of c
        return z * (-3.0 * chi_z(z) + 4.0 * chi_z(z + h) - chi_z(z + 2.0 * h)) / (2.0 * h);
      };
      const double d = gaussian_expectation(z_dchi, t.c);
      const double m2 = gaussian_expectation([&](double z) { return chi_z(z) * chi_z(z); }, t.c);
      EXPECT_NEAR(d * d / (2.0 * (m2 - t.a * t.a)), e, 1e-7) << to_string(kind) << " eff " << e;
    }
  }
}

TEST(RobustTuning, ExpansionConstantsAreTheDerivativesOfTheGaussianEstimatingEquation) {
  // F(t) = E[chi(Z^2 / t)]: F'(1) = -slope, F''(1) = curvature (tuning.h), which the
  // small-sample correction uses. Central differences with h = 1e-3 of the quadrature
  // above (kink of Huber's chi at |Z| = c sqrt(t)): truncation ~h^2 F'''' ~ 1e-6,
  // quadrature round-off 1e-14 / h^2 = 1e-8; tolerance 1e-5.
  constexpr double h = 1e-3;
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double eff : {0.6, 0.9}) {
      const Tuning t = tune(kind, eff);
      auto F = [&](double s) {
        return gaussian_expectation([&](double z) { return chi(kind, t.c, z * z / s); }, t.c * std::sqrt(s));
      };
      const double f0 = F(1.0), fp = F(1.0 + h), fm = F(1.0 - h);
      EXPECT_NEAR(f0, t.a, 1e-10) << to_string(kind) << " " << eff;
      EXPECT_NEAR(-(fp - fm) / (2.0 * h), t.slope, 1e-5) << to_string(kind) << " " << eff;
      EXPECT_NEAR((fp - 2.0 * f0 + fm) / (h * h), t.curvature, 1e-5) << to_string(kind) << " " << eff;
    }
  }
  // Huber at eff 0.6: the i.i.d. second-order bias these give, -Cov(chi, chi' U) /
  // slope^2 + curvature Var(chi) / (2 slope^3) = +0.976 / n, is the measured +0.96 / n.
  const Tuning h6 = tune(RobustKind::kHuber, 0.6);
  const double mu4 = gaussian_expectation([&](double z) { return z * z <= h6.c * h6.c ? z * z * z * z : 0.0; }, h6.c);
  const double var = gaussian_expectation(
                         [&](double z) {
                           const double x = chi(RobustKind::kHuber, h6.c, z * z);
                           return x * x;
                         },
                         h6.c) -
                     h6.a * h6.a;
  const double cov = mu4 - h6.a * h6.slope;
  const double bias = -cov / (h6.slope * h6.slope) + h6.curvature * var / (2.0 * std::pow(h6.slope, 3));
  EXPECT_NEAR(bias, 0.9758, 1e-3);
}

TEST(RobustTuning, ChiIsClippedForHuberAndRedescendingForBisquare) {
  const double c = 1.5;
  EXPECT_DOUBLE_EQ(chi(RobustKind::kHuber, c, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(chi(RobustKind::kHuber, c, 100.0), c * c);
  EXPECT_DOUBLE_EQ(chi(RobustKind::kBisquare, c, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(chi(RobustKind::kBisquare, c, c * c), 0.0);
  EXPECT_DOUBLE_EQ(chi(RobustKind::kBisquare, c, 100.0), 0.0);
  const double r2 = 1.0, u = 1.0 - r2 / (c * c);
  EXPECT_NEAR(chi(RobustKind::kBisquare, c, r2), r2 * std::pow(u, 4), 1e-15);
}

TEST(RobustTuning, TuneRejectsEfficienciesOutsideTheOpenUnitInterval) {
  for (RobustKind kind : {RobustKind::kHuber, RobustKind::kBisquare}) {
    for (double e : {0.0, -0.5, 1.0, 1.5, std::nan("")}) {
      try {
        (void)tune(kind, e);
        ADD_FAILURE() << "tune(" << to_string(kind) << ", " << e << ") did not throw";
      } catch (const InvalidArgument& ex) {
        EXPECT_NE(std::string(ex.what()).find("efficiency"), std::string::npos) << ex.what();
      }
    }
  }
}

TEST(RobustTuning, ParsesAndPrintsEstimatorNames) {
  EXPECT_EQ(parse_robust_kind("huber"), RobustKind::kHuber);
  EXPECT_EQ(parse_robust_kind("bisquare"), RobustKind::kBisquare);
  EXPECT_FALSE(parse_robust_kind("foo").has_value());
  EXPECT_FALSE(parse_robust_kind("").has_value());
  EXPECT_STREQ(to_string(RobustKind::kHuber), "huber");
  EXPECT_STREQ(to_string(RobustKind::kBisquare), "bisquare");
  EXPECT_EQ(parse_robust_kind(to_string(RobustKind::kBisquare)), RobustKind::kBisquare);
}

TEST(RobustTuning, DefaultEfficiencyIsTheSpecDefault) {
  EXPECT_EQ(kDefaultEfficiency, 0.6);
  const Tuning t;
  EXPECT_EQ(t.kind, RobustKind::kHuber);
  EXPECT_EQ(t.efficiency, 0.6);
}

}  // namespace
}  // namespace gmwm::robust
