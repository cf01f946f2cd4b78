#include "gmwm/engine/random.h"

#include <algorithm>
#include <bit>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <boost/random/normal_distribution.hpp>

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

// The first try of Boost.Random's unit normal (detail::unit_normal_distribution, 128
// layers, with detail::generate_int_float_pair<double, 8> on a 64-bit engine: one word a
// try) for each word: bits 0-7 pick the sign (bit 0) and the layer i (bits 1-7); bits 8-63,
// with the word's bit 11 cleared as Boost clears it, are the fraction r = (u >> 8) / 2^56;
// x = r table_x[i] is taken when x < table_x[i + 1], and its value is x times the sign.
//
// Both versions below compute, for the words [from, to) (from and to multiples of four),
// value[k] and bit k of `taken` (bit k % 64 of taken[k / 64]) the same way:
// - (u >> 8) < 2^56 converted as two exact halves (28 bits each, made doubles by the
//   2^52 exponent trick) summed once: one correctly rounded operation on the exact value,
//   which is what a direct conversion is, and vectorises where a 64-bit conversion does not;
// - the product with the sign (+1 when bit 0 is set, else -1) as a flip of the sign bit,
//   which is what a product with -1 does, without a branch on a random bit.
constexpr std::uint64_t kClearedBit = ~(std::uint64_t{1} << 11);
constexpr std::uint64_t kExponent52 = 0x4330000000000000ULL;  // 2^52 as a double's bits
constexpr std::uint64_t kLow28 = (std::uint64_t{1} << 28) - 1;
constexpr double k2p52 = 0x1p52, k2p28 = 0x1p28, kFraction = 0x1p-56;

const double* ziggurat_table() { return boost::random::detail::normal_table<double>::table_x; }

void first_tries_portable(const std::uint64_t* words, std::size_t from, std::size_t to, double* value,
                          std::uint64_t* taken) {
  const double* table = ziggurat_table();
  for (std::size_t k = from; k < to; k += 4) {
    std::uint64_t bits = 0;
    for (std::size_t l = 0; l < 4; ++l) {
      const std::uint64_t w = words[k + l];
      const std::uint64_t v = (w & kClearedBit) >> 8;
      const double high = std::bit_cast<double>(kExponent52 | (v >> 28)) - k2p52;
      const double low = std::bit_cast<double>(kExponent52 | (v & kLow28)) - k2p52;
      const double r = (high * k2p28 + low) * kFraction;
      const auto i = static_cast<std::size_t>((w & 0xFF) >> 1);
      const double x = r * table[i];
      bits |= static_cast<std::uint64_t>(x < table[i + 1]) << l;
      value[k + l] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) ^ ((~w & 1) << 63));
    }
    taken[k / 64] = (taken[k / 64] & ~(std::uint64_t{15} << (k % 64))) | (bits << (k % 64));
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(GMWM_NO_VECTOR_CLONES)
#define GMWM_FIRST_TRIES_AVX2 1
// The same four words at a time in AVX2 (the table read by scalar loads: AVX2's gathers
// were slower on this machine kind). A whole draw (tools/bench: 5e7 draws in runs of 512)
// took 4.2 ns one Boost call at a time, 3.8 ns with the portable tries, 2.55 ns with these.
// No FMA: each operation rounds as the portable one's does.
[[gnu::target("avx2")]] void first_tries_avx2(const std::uint64_t* words, std::size_t from, std::size_t to,
                                              double* value, std::uint64_t* taken) {
  const double* table = ziggurat_table();
  const __m256i cleared = _mm256_set1_epi64x(static_cast<long long>(kClearedBit));
  const __m256i exponent = _mm256_set1_epi64x(static_cast<long long>(kExponent52));
  const __m256i low28 = _mm256_set1_epi64x(static_cast<long long>(kLow28));
  const __m256i one = _mm256_set1_epi64x(1);
  const __m256d p52 = _mm256_set1_pd(k2p52), p28 = _mm256_set1_pd(k2p28), fraction = _mm256_set1_pd(kFraction);
  for (std::size_t k = from; k < to; k += 4) {
    const __m256i w = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(words + k));
    const __m256i v = _mm256_srli_epi64(_mm256_and_si256(w, cleared), 8);
    const __m256d high = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(exponent, _mm256_srli_epi64(v, 28))), p52);
    const __m256d low = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(exponent, _mm256_and_si256(v, low28))), p52);
    const __m256d r = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(high, p28), low), fraction);
    const std::size_t i0 = (words[k] >> 1) & 0x7F, i1 = (words[k + 1] >> 1) & 0x7F, i2 = (words[k + 2] >> 1) & 0x7F,
                      i3 = (words[k + 3] >> 1) & 0x7F;
    const __m256d x = _mm256_mul_pd(r, _mm256_set_pd(table[i3], table[i2], table[i1], table[i0]));
    const __m256d next = _mm256_set_pd(table[i3 + 1], table[i2 + 1], table[i1 + 1], table[i0 + 1]);
    const auto bits = static_cast<std::uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(x, next, _CMP_LT_OQ)));
    const __m256i flip = _mm256_slli_epi64(_mm256_andnot_si256(w, one), 63);
    _mm256_storeu_pd(value + k, _mm256_castsi256_pd(_mm256_xor_si256(_mm256_castpd_si256(x), flip)));
    taken[k / 64] = (taken[k / 64] & ~(std::uint64_t{15} << (k % 64))) | (bits << (k % 64));
  }
}
#endif

