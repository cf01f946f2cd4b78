#include "gap_summary.h"
#include "gap_levels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/integrated_error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::gap::detail {

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
  const int first = levels_from(levels);
  GapBand b;
  b.direction = "excess";
  b.last_level = first + static_cast<int>(levels.size()) - 1;
  b.first_level = b.last_level;
  while (b.first_level > first && ratio(b.first_level - 1 - first) >= 0.5 * peak) --b.first_level;
  b.tau_from = levels[static_cast<std::size_t>(b.first_level - first)].tau;
  b.tau_to = levels.back().tau;
  for (int j = b.first_level; j <= b.last_level; ++j)
    b.peak_ratio = std::max(b.peak_ratio, levels[static_cast<std::size_t>(j - first)].ratio);
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

namespace {

std::string g3(double x, int digits = 3) {
  std::ostringstream os;
  os.precision(digits);
  os << x;
  return os.str();
}

std::string band_text(const GapBand& b, const ProcessContext& ctx) {
  std::string out = scale_text(b.tau_from, ctx);
  if (b.tau_to > b.tau_from) out += " - " + scale_text(b.tau_to, ctx);
  return out;
}

}  // namespace

std::string scale_text(double tau, const ProcessContext& ctx) {
  return ctx.freq_known ? g3(tau / ctx.freq) + " s" : g3(tau, 6) + " samples";
}

namespace {
std::string unit_text(const std::string& unit) { return unit.empty() ? std::string("data units") : unit; }
}  // namespace

std::string time_step_text(GapEffect e, const GapResult& g, const ProcessContext& ctx, const std::string& unit) {
  std::string out = to_string(e);
  std::string u(" ");
  u += unit_text(unit);
  const double rate = ctx.freq_known ? ctx.freq : 1.0;
  const std::string time_unit = ctx.freq_known ? " s" : " samples";
  if ((e == GapEffect::kStep || e == GapEffect::kTransient || e == GapEffect::kOutliers) && g.event &&
      g.event->effect == e) {
    const GapEvent& ev = *g.event;
    if (e == GapEffect::kOutliers)
      out += " (a burst of " + std::to_string(ev.length) + " samples at " +
             g3(static_cast<double>(ev.sample) / rate, 6) + time_unit + ", peak departure " + g3(ev.size) + u + ")";
    else if (e == GapEffect::kStep)
      out += " of " + g3(ev.size) + u + " at " + g3(static_cast<double>(ev.sample) / rate, 6) + time_unit;
    else
      out += " " + g3(ev.size) + u + " x exp(-t / " + g3(ev.time_constant / rate) + time_unit + ")";
  }
  if (e == GapEffect::kDR && g.trend)
    out += " of " + g3(g.trend->omega * rate) + u + (ctx.freq_known ? " per s" : " per sample");
  if (e == GapEffect::kTemperature && g.temperature)
    out += " (coupling " + g3(g.temperature->k, 4) + u + " per temperature unit, 95% CI " + g3(g.temperature->ci_low) +
           " to " + g3(g.temperature->ci_high) + ")";
  return out;
}

std::string effect_step_text(GapEffect e, const FitResult& f, const ProcessContext& ctx, const std::string& unit) {
  std::string out = to_string(e);
  if (f.status == FitStatus::kFailed || f.theta.size() == 0 || f.model.num_components() == 0) return out;
  const Process& p = *f.model.components()[0].process;
  if (e == GapEffect::kSin && f.theta.size() >= 2)
    out += " at " + g3(p.to_display(1, f.theta(1)), 4) + (ctx.freq_known ? " Hz" : " cycles/sample");
  else if (e == GapEffect::kDR)
    out += " of " + g3(f.theta(0) * (ctx.freq_known ? ctx.freq : 1.0)) + " " + unit_text(unit) +
           (ctx.freq_known ? " per s" : " per sample");
  else if (e == GapEffect::kAR1 && f.theta(0) > 0.0 && f.theta(0) < 1.0) {
    const double T = -1.0 / std::log(f.theta(0));
    out += " with correlation time " + (ctx.freq_known ? g3(T / ctx.freq) + " s" : g3(T, 4) + " samples");
  }
  return out;
}

