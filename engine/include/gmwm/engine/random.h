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

  /// n draws of Boost.Random's standard normal into out: the numbers of n calls of
  /// boost::random::normal_distribution<double>(0, 1) on this engine, and the words they
  /// consume, exactly (its ziggurat's first try is a function of one word: it is taken for a
  /// run of words in one vectorised pass, and Boost itself draws the ~1.2% of normals whose
  /// first try fails). normal_distribution<double>(0, s) is unit * s + 0.0 of these.
  void unit_normals(double* out, std::size_t n);

 private:
  void refill();
  result_type state_[kStateWords];
  result_type out_[kStateWords];
  std::size_t next_ = kStateWords;
  std::uint64_t refills_ = 0;  // blocks generated so far (unit_normals' candidates are per block)
};

/// Calls f(z, t, m) for consecutive runs z[0, m) of the standard normals of samples
/// [t, t + m), t from 0 to n: the draws of n calls of normal_distribution<double>(0, 1) on
/// rng, in order, a run at a time on the stack (Rng::unit_normals). A process's simulate
/// draws its innovations this way: one call per sample was the simulations' largest cost.
template <class F>
void for_unit_normals(Rng& rng, std::size_t n, F&& f) {
  constexpr std::size_t kRun = 512;  // 4 KiB of draws: in L1 while the process reads them
  double z[kRun];
  for (std::size_t t = 0; t < n; t += kRun) {
    const std::size_t m = n - t < kRun ? n - t : kRun;
    rng.unit_normals(z, m);
    f(static_cast<const double*>(z), t, m);
  }
}

/// normal_distribution<double>(0, s)'s value from the unit draw z, as Boost forms it
/// (z * s + mean, the mean 0: a -0 draw gives +0).
inline double scaled_normal(double z, double s) { return z * s + 0.0; }

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
