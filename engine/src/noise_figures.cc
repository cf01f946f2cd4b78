#include "gmwm/engine/noise_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "noise_figures_internal.h"

namespace gmwm {

const char* to_string(ReadoffStatus s) {
  switch (s) {
    case ReadoffStatus::kRead:
      return "read";
    case ReadoffStatus::kExtrapolated:
      return "extrapolated";
    case ReadoffStatus::kBound:
      return "bound";
  }
  return "?";
}

std::optional<ReadoffStatus> parse_readoff_status(const std::string& name) {
  for (ReadoffStatus s : {ReadoffStatus::kRead, ReadoffStatus::kExtrapolated, ReadoffStatus::kBound})
    if (name == to_string(s)) return s;
  return std::nullopt;
}

std::string ReadoffOptions::Validate() const {
  if (!(slope_tolerance > 0.0 && slope_tolerance < 0.5))
    return "noise figures: slope tolerance must be in (0, 0.5), got " + std::to_string(slope_tolerance);
  if (!(min_edf >= 1.0)) return "noise figures: min_edf must be at least 1, got " + std::to_string(min_edf);
  if (!(alpha > 0.0 && alpha < 1.0)) return "noise figures: alpha must be in (0, 1), got " + std::to_string(alpha);
  return {};
}

namespace {

using figures::Curve;
using figures::fmt;
using figures::kMinRegionPoints;
using figures::kWhiteTau;
using figures::Region;
using figures::shows;
using figures::SlopeFigure;

// How far beyond the record a model's curve is searched for its power-law slopes.
constexpr double kModelReachRecords = 100.0;
// Local slopes are least-squares fits over points within half an octave on each side.
constexpr double kSlopeHalfWindowOctaves = 0.5;

/// (low, high) of sigma_i times `scale` at 1 - alpha.
using IntervalFn = std::function<std::pair<double, double>(std::size_t i, double scale)>;

std::vector<double> local_slopes(const Curve& c) {
  const std::size_t K = c.tau.size();
  std::vector<double> out(K, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < K; ++i) {
    if (!c.usable[i]) continue;
    // Half an octave each side, and at least the next point on each side (octave grids).
    double half = kSlopeHalfWindowOctaves;
    if (i > 0) half = std::max(half, std::log2(c.tau[i] / c.tau[i - 1]));
    if (i + 1 < K) half = std::max(half, std::log2(c.tau[i + 1] / c.tau[i]));
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (std::size_t j = 0; j < K; ++j) {
      if (!c.usable[j] || !(c.sigma[j] > 0.0)) continue;
      const double x = std::log2(c.tau[j] / c.tau[i]);
      if (std::abs(x) > half + 1e-9) continue;
      const double y = std::log2(c.sigma[j]);
      sx += x, sy += y, sxx += x * x, sxy += x * y;
      ++n;
    }
    const double den = n * sxx - sx * sx;
    if (n >= 2 && den > 0.0) out[i] = (n * sxy - sx * sy) / den;
  }
  return out;
}

/// The upper bound a curve puts on a figure: a white noise's (or a random walk's) Allan
/// deviation never exceeds the total, so the figure is at most min sigma(tau) scale(tau)
/// over the points bounds may come from; `why` starts the line.
Readoff bound_of(const Curve& c, const std::function<double(double)>& scale, const std::string& why,
                 const char* slope_name) {
  Readoff out;
  for (std::size_t i = 0; i < c.tau.size(); ++i) {
    if (!c.bounds_from(i) || !(c.sigma[i] > 0.0)) continue;
    const double v = c.sigma[i] * scale(c.tau[i]);
    if (!(v >= out.value)) {
      out.value = v;
      out.tau = c.tau[i];
    }
  }
  out.status = ReadoffStatus::kBound;
  out.high = out.value;
  out.how = why + ": an upper bound, the " + slope_name + " line touching the curve at " + fmt(out.tau) + " s";
  return out;
}

// A bump near the IEEE tau above the white floor's -1/2 line: how far past the floor it is
// sought (the ADIS accelerometers' 0.46-0.53 Hz tone bends their curves over 0.3-2 s) and
// how far above the line the curve must rise to be one (twice the 95% half-width of an
// Allan deviation point with ~1000 degrees of freedom, sqrt(2/edf) * 1.96 ~ 0.09: a
// wiggle of the curve stays below it).
constexpr double kBumpReachTau = 10.0 * kWhiteTau;
constexpr double kBumpExcess = 0.10;

struct Bump {
  double from = 0.0, to = 0.0;  ///< seconds: where the curve leaves the line, where the bump ends
  double peak_tau = 0.0;        ///< seconds: the highest point above the line
  double excess = 0.0;          ///< there, sigma sqrt(tau) / N - 1
  bool returns = false;         ///< a local maximum (a tone), else a raised -1/2 stretch after it
};

// A bump near the floor [first, last]: the curve sigma sqrt(tau) / N (1 on the line) has a
// local maximum above 1 + kBumpExcess within kBumpReachTau, before or after the floor (a
// tone's peak), or a -1/2 stretch after the floor above it (a fast correlated term, white
// beyond its correlation time). A curve rising for good (a random walk, a bias) is neither.
std::optional<Bump> find_bump(const Curve& c, const std::vector<double>& slopes, std::size_t first, std::size_t last,
                              double value, const ReadoffOptions& o) {
  if (!(value > 0.0)) return std::nullopt;
  const auto ratio = [&](std::size_t i) { return c.sigma[i] * std::sqrt(c.tau[i]) / value; };
  const auto usable = [&](std::size_t i) { return i < c.tau.size() && c.usable[i] && c.sigma[i] > 0.0; };
  const auto on_line = [&](std::size_t i) { return std::abs(slopes[i] + 0.5) <= o.slope_tolerance; };
  const auto above = [&](std::size_t i) { return ratio(i) > 1.0 + kBumpExcess; };
  // The run of points above the line around i (its extent, and its highest point).
  const auto bump_around = [&](std::size_t i, bool returns) {
    Bump b;
    std::size_t lo = i, hi = i, peak = i;
    while (lo > 0 && usable(lo - 1) && ratio(lo - 1) > 1.0 + kBumpExcess / 2.0) --lo;
    while (usable(hi + 1) && ratio(hi + 1) > 1.0 + kBumpExcess / 2.0 && (returns || !on_line(hi))) ++hi;
    for (std::size_t k = lo; k <= hi; ++k)
      if (ratio(k) > ratio(peak)) peak = k;
    b.from = c.tau[lo];
    b.to = c.tau[hi];
    b.peak_tau = c.tau[peak];
    b.excess = ratio(peak) - 1.0;
    b.returns = returns;
    return b;
  };
  for (std::size_t i = 1; usable(i) && c.tau[i] <= kBumpReachTau; ++i) {
    if (first <= i && i <= last) continue;
    if (!(usable(i - 1) && usable(i + 1) && ratio(i) >= ratio(i - 1) && ratio(i) > ratio(i + 1) && above(i))) continue;
    // It falls back by half the excess bar (a wiggle of a rising curve does not).
    for (std::size_t j = i + 1; usable(j); ++j)
      if (ratio(j) < ratio(i) - kBumpExcess / 2.0) return bump_around(i, true);
  }
  for (std::size_t i = last + 1; usable(i + 1) && c.tau[i] <= kBumpReachTau; ++i)
    if (on_line(i) && on_line(i + 1) && above(i)) return bump_around(i, false);
  return std::nullopt;
}

// One line; `what` names the model's component making the bump ("" for the data).
std::string bump_text(const Bump& b, const std::string& what) {
  const std::string range = fmt(b.from) + "-" + fmt(b.to) + " s";
  return "a bump over " + range + " lifts the curve above the white floor's -1/2 line (+" + fmt(100.0 * b.excess) +
         "% at " + fmt(b.peak_tau) + " s" + (b.returns ? "" : ", then a raised -1/2 stretch") +
         "): " + (what.empty() ? "a tone or a fast correlated term" : what) + ", not white noise and not counted in N";
}

/// The line of figure `sf`'s slope (N: -1/2, K: +1/2, Q: -1, R: +1): value = sigma(tau_i) *
/// scale(tau_i) on the region pick_region chooses.
Readoff read_slope(const Curve& c, const std::vector<double>& slopes, const SlopeFigure& sf, const IntervalFn& interval,
                   const ReadoffOptions& o) {
  const std::size_t K = c.tau.size();
  const double target = sf.slope, ieee_tau = sf.tau;
  const char* slope_name = sf.slope_name;
  // Runs of consecutive usable points on the slope.
  std::vector<Region> regions;
  for (std::size_t i = 0; i < K; ++i) {
    const bool on = c.usable[i] && std::isfinite(slopes[i]) && std::abs(slopes[i] - target) <= o.slope_tolerance;
    if (!on) continue;
    if (!regions.empty() && regions.back().last + 1 == i) {
      regions.back().last = i;
      ++regions.back().count;
    } else {
      regions.push_back({i, i, 1});
    }
  }
  auto log_distance = [&](std::size_t i) { return std::abs(std::log(c.tau[i] / ieee_tau)); };
  const Region* best = figures::pick_region(c, regions, sf);
  Readoff out;
  if (best) {
    std::size_t at = best->first;
    for (std::size_t i = best->first; i <= best->last; ++i)
      if (log_distance(i) < log_distance(at)) at = i;
    const double s = sf.scale(c.tau[at]);
    out.value = c.sigma[at] * s;
    std::tie(out.low, out.high) = interval(at, s);
    out.tau = c.tau[at];
    out.region_from = c.tau[best->first];
    out.region_to = c.tau[best->last];
    const bool holds = out.region_from <= ieee_tau && ieee_tau <= out.region_to;
    out.status = holds ? ReadoffStatus::kRead : ReadoffStatus::kExtrapolated;
    out.how = std::string("on the ") + slope_name + " slope over " + fmt(out.region_from) + "-" + fmt(out.region_to) +
              " s, " +
              (holds ? "at " + fmt(out.tau) + " s" : "extended from " + fmt(out.tau) + " s to " + fmt(ieee_tau) + " s");
    if (sf.rule == figures::RegionRule::kLongest) {  // N
      if (const std::optional<Bump> b = find_bump(c, slopes, best->first, best->last, out.value, o))
        out.bends = bump_text(*b, "");
      // A finer -1/2 stretch on a lower line: a fast correlated term (white beyond its
      // correlation time) adds to the white noise where N is read; said, and counted.
      for (const auto& r : regions) {
        if (&r == best || r.last >= best->first || r.count < kMinRegionPoints) continue;
        const double below = 1.0 - c.sigma[r.last] * std::sqrt(c.tau[r.last]) / out.value;
        if (below > kBumpExcess && out.bends.empty())
          out.bends = "a finer -1/2 stretch over " + fmt(c.tau[r.first]) + "-" + fmt(c.tau[r.last]) + " s lies " +
                      fmt(100.0 * below) +
                      "% lower: a fast correlated term, white beyond its correlation time, adds to the white noise "
                      "where N is read (counted in N)";
      }
    }
    return out;
  }
  return bound_of(c, sf.scale, std::string("no ") + slope_name + " slope", slope_name);
}

// B: the minimum of the curve (IEEE 952: the bias instability is the floor of the flat
// part). Candidates are the interior local minima (below both usable neighbours) and the
// lowest point of each flat stretch (slope within the tolerance of 0 over at least two
// points); the lowest candidate wins. A flat stretch above a lower minimum is not the
// floor: preferring any flat stretch to a sharper minimum read a model's B at a plateau
// over 463-927 s, 2.4x the minimum at 17.2 s (issue 43, item 1). Without a candidate the
// curve only bounds B.
Readoff read_minimum(const Curve& c, const std::vector<double>& slopes, const IntervalFn& interval,
                     const ReadoffOptions& o) {
  const std::size_t K = c.tau.size();
  std::vector<std::size_t> points;  // usable, positive
  std::size_t lowest = K;
  for (std::size_t i = 0; i < K; ++i) {
    if (!c.usable[i] || !(c.sigma[i] > 0.0)) continue;
    points.push_back(i);
    if (lowest == K || c.sigma[i] < c.sigma[lowest]) lowest = i;
  }
  Readoff out;
  if (lowest == K) {
    out.how = "no usable point";
    return out;
  }
  const double s = 1.0 / kBiasInstabilityFactor;
  auto flat = [&](std::size_t i) {
    return c.usable[i] && c.sigma[i] > 0.0 && std::isfinite(slopes[i]) && std::abs(slopes[i]) <= o.slope_tolerance;
  };
  // The flat stretch around point i (itself when it is not flat).
  auto stretch = [&](std::size_t p) {
    std::size_t a = p, b = p;
    while (a > 0 && flat(points[a - 1]) && flat(points[a])) --a;
    while (b + 1 < points.size() && flat(points[b + 1]) && flat(points[b])) ++b;
    return std::make_pair(a, b);
  };
  std::size_t best = points.size();  // index into points
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double v = c.sigma[points[p]];
    const bool local_minimum =
        p > 0 && p + 1 < points.size() && v < c.sigma[points[p - 1]] && v < c.sigma[points[p + 1]];
    const auto [a, b] = stretch(p);
    bool flat_floor = b > a;  // the lowest point of a flat stretch of at least two points
    for (std::size_t q = a; flat_floor && q <= b; ++q) flat_floor = !(c.sigma[points[q]] < v);
    if ((local_minimum || flat_floor) && (best == points.size() || v < c.sigma[points[best]])) best = p;
  }
  // A curve that ends still falling below a minimum has not reached its floor: that minimum,
  // its whole interval above the curve's last point, is a dip between bumps (a tone over
  // 0.06-0.07 s on a record whose gaps end its curve at 49 s read B 22x the complete
  // record's), and the curve then only bounds B. (A curve rising from its first point, lower
  // there than at a later minimum, has no floor at that point: the minimum stands.)
  if (best != points.size() && lowest == points.back() && interval(points[best], 1.0).first > c.sigma[lowest])
    best = points.size();
  if (best == points.size()) {
    out.value = c.sigma[lowest] * s;
    out.tau = c.tau[lowest];
    out.status = ReadoffStatus::kBound;
    out.high = out.value;
    out.how = lowest == points.back()
                  ? "no flat part or minimum at the curve's lowest level: an upper bound, the curve still falls at "
                    "its last usable point (" +
                        fmt(out.tau) + " s)"
                  : "no flat part or minimum: an upper bound, the curve rises from its first point";
    return out;
  }
  const std::size_t at = points[best];
  const auto [a, b] = stretch(best);
  out.value = c.sigma[at] * s;
  std::tie(out.low, out.high) = interval(at, s);
  out.tau = c.tau[at];
  out.region_from = c.tau[points[a]];
  out.region_to = c.tau[points[b]];
  out.status = ReadoffStatus::kRead;
  out.how = (b > a ? "on the flat part over " + fmt(out.region_from) + "-" + fmt(out.region_to) + " s, lowest at " +
                         fmt(out.tau) + " s"
                   : "at the minimum, " + fmt(out.tau) + " s") +
            ", divided by 0.664";
  return out;
}

NoiseFigures read_all(const Curve& c, const IntervalFn& interval, const ReadoffOptions& o) {
  const std::vector<double> slopes = local_slopes(c);
  NoiseFigures f;
  f.white = read_slope(c, slopes, figures::kWhiteSlope, interval, o);
  f.walk = read_slope(c, slopes, figures::kWalkSlope, interval, o);
  f.instability = read_minimum(c, slopes, interval, o);
  f.quantization = read_slope(c, slopes, figures::kQuantizationSlope, interval, o);
  f.ramp = read_slope(c, slopes, figures::kRampSlope, interval, o);
  return f;
}

std::vector<bool> usable_points(const AllanDeviation& a, const ReadoffOptions& o) {
  std::vector<bool> u(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) u[i] = a.edf[i] >= o.min_edf;
  return u;
}

// The IEEE 952 slopes of an Allan deviation: quantization -1, white noise -1/2, flicker 0,
// random walk +1/2, rate ramp +1 (IEEE Std 952-1997, annex C).
constexpr double kCanonicalSlopes[] = {-1.0, -0.5, 0.0, 0.5, 1.0};

// Whether a component's local slope belongs to `target` among the canonical slopes: the
// nearest one. A fast Gauss-Markov term a few correlation times below tau* has not yet
// reached -1/2 (slope -0.31 at five correlation times), but it is white noise in the
// making, not a flicker floor: a tolerance of 0.1 around -1/2 dropped it from N and
// wrote a density 18% below the Allan deviation the model itself matches at 1 s (issue 26,
// adis_16405_imu1 gyro_z: AR1 with T = 0.19 s).
bool nearest_canonical(double slope, double target) {
  double best = kCanonicalSlopes[0];
  for (double s : kCanonicalSlopes)
    if (std::abs(slope - s) < std::abs(slope - best)) best = s;
  return best == target;
}

// Each component's own log-log Allan deviation slope at grid point i (least squares
// through its neighbours); NaN where it has no positive Allan variance there.
std::vector<double> component_slopes(const Model& model, const Eigen::VectorXd& theta, const AllanDeviation& grid,
                                     std::size_t i) {
  std::vector<double> out(static_cast<std::size_t>(model.num_components()), NAN);
  const std::size_t lo = i > 0 ? i - 1 : i, hi = i + 1 < grid.size() ? i + 1 : i;
  if (lo == hi) return out;
  const auto left = component_allan_variances(model, theta, grid.m[lo]);
  const auto right = component_allan_variances(model, theta, grid.m[hi]);
  const double span = std::log(grid.tau[hi] / grid.tau[lo]);
  for (std::size_t c = 0; c < out.size(); ++c)
    if (left[c] > 0.0 && right[c] > 0.0) out[c] = 0.5 * std::log(right[c] / left[c]) / span;
  return out;
}

// A model's N (or K, Q, R) at grid point `at` of its curve: only the components whose own
// slope there is nearest that slope among the canonical ones count (the others' share is not
// white noise, or not random walk), each with its exact continuous figure when it states
// one (WN's noise density, RW's random walk, QN's quantization, DR's drift rate:
// engine/physical.h) and otherwise its Allan variance there on the line (a fast AR1's
// long-run white level, a slow one's early random walk). So a WN + RW + QN + DR model gives
// back sqrt(sigma2 / f), sqrt(gamma2 f), sqrt(Q2) / f and |omega| f exactly, and the
// separation of the lines is not needed.
//
// K counts only what is itself a random walk over the record (`record_end`: the record's
// last usable point): a component whose Allan deviation still rises there, i.e. RW, or an
// AR1/GM that has not reached its peak within the record (T > tau_end / 1.8926, the GM
// peak, kGaussMarkovPeakTau). (Asking for a slope nearest +1/2 at the record's end too,
// i.e. T > 1.3 tau_end, dropped 13.7% of WN + AR1 fits with T = 10 records, whose fitted
// T is that uncertain: tools/bench/bench_k_without_random_walk.cc.) An AR1 that peaks and falls
// within the record is a bias (B), and a +1/2 stretch where a white noise crosses into a
// drift is no random walk at all: GM + WN + DR fits read K = 0.0027 +- 0.7% there, "from
// the model", in 20 of 20 series (issue 43, item 2).
//
// Its interval, with `cov` (of theta; NaN-free), is the delta method on the counted
// components alone: value^2 = sum_c value_c^2, d value_c^2 = 2 scale2 d nu_c^2(2m) (the
// Jacobian's columns of c at the read point m), so that a slow term the curve carries there
// but the figure does not count adds nothing to its uncertainty (the whole curve's interval
// made a 2*AR1 model's N twice as uncertain as its simulated spread, and so the record
// planned for it 4x too long: tools/bench/bench_record_plan, issue 43 item 8).
//
// False when no component is on the slope there (r unchanged).
bool refine_from_components(const Model& model, const Eigen::VectorXd& theta, const AllanDeviation& grid,
                            std::size_t at, Readoff& r, const SlopeFigure& sf, std::size_t record_end,
                            const Eigen::MatrixXd* cov, double z) {
  const double target = sf.slope;
  const bool walk = sf.rule == figures::RegionRule::kNearest;  // K
  if (!r.available() || r.status == ReadoffStatus::kBound) return false;
  if (grid.size() < 2) return false;
  const auto here = component_allan_variances(model, theta, grid.m[at]);
  const std::vector<double> slopes = component_slopes(model, theta, grid, at);
  const std::vector<double> end_slopes =
      walk ? component_slopes(model, theta, grid, record_end) : std::vector<double>();
  const double scale2 = sf.scale(grid.tau[at]) * sf.scale(grid.tau[at]);  // value^2 = AVAR * scale2
  double sum = 0.0;
  const double tau2[1] = {2.0 * static_cast<double>(grid.m[at])};
  const Eigen::RowVectorXd jac = cov ? Eigen::RowVectorXd(model.jacobian(theta, tau2).row(0)) : Eigen::RowVectorXd();
  Eigen::RowVectorXd g = Eigen::RowVectorXd::Zero(theta.size());  // d value^2 / d theta
  for (int k = 0; k < model.num_components(); ++k) {
    const auto c = static_cast<std::size_t>(k);
    if (!std::isfinite(slopes[c]) || !nearest_canonical(slopes[c], target)) continue;
    if (walk && !(std::isfinite(end_slopes[c]) && end_slopes[c] > 0.0)) continue;
    const Process& p = *model.components()[c].process;
    const std::span<const double> th(theta.data() + model.offset(k), static_cast<std::size_t>(p.size()));
    const double exact = quantity_of_kind(p.physical(th, grid.freq), sf.kind);  // DR's is signed: squared
    sum += std::isfinite(exact) ? exact * exact : here[c] * scale2;
    if (cov) g.segment(model.offset(k), p.size()) = 2.0 * scale2 * jac.segment(model.offset(k), p.size());
  }
  if (!(sum > 0.0)) return false;
  const double ratio = std::sqrt(sum) / r.value;
  r.value *= ratio;
  r.low = r.high = std::numeric_limits<double>::quiet_NaN();
  if (cov) {
    const double var = (g * *cov * g.transpose())(0, 0);  // of value^2
    if (var >= 0.0 && std::isfinite(var)) {
      const double rel = z * std::sqrt(var) / (2.0 * sum);  // of value
      r.low = r.value * std::exp(-rel), r.high = r.value * std::exp(rel);
    }
  }
  r.how += walk ? "; the components random-walk-like over the record at " + fmt(grid.tau[at]) + " s only"
                : "; the components on this slope at " + fmt(grid.tau[at]) + " s only";
  return true;
}

std::size_t nearest_index(const std::vector<double>& tau, double t) {
  std::size_t at = 0;
  for (std::size_t i = 1; i < tau.size(); ++i)
    if (std::abs(tau[i] - t) < std::abs(tau[at] - t)) at = i;
  return at;
}

// The model's component making a bump: the one with the largest Allan variance at the bump's
// peak beyond what a white noise with its Allan variance at the floor's read point `floor`
// would have there (AVAR_c(peak) - AVAR_c(floor) tau_floor / tau_peak: 0 for WN), with its
// share of the Allan variance at the peak.
std::string bump_maker(const Model& model, const Eigen::VectorXd& theta, const AllanDeviation& grid, std::size_t floor,
                       double peak_tau) {
  const std::size_t peak = nearest_index(grid.tau, peak_tau);
  const auto at_peak = component_allan_variances(model, theta, grid.m[peak]);
  const auto at_floor = component_allan_variances(model, theta, grid.m[floor]);
  double total = 0.0, largest = 0.0;
  int best = -1;
  for (std::size_t c = 0; c < at_peak.size(); ++c) {
    if (!(at_peak[c] > 0.0)) continue;
    total += at_peak[c];
    const double white_like = std::max(0.0, at_floor[c]) * grid.tau[floor] / grid.tau[peak];
    if (at_peak[c] - white_like > largest) largest = at_peak[c] - white_like, best = static_cast<int>(c);
  }
  if (best < 0 || !(total > 0.0)) return "";
  return "the model's " + component_text(model, best, theta, 3) + " (" +
         fmt(100.0 * at_peak[static_cast<std::size_t>(best)] / total) + "% of its Allan variance there)";
}

}  // namespace

