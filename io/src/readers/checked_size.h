#pragma once
// Overflow-safe arithmetic on the sizes, counts and offsets a binary file states (issue 25):
// every sum or product of values read from a file goes through these, so that a crafted
// size wraps around to nothing small. nullopt when the result does not fit in 64 bits.

#include <cstdint>
#include <optional>

namespace gmwm::io::detail {

inline std::optional<std::uint64_t> checked_add(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r;
  if (__builtin_add_overflow(a, b, &r)) return std::nullopt;
  return r;
}

inline std::optional<std::uint64_t> checked_mul(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r;
  if (__builtin_mul_overflow(a, b, &r)) return std::nullopt;
  return r;
}

/// True when [offset, offset + length) lies within [0, size).
inline bool fits(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
  return offset <= size && length <= size - offset;
}

}  // namespace gmwm::io::detail
