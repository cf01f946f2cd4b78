#pragma once
// Whole-buffer decompression for the chunked log formats (ROS 1 bags, MCAP): bz2, LZ4 frames
// and zstd frames, each into a buffer of the size the container states, and the limits on
// what chunks may claim (docs/cli.md "Memory and limits"): a chunk of at most kMaxChunkBytes
// uncompressed, and over a file at most kMaxInflationRatio times the compressed bytes once
// past kInflationRatioFloorBytes, the rule gzip text follows (gmwm/io/signal_reader.h).
//
// Both are checked on the sizes the chunks state, before anything is allocated or inflated;
// the output buffer is then exactly the stated size and a codec stops when it is full, so no
// chunk inflates past what was checked, whatever its data hold.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

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

/// A chunk's uncompressed size above this is refused before allocating (bag and MCAP):
/// rosbag's chunks are 768 kB by default (`rosbag record --chunksize` takes a few MB), MCAP
/// writers use 1-4 MB.
inline constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;

/// The chunks of one file as they are read: each chunk's stated uncompressed size against
/// its stored (compressed) bytes, summed over the file, must keep within the inflation rule
/// of gmwm::io::inflation_exceeds (uncompressed chunks count with a ratio of 1).
class ChunkBudget {
 public:
  /// "" when a chunk of `stored` bytes stating `size` uncompressed keeps within the limits,
  /// else what it breaks ("claims ... more than 250 times its compressed size ...").
  std::string add(std::uint64_t stored, std::uint64_t size);

 private:
  std::uint64_t stored_ = 0, size_ = 0;
};

/// Bytes not zero-filled: pages are touched only as they are written.
class ByteBuffer {
 public:
  ByteBuffer() = default;
  explicit ByteBuffer(std::size_t n) : data_(n ? new unsigned char[n] : nullptr), size_(n) {}
  unsigned char* data() { return data_.get(); }
  const unsigned char* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

 private:
  std::unique_ptr<unsigned char[]> data_;
  std::size_t size_ = 0;
};

/// Decompresses `in` (n bytes) into exactly `size` bytes (checked by the caller against
/// kMaxChunkBytes and a ChunkBudget). On failure returns an empty buffer and sets `error`
/// ("zstd data does not decompress to its 4096 bytes (...)").
ByteBuffer decompress(Compression c, const unsigned char* in, std::size_t n, std::uint64_t size, std::string& error);

}  // namespace gmwm::io::detail
