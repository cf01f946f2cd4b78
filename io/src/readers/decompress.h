#pragma once
// Whole-buffer decompression for the chunked log formats (ROS 1 bags, MCAP): bz2, LZ4 frames
// and zstd frames, each into a buffer of the size the container states.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gmwm::io::detail {

enum class Compression { kNone, kBz2, kLz4Frame, kZstd };

/// A container format's names for its compressions.
struct CompressionName {
  const char* name;
  Compression compression;
};

/// The compression `name` stands for in `names`, or nothing.
template <std::size_t N>
const Compression* compression_named(const CompressionName (&names)[N], const std::string& name) {
  for (const CompressionName& c : names)
    if (name == c.name) return &c.compression;
  return nullptr;
}

/// "none, bz2 or lz4": the names, for messages.
template <std::size_t N>
std::string compression_list(const CompressionName (&names)[N]) {
  std::string out;
  for (std::size_t k = 0; k < N; ++k)
    out += (k == 0 ? "" : k + 1 == N ? " or " : ", ") + (*names[k].name ? std::string(names[k].name) : "'' (none)");
  return out;
}

/// Decompresses `in` (n bytes) into exactly `size` bytes. On failure returns an empty
/// vector and sets `error` ("zstd data does not decompress to its 4096 bytes (...)").
std::vector<unsigned char> decompress(Compression c, const unsigned char* in, std::size_t n, std::uint64_t size,
                                      std::string& error);

}  // namespace gmwm::io::detail
