#pragma once
// Sliding-window map of the gap diagnosis (docs/gap.md, method note 2), internal to gap.cc.
#include <vector>

#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

/// Non-overlapping windows of length L (a power of two, at least kMinWindows of them);
/// their classical WV at levels with tau <= L / kWindowScaleRatio (docs/gap.md, method note 2: the window is
/// at least 16 x the largest scale) against a reference of the baseline simulated at
/// length L (its spread of log WV), each window's log WV against the median over windows:
/// a window is flagged when it departs from the rest of the record, i.e. where the
/// series is not stationary. Fills result.windows, windows_checked and window_length.
void map_windows(const std::vector<double>& x, const Model& baseline, const Eigen::VectorXd& theta,
                 const GapOptions& options, GapResult& result);

/// The split-half check: the classical WV of each half of x at every level both have,
/// compared through their 1 - alpha chi-square CIs. Fills result.split_half.
void split_halves(const std::vector<double>& x, double alpha, GapResult& result);

}  // namespace gmwm::gap::detail
