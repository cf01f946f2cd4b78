#include "gmwm/robust/spike_screen.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gmwm::robust {

void level_one_jumps(const double* x, std::int64_t n, std::vector<double>& out) {
  out.resize(static_cast<std::size_t>(std::max<std::int64_t>(n - 1, 0)));
  for (std::int64_t t = 1; t < n; ++t) out[static_cast<std::size_t>(t - 1)] = 0.5 * (x[t] - x[t - 1]);
}

std::vector<double> level_one_jumps(const double* x, std::int64_t n) {
  std::vector<double> w;
  level_one_jumps(x, n, w);
  return w;
}

SpikeScreen screen_spikes(const double* x, std::int64_t n, double level_one_scale) {
  SpikeScreen out;
  if (n < 2 || !(level_one_scale > 0.0) || !std::isfinite(level_one_scale)) {
    out.note = "spike screen not applied: the level-1 robust scale is undefined";
    return out;
  }
  const double s_scale = level_one_scale;
  out.applied = true;
  out.scale = s_scale;
  const double cut = kSpikeThreshold * std::sqrt(s_scale);
  std::int64_t first = -1, last = -1, count = 0;
  auto close_cluster = [&] {
    if (count >= 2) out.ranges.emplace_back(first, last - 1);
    // A lone jump next to an end is a spike or glitch cut by the record's boundary.
    else if (count == 1 && first <= kSpikeMaxGap)
      out.ranges.emplace_back(0, first - 1);
    else if (count == 1 && first >= n - kSpikeMaxGap)
      out.ranges.emplace_back(first, n - 1);
  };
  for (std::int64_t t = 1; t < n; ++t) {
    // The level-one jump of level_one_jumps, computed in place (a second 8 MB vector of
    // them cost page faults and zeroing: issue 44).
    if (!(std::abs(0.5 * (x[t] - x[t - 1])) > cut)) continue;
    if (count > 0 && t - last <= kSpikeMaxGap) {
      last = t;
      ++count;
      continue;
    }
    if (count > 0) close_cluster();
    first = last = t;
    count = 1;
  }
  if (count > 0) close_cluster();
  for (const auto& [a, b] : out.ranges) out.samples += b - a + 1;
  out.note = describe_screen(out);
  return out;
}

std::string describe_screen(const SpikeScreen& screen) {
  std::ostringstream os;
  os << "spike screen: " << screen.samples << " sample" << (screen.samples == 1 ? "" : "s") << " in "
     << screen.ranges.size() << " range" << (screen.ranges.size() == 1 ? "" : "s")
     << " replaced by interpolation (clusters of level-1 jumps beyond " << kSpikeThreshold << " robust sd, at most "
     << kSpikeMaxGap << " samples apart)";
  return os.str();
}

namespace {

// The median of x[from, to) (to > from).
double median_of(const double* x, std::int64_t from, std::int64_t to) {
  std::vector<double> v(x + from, x + to);
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

}  // namespace

std::vector<double> replace_ranges(const double* x, std::int64_t n,
                                   const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges) {
  std::vector<double> y(x, x + n);
  for (const auto& [a, b] : ranges) {
    if (a > b || a < 0 || b >= n) continue;
    if (a == 0 && b == n - 1) continue;  // nothing to interpolate from
    // Anchors: medians of the kAnchorSamples samples on each side, not the neighbours
    // themselves: the first samples of a contaminated stretch often precede its first
    // flagged jump, and a line from one of them would add a ramp as large as the
    // contamination.
    const bool has_left = a > 0, has_right = b < n - 1;
    const double left = has_left ? median_of(x, std::max<std::int64_t>(0, a - kAnchorSamples), a) : 0.0;
    const double right = has_right ? median_of(x, b + 1, std::min(n, b + 1 + kAnchorSamples)) : 0.0;
    const double l = has_left ? left : right, r = has_right ? right : left;
    const double span = static_cast<double>(b - a + 2);
    for (std::int64_t t = a; t <= b; ++t)
      y[static_cast<std::size_t>(t)] = l + (r - l) * static_cast<double>(t - a + 1) / span;
  }
  return y;
}

}  // namespace gmwm::robust
