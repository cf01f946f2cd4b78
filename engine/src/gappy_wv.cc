#include "gmwm/engine/gappy_wv.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/allan.h"

namespace gmwm {

std::int64_t missing_samples(std::span<const MissingRun> missing) {
  std::int64_t total = 0;
  for (const MissingRun& r : missing) total += r.length;
  return total;
}

std::string missing_runs_problem(std::int64_t observed, std::span<const MissingRun> missing) {
  std::int64_t grid = observed;
  for (const MissingRun& r : missing) {
    if (r.length < 1) return "missing run at " + std::to_string(r.start) + ": its length must be at least 1";
    if (r.length > std::numeric_limits<std::int64_t>::max() - grid)
      return "missing run at " + std::to_string(r.start) + ": the record would exceed 2^63 samples";
    grid += r.length;
  }
  std::int64_t end = -1;  // one past the previous run's last sample (-1: no run yet)
  for (std::size_t k = 0; k < missing.size(); ++k) {
    const MissingRun& r = missing[k];
    const std::string which = "missing run " + std::to_string(k + 1) + " (at " + std::to_string(r.start) + ")";
    if (r.start < 0 || r.start > grid - r.length)
      return which + ": outside the record's " + std::to_string(grid) + " samples";
    if (end >= 0 && r.start <= end)
      return which + ": overlaps or touches the run before it (runs must be increasing and apart)";
    end = r.start + r.length;
  }
  return {};
}

namespace {

// The record as its segments: the runs of consecutive observed samples between the gaps.
// A complete window lies inside one segment, and each segment is summed on its own; a
// near-complete window reads the same sums across the gaps it spans. Prefix sums of the
// mean-centred observed values (8 bytes a sample, whatever the gaps' lengths: a gap of a
// day at 1 kHz costs nothing), and the first sample of each segment.
struct Segments {
  std::vector<double> s;            // S_0 .. S_n over the observed samples, mean-centred
  std::vector<std::int64_t> begin;  // the observed index each segment starts at, then n
  std::int64_t grid = 0;            // observed and missing samples together
};

Segments segments(std::span<const double> observed, std::span<const MissingRun> missing) {
  double mean = 0.0;
  for (const double v : observed) mean += v;
  mean /= static_cast<double>(observed.size());
  Segments g;
  g.s.resize(observed.size() + 1);
  for (std::size_t i = 0; i < observed.size(); ++i) g.s[i + 1] = g.s[i] + (observed[i] - mean);
  g.grid = static_cast<std::int64_t>(observed.size());
  std::int64_t before = 0;  // missing samples before the current run
  g.begin.push_back(0);
  for (const MissingRun& r : missing) {
    const std::int64_t at = r.start - before;  // the observed index after the run
    if (at > g.begin.back())
      g.begin.push_back(at);
    else
      g.begin.back() = at;  // a run at the very start: the first segment starts after it
    before += r.length;
    g.grid += r.length;
  }
  g.begin.push_back(static_cast<std::int64_t>(observed.size()));
  return g;
}

// A window pass's sink for its terms: none (the sums alone), or a buffer that keeps them.
struct NoSink {
  void operator()(double) const {}
};

// Sum over the complete windows of 2 * half samples of ((second half - first half) / width)^2
// with width = 2 * half, and their count; each term's root ((second half - first half) /
// width) goes to `sink` in time order.
template <class Sink = NoSink>
std::pair<double, std::int64_t> complete_window_sum(const Segments& g, std::int64_t half, double width,
                                                    Sink&& sink = {}) {
  const std::int64_t w = 2 * half;
  double sum = 0.0;
  std::int64_t count = 0;
  for (std::size_t k = 0; k + 1 < g.begin.size(); ++k) {
    const std::int64_t b = g.begin[k], e = g.begin[k + 1];
    for (std::int64_t t = b + w; t <= e; ++t) {  // the window [t - w, t)
      const auto i = static_cast<std::size_t>(t);
      const double c =
          (g.s[i] - 2.0 * g.s[i - static_cast<std::size_t>(half)] + g.s[i - static_cast<std::size_t>(w)]) / width;
      sum += c * c;
      sink(c);
    }
    if (e - b >= w) count += e - b - w + 1;
  }
  return {sum, count};
}

// The Allan windows of 2m samples at one factor: the sum of (second half's mean - first
// half's mean)^2 over the windows used, their count and how many of them hold no missing
// sample.
struct WindowSums {
  double sum = 0.0;
  std::int64_t used = 0;
  std::int64_t complete = 0;
};

WindowSums complete_windows(const Segments& g, std::int64_t m) {
  // complete_window_sum's terms are ((second sum - first sum) / 2m)^2: a quarter of the
  // squared difference of the half means.
  const auto [sum, complete] = complete_window_sum(g, m, 2.0 * static_cast<double>(m));
  return {4.0 * sum, complete, complete};
}

// The observed samples before grid position p, for positions that never decrease: the runs
// wholly before p are passed once.
class ObservedBefore {
 public:
  explicit ObservedBefore(std::span<const MissingRun> runs) : runs_(runs) {}
  std::int64_t operator()(std::int64_t p) {
    at_ = p + 1;  // gap_end: the run holding p (its start <= p < its end)
    while (k_ < runs_.size() && runs_[k_].start + runs_[k_].length <= p) missing_ += runs_[k_++].length;
    const std::int64_t inside = k_ < runs_.size() && runs_[k_].start < p ? p - runs_[k_].start : 0;
    return p - missing_ - inside;
  }
  /// One past the missing run that holds the position last asked (0 when none does).
  std::int64_t gap_end() const {
    return k_ < runs_.size() && runs_[k_].start < at_ ? runs_[k_].start + runs_[k_].length : 0;
  }
  /// How many grid samples from the position last asked on (itself included) are observed
  /// before the next missing one: 0 when it is missing, the int64 maximum after the last run.
  std::int64_t observed_ahead() const {
    if (k_ >= runs_.size()) return std::numeric_limits<std::int64_t>::max();
    const std::int64_t q = at_ - 1;
    return runs_[k_].start <= q ? 0 : runs_[k_].start - q;
  }

