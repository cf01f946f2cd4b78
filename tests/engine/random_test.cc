// The project's random stream (gmwm::Rng): MT19937-64 bit for bit, so that every
// simulation draws the numbers Boost's engine gave it.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>
#include <random>
#include <type_traits>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

#include "gmwm/engine/random.h"

namespace gmwm {
namespace {

TEST(Rng, TheTenThousandthWordFromTheDefaultSeedIsTheStandardsCheckValue) {
  // C++ standard [rand.predef]: the 10000th consecutive invocation of a default-constructed
  // mt19937_64 produces 9981545732273789042.
  Rng g;
  Rng::result_type v = 0;
  for (int k = 0; k < 10000; ++k) v = g();
  EXPECT_EQ(v, 9981545732273789042ULL);
}

TEST(Rng, GivesBoostsAndTheStandardLibrarysWordsForEverySeedAcrossManyRefills) {
  // 5000 words cross 16 regenerations of the 312-word state; seeds with high bits set and 0.
  const std::uint64_t seeds[] = {0, 1, 5489, 0x8000000000000000ULL, 0xFFFFFFFFFFFFFFFFULL, splitmix64(20261121)};
  for (std::uint64_t seed : seeds) {
    Rng g(seed);
    boost::random::mt19937_64 b(seed);
    std::mt19937_64 s(seed);
    for (int k = 0; k < 5000; ++k) {
      const auto v = g();
      ASSERT_EQ(v, b()) << "seed " << seed << ", word " << k;
      ASSERT_EQ(v, s()) << "seed " << seed << ", word " << k;
    }
  }
}

TEST(Rng, BoostsNormalDistributionDrawsTheSameNumbersFromItAsFromBoostsEngine) {
  // The ziggurat consumes a varying number of words per draw (its rejections): the same
  // draws over a long stretch show the streams stay aligned.
  Rng g = make_stream(20261121, {3, 1});
  std::uint64_t h = splitmix64(20261121);
  for (std::uint64_t id : {std::uint64_t{3}, std::uint64_t{1}})
    h = splitmix64(h ^ splitmix64(id + 0x632BE59BD9B4E019ULL));
  boost::random::mt19937_64 b(h);
  boost::random::normal_distribution<double> z(0.0, 2.5), zb(0.0, 2.5);
  for (int k = 0; k < 200000; ++k) ASSERT_EQ(z(g), zb(b)) << "draw " << k;
}

// The draws of unit_normals against Boost's normal_distribution(0, 1) on an identical
// engine, number for number (as bits: -0 and +0 told apart) and word for word (the next
// word after them agrees).
void expect_boosts_normals(std::uint64_t seed, const std::vector<std::size_t>& runs) {
  Rng g(seed);
  boost::random::mt19937_64 b(seed);
  boost::random::detail::unit_normal_distribution<double> z;
  std::vector<double> out;
  std::size_t drawn = 0;
  for (std::size_t m : runs) {
    out.assign(m, 0.0);
    if (m == 1 && drawn % 3 == 0) {
      out[0] = z(g);  // a single draw between runs: the candidates must not outlive it
    } else {
      g.unit_normals(out.data(), m);
    }
    for (std::size_t k = 0; k < m; ++k)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(out[k]), std::bit_cast<std::uint64_t>(z(b)))
          << "seed " << seed << ", draw " << drawn + k << " (" << out[k] << ")";
    drawn += m;
    ASSERT_EQ(g(), b()) << "seed " << seed << ": the word after draw " << drawn;
  }
}

TEST(Rng, UnitNormalsAreBoostsNormalsNumberForNumberAndWordForWord) {
  // Runs shorter and longer than a block of 312 words, ones, and runs ending on a block's
  // edge; 10^6 draws a seed meet ~12000 failed first tries (wedges and ~600 tails).
  std::vector<std::size_t> runs;
  const std::size_t sizes[] = {1, 311, 312, 313, 1, 1, 1, 7, 1000, 4096, 1, 65536, 2};
  std::size_t total = 0;
  for (std::size_t k = 0; total < 1000000; ++k) {
    runs.push_back(sizes[k % std::size(sizes)]);
    total += runs.back();
  }
  for (std::uint64_t seed : {std::uint64_t{5489}, splitmix64(1), splitmix64(20261121)})
    expect_boosts_normals(seed, runs);
  // One run of a million: blocks crossed inside the run and inside Boost's own draws.
  expect_boosts_normals(splitmix64(7), {1000000});
}

TEST(Rng, ForUnitNormalsHandsOutTheDrawsInOrderInRunsCoveringEverySample) {
  Rng g(11), h(11);
  boost::random::detail::unit_normal_distribution<double> z;
  std::size_t next = 0;
  for_unit_normals(g, 1300, [&](const double* v, std::size_t t, std::size_t m) {
    EXPECT_EQ(t, next);
    EXPECT_GT(m, 0U);
    for (std::size_t k = 0; k < m; ++k) EXPECT_EQ(v[k], z(h)) << "sample " << t + k;
    next = t + m;
  });
  EXPECT_EQ(next, 1300U);
  EXPECT_EQ(scaled_normal(-0.0, 2.0), 0.0);
  EXPECT_FALSE(std::signbit(scaled_normal(-0.0, 2.0)));  // Boost adds its mean 0
  EXPECT_EQ(scaled_normal(-1.5, 2.0), -3.0);
}

TEST(Rng, IsAUniformRandomBitGenerator) {
  static_assert(std::uniform_random_bit_generator<Rng>);
  EXPECT_EQ(Rng::min(), 0U);
  EXPECT_EQ(Rng::max(), ~std::uint64_t{0});
}

}  // namespace
}  // namespace gmwm