NoiseFigures read_noise_figures(const AllanDeviation& adev, const ReadoffOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  Curve c{adev.tau, adev.adev, usable_points(adev, options), {}};
  NoiseFigures f = read_all(
      c, [&](std::size_t i, double s) { return std::make_pair(adev.ci_low[i] * s, adev.ci_high[i] * s); }, options);
  figures::separate_power_laws(f);
  return f;
}

namespace {

// The averaging factors of `grid` extended to kModelReachRecords records, at the Allan
// grid's own density (the model's curve is known beyond the record).
AllanDeviation extended_grid(const AllanDeviation& grid) {
  AllanDeviation ext;
  ext.freq = grid.freq;
  ext.n = grid.n;
  ext.m = grid.m;
  const std::int64_t reach = static_cast<std::int64_t>(kModelReachRecords) * std::max<std::int64_t>(grid.n, 2);
  while (!ext.m.empty()) {
    const double v = std::round(static_cast<double>(ext.m.back()) * std::exp2(1.0 / AllanOptions{}.points_per_octave));
    if (v > static_cast<double>(reach)) break;
    ext.m.push_back(std::max(static_cast<std::int64_t>(v), ext.m.back() + 1));
  }
  for (std::int64_t m : ext.m) ext.tau.push_back(static_cast<double>(m) / grid.freq);
  return ext;
}

// What a model's curve showing a slope lacks when no component of that kind makes it.
const char* no_term_of(const SlopeFigure& sf) {
  switch (sf.rule) {
    case figures::RegionRule::kLongest:
      return "no white noise";
    case figures::RegionRule::kNearest:
      return "no random walk (no RW, nor an AR1/GM random-walk-like over the record)";
    case figures::RegionRule::kFirst:
      return "no quantization noise";
    case figures::RegionRule::kLast:
      break;
  }
  return "no rate ramp";
}

// A model's curve as its read-offs see it: on the data's grid (cd: B, and the data's read
// points) and extended beyond the record (ce: the power-law slopes, a bound only over the
// record), with the delta method's covariance. (N and K: a fitted random walk shows its +1/2
// slope even where the record is too short to; whether the data allow it is decided by
// choose_noise_figures. B: the data's usable range only, a minimum is about the record.)
struct ModelCurves {
  const Model& model;
  const Eigen::VectorXd& theta;
  const AllanDeviation& grid;
  AllanDeviation ext;
  Curve cd, ce;
  Eigen::MatrixXd cov;
  bool with_cov = false;
  double z = 0.0;
  std::size_t record_end = 0;  // the record's last usable point: where a random walk must still be one

