#pragma once
// Pieces of the gap diagnosis' result derived from its findings (GAP.md s.4), internal to
// gap.cc: the drift found in the time domain as a fit and as a band, and what the noise
// means for navigation.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/selection/gap.h"

namespace gmwm::selection::detail {

/// The drift found in the time domain as a one-parameter fit (DR omega with its interval).
FitResult drift_fit(const GapTrend& t, const GapOptions& o);

/// The band of a drift found in the time domain when the WV shows none: the levels where
/// its WV is at least half its largest ratio to the baseline's (up to the coarsest).
std::vector<GapBand> drift_band(double omega, const WaveletVariance& wv, const Eigen::VectorXd& nu_base,
                                const ProcessContext& ctx, const std::vector<GapLevel>& levels);

/// RMS of the noise's integral over kNavigationHorizonSeconds (NaN without a known rate;
/// a note when the model cannot be integrated).
double navigation_rms(const Model& m, const Eigen::VectorXd& theta, const ProcessContext& ctx,
                      std::vector<std::string>& notes);

}  // namespace gmwm::selection::detail