using FirstTries = void (*)(const std::uint64_t*, std::size_t, std::size_t, double*, std::uint64_t*);

FirstTries first_tries() {
#ifdef GMWM_FIRST_TRIES_AVX2
  static const FirstTries chosen = [] {
    __builtin_cpu_init();  // a draw may come from a static initialiser, before libgcc's own
    return __builtin_cpu_supports("avx2") ? first_tries_avx2 : first_tries_portable;
  }();
  return chosen;
#else
  return first_tries_portable;
#endif
}

}  // namespace

void Rng::unit_normals(double* out, std::size_t n) {
  static_assert(kStateWords % 4 == 0, "first tries go four words at a time");
  boost::random::detail::unit_normal_distribution<double> boost_normal;
  const FirstTries tries = first_tries();
  double value[kStateWords];
  std::uint64_t taken[(kStateWords + 63) / 64] = {};
  std::uint64_t block = refills_ + 1;  // no candidates yet
  std::size_t valid_to = 0;            // candidates hold for the block's words [next_, valid_to)
  std::size_t done = 0;
  while (done < n) {
    if (next_ == kStateWords) refill();
    if (block != refills_ || next_ >= valid_to) {
      block = refills_;
      // At least a word a normal; whole fours (312 is a multiple of four).
      const std::size_t from = next_ & ~std::size_t{3};
      valid_to = std::min(kStateWords, (next_ + (n - done) + 3) & ~std::size_t{3});
      tries(out_, from, valid_to, value, taken);
    }
    // The run of taken first tries from next_: copied at once.
    const std::size_t limit = std::min(valid_to, next_ + (n - done));
    std::size_t k = next_;
    while (k < limit) {
      const std::uint64_t refused = ~taken[k / 64] >> (k % 64);
      if (refused != 0) {
        k = std::min(limit, k + static_cast<std::size_t>(std::countr_zero(refused)));
        break;
      }
      k = std::min(limit, (k | 63) + 1);
    }
    std::copy(value + next_, value + k, out + done);
    done += k - next_;
    next_ = k;
    // A first try that fails: Boost's own draw from that word on (the same try, then its
    // tail or wedge, consuming what it consumes).
    if (done < n && k < valid_to) out[done++] = boost_normal(*this);
  }
}

Rng::Rng(result_type seed) {
  state_[0] = seed;
  for (std::size_t j = 1; j < kN; ++j)
    state_[j] = kInitMultiplier * (state_[j - 1] ^ (state_[j - 1] >> 62)) + static_cast<std::uint64_t>(j);
}

void Rng::refill() {
  regenerate(state_, out_);
  next_ = 0;
  ++refills_;
}

}  // namespace gmwm
