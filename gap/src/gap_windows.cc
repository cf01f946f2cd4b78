#include "gap_windows.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>

#include "gap_reference.h"
#include "gmwm/engine/classical_wv.h"

namespace gmwm::gap::detail {
namespace {

// docs/gap.md, method note 2: "window at least 16 x the largest scale of interest".
constexpr int kWindowScaleRatio = 16;
// Fewest windows worth a map (fewer cannot say where in time something happens).
constexpr std::int64_t kMinWindows = 8;
// Fewest levels per window (tau = 2, 4, 8, 16 at least: L >= 16 x 16 = 256 samples).
constexpr int kMinWindowLevels = 4;
// Shortest half worth comparing (the WV's minimum length, classical_wv.h).
constexpr std::int64_t kMinHalfLength = 16;
// Stream family of the window reference (apart from the full-length reference's).
constexpr std::uint64_t kWindowSeedOffset = 0x77696eULL;

}  // namespace

void map_windows(const std::vector<double>& x, const Model& baseline, const Eigen::VectorXd& theta,
                 const GapOptions& options, GapResult& result) {
  const auto n = static_cast<std::int64_t>(x.size());
  std::int64_t L = 1;
  while (2 * L <= n / kMinWindows) L *= 2;
  const int levels = static_cast<int>(std::log2(static_cast<double>(L / kWindowScaleRatio)));
  if (levels < kMinWindowLevels) return;
  const ClassicalWvEstimator classical;
  const WvEstimator& est = options.estimator ? *options.estimator : classical;
  const std::string key = reference_key(baseline, theta, L, 1, levels, options.replicates,
                                        options.seed + kWindowSeedOffset, options.estimator, 0.05, "windows");
  const std::shared_ptr<const Reference> kept = cached_reference(options.references.get(), key, [&] {
    return build_reference(baseline, theta, L, 1, levels, options.replicates, options.seed + kWindowSeedOffset, est,
                           0.05, nullptr);
  });
  const Reference& ref = *kept;
  const std::int64_t W = n / L;
  const double cells = static_cast<double>(W) * levels;
  const double z_threshold =
      boost::math::quantile(boost::math::complement(boost::math::normal(), options.alpha / (2.0 * cells)));
  result.windows_checked = true;
  result.window_length = L;
  std::vector<WaveletVariance> wvs;
  for (std::int64_t w = 0; w < W; ++w) wvs.push_back(est.compute(x.data() + w * L, L, levels, 0.05));
  for (int j = 0; j < levels; ++j) {
    // The record's typical window at this scale: the median over windows of log WV (a
    // burst in one or two windows does not move it); a stationary gap shows in every
    // window alike and cancels, a local effect stands out.
    std::vector<double> logs;
    for (const auto& v : wvs) {
      const double nu = v.wv[static_cast<std::size_t>(j)];
      if (nu > 0.0 && std::isfinite(nu)) logs.push_back(std::log(nu));
    }
    if (logs.size() < static_cast<std::size_t>(kMinWindows)) continue;
    std::nth_element(logs.begin(), logs.begin() + static_cast<std::ptrdiff_t>(logs.size() / 2), logs.end());
    const double expected = logs[logs.size() / 2];
    for (std::int64_t w = 0; w < W; ++w) {
      const double nu = wvs[static_cast<std::size_t>(w)].wv[static_cast<std::size_t>(j)];
      if (!(nu > 0.0) || !std::isfinite(nu)) continue;
      const double z = (std::log(nu) - expected) / ref.sd_log(j);
      const double ratio = nu / std::exp(expected);
      if (std::abs(z) > z_threshold && std::abs(ratio - 1.0) > options.min_effect)
        result.windows.push_back({w * L, (w + 1) * L - 1, std::ldexp(1.0, j + 1), ratio, z});
    }
  }
}

void split_halves(const std::vector<double>& x, double alpha, GapResult& result) {
  const auto half = static_cast<std::int64_t>(x.size()) / 2;
  if (half < kMinHalfLength) return;
  WvOptions o;
  o.alpha = alpha;
  const WaveletVariance a = classical_wv(x.data(), half, o), b = classical_wv(x.data() + half, half, o);
  for (int j = 0; j < std::min(a.levels(), b.levels()); ++j) {
    const auto k = static_cast<std::size_t>(j);
    GapSplitHalf h;
    h.tau = a.tau[k];
    h.ratio = a.wv[k] > 0.0 ? b.wv[k] / a.wv[k] : std::numeric_limits<double>::quiet_NaN();
    h.disjoint = a.ci_high[k] < b.ci_low[k] || b.ci_high[k] < a.ci_low[k];
    result.split_half.push_back(h);
  }
}

}  // namespace gmwm::gap::detail
