#include "gap_events.h"
#include "gap_levels.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/haar_modwt.h"

namespace gmwm::gap::detail {
namespace {

// Euler-Mascheroni constant: the mean of the standard Gumbel law (its variance is
// pi^2 / 6), for the method-of-moments fit of the event statistic's null maximum.
constexpr double kEulerGamma = 0.5772156649015329;
// TRANSIENT check: the start segment is this many filter lengths of the event's level,
// and the time constants tried are 2^(k / kTransientGridPerOctave) samples up to it.
constexpr int kTransientSegmentBlocks = 4;
constexpr int kTransientGridPerOctave = 4;

double mean_of(const Eigen::VectorXd& v) { return v.mean(); }

double sd_of(const Eigen::VectorXd& v) {
  const double m = v.mean();
  return std::sqrt((v.array() - m).square().sum() / std::max<Eigen::Index>(1, v.size() - 1));
}

}  // namespace

double gumbel_quantile(const Eigen::VectorXd& sample, double level) {
  const double beta = sd_of(sample) * std::sqrt(6.0) / M_PI;
  const double mu = mean_of(sample) - kEulerGamma * beta;
  return mu - beta * std::log(-std::log1p(-level));
}

namespace {

// Prefix sums of x and x^2 (size n + 1), for segment means and residual sums of squares.
struct Prefix {
  std::vector<double> s, s2;
  explicit Prefix(const std::vector<double>& x) : s(x.size() + 1, 0.0), s2(x.size() + 1, 0.0) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      s[i + 1] = s[i] + x[i];
      s2[i + 1] = s2[i] + x[i] * x[i];
    }
  }
  double sum(std::int64_t a, std::int64_t b) const {
    return s[static_cast<std::size_t>(b)] - s[static_cast<std::size_t>(a)];
  }
  double sum2(std::int64_t a, std::int64_t b) const {
    return s2[static_cast<std::size_t>(b)] - s2[static_cast<std::size_t>(a)];
  }
  // Residual sum of squares of x[a, b) about its mean.
  double rss(std::int64_t a, std::int64_t b) const {
    const double m = static_cast<double>(b - a);
    return m > 0 ? sum2(a, b) - sum(a, b) * sum(a, b) / m : 0.0;
  }
};

// The best two-mean split of x[a, b) with the split point in [lo, hi]: the first sample
// of the right part, its jump (right mean - left mean) and the split's residual sum.
struct Split {
  std::int64_t at = 0;
  double jump = 0.0, rss = std::numeric_limits<double>::infinity();
};
Split best_split(const Prefix& p, std::int64_t a, std::int64_t b, std::int64_t lo, std::int64_t hi) {
  Split best;
  for (std::int64_t s = std::max(lo, a + 1); s <= std::min(hi, b - 1); ++s) {
    const double r = p.rss(a, s) + p.rss(s, b);
    if (r < best.rss) {
      best.rss = r;
      best.at = s;
      best.jump = p.sum(s, b) / static_cast<double>(b - s) - p.sum(a, s) / static_cast<double>(s - a);
    }
  }
  return best;
}

// Least squares of x[0, L) on (1, exp(-t / T)) over the grid of T: the best T, its
// amplitude and residual sum.
struct Decay {
  double T = 0.0, amplitude = 0.0, rss = std::numeric_limits<double>::infinity();
};
Decay best_decay(const std::vector<double>& x, std::int64_t L) {
  Decay best;
  double sx = 0.0, sxx = 0.0;
  for (std::int64_t t = 0; t < L; ++t) {
    sx += x[static_cast<std::size_t>(t)];
    sxx += x[static_cast<std::size_t>(t)] * x[static_cast<std::size_t>(t)];
  }
  const double n = static_cast<double>(L);
  const int steps = static_cast<int>(std::floor(std::log2(n) * kTransientGridPerOctave));
  for (int k = 0; k <= steps; ++k) {
    const double T = std::exp2(static_cast<double>(k) / kTransientGridPerOctave);
    double se = 0.0, see = 0.0, sxe = 0.0;
    for (std::int64_t t = 0; t < L; ++t) {
      const double e = std::exp(-static_cast<double>(t) / T);
      se += e;
      see += e * e;
      sxe += x[static_cast<std::size_t>(t)] * e;
    }
    const double vee = see - se * se / n, vxe = sxe - sx * se / n, vxx = sxx - sx * sx / n;
    if (!(vee > 0.0)) continue;
    const double a = vxe / vee, r = vxx - a * vxe;
    if (r < best.rss) best = {T, a, r};
  }
  return best;
}

}  // namespace