 private:
  std::span<const MissingRun> runs_;
  std::size_t k_ = 0;
  std::int64_t missing_ = 0;  // the samples of runs_[0, k_)
  std::int64_t at_ = 0;
};

// Every window of 2m grid samples whose halves each miss at most `allowed` samples, each
// half's mean over its observed samples. Windows that cannot be used are stepped over: a
// half that misses `excess` samples too many needs a shift of at least `excess` (a shift by
// one frees at most one place), and a half that starts inside a gap must start at most
// `allowed` samples before its end, so a gap of any length costs a few steps.
// Each window's (second half's mean - first half's mean) / 2, its Haar coefficient, goes to
// `sink` in time order.
template <class Sink = NoSink>
WindowSums near_complete_windows(const Segments& g, std::span<const MissingRun> missing, std::int64_t m,
                                 std::int64_t allowed, Sink&& sink = {}) {
  ObservedBefore at0(missing), at1(missing), at2(missing);
  WindowSums w;
  for (std::int64_t p = 0; p + 2 * m <= g.grid;) {
    const std::int64_t o0 = at0(p), o1 = at1(p + m), o2 = at2(p + 2 * m);
    const std::int64_t lost1 = m - (o1 - o0), lost2 = m - (o2 - o1);
    const std::int64_t excess = std::max(lost1, lost2) - allowed;
    if (excess > 0) {
      p = std::max({p + excess, at0.gap_end() - allowed, at1.gap_end() - allowed - m});
      continue;
    }
    // The windows from p on whose three edges all pass observed samples keep their halves'
    // counts: one stretch of them, each half mean by one reciprocal (the per-window divisions
    // were most of a gap diagnosis's time on a gappy record).
    const std::int64_t stretch =
        std::min({at0.observed_ahead(), at1.observed_ahead(), at2.observed_ahead(), g.grid - 2 * m - p + 1});
    const std::int64_t steps = std::max<std::int64_t>(stretch, 1);
    const double r1 = 1.0 / static_cast<double>(o1 - o0), r2 = 1.0 / static_cast<double>(o2 - o1);
    const auto i0 = static_cast<std::size_t>(o0), i1 = static_cast<std::size_t>(o1), i2 = static_cast<std::size_t>(o2);
    for (std::size_t k = 0; k < static_cast<std::size_t>(steps); ++k) {
      const double d = (g.s[i2 + k] - g.s[i1 + k]) * r2 - (g.s[i1 + k] - g.s[i0 + k]) * r1;
      w.sum += d * d;
      sink(0.5 * d);
    }
    w.used += steps;
    if (lost1 == 0 && lost2 == 0) w.complete += steps;
    p += steps;
  }
  return w;
}

// Near-complete windows enter a level (each half averaged over its observed samples, at
// most kAllanMaxMissingShare of it missing) only where they at least double its windows: a
// level's interval narrows with its windows (eta = M / 2^j), and the price, white noise's
// share read at most 1 / (1 - 0.1) = 1.11 times too high in a window missing its whole
// allowance, is small where complete windows are that scarce (long windows, where the slow
// noises dominate). So the levels beyond the longest run without a gap are read, not lost
// (issue 47: 5% lost in bursts ~20 s apart left 13 levels of the complete record's 19).
constexpr double kNearCompleteGain = 2.0;

// The samples each half of level j's window may miss when near-complete windows are read.
std::int64_t allowed_missing(std::int64_t half) {
  return static_cast<std::int64_t>(std::floor(kAllanMaxMissingShare * static_cast<double>(half)));
}

// Whether a level reads its near-complete windows instead of its `complete` ones.
bool reads_near_complete(std::int64_t complete, const WindowSums& near) {
  return near.used > 0 && static_cast<double>(near.used) >= kNearCompleteGain * static_cast<double>(complete);
}

// Whether a level of `all` windows, `complete` of them without a gap, may read near-complete
// ones: they must at least double its windows, and there are at most `all`, so where the
// complete ones are more than half of them the near-complete pass (the gappy WV's costliest:
// 65% of a gap diagnosis's time when run at every level) cannot change the level.
bool may_read_near_complete(std::int64_t complete, std::int64_t all, std::int64_t allowed) {
  return complete < all && allowed > 0 && static_cast<double>(all) >= kNearCompleteGain * static_cast<double>(complete);
}

void fill_gappy_level(const Segments& g, std::span<const MissingRun> missing, int j, WaveletVariance& w) {
  const auto i = static_cast<std::size_t>(j - 1);
  const std::int64_t width = std::int64_t{1} << j, half = width / 2;
  auto [sum, complete] = complete_window_sum(g, half, static_cast<double>(width));
  const std::int64_t all = g.grid - width + 1;
  const double tau = static_cast<double>(width);
  std::int64_t used = complete, partial = 0;
  const std::int64_t allowed = allowed_missing(half);
  bool near = false;
  if (may_read_near_complete(complete, all, allowed)) {
    const WindowSums n = near_complete_windows(g, missing, half, allowed);
    // Each term is (ybar_2 - ybar_1)^2; the Haar coefficient is half that difference.
    near = reads_near_complete(complete, n);
    if (near) sum = n.sum / 4.0, used = n.used, partial = n.used - n.complete;
  }
  w.tau[i] = tau;
  w.coefficients[i] = used;
  w.partial[i] = partial;
  if (complete < all)
    w.notes[i] = std::to_string(complete) + " of " + std::to_string(all) + " windows of " + std::to_string(width) +
                 " samples complete (" + std::to_string(all - complete) + " hold a missing sample)" +
                 (near ? "; read from the " + std::to_string(used) + " whose halves each miss at most " +
                             std::to_string(allowed) + " samples, averaged over their observed ones"
                       : std::string());
  if (used == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    w.wv[i] = w.ci_low[i] = w.ci_high[i] = w.variance[i] = w.eta[i] = nan;
    return;
  }
  const double v = sum / static_cast<double>(used);
  const double eta = wv_eta(used, tau);
  w.wv[i] = v;
  w.eta[i] = eta;
  w.variance[i] = 2.0 * v * v / eta;
  std::tie(w.ci_low[i], w.ci_high[i]) = chi_square_ci(v, eta, w.alpha);
}

void check_gappy_input(const char* what, std::span<const double> observed, std::span<const MissingRun> missing) {
  const auto observed_n = static_cast<std::int64_t>(observed.size());
  if (observed_n < kMinSeriesLength)
    detail::throw_check(what, "observed samples", static_cast<double>(observed_n),
                        "at least " + std::to_string(kMinSeriesLength));
  if (const std::string why = missing_runs_problem(observed_n, missing); !why.empty())
    throw InvalidArgument(std::string(what) + ": " + why);
}

}  // namespace

WaveletVariance classical_wv_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                       const WvOptions& options) {
  check_gappy_input("classical_wv_with_gaps", observed, missing);
  if (const std::string why = options.Validate(); !why.empty()) throw InvalidArgument("classical_wv_with_gaps: " + why);
  const Segments g = segments(observed, missing);
  int J = 0;
  while (J < 62 && (std::int64_t{1} << (J + 1)) <= g.grid) ++J;
  if (options.levels > 0) J = std::min(J, options.levels);
  WaveletVariance w;
  w.n = g.grid;
  w.alpha = options.alpha;
  const auto sz = static_cast<std::size_t>(J);
  for (auto* v : {&w.tau, &w.wv, &w.ci_low, &w.ci_high, &w.variance, &w.eta}) v->resize(sz);
  w.coefficients.resize(sz);
  w.partial.resize(sz);
  w.notes.resize(sz);
  for (int j = 1; j <= J; ++j) fill_gappy_level(g, missing, j, w);
  return w;
}

