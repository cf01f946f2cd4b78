#include "decompress.h"

#include <cstring>

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

namespace gmwm::io::detail {
namespace {

std::string size_text(std::uint64_t size) { return std::to_string(size) + " bytes"; }

bool lz4_frame(const unsigned char* in, std::size_t n, std::vector<unsigned char>& out, std::string& error) {
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
            (ret != 0 ? ", the frame is cut short)" : ")");
    return false;
  }
  return true;
}

}  // namespace

std::vector<unsigned char> decompress(Compression c, const unsigned char* in, std::size_t n, std::uint64_t size,
                                      std::string& error) {
  std::vector<unsigned char> out;
  if (c == Compression::kNone) {
    if (n != size) {
      error = "uncompressed data of " + size_text(n) + ", its header says " + size_text(size);
      return out;
    }
    out.assign(in, in + n);
    return out;
  }
  out.resize(size);
  bool ok = false;
  switch (c) {
    case Compression::kBz2: {
      auto dest = static_cast<unsigned int>(size);
      const int rc = size > 0xffffffffull ? BZ_OUTBUFF_FULL
                                          : BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &dest,
                                                                       const_cast<char*>(reinterpret_cast<const char*>(in)),
                                                                       static_cast<unsigned int>(n), 0, 0);
      ok = rc == BZ_OK && dest == size;
      if (!ok) error = "bz2 data does not decompress to its " + size_text(size) + " (libbz2 code " + std::to_string(rc) + ")";
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
  if (!ok) out.clear();
  return out;
}

}  // namespace gmwm::io::detail