namespace {

// "re-sized baseline (96% of the excess); explained by A (62% of the rest) + B (30%);
// minor: C (2%)": an effect is named as an explanation only when it removed at least
// kExplainedShare of the excess the re-sizing leaves (GapResult::step_shares).
std::string effects_text(const GapResult& g) {
  const auto detail_of = [&](std::size_t k) {
    return k < g.step_details.size() ? g.step_details[k] : std::string(to_string(g.steps[k]));
  };
  const auto share_of = [&](std::size_t k) {
    return k < g.step_shares.size() ? g.step_shares[k] : std::numeric_limits<double>::quiet_NaN();
  };
  if (g.steps.empty()) return {};
  if (!(g.shrinkage.excess_before > 0.0)) {
    std::string out = "effects added (the baseline's objective is within its null mean: no share of an excess): ";
    for (std::size_t k = 0; k < g.steps.size(); ++k) {
      if (k) out += " + ";
      out += detail_of(k);
    }
    return out;
  }
  std::string resized, explained, minor;
  const bool any_resize = std::find(g.steps.begin(), g.steps.end(), GapEffect::kReparameterise) != g.steps.end();
  bool first = true;
  for (std::size_t k = 0; k < g.steps.size(); ++k) {
    const double share = share_of(k);
    const std::string pct = std::isfinite(share) ? g3(100.0 * share) + "%" : std::string("no excess left");
    if (g.steps[k] == GapEffect::kReparameterise) {
      resized = "REPARAMETERISE (" + pct + " of the excess)";
      continue;
    }
    if (share >= kExplainedShare) {
      if (!explained.empty()) explained += " + ";
      explained += detail_of(k);
      explained += " (";
      explained += pct;
      if (first) explained += any_resize ? " of the rest" : " of the excess";
      explained += ")";
      first = false;
    } else {
      if (!minor.empty()) minor += ", ";
      minor += detail_of(k);
      minor += " (";
      minor += pct;
      minor += ")";
    }
  }
  if (!resized.empty() && explained.empty() && minor.empty()) return "explained by " + resized;
  std::string out = resized.empty() ? std::string() : resized + "; ";
  out += explained.empty()
             ? "no effect removes " + g3(100.0 * kExplainedShare) + "% of the " + (any_resize ? "rest" : "excess")
             : "explained by " + explained;
  if (!minor.empty()) out += "; minor: " + minor;
  return out;
}

}  // namespace

std::string headline(const GapResult& g, const ProcessContext& ctx, double alpha) {
  std::ostringstream os;
  const GapShrinkage& s = g.shrinkage;
  if (!g.detected && g.p_value < alpha) {
    os << "departures below the effect size: the global test rejects (p = " << g3(g.p_value) << "), "
       << s.levels_outside_before << " of " << g.levels.size()
       << " levels outside the 95% reference band, but no band of deciding levels departs by more than the "
          "effect size; no effect sought";
    return os.str();
  }
  if (!g.detected) {
    os << "no gap (global test p = " << g3(g.p_value) << ", " << s.levels_outside_before << " of " << g.levels.size()
       << " levels outside the 95% reference band)";
    return os.str();
  }
  for (std::size_t b = 0; b < g.bands.size(); ++b)
    os << (b ? ", " : "") << g.bands[b].direction << " at " << band_text(g.bands[b], ctx) << " (up to "
       << g3(g.bands[b].peak_ratio) << "x)";
  os << "; ";
  if (g.steps.empty()) {
    os << "no unmodelled effect found";
  } else {
    os << effects_text(g);
    if (!(g.p_value < alpha))
      os << " (found in the time domain by its own calibrated test; the WV's global test does not reject the "
            "baseline, p = "
         << g3(g.p_value) << ")";
  }
  os << "; levels outside " << s.levels_outside_before << " -> " << s.levels_outside_after << " of " << g.levels.size()
     << ", global p " << g3(s.p_value_before) << " -> " << g3(s.p_value_after);
  if (!g.steps.empty()) os << ", excess removed " << g3(100.0 * s.excess_removed) << "%";
  if (!g.remaining.empty()) {
    os << "; gap remains at ";
    for (std::size_t b = 0; b < g.remaining.size(); ++b) os << (b ? ", " : "") << band_text(g.remaining[b], ctx);
  } else if (s.p_value_after < alpha) {
    os << "; gap remains (the global test still rejects)";
  } else {
    os << "; gap closed (the final model is not rejected)";
  }
  return os.str();
}

}  // namespace gmwm::gap::detail
