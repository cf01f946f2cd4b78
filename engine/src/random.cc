#include "gmwm/engine/random.h"

#include "gmwm/engine/vector_clones.h"

namespace gmwm {
namespace {

// MT19937-64's parameters (Nishimura 2000; the C++ standard's mt19937_64): degree n = 312,
// middle word m = 156, twist matrix a, tempering (u, d), (s, b), (t, c), l, and the
// initialisation multiplier f.
constexpr std::size_t kN = Rng::kStateWords, kM = 156;
constexpr std::uint64_t kMatrixA = 0xB5026F5AA96619E9ULL;
constexpr std::uint64_t kUpperMask = 0xFFFFFFFF80000000ULL, kLowerMask = 0x7FFFFFFFULL;  // r = 31
constexpr std::uint64_t kTemperD = 0x5555555555555555ULL, kTemperB = 0x71D67FFFEDA60000ULL,
                        kTemperC = 0xFFF7EEE000000000ULL;
constexpr int kTemperU = 29, kTemperS = 17, kTemperT = 37, kTemperL = 43;
constexpr std::uint64_t kInitMultiplier = 6364136223846793005ULL;

std::uint64_t twisted(std::uint64_t upper_from, std::uint64_t lower_from, std::uint64_t far) {
  const std::uint64_t y = (upper_from & kUpperMask) | (lower_from & kLowerMask);
  // (y odd ? a : 0) without a branch: the loops below vectorise.
  return far ^ (y >> 1) ^ ((std::uint64_t{0} - (y & 1U)) & kMatrixA);
}

// The next n words of the state and their tempered outputs (the recurrence in place:
// word j reads j + 1 and j + m, which are still the old ones for j < n - m, then the new
// ones j - (n - m)).
GMWM_VECTOR_CLONES void regenerate(std::uint64_t* x, std::uint64_t* out) {
  for (std::size_t j = 0; j < kN - kM; ++j) x[j] = twisted(x[j], x[j + 1], x[j + kM]);
  for (std::size_t j = kN - kM; j < kN - 1; ++j) x[j] = twisted(x[j], x[j + 1], x[j - (kN - kM)]);
  x[kN - 1] = twisted(x[kN - 1], x[0], x[kM - 1]);
  for (std::size_t j = 0; j < kN; ++j) {
    std::uint64_t z = x[j];
    z ^= (z >> kTemperU) & kTemperD;
    z ^= (z << kTemperS) & kTemperB;
    z ^= (z << kTemperT) & kTemperC;
    out[j] = z ^ (z >> kTemperL);
  }
}

}  // namespace

Rng::Rng(result_type seed) {
  state_[0] = seed;
  for (std::size_t j = 1; j < kN; ++j)
    state_[j] = kInitMultiplier * (state_[j - 1] ^ (state_[j - 1] >> 62)) + static_cast<std::uint64_t>(j);
}

void Rng::refill() {
  regenerate(state_, out_);
  next_ = 0;
}

}  // namespace gmwm
