#include "decompress.h"

#include <cstdio>
#include <cstring>

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

#include "gmwm/io/signal_reader.h"

namespace gmwm::io::detail {
namespace {

std::string size_text(std::uint64_t size) { return std::to_string(size) + " bytes"; }

bool lz4_frame(const unsigned char* in, std::size_t n, ByteBuffer& out, std::string& error) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
    error = "cannot create an LZ4 decompression context";
    return false;
  }
  std::size_t done = 0, used = 0, ret = 1;
  while (ret != 0 && used < n) {
    std::size_t dst = out.size() - done, src = n - used;
    ret = LZ4F_decompress(ctx, out.data() + done, &dst, in + used, &src, nullptr);
    if (LZ4F_isError(ret)) break;
    done += dst;
    used += src;
    if (dst == 0 && src == 0) break;  // no progress: the output is full before the frame ends
  }
  LZ4F_freeDecompressionContext(ctx);
  if (LZ4F_isError(ret)) {
    error = std::string("lz4 data does not decompress (") + LZ4F_getErrorName(ret) + ")";
    return false;
  }
  if (ret != 0 || done != out.size()) {
    error = "lz4 data does not decompress to its " + size_text(out.size()) + " (found " + size_text(done) +
            (ret != 0 ? ", the frame is cut short or holds more)" : ")");
    return false;
  }
  return true;
}

}  // namespace

std::string ChunkBudget::add(std::uint64_t stored, std::uint64_t size) {
  if (size > kMaxChunkBytes)
    return "uncompressed size " + size_text(size) + ", above the limit of " + size_text(kMaxChunkBytes) +
           " a chunk (docs/cli.md \"Memory and limits\")";
  stored_ += stored;  // both sums stay far from 2^64: each term is at most a file's size or 1 GiB
  size_ += size;
  if (inflation_exceeds(stored_, size_)) {
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.0f", kMaxInflationRatio);
    return "claims " + size_text(size) + " uncompressed from " + size_text(stored) +
           ", which brings the file's chunks to " + size_text(size_) + " from " + size_text(stored_) + ": more than " +
           ratio + " times their compressed size past " + std::to_string(kInflationRatioFloorBytes >> 20) +
           " MiB (a decompression bomb?), expected compressed messages";
  }
  return {};
}

ByteBuffer decompress(Compression c, const unsigned char* in, std::size_t n, std::uint64_t size, std::string& error) {
  if (c == Compression::kNone) {
    if (n != size) {
      error = "uncompressed data of " + size_text(n) + ", its header says " + size_text(size);
      return {};
    }
    ByteBuffer out(n);
    if (n) std::memcpy(out.data(), in, n);
    return out;
  }
  ByteBuffer out(static_cast<std::size_t>(size));
  bool ok = false;
  switch (c) {
    case Compression::kBz2: {
      auto dest = static_cast<unsigned int>(size);
      const int rc = size > 0xffffffffull
                         ? BZ_OUTBUFF_FULL
                         : BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &dest,
                                                      const_cast<char*>(reinterpret_cast<const char*>(in)),
                                                      static_cast<unsigned int>(n), 0, 0);
      ok = rc == BZ_OK && dest == size;
      if (!ok)
        error = "bz2 data does not decompress to its " + size_text(size) + " (libbz2 code " + std::to_string(rc) +
                (rc == BZ_OUTBUFF_FULL ? ": they hold more)" : ")");
      break;
    }
    case Compression::kLz4Frame:
      ok = lz4_frame(in, n, out, error);
      break;
    case Compression::kZstd: {
      const std::size_t r = ZSTD_decompress(out.data(), out.size(), in, n);
      ok = !ZSTD_isError(r) && r == size;
      if (!ok)
        error = "zstd data does not decompress to its " + size_text(size) + " (" +
                (ZSTD_isError(r) ? std::string(ZSTD_getErrorName(r)) : "found " + size_text(r)) + ")";
      break;
    }
    case Compression::kNone:
      break;
  }
  if (!ok) return {};
  return out;
}

}  // namespace gmwm::io::detail