  ModelCurves(const Model& m, const Eigen::VectorXd& th, const AllanDeviation& g, const Eigen::MatrixXd* covariance,
              const ReadoffOptions& o)
      : model(m), theta(th), grid(g), ext(extended_grid(g)) {
    cd = Curve{grid.tau, model_allan_deviation(model, theta, grid.m), usable_points(grid, o), {}};
    std::vector<bool> in_record = cd.usable;
    in_record.resize(ext.m.size(), false);
    ce = Curve{ext.tau, model_allan_deviation(model, theta, ext.m), std::vector<bool>(ext.m.size(), true), in_record};
    // Components at a boundary have no standard errors (NaN rows in the fit's covariance):
    // they enter the delta method with none.
    with_cov = covariance && covariance->rows() == theta.size() && covariance->cols() == theta.size();
    if (with_cov) cov = covariance->unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
    z = boost::math::quantile(boost::math::normal(), 1.0 - o.alpha / 2.0);
    for (std::size_t i = 0; i < cd.usable.size(); ++i)
      if (cd.usable[i]) record_end = i;
  }

  // Delta method on log(value): value = sigma(tau_i) s, d sigma = d AVAR / (2 sigma) = d nu^2(2m) / sigma.
  IntervalFn interval_on(const Curve& c, const std::vector<std::int64_t>& ms) const {
    return [this, &c, &ms](std::size_t i, double s) -> std::pair<double, double> {
      if (!with_cov || !(c.sigma[i] > 0.0)) return {NAN, NAN};
      const double tau2[1] = {2.0 * static_cast<double>(ms[i])};
      const Eigen::RowVectorXd g = model.jacobian(theta, tau2).row(0) / c.sigma[i];
      const double var = (g * cov * g.transpose())(0, 0);
      if (!(var >= 0.0) || !std::isfinite(var)) return {NAN, NAN};
      const double rel = z * std::sqrt(var) / c.sigma[i];
      const double v = c.sigma[i] * s;
      return {v * std::exp(-rel), v * std::exp(rel)};
    };
  }

