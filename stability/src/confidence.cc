// The deviations' confidence intervals (confidence.h): noise identification -> equivalent
// degrees of freedom -> chi-square interval, at each factor in parallel.
#include "gmwm/stability/confidence.h"

#include <array>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/samples.h"

namespace gmwm::stability {
namespace {

// TOTVAR's degrees of freedom b (T / tau) - c, T = N tau0 the record's length, for white,
// flicker and random-walk FM (NIST SP 1065, Table 7; D. A. Howe, "The total deviation
// approach to long-term characterization of frequency stability", IEEE UFFC 47, 2000).
struct TotalDof {
  int alpha;
  double b, c;
};
constexpr std::array<TotalDof, 3> kTotvarDof = {{{0, 1.50, 0.0}, {-1, 1.17, 0.22}, {-2, 0.93, 0.36}}};

// MTOTVAR's (and TTOTVAR's) b (T / tau) - c for the five noises from white PM to random-walk
// FM (NIST SP 1065, Table 8). Stable32's intervals on PHASE.DAT do not follow it: at m <= 8
// they carry MDEV's Greenhall edf, at 16 .. 256 about 4/3 (T / tau) - 1.89 for white FM (21%
// above this table; docs/stability.md, "Confidence intervals").
constexpr std::array<TotalDof, 5> kMtotvarDof = {
    {{2, 1.90, 2.10}, {1, 1.20, 1.40}, {0, 1.10, 1.20}, {-1, 0.85, 0.50}, {-2, 0.75, 0.31}}};

template <std::size_t K>
std::optional<double> table_dof(const std::array<TotalDof, K>& table, int alpha, std::int64_t n, std::int64_t m) {
  for (const TotalDof& t : table)
    if (t.alpha == alpha) return t.b * static_cast<double>(n) / static_cast<double>(m) - t.c;
  return std::nullopt;
}

}  // namespace

std::optional<double> equivalent_dof(DeviationKind kind, int alpha, std::int64_t n, std::int64_t m) {
  switch (kind) {
    case DeviationKind::kAdev:
      return greenhall_edf(alpha, 2, m, n, m, 1);
    case DeviationKind::kOadev:
      return greenhall_edf(alpha, 2, m, n, m, m);
    case DeviationKind::kMdev:
    case DeviationKind::kTdev:
      return greenhall_edf(alpha, 2, m, n, 1, m);
    case DeviationKind::kHdev:
      return greenhall_edf(alpha, 3, m, n, m, 1);
    case DeviationKind::kOhdev:
      return greenhall_edf(alpha, 3, m, n, m, m);
    case DeviationKind::kTotdev:
      if (const auto dof = table_dof(kTotvarDof, alpha, n, m)) return dof;
      return greenhall_edf(alpha, 2, m, n, m, m);  // phase noise: TOTVAR reads as OAVAR
    case DeviationKind::kMtotdev:
    case DeviationKind::kTtotdev:
      return table_dof(kMtotvarDof, alpha, n, m);
    case DeviationKind::kHtotdev:
      // No published rule: OHDEV's, a lower bound (a total variance averages more; Stable32's
      // HTOTDEV edf on PHASE.DAT are 1.1-1.5 times these), so the interval is conservative.
      return greenhall_edf(alpha, 3, m, n, m, m);
    case DeviationKind::kTheo1:  // no published rule that Stable32's tables show (they print none)
    case DeviationKind::kMtie:   // not variances: no chi-square interval
    case DeviationKind::kTierms:
      return std::nullopt;
  }
  return std::nullopt;
}

std::string_view interval_method_name(IntervalMethod method) {
  return method == IntervalMethod::kExact ? "exact" : "stable32";
}

std::optional<IntervalMethod> interval_method_from_name(std::string_view name) {
  for (const IntervalMethod m : {IntervalMethod::kStable32, IntervalMethod::kExact})
    if (interval_method_name(m) == name) return m;
  return std::nullopt;
}

ChiSquareInterval chi_square_interval(double deviation, double edf, double confidence, IntervalMethod method) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError("confidence: found " + significant(confidence, 6) + ", expected a number between 0 and 1");
  if (!(edf > 0.0) || !std::isfinite(edf))
    throw InputError("edf: found " + significant(edf, 6) + ", expected a positive number of degrees of freedom");
  const double tail = (1.0 - confidence) / 2.0;
  double upper = 0.0, lower = 0.0;  // chi2 quantiles at 1 - tail and tail
  if (method == IntervalMethod::kExact || edf <= kStable32ExactDof) {
    const boost::math::chi_squared_distribution<double> chi2(edf);
    upper = boost::math::quantile(chi2, 1.0 - tail);
    lower = boost::math::quantile(chi2, tail);
  } else {
    const double q = std::round((1.0 - tail) * 100.0) / 100.0;
    const double z = boost::math::quantile(boost::math::normal_distribution<double>(), q);
    const double a = 2.0 / (9.0 * edf);
    upper = edf * std::pow(1.0 - a + z * std::sqrt(a), 3);
    lower = edf * std::pow(1.0 - a - z * std::sqrt(a), 3);
  }
  ChiSquareInterval ci;
  ci.low = deviation * std::sqrt(edf / upper);
  ci.high = deviation * std::sqrt(edf / lower);
  return ci;
}

std::string IntervalOptions::Validate() const {
  if (!(confidence > 0.0 && confidence < 1.0))
    return "confidence: found " + significant(confidence, 6) + ", expected a number between 0 and 1";
  if (noise_alpha && (*noise_alpha < -4 || *noise_alpha > 2))
    return "noise_alpha: found " + std::to_string(*noise_alpha) +
           ", expected an integer from -4 (random-run FM) to 2 (white PM)";
  return "";
}

DeviationIntervals deviation_intervals(const DeviationCurve& curve, std::span<const double> phase,
                                       const IntervalOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  const auto n = static_cast<std::int64_t>(phase.size());
  const std::int64_t top = max_factor(curve.kind, n);
  for (const std::int64_t f : curve.m)
    if (f < 1 || f > top)
      throw InputError(std::string(deviation_name(curve.kind)) + ": averaging factor " + std::to_string(f) +
                       " is outside 1 .. " + std::to_string(top) + " (" + std::to_string(n) + " phase points)");
  const std::size_t k = curve.m.size();
  DeviationIntervals out;
  out.options = options;
  out.noise.resize(k);
  out.edf.assign(k, NAN);
  out.low.assign(k, NAN);
  out.high.assign(k, NAN);
  gmwm::parallel_for(std::size_t{0}, k, [&](std::size_t i) {
    if (options.noise_alpha)
      out.noise[i] = {*options.noise_alpha, NAN, NoiseIdMethod::kFixed};
    else
      out.noise[i] = identify_noise(curve.kind, phase, curve.m[i]);
    // A phase in a temporary file: its pages dropped after each factor (samples.h; nothing
    // for a phase in memory).
    gmwm::detail::release_file_pages(phase.data(), phase.data() + phase.size());
    const auto edf = equivalent_dof(curve.kind, out.noise[i].alpha, n, curve.m[i]);
    if (!edf || !(*edf > 0.0)) return;
    out.edf[i] = *edf;
    const ChiSquareInterval ci = chi_square_interval(curve.value[i], *edf, options.confidence, options.method);
    out.low[i] = ci.low;
    out.high[i] = ci.high;
  });
  return out;
}

}  // namespace gmwm::stability
