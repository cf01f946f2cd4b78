#pragma once
// Pieces of the gap diagnosis' result derived from its findings (docs/gap.md, method note 4), internal to
// gap.cc: the drift found in the time domain as a fit and as a band, and what the noise
// means for navigation.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

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

/// A scale in seconds when the rate is known, else in samples ("2.56 s", "256 samples").
std::string scale_text(double tau, const ProcessContext& ctx);

/// A time-domain step (STEP, TRANSIENT, DR, TEMPERATURE) in a few words, from what g holds.
std::string time_step_text(GapEffect e, const GapResult& g, const ProcessContext& ctx, const std::string& unit);

/// A WV effect added at a step in a few words, from its fit (SIN's frequency, AR1's
/// correlation time, DR's signed rate, ...).
std::string effect_step_text(GapEffect e, const FitResult& fit, const ProcessContext& ctx, const std::string& unit);

/// A step's share of the baseline's excess at or above which the headline says the gap is
/// "explained by" it; below it the step is listed as "minor". One tenth: an effect that
/// removes less leaves 90% of the excess where it was, and naming it as the explanation
/// is what issue 26 found misleading ("explained by STEP + AR1 + SIN + SIN" for 3.2%).
inline constexpr double kExplainedShare = 0.10;

/// The summary line (GapResult::headline): bands, effects (explained by / minor, each with
/// its share of the excess), levels outside before -> after, the global p after, "gap
/// remains at SCALES" while the final model is still rejected, and the share of the
/// excess removed.
std::string headline(const GapResult& g, const ProcessContext& ctx, double alpha);

}  // namespace gmwm::gap::detail
