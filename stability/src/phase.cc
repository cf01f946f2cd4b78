// The phase of a rate or fractional-frequency series (deviation.h): one pass for each chunk's
// sum (the record's mean and every chunk's start), one for the running sums within the
// chunks. The chunks run in parallel for a series in memory and in turn, block by block, for
// one in a temporary file: the same arithmetic, the same values.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/samples.h"
#include "gmwm/stability/deviation.h"

namespace gmwm::stability {
namespace {

// Samples a chunk holds: 2^16 (512 kB), 16 to a for_each_block block of 2^20 (samples.h), so
// the blocks of a series in a file cut no chunk; a record of 1e6 samples has 16 chunks, enough
// for every thread. Within a chunk the running sum is one long-double chain (~1 ns a sample).
constexpr std::size_t kPhaseChunk = std::size_t{1} << 16;
// Four interleaved long-double lanes in a chunk's sum (independent chains: the pass runs at
// the adder's throughput, not its latency).
constexpr std::size_t kSumLanes = 4;

std::string text_of(double v) { return significant(v, 6); }

// The sum of y over [0, count) in kSumLanes lanes.
long double chunk_sum(const double* y, std::size_t count) {
  std::array<long double, kSumLanes> lane{};
  std::size_t i = 0;
  for (; i + kSumLanes <= count; i += kSumLanes)
    for (std::size_t l = 0; l < kSumLanes; ++l) lane[l] += y[i + l];
  for (; i < count; ++i) lane[0] += y[i];
  return (lane[0] + lane[1]) + (lane[2] + lane[3]);
}

// Each chunk's sum of y (a series in a file read block by block, released behind). A sum of
// finite doubles cannot overflow a long double, so a chunk whose sum is not finite holds a
// sample that is not: the first such is named.
std::vector<long double> chunk_sums(std::span<const double> y) {
  const std::size_t chunks = (y.size() + kPhaseChunk - 1) / kPhaseChunk;
  std::vector<long double> sum(chunks);
  const auto one = [&](std::size_t k) {
    sum[k] = chunk_sum(y.data() + k * kPhaseChunk, std::min(kPhaseChunk, y.size() - k * kPhaseChunk));
  };
  if (gmwm::detail::in_sample_file(y.data(), y.size()))
    gmwm::for_each_block(y, [&](std::span<const double> part, std::size_t at) {
      for (std::size_t k = at / kPhaseChunk; k * kPhaseChunk < at + part.size(); ++k) one(k);
    });
  else
    gmwm::parallel_for(std::size_t{0}, chunks, one);
  for (std::size_t k = 0; k < chunks; ++k)
    if (!std::isfinite(sum[k]))
      for (std::size_t i = k * kPhaseChunk; i < y.size(); ++i)
        if (!std::isfinite(y[i])) throw InputError("sample " + std::to_string(i) + " is not a finite number");
  return sum;
}

// Chunk k's phase x_{i+1}, i in the chunk, into out: its start (the chunks before it, less the
// offset) then the running sum of (y_i - offset) tau0.
struct PhaseChunks {
  std::span<const double> y;
  double tau0, offset;
  std::vector<long double> start;  // x at each chunk's first sample

  PhaseChunks(std::span<const double> series, double spacing, double less, const std::vector<long double>& sum)
      : y(series), tau0(spacing), offset(less), start(sum.size()) {
    long double x = 0.0L;
    for (std::size_t k = 0; k < sum.size(); ++k) {
      start[k] = x;
      const auto count = static_cast<long double>(std::min(kPhaseChunk, y.size() - k * kPhaseChunk));
      x += (sum[k] - count * offset) * tau0;
    }
  }
  void write(std::size_t k, double* out) const {
    const std::size_t first = k * kPhaseChunk, count = std::min(kPhaseChunk, y.size() - first);
    long double x = start[k];
    for (std::size_t i = 0; i < count; ++i) {
      x += (static_cast<long double>(y[first + i]) - offset) * tau0;
      out[i] = static_cast<double>(x);
    }
  }
};

void check_spacing(double tau0) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw InputError("tau0: found " + text_of(tau0) + ", expected a positive, finite spacing in seconds");
}

// The phase in memory: x_0 = 0, the chunks in parallel.
std::vector<double> phase_in_memory(const PhaseChunks& chunks) {
  std::vector<double> x(chunks.y.size() + 1);
  x[0] = 0.0;
  gmwm::parallel_for(std::size_t{0}, chunks.start.size(),
                     [&](std::size_t k) { chunks.write(k, x.data() + 1 + k * kPhaseChunk); });
  return x;
}

// The phase of a series in a file, into one: the chunks in turn, block by block.
Samples phase_in_file(const PhaseChunks& chunks) {
  SampleFileWriter writer;
  const double zero = 0.0;
  writer.append(&zero, 1);
  std::vector<double> buffer(kPhaseChunk);
  gmwm::for_each_block(chunks.y, [&](std::span<const double> part, std::size_t at) {
    for (std::size_t k = at / kPhaseChunk; k * kPhaseChunk < at + part.size(); ++k) {
      chunks.write(k, buffer.data());
      writer.append(buffer.data(), std::min(kPhaseChunk, chunks.y.size() - k * kPhaseChunk));
    }
  });
  return writer.finish();
}

}  // namespace

std::vector<double> phase_from_frequency(std::span<const double> y, double tau0, double offset) {
  check_spacing(tau0);
  const std::vector<long double> sum = chunk_sums(y);
  if (!std::isfinite(offset)) throw InputError("offset: found " + text_of(offset) + ", expected a finite number");
  return phase_in_memory(PhaseChunks(y, tau0, offset, sum));
}

Samples phase_from_record(const Samples& y, double tau0) {
  check_spacing(tau0);
  const std::vector<long double> sum = chunk_sums(y);
  long double total = 0.0L;
  for (const long double s : sum) total += s;
  const double mean = y.empty() ? 0.0 : static_cast<double>(total / static_cast<long double>(y.size()));
  const PhaseChunks chunks(y, tau0, mean, sum);
  if (y.in_file()) return phase_in_file(chunks);
  return phase_in_memory(chunks);
}

}  // namespace gmwm::stability
