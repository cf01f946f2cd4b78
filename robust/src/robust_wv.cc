#include "gmwm/robust/robust_wv.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <utility>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/vector_clones.h"
#include "gmwm/robust/spike_screen.h"
#include "robust_level.h"
#include "small_sample.h"

namespace gmwm::robust {
namespace {

// Root solving in l = log s: stop when a step or the bracket is below this (a relative
// change of s of 1e-10, far below the estimate's sampling error of >= 1e-3 even at
// 10^6 coefficients; quantized data make g piecewise smooth with large kinks, where a
// tighter tolerance only buys oscillation between pieces).
constexpr double kLogTolerance = 1e-10;
constexpr int kMaxPasses = 200;
// Bracket search: factors of 2 in s, at most this many (2^-300 of the start).
constexpr int kMaxBracketSteps = 300;
// Levels with more coefficients than this first solve on an evenly strided subsample
// of about kSubsampleSize coefficients: its root (within ~1%) starts Newton on the full
// level, which then needs two or three passes instead of eight or ten.
constexpr std::size_t kSubsampleThreshold = 1 << 17;
constexpr std::size_t kSubsampleSize = 1 << 14;

struct Eval {
  double g = 0.0;   // mean chi(W^2 / s) - a
  double dg = 0.0;  // d g / d log s
};

// The passes' sums run in kLanes independent partial sums (combined at the end): one
// running sum is a chain of dependent additions that neither vectorises nor pipelines
// (x86's 4-cycle add latency per coefficient). The solver was 17% of `wv --robust`, now
// 15%: at 1e6 coefficients a pass is bound by reading them from memory (issue 44). The
// kernels have AVX2 clones (vector_clones.h: the same sums bit for bit).
constexpr std::size_t kLanes = 4;

// The estimating equation of one level, g(l) = mean chi(W^2 / (c^2 e^l)) - a and its
// derivative in l, from one pass over the coefficients per window of l (issue 44: Newton
// took three passes over 8 MB per level, memory-bound, 35% of the robust WV). In a pass
// centred at s0 = e^l0 each coefficient has v0 = W^2 / (c^2 s0), and at l = l0 + d its
// v = v0 e^-d. Both estimators' chi is a polynomial in v below the cut v = 1 and a
// constant above it, so a coefficient that stays on one side of the cut over the window
// |d| <= kEvalHalfWidth enters only through the power sums P_m = sum v0^m (bisquare's
// psi^2 / c^2 = v (1 - v)^4 = v - 4v^2 + 6v^3 - 4v^4 + v^5; Huber's min(v, 1)), which
// scale exactly by e^-md; the few whose v0 lies within e^(+-kMemberHalfWidth) of the cut
// (a wider margin, so no rounding puts one on the wrong side) are kept and evaluated one
// by one. The equation is then exact at every l of the window without touching the level
// again: the Newton steps from the subsample's root (within ~1%) all land in it. A step
// outside re-centres (one more pass), so no level takes more passes than before.
// Rounding: the power sums differ from the direct sums by a few units in the 16th digit
// (at Gaussian levels P_1 dominates: v ~ z^2 / c^2 << 1, no cancellation), far inside
// the root's tolerance kLogTolerance.
constexpr double kEvalHalfWidth = 0.05;
constexpr double kMemberHalfWidth = 0.1;
// The pass goes in blocks of this many coefficients: a block holding a coefficient near
// the cut is read again from L1 to collect it (the vectorised sums cannot branch).
constexpr std::size_t kSummaryBlock = 256;

struct PowerSums {
  double p[5][kLanes] = {};   // sum v0^(m+1) over the coefficients below the cut at every l of the window
  double above[kLanes] = {};  // how many lie above it at every l (Huber's clipped ones)
};

// Adds a block's power sums; returns whether it holds a coefficient near the cut. The
// sums are copied in and out (stores through `sums` could alias `x`), and the file is
// compiled with -fno-trapping-math (CMakeLists.txt): under trapping math GCC keeps a
// branch around the masked products, and the loop does not vectorise (2.2 ns a
// coefficient instead of 0.6). No value changes, only the floating-point exception
// flags, which nothing reads.
GMWM_VECTOR_CLONES bool add_power_sums(const double* x, std::size_t n, double k0, double inner, double outer,
                                       PowerSums& sums) {
  double p0[kLanes], p1[kLanes], p2[kLanes], p3[kLanes], p4[kLanes], above[kLanes], near[kLanes] = {};
  for (std::size_t l = 0; l < kLanes; ++l) {
    p0[l] = sums.p[0][l];
    p1[l] = sums.p[1][l];
    p2[l] = sums.p[2][l];
    p3[l] = sums.p[3][l];
    p4[l] = sums.p[4][l];
    above[l] = sums.above[l];
  }
  const std::size_t whole = n - n % kLanes;
  for (std::size_t i = 0; i < whole; i += kLanes)
    for (std::size_t l = 0; l < kLanes; ++l) {
      const double v = x[i + l] * x[i + l] * k0;
      const double v1 = v < inner ? v : 0.0, v2 = v1 * v1, v3 = v2 * v1;
      p0[l] += v1;
      p1[l] += v2;
      p2[l] += v3;
      p3[l] += v2 * v2;
      p4[l] += v3 * v2;
      above[l] += v > outer ? 1.0 : 0.0;
      near[l] += ((v >= inner) & (v <= outer)) ? 1.0 : 0.0;
    }
  for (std::size_t i = whole; i < n; ++i) {
    const double v = x[i] * x[i] * k0;
    const double v1 = v < inner ? v : 0.0, v2 = v1 * v1, v3 = v2 * v1;
    p0[0] += v1;
    p1[0] += v2;
    p2[0] += v3;
    p3[0] += v2 * v2;
    p4[0] += v3 * v2;
    above[0] += v > outer ? 1.0 : 0.0;
    near[0] += ((v >= inner) & (v <= outer)) ? 1.0 : 0.0;
  }
  for (std::size_t l = 0; l < kLanes; ++l) {
    sums.p[0][l] = p0[l];
    sums.p[1][l] = p1[l];
    sums.p[2][l] = p2[l];
    sums.p[3][l] = p3[l];
    sums.p[4][l] = p4[l];
    sums.above[l] = above[l];
  }
  return (near[0] + near[1]) + (near[2] + near[3]) > 0.0;
}

class LevelEquation {
 public:
  LevelEquation(std::span<const double> w, const Tuning& t) : w_(w), t_(t), c2_(t.c * t.c) {}