int complete_levels(const WaveletVariance& wv) {
  int j = 0;
  while (j < wv.levels() && wv.coefficients[static_cast<std::size_t>(j)] > 0) ++j;
  return j;
}

void drop_incomplete_levels(WaveletVariance& wv) {
  const auto keep = static_cast<std::size_t>(complete_levels(wv));
  for (auto* v : {&wv.tau, &wv.wv, &wv.ci_low, &wv.ci_high, &wv.variance, &wv.eta}) v->resize(keep);
  wv.coefficients.resize(keep);
  if (wv.partial.size() > keep) wv.partial.resize(keep);
  if (wv.notes.size() > keep) wv.notes.resize(keep);
}

struct GappyWindows::Sums {
  Segments g;
  std::vector<MissingRun> missing;
  double largest = 0.0;  // the largest |prefix sum|, for the rounding floor
};

GappyWindows::GappyWindows(std::span<const double> observed, std::span<const MissingRun> missing) {
  check_gappy_input("GappyWindows", observed, missing);
  auto sums = std::make_unique<Sums>();
  sums->g = segments(observed, missing);
  sums->missing.assign(missing.begin(), missing.end());
  for (const double v : sums->g.s) sums->largest = std::max(sums->largest, std::abs(v));
  sums_ = std::move(sums);
}

