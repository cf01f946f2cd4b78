#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "gmwm/engine/random.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(DriftProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("DR");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)), {0.25, 1, 4, 16, 64, 256}, 1e-15,
                             "DR(1)");
}

TEST(DriftProcess, IsDeterministicWithZeroAutocovariance) {
  const auto p = make_process("DR");
  EXPECT_TRUE(p->deterministic());
  EXPECT_EQ(p->canonical_rank(), 80);
  std::vector<double> g(5, 1.0);
  p->generalized_autocovariance(std::vector<double>{2.0}, g);
  for (double v : g) EXPECT_EQ(v, 0.0);
}

TEST(DriftProcess, DerivativesMatchFiniteDifferences) {
  const auto p = make_process("DR");
  expect_derivatives_match_finite_differences(*p, {0.03}, dyadic_scales(10));
}

TEST(DriftProcess, SimulatesAStraightLineFromZero) {
  const auto p = make_process("DR");
  Rng rng = make_stream(1, {1});
  std::vector<double> x(100, 1.0);
  p->simulate(std::vector<double>{0.25}, rng, x);
  for (std::size_t t = 0; t < x.size(); ++t) EXPECT_DOUBLE_EQ(x[t], 1.0 + 0.25 * static_cast<double>(t));
}

TEST(DriftProcess, AcceptsANegativeOmegaAndRejectsZero) {
  const auto p = make_process("DR");
  EXPECT_EQ(p->validate(std::vector<double>{-0.5}), "");
  EXPECT_EQ(p->validate(std::vector<double>{0.5}), "");
  const std::string why = p->validate(std::vector<double>{0.0});
  EXPECT_NE(why.find("omega must be non-zero"), std::string::npos) << why;
}

TEST(DriftProcess, ANegativeDriftHasTheSameWaveletVarianceAndAFallingPath) {
  const auto p = make_process("DR");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{-1.0}, dyadic_scales(6)), {0.25, 1, 4, 16, 64, 256}, 1e-15,
                             "DR(-1)");
  Rng rng = make_stream(1, {1});
  std::vector<double> x(10, 0.0);
  p->simulate(std::vector<double>{-0.25}, rng, x);
  for (std::size_t t = 0; t < x.size(); ++t) EXPECT_DOUBLE_EQ(x[t], -0.25 * static_cast<double>(t));
  // The integrated error keeps the sign: x_1 + ... + x_4 = -0.25 (0 + 1 + 2 + 3)... with t = 1..K: -2.5.
  const auto m = p->sum_moments(std::vector<double>{-0.25}, std::vector<std::int64_t>{4});
  EXPECT_DOUBLE_EQ(m[0].mean, -2.5);
}

TEST(DriftProcess, InitialGuessExplainsTheCoarsestScale) {
  const auto p = make_process("DR");
  const auto tau = dyadic_scales(12);
  const auto wv = wv_of(*p, std::vector<double>{1e-3}, tau);
  const auto guess = p->initial_guess({tau, wv, 0.0});
  EXPECT_NEAR(guess.at(0), 1e-3, 1e-15);
}

TEST(DriftProcess, PhysicalDriftRate) {
  // omega = 3e-7 deg/s per sample at f = 200 Hz: R = 3e-7 * 200 = 6e-5 deg/s^2.
  const auto p = make_process("DR");
  const std::vector<double> theta{3e-7};
  const auto q = p->physical(theta, 200.0);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].name, "drift rate");
  EXPECT_NEAR(q[0].value, 6e-5, 1e-12 * 6e-5);
  EXPECT_EQ(render_unit(q[0].unit_pattern, "deg/s"), "deg/s^2");
  // The derivation: AVAR(T) = 2 WV(2m) = omega^2 m^2 / 2 equals R^2 T^2 / 2, T = m / f.
  const double m = 256.0, T = m / 200.0;
  const std::vector<double> tau{2.0 * m};
  EXPECT_NEAR(2.0 * wv_of(*p, theta, tau)[0] / (q[0].value * q[0].value * T * T / 2.0), 1.0, 1e-12);
}

TEST(DriftProcess, SumMomentsAreDeterministic) {
  // x_t = omega t, t = 1..K: K = 1: omega; K = 4: 10 omega; K = 100: 5050 omega.
  const auto p = make_process("DR");
  const std::vector<std::int64_t> counts{1, 4, 100};
  const auto m = p->sum_moments(std::vector<double>{0.5}, counts);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_DOUBLE_EQ(m[0].mean, 0.5);
  EXPECT_DOUBLE_EQ(m[1].mean, 5.0);
  EXPECT_DOUBLE_EQ(m[2].mean, 2525.0);
  for (const auto& x : m) EXPECT_EQ(x.variance, 0.0);
}

}  // namespace
}  // namespace gmwm::test