  // A power-law figure from the components on its slope where it is read; where none is, the
  // model's curve only bounds the figure (the slope is other terms crossing).
  void components_or_bound(Readoff& r, const SlopeFigure& sf) const {
    if (!shows(r)) return;
    const std::size_t i = nearest_index(ext.tau, r.tau);
    if (refine_from_components(model, theta, ext, i, r, sf, record_end, with_cov ? &cov : nullptr, z)) return;
    Readoff b = bound_of(
        ce, sf.scale,
        std::string("the model's ") + sf.slope_name + " slope at " + fmt(ext.tau[i]) + " s is " + no_term_of(sf),
        sf.slope_name);
    b.region_from = r.region_from;
    b.region_to = r.region_to;
    r = b;
  }

  // The model's curve where the data's figure `d` is read (false, r unchanged, when the data
  // do not show it): `scale` the figure's at tau, `slope_name` nullptr for B.
  bool at_data(const Readoff& d, Readoff& r, const std::function<double(double)>& scale, const char* slope_name) const {
    if (!shows(d)) return false;
    const std::size_t i = nearest_index(grid.tau, d.tau);
    const double sc = scale(grid.tau[i]);
    Readoff x;
    x.value = cd.sigma[i] * sc;
    std::tie(x.low, x.high) = interval_on(cd, grid.m)(i, sc);
    x.tau = grid.tau[i];
    x.region_from = d.region_from;
    x.region_to = d.region_to;
    x.status = d.status;
    x.how = std::string("the model's curve where the data's figure is read, ") + fmt(x.tau) + " s" +
            (slope_name ? std::string(" (on the data's ") + slope_name + " slope)" : std::string());
    r = x;
    return true;
  }

