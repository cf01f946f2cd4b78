// The hot loops marked GMWM_VECTOR_CLONES (vector_clones.h) run as an AVX2 clone on an AVX2
// machine and as the baseline x86-64 clone elsewhere; their results must not depend on which.
// This file is compiled for the baseline (no -mavx2), so its reference loops are the
// baseline's arithmetic in the documented order, while the library's calls take the clone
// the loader chose (on an AVX2 machine, the AVX2 one): equality bit for bit is the check.
// (gmwm's JSON from every command on the ADIS recordings was also the same with and without
// the clones: tools/bench/json_identity.py, issue 44.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/vector_clones.h"

namespace gmwm {
namespace {

// s_0 = 7, s_{k+1} = (6364136223846793005 s_k + 1442695040888963407) mod 2^64; x_k from the
// top 53 bits, a random walk's partial sums added so the prefix sums are large.
std::vector<double> test_series(int n) {
  std::vector<double> x;
  std::uint64_t s = 7;
  double walk = 0.0;
  for (int k = 0; k < n; ++k) {
    s = 6364136223846793005ULL * s + 1442695040888963407ULL;
    const double u = static_cast<double>(s >> 11) / 9007199254740992.0 - 0.5;
    walk += 1e-3 * u;
    x.push_back(u + walk);
  }
  return x;
}

TEST(VectorClones, EachLevelsSumOfSquaresIsTheFourLaneSumOfTheBaselineBitForBit) {
  // A length that is not a multiple of four, so each level has a tail beside its lanes.
  const int n = (1 << 16) + 7;
  const auto x = test_series(n);
  const HaarModwt modwt(x.data(), n);
  std::vector<double> w;
  for (int j = 1; j <= modwt.max_levels(); ++j) {
    // The coefficients are (a - 2b + c) / tau, and tau a power of two: times tau they are the
    // differences d whose squares the level's sum adds, exactly.
    modwt.coefficients(j, w);
    const double tau = static_cast<double>(std::int64_t{1} << j), inv = 1.0 / tau;
    double lane[4] = {0.0, 0.0, 0.0, 0.0}, peak[4] = {0.0, 0.0, 0.0, 0.0};
    const std::size_t whole = w.size() - w.size() % 4;
    for (std::size_t k = 0; k < whole; ++k) {
      const double d = w[k] * tau, e = d * d;
      lane[k % 4] += e;
      peak[k % 4] = std::max(peak[k % 4], e);
    }
    double s0 = lane[0], top = std::max(std::max(peak[0], peak[1]), std::max(peak[2], peak[3]));
    for (std::size_t k = whole; k < w.size(); ++k) {
      const double d = w[k] * tau;
      s0 += d * d;
      top = std::max(top, d * d);
    }
    const double sum = (s0 + lane[1] + lane[2] + lane[3]) * inv * inv;
    EXPECT_EQ(modwt.sum_of_squares(j), sum) << "level " << j;
    const HaarModwt::Squares sq = modwt.squares_of_level(j);
    EXPECT_EQ(sq.sum, sum) << "level " << j;
    EXPECT_EQ(sq.peak, top * inv * inv) << "level " << j;
  }
}

TEST(VectorClones, KeptSquaresOfTheSharedPassesEqualTheBaselinesFourLaneSums) {
  const int n = (1 << 16) + 5;
  const auto x = test_series(n);
  HaarModwt kept(x.data(), n);
  const HaarModwt fresh(x.data(), n);
  kept.keep_squares(3, kept.max_levels());
  std::vector<double> w;
  for (int j = 3; j <= kept.max_levels(); ++j) {
    fresh.coefficients(j, w);
    const double tau = static_cast<double>(std::int64_t{1} << j), inv = 1.0 / tau;
    double lane[4] = {0.0, 0.0, 0.0, 0.0};
    const std::size_t whole = w.size() - w.size() % 4;
    for (std::size_t k = 0; k < whole; ++k) lane[k % 4] += (w[k] * tau) * (w[k] * tau);
    double s0 = lane[0];
    for (std::size_t k = whole; k < w.size(); ++k) s0 += (w[k] * tau) * (w[k] * tau);
    EXPECT_EQ(kept.squares_of_level(j).sum, (s0 + lane[1] + lane[2] + lane[3]) * inv * inv) << "level " << j;
  }
}

}  // namespace
}  // namespace gmwm
