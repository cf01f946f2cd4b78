// Cross-axis wavelet correlation (gap/src/cross_axis.cc): independent axes show none,
// a shared component shows at its scales with the correlation its variance share implies.
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/gap/cross_axis.h"

namespace gmwm::gap {
namespace {

constexpr std::int64_t kN = 1 << 15;

std::vector<double> white(std::uint64_t seed) {
  const Model m = parse_model("WN(sigma2=1)");
  return simulate(m, m.given_values(), kN, seed, 0);
}

TEST(CrossAxisCorrelation, FindsNothingBetweenIndependentAxes) {
  const auto a = white(11), b = white(12), c = white(13);
  const auto pairs = cross_axis_correlation({a, b, c}, 0, 0.05);
  ASSERT_FALSE(pairs.empty());
  for (const auto& p : pairs) {
    EXPECT_FALSE(p.significant) << p.a << "," << p.b << " level " << p.level << " rho " << p.rho;
    EXPECT_LT(std::abs(p.rho), 0.3);
  }
}

TEST(CrossAxisCorrelation, FindsASharedComponentAtItsScalesWithItsVarianceShare) {
  // A shared random walk dominates the coarse levels: there rho -> its share of each
  // axis' WV, gamma2 tau / 12 / (gamma2 tau / 12 + 1 / tau), close to 1 at tau >= 64.
  const Model rw = parse_model("RW(gamma2=0.01)");
  const auto shared = simulate(rw, rw.given_values(), kN, 21, 0);
  auto a = white(22), b = white(23);
  for (std::int64_t t = 0; t < kN; ++t) {
    a[static_cast<std::size_t>(t)] += shared[static_cast<std::size_t>(t)];
    b[static_cast<std::size_t>(t)] += shared[static_cast<std::size_t>(t)];
  }
  const auto pairs = cross_axis_correlation({a, b}, 0, 0.05);
  bool coarse_found = false;
  for (const auto& p : pairs) {
    const double share = 0.01 * p.tau / 12.0 / (0.01 * p.tau / 12.0 + 1.0 / p.tau);
    if (p.level == 1) {
      EXPECT_FALSE(p.significant) << "level 1 share " << share;
    }
    if (p.tau >= 64) {
      EXPECT_TRUE(p.significant) << p.level;
      EXPECT_NEAR(p.rho, share, 0.1) << p.level;
      coarse_found = true;
    }
  }
  EXPECT_TRUE(coarse_found);
}

TEST(CrossAxisCorrelation, RejectsSignalsOfDifferentLengths) {
  const std::vector<double> a(100, 0.0), b(99, 0.0);
  try {
    cross_axis_correlation({a, b}, 0, 0.05);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cross-axis correlation: signal 2 has 99 samples, signal 1 has 100");
  }
}

}  // namespace
}  // namespace gmwm::gap