double trend_slope(const std::vector<double>& x) {
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t L = std::max<std::int64_t>(1, n / kTrendSegments);
  if (n < 2 * L) return 0.0;
  double head = 0.0, tail = 0.0;
  for (std::int64_t t = 0; t < L; ++t) {
    head += x[static_cast<std::size_t>(t)];
    tail += x[static_cast<std::size_t>(n - L + t)];
  }
  return (tail - head) / static_cast<double>(L) / static_cast<double>(n - L);
}

std::vector<double> autocovariance(const Model& m, const Eigen::VectorXd& theta, std::size_t size) {
  std::vector<double> g(size, 0.0), part(size);
  for (int k = 0; k < m.num_components(); ++k) {
    const Process& p = *m.components()[static_cast<std::size_t>(k)].process;
    std::fill(part.begin(), part.end(), 0.0);
    p.generalized_autocovariance(
        std::span<const double>(theta.data() + m.offset(k), static_cast<std::size_t>(p.size())), part);
    for (std::size_t h = 0; h < g.size(); ++h) g[h] += part[h];
  }
  return g;
}

double trend_slope_sd(const Model& m, const Eigen::VectorXd& theta, std::int64_t n) {
  const std::int64_t L = std::max<std::int64_t>(1, n / kTrendSegments);
  if (n < 2 * L) return 0.0;
  const std::vector<double> g = autocovariance(m, theta, static_cast<std::size_t>(n));
  // Var(sum_tail - sum_head) = 2 [L g(0) + 2 sum_{h<L} (L - h) g(h)] - 2 sum_d c(d) g(d),
  // d = l - k over head k and tail l: from n - 2L + 1 to n - 1, c(d) = L - |d - (n - L)|.
  double within = static_cast<double>(L) * g[0];
  for (std::int64_t h = 1; h < L; ++h) within += 2.0 * static_cast<double>(L - h) * g[static_cast<std::size_t>(h)];
  double across = 0.0;
  for (std::int64_t d = n - 2 * L + 1; d <= n - 1; ++d)
    across += static_cast<double>(L - std::abs(d - (n - L))) * g[static_cast<std::size_t>(d)];
  const double var_sum = 2.0 * within - 2.0 * across;
  if (!(var_sum > 0.0)) return 0.0;
  return std::sqrt(var_sum) / static_cast<double>(L) / static_cast<double>(n - L);
}

std::pair<int, int> event_levels(std::int64_t n) {
  int last = 0;
  while (std::ldexp(static_cast<double>(kEventMinBlocks), last + 1) <= static_cast<double>(n)) ++last;
  return {kEventMinLevel, last};
}

Eigen::VectorXd series_statistics(const std::vector<double>& x, HaarModwt& modwt,
                                  const std::vector<double>* temperature, const Eigen::VectorXd& nu_base,
                                  const StepScan& scan, StepScanResult* details) {
  const auto n = static_cast<std::int64_t>(x.size());
  const auto [first, last] = event_levels(n);
  const int L = std::max(0, last - first + 1);
  Eigen::VectorXd out(L + 2 + (temperature ? 1 : 0));
  {
    StepScanResult r = scan_step(modwt, scan);
    out(L) = r.statistic;
    if (details) *details = std::move(r);
  }
  out(L + 1) = trend_slope(x);
  std::vector<double> w, wt;
  // Every level, not only the event levels: the WV that follows on every reference
  // replicate then reads its sums from this one blocked pass (the same sums, bit for bit)
  // instead of a pass over the prefix sums per remaining level (5% of a gap run; issue 44).
  modwt.keep_squares(1, modwt.max_levels());
  for (int j = first; j <= last; ++j) {
    const HaarModwt::Squares s = modwt.squares_of_level(j);
    const double mean = s.sum / static_cast<double>(modwt.count(j));
    out(j - first) = mean > 0.0 ? std::log(s.peak / mean) : 0.0;
  }
  if (temperature) {
    const HaarModwt tm(temperature->data(), n);
    double num = 0.0, den = 0.0;
    const int top = std::min<int>(std::max(last, 1), static_cast<int>(nu_base.size()));
    for (int j = 1; j <= top; ++j) {
      modwt.coefficients(j, w);
      tm.coefficients(j, wt);
      double c = 0.0, v = 0.0;
      for (std::size_t t = 0; t < w.size(); ++t) {
        c += w[t] * wt[t];
        v += wt[t] * wt[t];
      }
      const double m = static_cast<double>(w.size());
      num += c / m / nu_base(j - 1);
      den += v / m / nu_base(j - 1);
    }
    out(L + 2) = den > 0.0 ? num / den : 0.0;
  }
  return out;
}

