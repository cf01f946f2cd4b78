#pragma once
// A regular record with missing samples taken out, as the gappy estimators' tests build it:
// the grid with NaN where a sample is missing (what a brute-force oracle sums over), the
// observed samples alone and the runs (what the estimators read).
#include <cmath>
#include <limits>
#include <vector>

#include "gmwm/engine/gappy_wv.h"

namespace gmwm::test {

struct Holed {
  std::vector<double> grid, observed;
  std::vector<MissingRun> runs;
};

inline Holed remove(const std::vector<double>& full, const std::vector<MissingRun>& runs) {
  Holed h{full, {}, runs};
  for (const MissingRun& r : runs)
    for (std::int64_t k = r.start; k < r.start + r.length; ++k)
      h.grid[static_cast<std::size_t>(k)] = std::numeric_limits<double>::quiet_NaN();
  for (const double v : h.grid)
    if (!std::isnan(v)) h.observed.push_back(v);
  return h;
}

}  // namespace gmwm::test