  // The components behind a figure: their shares of the Allan variance where it was read.
  std::vector<std::pair<std::string, double>> sources_at(double tau) const {
    constexpr double kShownShare = 0.01;
    std::vector<std::pair<std::string, double>> shares;
    const auto parts = component_allan_variances(model, theta, ext.m[nearest_index(ext.tau, tau)]);
    double total = 0.0;
    for (double v : parts) total += std::max(v, 0.0);
    if (!(total > 0.0)) return shares;
    for (int k = 0; k < model.num_components(); ++k) {
      const double share = std::max(parts[static_cast<std::size_t>(k)], 0.0) / total;
      if (share >= kShownShare) shares.emplace_back(component_text(model, k, theta), share);
    }
    std::sort(shares.begin(), shares.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    return shares;
  }
};

// The power-law figures with their slopes, in NoiseFigures.
constexpr std::pair<Readoff NoiseFigures::*, const SlopeFigure*> kPowerLaws[] = {
    {&NoiseFigures::white, &figures::kWhiteSlope},
    {&NoiseFigures::walk, &figures::kWalkSlope},
    {&NoiseFigures::quantization, &figures::kQuantizationSlope},
    {&NoiseFigures::ramp, &figures::kRampSlope},
};

}  // namespace

NoiseFigures model_noise_figures(const Model& model, const Eigen::VectorXd& theta, const AllanDeviation& grid,
                                 const Eigen::MatrixXd* covariance, const ReadoffOptions& options,
                                 const NoiseFigures* at) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_size_match("model_noise_figures", "theta", static_cast<std::size_t>(theta.size()), "parameters",
                   static_cast<std::size_t>(model.num_parameters()));
  const ModelCurves mc(model, theta, grid, covariance, options);
  NoiseFigures f;
  const std::vector<double> slopes_e = local_slopes(mc.ce);
  for (const auto& [figure, sf] : kPowerLaws)
    f.*figure = read_slope(mc.ce, slopes_e, *sf, mc.interval_on(mc.ce, mc.ext.m), options);
  const Readoff own_white = f.white;
  f.instability = read_minimum(mc.cd, local_slopes(mc.cd), mc.interval_on(mc.cd, grid.m), options);
  for (const auto& [figure, sf] : kPowerLaws) mc.components_or_bound(f.*figure, *sf);
  if (at) {
    // The one rule (issue 43): a figure the data show is read where they show it, on the
    // model's curve too, so that the model's value and the check of the model against the
    // data (choose_noise_figures) are about the same tau. (The model's own read-offs were
    // taken at its own taus: B at a plateau of the model's curve over 463-927 s was
    // accepted because the model matched the data at their minimum, 17.2 s.) N, K, Q and R
    // count the components on their slope there only (else the model only bounds them);
    // B is the curve itself.
    for (const auto& [figure, sf] : kPowerLaws)
      if (mc.at_data((*at).*figure, f.*figure, sf->scale, sf->slope_name)) mc.components_or_bound(f.*figure, *sf);
    // B: where the model's own curve has a floor (a white noise alone has none: its value at
    // the data's minimum is no bias instability of the model's).
    if (shows(f.instability))
      mc.at_data(
          at->instability, f.instability, [](double) { return 1.0 / kBiasInstabilityFactor; }, nullptr);
  }
  for (int k = 0; k < kFigureCount; ++k)
    if (std::isfinite(f[k].tau)) f[k].sources = mc.sources_at(f[k].tau);
  // A bump on the model's own curve after its white floor, with the component making it.
  if (shows(own_white)) {
    const std::size_t first = nearest_index(mc.ext.tau, own_white.region_from),
                      last = nearest_index(mc.ext.tau, own_white.region_to);
    if (const std::optional<Bump> b = find_bump(mc.ce, slopes_e, first, last, own_white.value, options))
      f.white.bends =
          bump_text(*b, bump_maker(model, theta, mc.ext, nearest_index(mc.ext.tau, own_white.tau), b->peak_tau));
  }
  return f;
}

}  // namespace gmwm