TimeEffectTests test_time_effects(const Eigen::VectorXd& data_stats, const Eigen::MatrixXd& reps, std::int64_t n,
                                  bool with_temperature, double level) {
  TimeEffectTests t;
  const auto [first, last] = event_levels(n);
  const int L = std::max(0, last - first + 1);
  const Eigen::Index B = reps.rows();
  if (L > 0 && B >= 2) {
    t.event_tested = true;
    t.first_event_level = first;
    Eigen::VectorXd mean(L), sd(L);
    for (int j = 0; j < L; ++j) {
      mean(j) = mean_of(reps.col(j));
      sd(j) = std::max(sd_of(reps.col(j)), std::numeric_limits<double>::min());
    }
    Eigen::VectorXd null_max(B);
    for (Eigen::Index b = 0; b < B; ++b)
      null_max(b) = ((reps.row(b).head(L).transpose() - mean).array() / sd.array()).maxCoeff();
    t.event_statistic = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < L; ++j) {
      const double z = (data_stats(j) - mean(j)) / sd(j);
      t.event_z.push_back(z);
      if (z > t.event_statistic) {
        t.event_statistic = z;
        t.event_level = first + j;
      }
    }
    t.event_threshold = gumbel_quantile(null_max, level);
  }
  if (L > 0 && B >= 2 && reps.col(L).maxCoeff() > 0.0) {
    t.step_tested = true;
    t.step_statistic = data_stats(L);
    t.step_threshold = scan_max_quantile(reps.col(L), level);
  }
  if (B >= 2) {
    const Eigen::VectorXd w = reps.col(L + 1);
    t.trend = data_stats(L + 1);
    t.trend_sd = sd_of(w);
    t.trend_mean = mean_of(w);
    t.trend_z = t.trend_sd > 0.0 ? (t.trend - t.trend_mean) / t.trend_sd : 0.0;
    t.trend_threshold = boost::math::quantile(boost::math::complement(boost::math::normal(), level / 2.0));
  }
  if (with_temperature && B >= 2) {
    t.coupling_tested = true;
    const Eigen::VectorXd k = reps.col(L + 2);
    t.coupling = data_stats(L + 2);
    t.coupling_sd = sd_of(k);
    t.coupling_z = t.coupling_sd > 0.0 ? (t.coupling - mean_of(k)) / t.coupling_sd : 0.0;
    t.coupling_threshold = boost::math::quantile(boost::math::complement(boost::math::normal(), level / 2.0));
  }
  return t;
}

namespace {

// An event located within one filter length of the record's start (t0 <= tau): a step
// there and a decay from t = 0 compete on the start segment, with the same number of
// parameters (level, jump, time / amplitude, T); the decay wins as a TRANSIENT.
void transient_or_step(const std::vector<double>& x, const Prefix& p, GapEvent& e) {
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t tau = std::int64_t{1} << e.level;
  if (e.sample > tau) return;
  const std::int64_t seg = std::min(n, kTransientSegmentBlocks * tau);
  const Split start = best_split(p, 0, seg, 1, seg - 1);
  const Decay d = best_decay(x, seg);
  if (d.rss < start.rss) {
    e.effect = GapEffect::kTransient;
    e.sample = 0;
    e.size = d.amplitude;
    e.time_constant = d.T;
  }
}

}  // namespace

GapEvent locate_event(const std::vector<double>& x, int level) {
  const auto n = static_cast<std::int64_t>(x.size());
  const HaarModwt modwt(x.data(), n);
  std::vector<double> w;
  modwt.coefficients(level, w);
  std::size_t peak = 0;
  for (std::size_t i = 1; i < w.size(); ++i)
    if (std::abs(w[i]) > std::abs(w[peak])) peak = i;
  // Coefficient i covers samples [i, i + tau); a step at t0 peaks where the recent half
  // starts at t0, i.e. i = t0 - tau / 2.
  const std::int64_t tau = std::int64_t{1} << level, half = tau / 2;
  const std::int64_t t0 = static_cast<std::int64_t>(peak) + half;
  const Prefix p(x);
  const std::int64_t a = std::max<std::int64_t>(0, t0 - tau), b = std::min(n, t0 + tau);
  const Split split = best_split(p, a, b, t0 - half, t0 + half);
  GapEvent e;
  e.effect = GapEffect::kStep;
  e.level = level;
  e.sample = split.at;
  e.size = split.jump;
  if (t0 <= tau) {
    GapEvent start = e;
    start.sample = t0;
    transient_or_step(x, p, start);
    if (start.effect == GapEffect::kTransient) e = start;
  }
  return e;
}