GappyWindows::~GappyWindows() = default;

std::int64_t GappyWindows::grid() const { return sums_->g.grid; }

GappyLevelWindows GappyWindows::coefficients(int j, std::vector<double>& out) const {
  if (j < 1 || j > 62) throw InvalidArgument("GappyWindows: level must be in 1..62, got " + std::to_string(j));
  const Segments& g = sums_->g;
  const std::int64_t width = std::int64_t{1} << j, half = width / 2;
  out.clear();
  GappyLevelWindows r;
  if (width > g.grid) return r;
  const auto keep = [&out](double c) { out.push_back(c); };
  r.complete = complete_window_sum(g, half, static_cast<double>(width), keep).second;
  r.used = r.complete;
  std::int64_t smallest_half = half;  // the fewest observed samples a half mean divides by
  const std::int64_t allowed = allowed_missing(half);
  if (may_read_near_complete(r.complete, g.grid - width + 1, allowed)) {
    thread_local std::vector<double> near_out;
    near_out.clear();
    const WindowSums n =
        near_complete_windows(g, sums_->missing, half, allowed, [](double c) { near_out.push_back(c); });
    if (reads_near_complete(r.complete, n)) {
      out.swap(near_out);
      r.used = n.used;
      smallest_half = half - allowed;
    }
  }
  // Each prefix sum carries a relative rounding error of eps / 2 of the largest; a
  // coefficient combines at most four of them, each divided by at least smallest_half, and
  // halves their difference (HaarModwt::noise_floor's bound with its safety factor 4).
  constexpr double kSafety = 4.0;
  r.noise_floor =
      kSafety * 2.0 * std::numeric_limits<double>::epsilon() * sums_->largest / static_cast<double>(smallest_half);
  return r;
}

