#include "gap_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/integrated_error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::selection::detail {

// The drift found in the time domain as a one-parameter fit (DR omega with its interval).
FitResult drift_fit(const GapTrend& t, const GapOptions& o) {
  FitResult f;
  f.model = parse_model("DR", o.context);
  f.theta = Eigen::VectorXd::Constant(1, t.omega);
  f.status = FitStatus::kConverged;
  const double z = boost::math::quantile(boost::math::complement(boost::math::normal(), o.alpha / 2.0));
  f.se = Eigen::VectorXd::Constant(1, (t.ci_high - t.ci_low) / (2.0 * z));
  f.ci_low = Eigen::VectorXd::Constant(1, t.ci_low);
  f.ci_high = Eigen::VectorXd::Constant(1, t.ci_high);
  return f;
}

// The band of a drift found in the time domain when the WV shows none: the levels where
// its WV is at least half its largest ratio to the baseline's (up to the coarsest).
std::vector<GapBand> drift_band(double omega, const WaveletVariance& wv, const Eigen::VectorXd& nu_base,
                                const ProcessContext& ctx, const std::vector<GapLevel>& levels) {
  const Eigen::VectorXd ratio =
      parse_model("DR", ctx).wv(Eigen::VectorXd::Constant(1, omega), wv.tau).cwiseQuotient(nu_base);
  const double peak = ratio.maxCoeff();
  GapBand b;
  b.direction = "excess";
  b.last_level = static_cast<int>(levels.size());
  b.first_level = b.last_level;
  while (b.first_level > 1 && ratio(b.first_level - 2) >= 0.5 * peak) --b.first_level;
  b.tau_from = levels[static_cast<std::size_t>(b.first_level - 1)].tau;
  b.tau_to = levels.back().tau;
  for (int j = b.first_level; j <= b.last_level; ++j) b.peak_ratio = std::max(b.peak_ratio, levels[static_cast<std::size_t>(j - 1)].ratio);
  return {b};
}

// RMS of the noise's integral over kNavigationHorizonSeconds (NaN without a known rate).
double navigation_rms(const Model& m, const Eigen::VectorXd& theta, const ProcessContext& ctx,
                      std::vector<std::string>& notes) {
  if (!ctx.freq_known) return std::numeric_limits<double>::quiet_NaN();
  try {
    return integrated_error(m, theta, ctx.freq, kNavigationHorizonSeconds).total_rms;
  } catch (const std::exception& e) {
    notes.push_back(std::string("integrated error not computed: ") + e.what());
    return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace gmwm::selection::detail