GapEvent locate_event(const std::vector<double>& x, const StepScan& scan) {
  const StepScanResult r = scan_step(x, scan);
  GapEvent e;
  e.effect = GapEffect::kStep;
  e.level = r.level;
  e.sample = r.sample;
  e.size = r.size;
  if (r.level > 0) transient_or_step(x, Prefix(x), e);
  return e;
}

bool step_persists(const std::vector<double>& x, const GapEvent& step, const Eigen::VectorXd& nuhat) {
  const auto n = static_cast<std::int64_t>(x.size());
  const Prefix p(x);
  const std::int64_t s = step.sample;
  double step_score = 0.0, burst_score = 0.0;
  int used = 0;
  for (int k = step.level + 1; k <= std::min<int>(step.level + kPersistLevels, static_cast<int>(nuhat.size())); ++k) {
    const std::int64_t half = std::int64_t{1} << (k - 1);
    if (s - half < 0 || s + half > n || !(nuhat(k - 1) > 0.0)) continue;
    // The level-k Haar coefficient centred on the step: half the difference of the means.
    const double w = 0.5 * (p.sum(s, s + half) - p.sum(s - half, s)) / static_cast<double>(half);
    step_score += (w - 0.5 * step.size) * (w - 0.5 * step.size) / nuhat(k - 1);
    burst_score += w * w / nuhat(k - 1);
    ++used;
  }
  return used == 0 || step_score <= burst_score;
}

std::optional<GapEvent> burst_alternative(const std::vector<double>& x, const GapEvent& step) {
  if (step.effect != GapEffect::kStep || step.level < 1) return std::nullopt;
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t tau = std::int64_t{1} << step.level;
  const std::int64_t a = std::max<std::int64_t>(0, step.sample - tau), b = std::min(n, step.sample + tau);
  if (b - a < 8) return std::nullopt;
  const auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  std::vector<double> window(x.begin() + a, x.begin() + b), diffs;
  for (std::size_t i = 1; i < window.size(); ++i) diffs.push_back(window[i] - window[i - 1]);
  const double level = median(window);
  const double d_med = median(diffs);
  for (double& d : diffs) d = std::abs(d - d_med);
  // 1.4826: the MAD's consistency factor for a Gaussian; a difference has twice the variance.
  const double sd = 1.4826 * median(diffs) / std::sqrt(2.0);
  if (!(sd > 0.0)) return std::nullopt;
  std::int64_t first = -1, last = -1;
  double peak = 0.0;
  for (std::int64_t t = a; t < b; ++t) {
    const double dev = x[static_cast<std::size_t>(t)] - level;
    if (std::abs(dev) <= kBurstZ * sd) continue;
    if (first < 0) first = t;
    last = t;
    if (std::abs(dev) > std::abs(peak)) peak = dev;
  }
  // A burst returns: it spans at most half the event's scale and ends inside the window.
  if (first < 0 || last - first + 1 > tau / 2 || last + 1 >= b) return std::nullopt;
  GapEvent e = step;
  e.effect = GapEffect::kOutliers;
  e.sample = first;
  e.length = last - first + 1;
  e.size = peak;
  e.fill = level;
  return e;
}

void remove_event(std::vector<double>& x, const GapEvent& e) {
  if (e.effect == GapEffect::kOutliers) {
    const auto from = static_cast<std::size_t>(std::max<std::int64_t>(0, e.sample));
    for (std::size_t t = from; t < std::min(x.size(), from + static_cast<std::size_t>(e.length)); ++t) x[t] = e.fill;
  } else if (e.effect == GapEffect::kStep) {
    for (std::size_t t = static_cast<std::size_t>(std::max<std::int64_t>(0, e.sample)); t < x.size(); ++t)
      x[t] -= e.size;
  } else if (e.effect == GapEffect::kTransient && e.time_constant > 0.0) {
    for (std::size_t t = 0; t < x.size(); ++t) {
      const double v = e.size * std::exp(-static_cast<double>(t) / e.time_constant);
      if (std::abs(v) < std::numeric_limits<double>::min()) break;
      x[t] -= v;
    }
  }
}

