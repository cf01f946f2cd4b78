#pragma once
// The fleet's band of Allan deviations on one axis: the units' curves (in one unit) brought
// to a common tau grid (log-log interpolation where their grids differ) and, at each tau,
// their median, min-max and (from kBandPercentileUnits units on) 5-95% envelopes. Computed
// here, drawn by the fleet page (report/fleet_page.h).

#include <vector>

#include "gmwm/engine/allan.h"

namespace gmwm::fleet {

/// The fewest units of a band for its 5-95% envelope: with fewer, the 5% and 95% quantiles
/// lie between the two lowest and the two highest units (1 / 0.05 = 20 units put one unit
/// beyond each end), so the band shows the min-max envelope and the median only.
inline constexpr int kBandPercentileUnits = 20;

/// A unit's Allan deviation as the band takes it: positive values only, tau (s) increasing.
struct AdevSeries {
  std::vector<double> tau, value;
};

struct FleetAdevBand {
  std::vector<double> tau;  ///< seconds
  std::vector<double> min, p05, median, p95, max;
  std::vector<int> count;     ///< units reaching each tau
  int units = 0;              ///< units in the band (with a curve, not flagged on the axis)
  bool percentiles = false;   ///< p05/p95 hold the 5-95% envelope (units >= kBandPercentileUnits)
  bool interpolated = false;  ///< the units' tau grids differ: each interpolated in log-log
};

/// a's positive, finite deviations (with a positive tau), times `factor` (a unit's conversion).
AdevSeries positive_series(const AllanDeviation& a, double factor);

/// The band of `units`: at each tau of the common grid, over the logs of the units reaching it
/// (quantiles of the logs, Hyndman and Fan's type 7: the median of an even count is the
/// geometric mean of the middle two, as the fleet summary's median).
FleetAdevBand adev_band(const std::vector<AdevSeries>& units);

}  // namespace gmwm::fleet
