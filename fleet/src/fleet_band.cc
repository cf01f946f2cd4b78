#include "gmwm/fleet/fleet_band.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gmwm::fleet {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Two taus of one grid: equal to this relative tolerance (they are m / freq).
constexpr double kSameTau = 1e-9;

bool same_tau(double a, double b) { return std::abs(a - b) <= kSameTau * std::max(std::abs(a), std::abs(b)); }

// The series at t, linear in log tau and log ADEV between its neighbours; NaN outside its range.
double loglog_at(const AdevSeries& s, double t) {
  if (s.tau.empty() || (t < s.tau.front() && !same_tau(t, s.tau.front())) ||
      (t > s.tau.back() && !same_tau(t, s.tau.back())))
    return kNaN;
  const std::size_t j = static_cast<std::size_t>(std::lower_bound(s.tau.begin(), s.tau.end(), t) - s.tau.begin());
  if (j < s.tau.size() && same_tau(s.tau[j], t)) return s.value[j];
  if (j > 0 && same_tau(s.tau[j - 1], t)) return s.value[j - 1];
  if (j == 0 || j >= s.tau.size()) return j == 0 ? s.value.front() : s.value.back();
  const double w = std::log(t / s.tau[j - 1]) / std::log(s.tau[j] / s.tau[j - 1]);
  return std::exp(std::log(s.value[j - 1]) + w * (std::log(s.value[j]) - std::log(s.value[j - 1])));
}

// The densest common grid drawn, points per decade (the ADEV grids hold a few per octave).
constexpr double kMaxGridPerDecade = 40.0;

// The grid the band is drawn on: the units' own when they share it, else a geometric grid
// from the smallest to the largest tau at the densest unit's points per decade.
std::vector<double> common_grid(const std::vector<AdevSeries>& units, bool& interpolated) {
  interpolated = false;
  for (const AdevSeries& s : units) {
    bool same = s.tau.size() == units.front().tau.size();
    for (std::size_t i = 0; same && i < s.tau.size(); ++i) same = same_tau(s.tau[i], units.front().tau[i]);
    interpolated = interpolated || !same;
  }
  if (!interpolated) return units.front().tau;
  double lo = INFINITY, hi = 0.0, per_decade = 1.0;
  for (const AdevSeries& s : units) {
    lo = std::min(lo, s.tau.front());
    hi = std::max(hi, s.tau.back());
    if (s.tau.size() > 1 && s.tau.back() > s.tau.front())
      per_decade =
          std::max(per_decade, static_cast<double>(s.tau.size() - 1) / std::log10(s.tau.back() / s.tau.front()));
  }
  per_decade = std::min(per_decade, kMaxGridPerDecade);
  const int n = std::max(1, static_cast<int>(std::ceil(std::log10(hi / lo) * per_decade)) + 1);
  std::vector<double> grid;
  for (int i = 0; i < n; ++i) grid.push_back(n == 1 ? lo : lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)));
  return grid;
}

// The p-quantile of sorted values (linear between order statistics: Hyndman and Fan's type 7).
double quantile(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

}  // namespace

AdevSeries positive_series(const AllanDeviation& a, double factor) {
  AdevSeries s;
  for (std::size_t i = 0; i < a.tau.size() && i < a.adev.size(); ++i)
    if (a.adev[i] > 0.0 && std::isfinite(a.adev[i]) && a.tau[i] > 0.0) {
      s.tau.push_back(a.tau[i]);
      s.value.push_back(a.adev[i] * factor);
    }
  return s;
}

// The band's envelopes: at each tau, over the logs of the units reaching it (quantiles of
// the logs: the median of an even count is the geometric mean of the middle two, as the
// summary's median).
FleetAdevBand adev_band(const std::vector<AdevSeries>& units) {
  FleetAdevBand b;
  b.units = static_cast<int>(units.size());
  b.percentiles = b.units >= kBandPercentileUnits;
  if (units.empty()) return b;
  for (const double t : common_grid(units, b.interpolated)) {
    std::vector<double> values, logs;
    for (const AdevSeries& s : units)
      if (const double v = loglog_at(s, t); v > 0.0) values.push_back(v), logs.push_back(std::log(v));
    if (logs.empty()) continue;
    std::sort(logs.begin(), logs.end());
    b.tau.push_back(t);
    b.min.push_back(*std::min_element(values.begin(), values.end()));  // the units' own values, not exp(log)
    b.max.push_back(*std::max_element(values.begin(), values.end()));
    b.median.push_back(std::exp(quantile(logs, 0.5)));
    b.p05.push_back(b.percentiles ? std::exp(quantile(logs, 0.05)) : kNaN);
    b.p95.push_back(b.percentiles ? std::exp(quantile(logs, 0.95)) : kNaN);
    b.count.push_back(static_cast<int>(logs.size()));
  }
  return b;
}

}  // namespace gmwm::fleet