TimeFindings run_time_tests(const std::vector<double>& x, const std::vector<double>* temperature,
                            const Eigen::VectorXd& nu_base, std::shared_ptr<const StepScan> scan,
                            const Eigen::MatrixXd& reps, double level, double alpha, GapResult& g) {
  TimeFindings f;
  if (reps.rows() < 2 || !scan) return f;
  HaarModwt transform(x.data(), static_cast<std::int64_t>(x.size()));
  const Eigen::VectorXd stats = series_statistics(x, transform, temperature, nu_base, *scan, &f.step_scan);
  const TimeEffectTests t =
      test_time_effects(stats, reps, static_cast<std::int64_t>(x.size()), temperature != nullptr, level);
  g.event_tested = t.event_tested;
  if (t.event_tested) {
    g.event_statistic = t.event_statistic;
    g.event_threshold = t.event_threshold;
    f.event = t.event_statistic > t.event_threshold;
    f.event_level = t.event_level;
    f.event_statistic = t.event_statistic;
    f.event_threshold = t.event_threshold;
    f.event_z = t.event_z;
    f.first_event_level = t.first_event_level;
  }
  g.step_scan_tested = t.step_tested;
  if (t.step_tested) {
    g.step_scan_statistic = t.step_statistic;
    g.step_scan_threshold = t.step_threshold;
    g.step_scan_sample = f.step_scan.sample;
    if (t.step_statistic > t.step_threshold && f.step_scan.level > 0) {
      // The scan locates the event (a step's evidence spread over the levels): it decides.
      f.step = true;
      f.event = true;
      f.scan = std::move(scan);
      f.event_level = f.step_scan.level;
      f.event_statistic = t.step_statistic;
      f.event_threshold = t.step_threshold;
      f.first_event_level = t.first_event_level;
    }
  }
  f.trend = std::abs(t.trend_z) > t.trend_threshold;
  f.trend_null_mean = t.trend_mean;
  f.trend_null_sd = t.trend_sd;
  f.trend_level_z = t.trend_threshold;
  f.ci_z = boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / 2.0));
  GapTrend tr;
  tr.omega = t.trend;
  tr.z = t.trend_z;
  tr.threshold = t.trend_threshold;
  tr.significant = f.trend;
  const double zt = boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / 2.0));
  tr.ci_low = t.trend - zt * t.trend_sd;
  tr.ci_high = t.trend + zt * t.trend_sd;
  g.trend = tr;
  if (t.coupling_tested) {
    const double zc = boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / 2.0));
    GapCoupling c;
    c.k = t.coupling;
    c.ci_low = t.coupling - zc * t.coupling_sd;
    c.ci_high = t.coupling + zc * t.coupling_sd;
    c.z = t.coupling_z;
    c.threshold = t.coupling_threshold;
    c.significant = std::abs(t.coupling_z) > t.coupling_threshold;
    f.coupling = c.significant;
    g.temperature = c;
  }
  return f;
}

std::vector<GapBand> event_bands(const TimeFindings& f, const std::vector<GapLevel>& levels) {
  if (!f.event) return {};
  const int peak = f.event_level - f.first_event_level;
  int lo = peak, hi = peak;
  const std::vector<double>& z = f.step ? f.step_scan.share : f.event_z;
  const double bar = f.step ? kStepBandShare : f.event_threshold;
  const int L = static_cast<int>(z.size());
  while (lo > 0 && z[static_cast<std::size_t>(lo - 1)] >= bar) --lo;
  while (hi + 1 < L && z[static_cast<std::size_t>(hi + 1)] >= bar) ++hi;
  // The event's levels are the series' own; the band keeps those the map compares.
  const int first = levels_from(levels), last = first + static_cast<int>(levels.size()) - 1;
  GapBand b;
  b.first_level = std::max(f.first_event_level + lo, first);
  b.last_level = std::min(f.first_event_level + hi, last);
  if (b.first_level > b.last_level) return {};
  b.direction = "excess";
  b.tau_from = levels[static_cast<std::size_t>(b.first_level - first)].tau;
  b.tau_to = levels[static_cast<std::size_t>(b.last_level - first)].tau;
  b.peak_ratio = 1.0;
  for (int j = b.first_level; j <= b.last_level; ++j)
    b.peak_ratio = std::max(b.peak_ratio, levels[static_cast<std::size_t>(j - first)].ratio);
  return {b};
}

