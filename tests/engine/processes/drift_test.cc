#include <gtest/gtest.h>

#include "gmwm/engine/random.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(DriftProcess, MatchesReferenceWaveletVariance) {
  const auto p = make_process("DR");
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0}, dyadic_scales(6)),
                             {0.25, 1, 4, 16, 64, 256}, 1e-15, "DR(1)");
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

TEST(DriftProcess, RejectsNonPositiveOmegaSayingTheSignIsNotIdentifiable) {
  const auto p = make_process("DR");
  const std::string why = p->validate(std::vector<double>{-0.5});
  EXPECT_NE(why.find("omega"), std::string::npos) << why;
  EXPECT_NE(why.find("|omega|"), std::string::npos) << why;
  EXPECT_NE(p->validate(std::vector<double>{0.0}), "");
  EXPECT_EQ(p->validate(std::vector<double>{0.5}), "");
}

TEST(DriftProcess, InitialGuessExplainsTheCoarsestScale) {
  const auto p = make_process("DR");
  const auto tau = dyadic_scales(12);
  const auto wv = wv_of(*p, std::vector<double>{1e-3}, tau);
  const auto guess = p->initial_guess({tau, wv, 0.0});
  EXPECT_NEAR(guess.at(0), 1e-3, 1e-15);
}

}  // namespace
}  // namespace gmwm::test