std::vector<double> observed_samples(const char* what, const double* x, std::int64_t n,
                                     std::span<const MissingRun> missing) {
  std::int64_t lost = 0;
  for (const MissingRun& r : missing) lost += r.length;
  if (lost >= n)
    throw InvalidArgument(std::string(what) + ": the missing runs fill a grid of " + std::to_string(n) + " samples");
  std::vector<double> observed;
  observed.reserve(static_cast<std::size_t>(n - lost));
  std::int64_t k = 0;
  for (const MissingRun& r : missing) {
    for (; k < std::min(r.start, n); ++k) observed.push_back(x[k]);
    k = r.start + r.length;
  }
  for (; k < n; ++k) observed.push_back(x[k]);
  return observed;
}

WaveletVariance GappyWvEstimator::compute(const double* x, std::int64_t n, int levels, double alpha) const {
  const std::vector<double> observed = observed_samples("GappyWvEstimator", x, n, missing_);
  WvOptions o;
  o.levels = levels;
  o.alpha = alpha;
  WaveletVariance w = classical_wv_with_gaps(observed, missing_, o);
  drop_incomplete_levels(w);
  return w;
}

AllanDeviation allan_deviation_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                         double freq, const AllanOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_positive("allan_deviation_with_gaps", "freq", freq);
  check_gappy_input("allan_deviation_with_gaps", observed, missing);
  const Segments g = segments(observed, missing);
  AllanDeviation a;
  a.freq = freq;
  a.n = g.grid;
  a.alpha = options.alpha;
  for (const std::int64_t m : allan_factors(g.grid, options.points_per_octave)) {
    const auto allowed = static_cast<std::int64_t>(std::floor(options.max_missing_share * static_cast<double>(m)));
    const WindowSums w = allowed == 0 ? complete_windows(g, m) : near_complete_windows(g, missing, m, allowed);
    // No usable window at this m: a longer one may still be (below 1 / max_missing_share a
    // half must be complete, from there it may miss a sample: segments of 14 samples leave no
    // complete window of 16, yet every window of 20 whose halves each miss one).
    if (w.used == 0) continue;
    const double avar = w.sum / (2.0 * static_cast<double>(w.used));
    const double eta = std::max(static_cast<double>(w.used) / static_cast<double>(2 * m), 1.0);
    a.m.push_back(m);
    a.tau.push_back(static_cast<double>(m) / freq);
    a.adev.push_back(std::sqrt(avar));
    a.edf.push_back(eta);
    const auto [low, high] = chi_square_ci(avar, eta, options.alpha);
    a.ci_low.push_back(std::sqrt(low));
    a.ci_high.push_back(std::sqrt(high));
    a.complete.push_back(w.complete);
    a.partial.push_back(w.used - w.complete);
  }
  return a;
}

}  // namespace gmwm
