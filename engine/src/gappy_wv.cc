#include "gmwm/engine/gappy_wv.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"

namespace gmwm {

std::string missing_runs_problem(std::int64_t observed, std::span<const MissingRun> missing) {
  std::int64_t grid = observed;
  for (const MissingRun& r : missing) {
    if (r.length < 1) return "missing run at " + std::to_string(r.start) + ": its length must be at least 1";
    if (r.length > std::numeric_limits<std::int64_t>::max() - grid)
      return "missing run at " + std::to_string(r.start) + ": the record would exceed 2^63 samples";
    grid += r.length;
  }
  std::int64_t end = -1;  // one past the previous run's last sample (-1: no run yet)
  for (std::size_t k = 0; k < missing.size(); ++k) {
    const MissingRun& r = missing[k];
    const std::string which = "missing run " + std::to_string(k + 1) + " (at " + std::to_string(r.start) + ")";
    if (r.start < 0 || r.start > grid - r.length)
      return which + ": outside the record's " + std::to_string(grid) + " samples";
    if (end >= 0 && r.start <= end)
      return which + ": overlaps or touches the run before it (runs must be increasing and apart)";
    end = r.start + r.length;
  }
  return {};
}

namespace {

// The grid's prefix sums of the mean-centred observed values (a missing sample adds 0) and
// of the missing count: a window's sum and whether it holds a gap, each in O(1).
struct GridSums {
  std::vector<double> s;        // S_0 .. S_N
  std::vector<std::int64_t> c;  // C_0 .. C_N: missing samples before k
};

GridSums grid_sums(std::span<const double> observed, std::span<const MissingRun> missing) {
  double mean = 0.0;
  for (const double v : observed) mean += v;
  mean /= static_cast<double>(observed.size());
  std::int64_t n = static_cast<std::int64_t>(observed.size());
  for (const MissingRun& r : missing) n += r.length;
  GridSums g;
  g.s.resize(static_cast<std::size_t>(n) + 1);
  g.c.resize(static_cast<std::size_t>(n) + 1);
  std::size_t next = 0, run = 0;
  for (std::int64_t k = 0; k < n; ++k) {
    const bool gap = run < missing.size() && k >= missing[run].start;
    const auto i = static_cast<std::size_t>(k);
    g.s[i + 1] = g.s[i] + (gap ? 0.0 : observed[next++] - mean);
    g.c[i + 1] = g.c[i] + (gap ? 1 : 0);
    if (gap && k + 1 == missing[run].start + missing[run].length) ++run;
  }
  return g;
}

void fill_gappy_level(const GridSums& g, int j, WaveletVariance& w) {
  const auto i = static_cast<std::size_t>(j - 1);
  const std::int64_t n = static_cast<std::int64_t>(g.s.size()) - 1;
  const std::int64_t width = std::int64_t{1} << j, half = width / 2;
  double sum = 0.0;
  std::int64_t complete = 0;
  for (std::int64_t t = width; t <= n; ++t) {  // the window [t - width, t) of the grid
    const auto e = static_cast<std::size_t>(t), b = static_cast<std::size_t>(t - width);
    if (g.c[e] != g.c[b]) continue;
    const double c = (g.s[e] - 2.0 * g.s[e - static_cast<std::size_t>(half)] + g.s[b]) / static_cast<double>(width);
    sum += c * c;
    ++complete;
  }
  const std::int64_t all = n - width + 1;
  const double tau = static_cast<double>(width);
  w.tau[i] = tau;
  w.coefficients[i] = complete;
  if (complete < all)
    w.notes[i] = std::to_string(complete) + " of " + std::to_string(all) + " windows of " + std::to_string(width) +
                 " samples complete (" + std::to_string(all - complete) + " hold a missing sample)";
  if (complete == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    w.wv[i] = w.ci_low[i] = w.ci_high[i] = w.variance[i] = w.eta[i] = nan;
    return;
  }
  const double v = sum / static_cast<double>(complete);
  const double eta = wv_eta(complete, tau);
  w.wv[i] = v;
  w.eta[i] = eta;
  w.variance[i] = 2.0 * v * v / eta;
  std::tie(w.ci_low[i], w.ci_high[i]) = chi_square_ci(v, eta, w.alpha);
}

}  // namespace

WaveletVariance classical_wv_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                       const WvOptions& options) {
  const auto observed_n = static_cast<std::int64_t>(observed.size());
  if (observed_n < kMinSeriesLength)
    detail::throw_check("classical_wv_with_gaps", "observed samples", static_cast<double>(observed_n),
                        "at least " + std::to_string(kMinSeriesLength));
  if (const std::string why = options.Validate(); !why.empty()) throw InvalidArgument("classical_wv_with_gaps: " + why);
  if (const std::string why = missing_runs_problem(observed_n, missing); !why.empty())
    throw InvalidArgument("classical_wv_with_gaps: " + why);
  const GridSums g = grid_sums(observed, missing);
  const std::int64_t n = static_cast<std::int64_t>(g.s.size()) - 1;
  int J = 0;
  while ((std::int64_t{1} << (J + 1)) <= n) ++J;
  if (options.levels > 0) J = std::min(J, options.levels);
  WaveletVariance w;
  w.n = n;
  w.alpha = options.alpha;
  const auto sz = static_cast<std::size_t>(J);
  for (auto* v : {&w.tau, &w.wv, &w.ci_low, &w.ci_high, &w.variance, &w.eta}) v->resize(sz);
  w.coefficients.resize(sz);
  w.notes.resize(sz);
  for (int j = 1; j <= J; ++j) fill_gappy_level(g, j, w);
  return w;
}

}  // namespace gmwm