  // g and dg at s = e^l: from the current window's sums, or after a pass centred at l.
  Eval at(double l) {
    if (!centred_ || std::abs(l - l0_) > kEvalHalfWidth) centre(l);
    const double e = std::exp(l0_ - l);  // v = v0 e
    double sum = 0.0, dsum = 0.0;
    if (t_.kind == RobustKind::kHuber) {
      sum = p_[0] * e + above_;
      dsum = -p_[0] * e;
      for (double v0 : near_) {
        const double v = v0 * e;
        sum += v < 1.0 ? v : 1.0;
        dsum -= v < 1.0 ? v : 0.0;
      }
    } else {
      // sum_m a_m P_m e^m and sum_m m a_m P_m e^m, a = (1, -4, 6, -4, 1).
      const double e2 = e * e, e3 = e2 * e, e4 = e2 * e2, e5 = e4 * e;
      const double t1 = p_[0] * e, t2 = p_[1] * e2, t3 = p_[2] * e3, t4 = p_[3] * e4, t5 = p_[4] * e5;
      sum = t1 - 4.0 * t2 + 6.0 * t3 - 4.0 * t4 + t5;
      double d = t1 - 8.0 * t2 + 18.0 * t3 - 16.0 * t4 + 5.0 * t5;
      for (double v0 : near_) {
        const double v = v0 * e;
        const double r = 1.0 - v;
        const double u = r > 0.0 ? r : 0.0;
        const double vu3 = v * u * u * u;
        sum += vu3 * u;
        d += vu3 * (u - 4.0 * v);
      }
      dsum = -d;
    }
    const double M = static_cast<double>(w_.size());
    return {c2_ * sum / M - t_.a, c2_ * dsum / M};
  }

  int passes() const { return passes_; }

 private:
  void centre(double l) {
    ++passes_;
    centred_ = true;
    l0_ = l;
    const double k0 = std::exp(-l) / c2_;
    const double inner = std::exp(-kMemberHalfWidth), outer = std::exp(kMemberHalfWidth);
    PowerSums s;
    near_.clear();
    const double* x = w_.data();
    for (std::size_t b = 0; b < w_.size(); b += kSummaryBlock) {
      const std::size_t n = std::min(kSummaryBlock, w_.size() - b);
      if (!add_power_sums(x + b, n, k0, inner, outer, s)) continue;
      for (std::size_t i = b; i < b + n; ++i) {
        const double v = x[i] * x[i] * k0;
        if (v >= inner && v <= outer) near_.push_back(v);
      }
    }
    for (int m = 0; m < 5; ++m) p_[m] = (s.p[m][0] + s.p[m][1]) + (s.p[m][2] + s.p[m][3]);
    above_ = (s.above[0] + s.above[1]) + (s.above[2] + s.above[3]);
  }

