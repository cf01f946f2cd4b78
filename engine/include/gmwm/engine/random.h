#pragma once
// Seeded random streams. One stream per task (signal x model x replicate x component),
// derived from a user seed and a list of stream identifiers, so results are
// bit-identical whatever the thread count. Distributions come from Boost.Random, whose
// output is defined by the library (unlike std::normal_distribution).

#include <cstddef>
#include <cstdint>
#include <initializer_list>

namespace gmwm {

/// MT19937-64 (Matsumoto & Nishimura 1998; Nishimura 2000): the sequence of
/// boost::random::mt19937_64 and std::mt19937_64, bit for bit (tests/engine/random_test.cc:
/// the standard's check value and Boost's words), so the Boost.Random distributions drawn
/// from it give the numbers they always gave. It regenerates and tempers its 312 words in
/// one vectorised pass where Boost tempers one word per call: a normal draw 4.0 -> 3.4 ns,
/// the simulations' largest cost (issue 44).
class Rng {
 public:
  using result_type = std::uint64_t;
  static constexpr std::size_t kStateWords = 312;
  static constexpr result_type default_seed = 5489U;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }

  explicit Rng(result_type seed = default_seed);
  result_type operator()() {
    if (next_ == kStateWords) refill();
    return out_[next_++];
  }

 private:
  void refill();
  result_type state_[kStateWords];
  result_type out_[kStateWords];
  std::size_t next_ = kStateWords;
};

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer used to
/// derive independent-looking seeds from (seed, id, id, ...).
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// The stream for task `ids` under user seed `seed`.
inline Rng make_stream(std::uint64_t seed, std::initializer_list<std::uint64_t> ids) {
  std::uint64_t h = splitmix64(seed);
  for (std::uint64_t id : ids) h = splitmix64(h ^ splitmix64(id + 0x632BE59BD9B4E019ULL));
  return Rng(h);
}

/// The default seed of every command (docs/cli.md: "default fixed: runs are reproducible").
inline constexpr std::uint64_t kDefaultSeed = 20261121;

}  // namespace gmwm
