// The robust WV of a record with missing samples: the regular form's estimating equation
// (robust_level.h) on the windows classical_wv_with_gaps reads, after a spike screen run
// segment by segment.
#include <algorithm>
#include <utility>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/spike_screen.h"
#include "robust_level.h"

namespace gmwm::robust {
namespace {

// The runs of consecutive observed samples between gaps: each one's first observed index
// and how many missing samples come before it on the grid (its grid offset).
struct Segment {
  std::int64_t begin = 0, end = 0;  // observed indices [begin, end)
  std::int64_t offset = 0;          // grid position = observed index + offset
};

std::vector<Segment> segments_of(std::int64_t observed, std::span<const MissingRun> missing) {
  std::vector<Segment> out{{0, observed, 0}};
  std::int64_t before = 0;
  for (const MissingRun& r : missing) {
    const std::int64_t at = r.start - before;  // the observed index after the run
    before += r.length;
    if (at == out.back().begin) {
      out.back().offset = before;  // a run at the record's start: the first segment follows it
      continue;
    }
    out.back().end = at;
    out.push_back({at, observed, before});
  }
  return out;
}

// The spike screen of each segment, against one level-1 robust scale from the jumps inside
// the segments; `cleaned` receives the replaced samples (a copy of x when any is replaced,
// else left empty). The replaced ranges are grid positions.
SpikeScreen screen_segments(std::span<const double> x, const std::vector<Segment>& segments, const Tuning& t,
                            std::vector<double>& cleaned) {
  std::vector<double>& jumps = internal::level_buffer();
  jumps.clear();
  for (const Segment& s : segments)
    for (std::int64_t i = s.begin + 1; i < s.end; ++i)
      jumps.push_back(0.5 * (x[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(i - 1)]));
  const ScaleSolution s1 = jumps.empty() ? ScaleSolution{} : internal::solve_jumps(jumps, t);
  SpikeScreen all;
  for (const Segment& s : segments) {
    if (s.end - s.begin < 2) continue;
    SpikeScreen one = screen_spikes(x.data() + s.begin, s.end - s.begin, s1.scale);
    all.applied = one.applied;
    all.scale = one.scale;
    all.note = std::move(one.note);  // "not applied" or the count's wording, redone below
    if (one.ranges.empty()) continue;
    if (cleaned.empty()) cleaned.assign(x.begin(), x.end());
    const std::vector<double> y = replace_ranges(x.data() + s.begin, s.end - s.begin, one.ranges);
    std::copy(y.begin(), y.end(), cleaned.begin() + s.begin);
    for (const auto& [a, b] : one.ranges) all.ranges.emplace_back(a + s.begin + s.offset, b + s.begin + s.offset);
  }
  if (jumps.empty()) {
    all.note = "spike screen not applied: no two consecutive samples between the record's gaps";
  } else if (!s1.has_root) {
    all.note = internal::unscreened_note(s1, t);
  } else if (all.applied) {
    for (const auto& [a, b] : all.ranges) all.samples += b - a + 1;
    all.note = describe_screen(all) + (segments.size() > 1 ? ", segment by segment between the record's gaps" : "");
  }
  return all;
}

}  // namespace

WaveletVariance robust_wv_with_gaps(std::span<const double> observed, std::span<const MissingRun> missing,
                                    const RobustWvOptions& options) {
  internal::check_options("robust_wv_with_gaps", options);
  const Tuning t = tune(options.estimator, options.efficiency);
  const auto n = static_cast<std::int64_t>(observed.size());
  if (n < kMinSeriesLength)
    detail::throw_check("robust_wv_with_gaps", "observed samples", static_cast<double>(n),
                        "at least " + std::to_string(kMinSeriesLength));
  if (const std::string why = missing_runs_problem(n, missing); !why.empty())
    throw InvalidArgument("robust_wv_with_gaps: " + why);
  SpikeScreen screen;
  std::vector<double> cleaned;
  if (options.screen_spikes)
    screen = screen_segments(observed, segments_of(n, missing), t, cleaned);
  else
    screen.note = "spike screen off";
  const std::span<const double> data = cleaned.empty() ? observed : std::span<const double>(cleaned);
  WvOptions co;
  co.levels = options.levels;
  co.alpha = options.alpha;
  WaveletVariance w = classical_wv_with_gaps(data, missing, co);
  internal::describe_robust(w, t, std::move(screen));
  // The levels in parallel (each writes its own entries of w; a thread's coefficients in
  // its own buffer): the same values whatever the thread count.
  const GappyWindows windows(data, missing);
  gmwm::parallel_for(1, w.levels() + 1, [&](int j) {
    if (w.coefficients[static_cast<std::size_t>(j - 1)] == 0 || internal::keeps_classical(j, w)) return;
    std::vector<double>& coef = internal::level_buffer();
    const GappyLevelWindows read = windows.coefficients(j, coef);
    internal::robust_level_from(coef, read.noise_floor, j, t, w);
  });
  return w;
}

GappyRobustWvEstimator::GappyRobustWvEstimator(RobustWvOptions options, std::vector<MissingRun> missing)
    : options_(std::move(options)), missing_(std::move(missing)) {
  options_.progress = nullptr;  // the caller's progress is the data's, not the draws'
  internal::check_options("GappyRobustWvEstimator", options_);
}

WaveletVariance GappyRobustWvEstimator::compute(const double* x, std::int64_t n, int levels, double alpha) const {
  const std::vector<double> observed = observed_samples("GappyRobustWvEstimator", x, n, missing_);
  RobustWvOptions o = options_;
  o.levels = levels;
  o.alpha = alpha;
  WaveletVariance w = robust_wv_with_gaps(observed, missing_, o);
  drop_incomplete_levels(w);
  return w;
}

}  // namespace gmwm::robust