  std::span<const double> w_;
  const Tuning& t_;
  double c2_;
  bool centred_ = false;
  double l0_ = 0.0;
  double p_[5] = {};
  double above_ = 0.0;
  std::vector<double> near_;
  int passes_ = 0;
};

// What the solver needs to know of the values besides the passes: how many are exactly
// zero and the smallest non-zero square (bisquare's lower limit).
struct ValueStats {
  std::size_t zeros = 0;
  double min_w2 = std::numeric_limits<double>::infinity();
};

GMWM_VECTOR_CLONES ValueStats value_stats(std::span<const double> w) {
  ValueStats v;
  for (double x : w) {
    v.zeros += (x == 0.0);
    if (x != 0.0) v.min_w2 = std::min(v.min_w2, x * x);
  }
  return v;
}

ScaleSolution solve(std::span<const double> w, const Tuning& t, double start, const ValueStats& stats) {
  ScaleSolution out;
  out.scale = std::numeric_limits<double>::quiet_NaN();
  const std::size_t zeros = stats.zeros;
  const double min_w2 = stats.min_w2;  // smallest non-zero W^2 (bisquare)
  out.zero_fraction = w.empty() ? 1.0 : static_cast<double>(zeros) / static_cast<double>(w.size());
  if (w.empty() || !(start > 0.0) || !std::isfinite(start)) return out;
  // Huber: the left side decreases from (1 - p0) c^2 (s -> 0) to 0 (s -> inf).
  if (t.kind == RobustKind::kHuber && (1.0 - out.zero_fraction) * t.c * t.c <= t.a) return out;

  // Newton in l = log s from the start, inside a bracket (lo, hi) that is tightened by
  // every evaluation: g > 0 puts the root above l, g < 0 on the decreasing side puts it
  // below (Huber's g decreases everywhere; bisquare's g rises from -a near s = 0 to a
  // hump and decreases to -a: a point with g < 0 and dg > 0 lies below the hump, and
  // the root sought, the upper one, is above it). Steps leaving the bracket bisect it, or
  // double/halve s while it is still open.
  const double ln2 = std::log(2.0);
  const double c2 = t.c * t.c;
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  double g_lo = 0.0, g_hi = 0.0;
  int side = 0;  // Illinois modification of regula falsi: which end was kept last
  double l = std::log(start);
  // A root is reported only once the search has converged after seeing g >= 0 (a sign
  // change: for bisquare, a hump that reaches a), or on a vanishing Newton step; with
  // all g < 0 the bracket collapses onto a bisquare hump, which is not a root.
  bool sign_change = false;
  // Bisquare, after such a collapse: the hump found stays below a, but it may be a
  // cluster of outliers' own hump (spikes covering 8% of a level's coefficients make
  // one) above the coefficients' hump. The search then descends past it, taking its
  // rising side (g < 0, dg > 0) as "above the root" until a decreasing point (dg < 0)
  // shows it has passed the valley below it.
  bool descending = false;
  LevelEquation equation(w, t);
  for (int k = 0; k < kMaxPasses + kMaxBracketSteps; ++k) {
    const Eval e = equation.at(l);
    out.passes = equation.passes();
    if (e.g == 0.0) {
      sign_change = true;
      break;
    }
    double next;
    bool newton = false;
    if (e.g > 0.0) {
      sign_change = true;
      lo = l;
      g_lo = e.g;
      if (side == -1) g_hi *= 0.5;
      side = -1;
      newton = e.dg < 0.0;
      next = newton ? l - e.g / e.dg : l + ln2;
    } else if (e.dg < 0.0 || descending) {
      if (e.dg < 0.0) descending = false;
      hi = l;
      g_hi = e.g;
      if (side == 1) g_lo *= 0.5;
      side = 1;
      newton = e.dg < 0.0;
      next = newton ? l - e.g / e.dg : l - ln2;
    } else {
      // Bisquare below its hump: go up. This end of the bracket has g < 0, so it is no
      // end for regula falsi (g_lo < 0 below selects bisection).
      lo = std::max(lo, l);
      g_lo = e.g;
      next = l + ln2;
    }
    // While the bracket is open on a side, a step towards it at most doubles/halves s:
    // an unbounded Newton step from far below (Huber: g' ~ 0 when every coefficient is
    // clipped) jumped to s = inf, and one from far above (g ~ m/s - a) past the
    // 2^-300 guard below, or into bisquare's spurious region.
    if (!std::isfinite(hi)) next = std::min(next, l + ln2);
    if (!std::isfinite(lo)) next = std::max(next, l - ln2);
    if (!(next > lo && next < hi)) {
      // Newton left the bracket (a kink of g): Illinois regula falsi inside it, or
      // bisection when the lower end is on bisquare's rising side.
      newton = false;
      if (std::isfinite(lo) && std::isfinite(hi))
        next = g_lo > 0.0 ? lo + (hi - lo) * g_lo / (g_lo - g_hi) : 0.5 * (lo + hi);
      else
        next = std::isfinite(lo) ? lo + ln2 : hi - ln2;
    }
    if ((newton && std::abs(next - l) < kLogTolerance) || (hi - lo) < kLogTolerance) {
      sign_change = sign_change || newton;  // a vanishing Newton step sits on the root
      l = next;
      if (sign_change || t.kind == RobustKind::kHuber) break;
      // Bisquare collapsed onto a hump below a: descend past it (see `descending`).
      descending = true;
      hi = std::min(lo, l);
      g_hi = -t.a;
      lo = -std::numeric_limits<double>::infinity();
      side = 0;
      next = hi - ln2;
    }
    // Below min W^2 / c^2 every bisquare coefficient is rejected (g = -a from there
    // down): descending further cannot find a root.
    if (next < l && t.kind == RobustKind::kBisquare && std::exp(next) * c2 < min_w2) return out;
    if (next < std::log(start) - kMaxBracketSteps * ln2) return out;  // no root above 2^-300 start
    l = next;
    if (k + 1 == kMaxPasses + kMaxBracketSteps) return out;  // not converged
  }
  if (!sign_change) return out;
  out.scale = std::exp(l);
  out.has_root = std::isfinite(out.scale) && out.scale > 0.0;
  return out;
}

void check_series(const char* fn, std::int64_t n, const RobustWvOptions& o) {
  if (n < kMinSeriesLength)
    detail::throw_check(fn, "series length", static_cast<double>(n), "at least " + std::to_string(kMinSeriesLength));
  internal::check_options(fn, o);
}

struct Prepared {
  std::unique_ptr<HaarModwt> owned;  // the screened series' own transform, when it needs one
  const HaarModwt* modwt = nullptr;  // owned, or the caller's transform of the unscreened series
  WaveletVariance w;                 // the classical WV, overwritten level by level
};

// The root of a long level: started from the root on an evenly strided subsample.
ScaleSolution solve_level(std::span<const double> coef, const Tuning& t, double start, const ValueStats& stats) {
  if (coef.size() > kSubsampleThreshold) {
    thread_local std::vector<double> sub;
    sub.clear();
    const std::size_t stride = coef.size() / kSubsampleSize;
    for (std::size_t k = 0; k < coef.size(); k += stride) sub.push_back(coef[k]);
    const ScaleSolution s0 = solve(sub, t, start, value_stats(sub));
    if (s0.has_root) start = s0.scale;
  }
  return solve(coef, t, start, stats);
}

// `shared`: the caller's transform of x (or null), used when the screen replaces nothing.
Prepared prepare(const double* x, std::int64_t n, const RobustWvOptions& o, const Tuning& t,
                 const HaarModwt* shared = nullptr) {
  Prepared p;
  WvOptions co;
  co.levels = o.levels;
  co.alpha = o.alpha;
  SpikeScreen screen;
  std::vector<double> cleaned;
  const double* data = x;
  if (o.screen_spikes) {
    std::vector<double>& jumps = internal::level_buffer();
    level_one_jumps(x, n, jumps);
    const ScaleSolution s1 = internal::solve_jumps(jumps, t);
    screen = screen_spikes(x, n, s1.scale);
    if (!s1.has_root) screen.note = internal::unscreened_note(s1, t);
    if (!screen.ranges.empty()) {
      cleaned = replace_ranges(x, n, screen.ranges);
      data = cleaned.data();
    }
  } else {
    screen.note = "spike screen off";
  }
  if (shared && data == x) {
    p.modwt = shared;
  } else {
    p.owned = std::make_unique<HaarModwt>(data, n);
    p.modwt = p.owned.get();
  }
  p.w = classical_wv(*p.modwt, co);
  internal::describe_robust(p.w, t, std::move(screen));
  return p;
}

void robust_level(const HaarModwt& modwt, int j, const Tuning& t, WaveletVariance& w) {
  if (internal::keeps_classical(j, w)) return;
  std::vector<double>& coef = internal::level_buffer();
  modwt.coefficients(j, coef);
  internal::robust_level_from(coef, modwt.noise_floor(j), j, t, w);
}

}  // namespace

namespace internal {

std::vector<double>& level_buffer() {
  thread_local std::vector<double> buffer;
  return buffer;
}

ScaleSolution solve_jumps(std::span<const double> jumps, const Tuning& t) {
  double ms = 0.0;
  for (double v : jumps) ms += v * v;
  ms /= static_cast<double>(std::max<std::size_t>(jumps.size(), 1));
  return solve_level(jumps, t, ms > 0.0 ? ms : 1.0, value_stats(jumps));
}

std::string unscreened_note(const ScaleSolution& s1, const Tuning& t) {
  std::ostringstream os;
  os.precision(3);
  os << "spike screen not applied: the level-1 " << to_string(t.kind) << " equation has no root ("
     << 100.0 * s1.zero_fraction << "% of the jumps are exactly 0)";
  return os.str();
}

void describe_robust(WaveletVariance& w, const Tuning& t, SpikeScreen screen) {
  w.estimator = to_string(t.kind);
  w.efficiency = t.efficiency;
  w.replaced = std::move(screen.ranges);
  w.screening = std::move(screen.note);
  std::ostringstream os;
  os << "second-order bias correction at levels with " << kRobustMinEta << " <= eta <= " << kSmallSampleMaxEta
     << " (long-run covariances by overlapping batch means); classical estimate below eta = " << kRobustMinEta;
  w.small_sample = os.str();
}

void add_note(WaveletVariance& w, std::size_t i, const std::string& note) {
  w.notes[i] = w.notes[i].empty() ? note : w.notes[i] + "; " + note;
}

bool keeps_classical(int j, WaveletVariance& w) {
  const auto i = static_cast<std::size_t>(j - 1);
  if (!(w.eta[i] < kRobustMinEta)) return false;
  std::ostringstream os;
  os << "classical estimate: eta = " << w.eta[i] << " < " << kRobustMinEta
     << " effective coefficients, too few for the robust estimator's consistency";
  add_note(w, i, os.str());
  return true;
}

void robust_level_from(std::vector<double>& coef, double floor, int j, const Tuning& t, WaveletVariance& w) {
  const auto i = static_cast<std::size_t>(j - 1);
  ValueStats stats;
  if (t.kind == RobustKind::kHuber) {  // two loops: each vectorises
    for (double& v : coef) {
      const bool zero = std::abs(v) <= floor;
      v = zero ? 0.0 : v;
      stats.zeros += zero;
    }
  } else {
    for (double& v : coef) {
      const bool zero = std::abs(v) <= floor;
      v = zero ? 0.0 : v;
      stats.zeros += zero;
      stats.min_w2 = std::min(stats.min_w2, zero ? stats.min_w2 : v * v);
    }
  }
  const ScaleSolution s = solve_level(coef, t, w.wv[i], stats);
  if (!s.has_root) {
    std::ostringstream os;
    os.precision(3);
    os << "no root: the " << to_string(t.kind) << " equation has no solution (" << 100.0 * s.zero_fraction
       << "% of the coefficients are exactly zero, quantized data";
    // The closed-form limit 1 - a/c^2 is Huber's; bisquare's depends on the non-zero part.
    if (t.kind == RobustKind::kHuber)
      os << "; the limit at efficiency " << t.efficiency << " is " << 100.0 * (1.0 - t.a / (t.c * t.c)) << "%";
    os << ")";
    add_note(w, i, os.str());
    w.wv[i] = w.ci_low[i] = w.ci_high[i] = w.variance[i] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  double scale = s.scale;
  if (w.eta[i] <= kSmallSampleMaxEta) {
    const double bias = small_sample_bias(coef, t, s.scale, w.tau[i]);
    // |bias| is ~1 / eta <= 0.1 at the robust levels; a value outside (-0.5, 1) would
    // mean the expansion does not hold (it never did in our studies): leave it.
    if (bias > -0.5 && bias < 1.0) scale /= 1.0 + bias;
  }
  const double eta = t.efficiency * w.eta[i];
  w.wv[i] = scale;

  w.eta[i] = eta;
  w.variance[i] = 2.0 * scale * scale / eta;
  std::tie(w.ci_low[i], w.ci_high[i]) = chi_square_ci(scale, eta, w.alpha);
}

void check_options(const char* fn, const RobustWvOptions& o) {
  if (const std::string why = o.Validate(); !why.empty()) throw InvalidArgument(std::string(fn) + ": " + why);
}

}  // namespace internal

std::string RobustWvOptions::Validate() const {
  std::ostringstream os;
  if (!(efficiency > 0.0 && efficiency < 1.0))
    os << "efficiency must be in (0, 1) (exclusive), got " << efficiency;
  else if (!(alpha > 0.0 && alpha < 1.0))
    os << "alpha must be in (0, 1), got " << alpha;
  else if (alpha < kMinAlpha)
    os << "alpha must be at least 1e-10 (the level 1 - alpha/2 rounds to 1 below ~1e-16), got " << alpha;
  else if (levels < 0)
    os << "levels must be positive (or 0 for all), got " << levels;
  return os.str();
}

ScaleSolution solve_scale(std::span<const double> w, const Tuning& tuning, double start) {
  return solve(w, tuning, start, value_stats(w));
}

WaveletVariance robust_wv(const double* x, std::int64_t n, const RobustWvOptions& options) {
  check_series("robust_wv", n, options);
  const Tuning t = tune(options.estimator, options.efficiency);
  Prepared p = prepare(x, n, options, t);
  for (int j = 1; j <= p.w.levels(); ++j) robust_level(*p.modwt, j, t, p.w);
  return std::move(p.w);
}

std::vector<WaveletVariance> robust_wv(const std::vector<std::span<const double>>& series,
                                       const RobustWvOptions& options) {
  return robust_wv(series, options, {});
}

std::vector<WaveletVariance> robust_wv(const std::vector<std::span<const double>>& series,
                                       const RobustWvOptions& options,
                                       const std::vector<std::unique_ptr<HaarModwt>>& transforms) {
  if (!transforms.empty()) check_size_match("robust_wv", "transforms", transforms.size(), "series", series.size());
  for (const auto& s : series) check_series("robust_wv", static_cast<std::int64_t>(s.size()), options);
  const Tuning t = tune(options.estimator, options.efficiency);
  std::vector<Prepared> p(series.size());
  // Progress (and the cancellation point) after each series prepared and each level: the
  // levels' count is known once every series is prepared, so the total grows then.
  std::atomic<int> done{0};
  std::atomic<int> total{static_cast<int>(series.size())};
  auto tick = [&] {
    const int d = ++done;
    if (options.progress) options.progress(d, total.load());
  };
  gmwm::parallel_for(std::size_t{0}, series.size(), [&](std::size_t c) {
    const HaarModwt* shared = transforms.empty() ? nullptr : transforms[c].get();
    if (shared && shared->size() != static_cast<std::int64_t>(series[c].size()))
      throw InvalidArgument("robust_wv: transform " + std::to_string(c) + " is not of its series' length");
    p[c] = prepare(series[c].data(), static_cast<std::int64_t>(series[c].size()), options, t, shared);
    tick();
  });
  // All levels of all series as one flat range (the fine levels cost the same as the
  // coarse ones: M_j ~ N at every level), so two cores share the work evenly.
  std::vector<std::pair<std::size_t, int>> tasks;
  for (std::size_t c = 0; c < series.size(); ++c)
    for (int j = 1; j <= p[c].w.levels(); ++j) tasks.emplace_back(c, j);
  total += static_cast<int>(tasks.size());
  gmwm::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t k) {
    const auto [c, j] = tasks[k];
    robust_level(*p[c].modwt, j, t, p[c].w);
    tick();
  });
  std::vector<WaveletVariance> out;
  out.reserve(series.size());
  for (auto& q : p) out.push_back(std::move(q.w));
  return out;
}

RobustWvEstimator::RobustWvEstimator(RobustWvOptions options) : options_(std::move(options)) {
  options_.progress = nullptr;  // the caller's progress is the data's, not the draws'
  if (const std::string why = options_.Validate(); !why.empty()) throw InvalidArgument("RobustWvEstimator: " + why);
}

WaveletVariance RobustWvEstimator::compute(const double* x, std::int64_t n, int levels, double alpha) const {
  RobustWvOptions o = options_;
  o.levels = levels;
  o.alpha = alpha;
  return robust_wv(x, n, o);
}

}  // namespace gmwm::robust
