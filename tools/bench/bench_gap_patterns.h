#pragma once
// Patterns of missing samples the gap benchmarks remove from a simulated grid: random bursts
// (runs of 1..200 samples) or the PX4 pattern (stretches of 2000 samples in which every tenth
// sample is dropped), a given share of the grid; and the observed samples a grid keeps.
#include <cstdint>
#include <vector>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/random.h"

namespace gmwm::bench {

constexpr std::int64_t kMaxBurst = 200;     // random bursts: 1..200 samples
constexpr std::int64_t kPx4Stretch = 2000;  // PX4: stretches of 2000 samples, every tenth dropped

enum class Pattern { kBursts, kPx4 };

// Grid positions [start, start + length) missing, increasing and apart.
inline std::vector<MissingRun> pattern_runs(Pattern p, std::int64_t n, double share, std::uint64_t seed) {
  Rng rng = make_stream(seed, {17});
  boost::random::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<MissingRun> runs;
  if (p == Pattern::kBursts) {
    const double start_probability = share / (static_cast<double>(kMaxBurst + 1) / 2.0);
    for (std::int64_t k = 1; k < n - kMaxBurst - 1; ++k) {
      if (u(rng) >= start_probability) continue;
      const auto len = 1 + static_cast<std::int64_t>(u(rng) * static_cast<double>(kMaxBurst));
      runs.push_back({k, len});
      k += len + 1;
    }
    return runs;
  }
  // PX4: a stretch drops a tenth of its samples, so stretches cover 10 x share of the record.
  const double stretch_probability = 10.0 * share / static_cast<double>(kPx4Stretch);
  for (std::int64_t k = 1; k < n - kPx4Stretch - 1; ++k) {
    if (u(rng) >= stretch_probability) continue;
    for (std::int64_t i = k + 9; i < k + kPx4Stretch; i += 10) runs.push_back({i, 1});
    k += kPx4Stretch;
  }
  return runs;
}

inline std::vector<double> observed_of(const std::vector<double>& full, const std::vector<MissingRun>& runs) {
  std::vector<double> out;
  out.reserve(full.size());
  std::int64_t k = 0;
  for (const MissingRun& r : runs) {
    for (; k < r.start; ++k) out.push_back(full[static_cast<std::size_t>(k)]);
    k = r.start + r.length;
  }
  for (; k < static_cast<std::int64_t>(full.size()); ++k) out.push_back(full[static_cast<std::size_t>(k)]);
  return out;
}

}  // namespace gmwm::bench