std::vector<GapBand> merge_event_band(const std::vector<GapBand>& bands, const TimeFindings& f,
                                      const std::vector<GapLevel>& levels, GapEffect effect) {
  std::vector<GapBand> eb = event_bands(f, levels);
  if (eb.empty()) return bands;
  const int first = levels_from(levels);
  GapBand e = eb.front();
  if (effect == GapEffect::kStep) e.last_level = first + static_cast<int>(levels.size()) - 1;
  std::vector<GapBand> out;
  for (const auto& b : bands) {
    if (b.direction == "excess" && b.last_level + 1 >= e.first_level && b.first_level <= e.last_level + 1) {
      e.first_level = std::min(e.first_level, b.first_level);
      e.last_level = std::max(e.last_level, b.last_level);
    } else {
      out.push_back(b);
    }
  }
  e.tau_from = levels[static_cast<std::size_t>(e.first_level - first)].tau;
  e.tau_to = levels[static_cast<std::size_t>(e.last_level - first)].tau;
  e.peak_ratio = 1.0;  // an excess band: its largest ratio
  for (int j = e.first_level; j <= e.last_level; ++j)
    e.peak_ratio = std::max(e.peak_ratio, levels[static_cast<std::size_t>(j - first)].ratio);
  out.push_back(e);
  std::sort(out.begin(), out.end(), [](const GapBand& a, const GapBand& b) { return a.first_level < b.first_level; });
  return out;
}

std::vector<double> apply_time_effects(const std::vector<double>& x, const std::vector<double>* temperature,
                                       const TimeFindings& f, GapResult& g, const GapEvent* event) {
  std::vector<double> out = x;
  if (f.coupling && temperature && g.temperature) {
    for (std::size_t t = 0; t < out.size(); ++t) out[t] -= g.temperature->k * (*temperature)[t];
    g.steps.push_back(GapEffect::kTemperature);
    g.notes.push_back("the signal follows the temperature channel (coupling z = " + std::to_string(g.temperature->z) +
                      " against the baseline's replicates): the coupled part is removed before the WV is compared");
  }
  if (f.event && !(event && event->effect == GapEffect::kNone)) {
    GapEvent e = event ? *event : f.step ? locate_event(out, *f.scan) : locate_event(out, f.event_level);
    e.statistic = f.event_statistic;
    e.threshold = f.event_threshold;
    remove_event(out, e);
    g.steps.push_back(e.effect);
    g.event = e;
    const char* what = e.effect == GapEffect::kStep       ? "a bias step"
                       : e.effect == GapEffect::kOutliers ? "a burst (a short excursion that returns)"
                                                          : "a warm-up transient";
    if (f.step)
      g.notes.push_back(std::string(what) + " found by the step scan (statistic " + std::to_string(e.statistic) +
                        " > threshold " + std::to_string(e.threshold) + ", mostly from level " +
                        std::to_string(e.level) + "): it is removed before the WV is compared");
    else
      g.notes.push_back(std::string(what) + " concentrates the coarse-level coefficients (statistic " +
                        std::to_string(e.statistic) + " > threshold " + std::to_string(e.threshold) + " at level " +
                        std::to_string(e.level) + "): it is removed before the WV is compared");
  }
  if (f.trend && g.trend && f.trend_null_sd > 0.0) {
    GapTrend& tr = *g.trend;
    if (f.event) {  // re-test on the series without the event
      tr.omega = trend_slope(out);
      tr.z = (tr.omega - f.trend_null_mean) / f.trend_null_sd;
      tr.ci_low = tr.omega - f.ci_z * f.trend_null_sd;
      tr.ci_high = tr.omega + f.ci_z * f.trend_null_sd;
      tr.significant = std::abs(tr.z) > f.trend_level_z;
    }
    if (tr.significant) {
      const double mid = 0.5 * static_cast<double>(out.size() - 1);
      for (std::size_t t = 0; t < out.size(); ++t) out[t] -= tr.omega * (static_cast<double>(t) - mid);
      g.steps.push_back(GapEffect::kDR);
      g.notes.push_back("the record drifts (end-segment slope z = " + std::to_string(tr.z) +
                        " against the baseline's replicates): the linear trend is removed before the WV is compared");
    }
  }
  return out;
}

}  // namespace gmwm::gap::detail
