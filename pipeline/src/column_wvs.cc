#include "column_wvs.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"

namespace gmwm::pipeline::detail {

ColumnWvs classical_column_wvs(const std::vector<std::span<const double>>& series, const WvOptions& wv, double freq,
                               const std::optional<AllanOptions>& allan) {
  using Clock = std::chrono::steady_clock;
  ColumnWvs out;
  const auto wv_start = Clock::now();
  // classical_wv's own refusals (a short series, invalid options) before any transform.
  for (const auto& s : series)
    if (static_cast<std::int64_t>(s.size()) < kMinSeriesLength)
      gmwm::detail::throw_check("classical_wv", "series length", static_cast<double>(s.size()),
                                "at least " + std::to_string(kMinSeriesLength));
  if (const std::string why = wv.Validate(); !why.empty()) throw InvalidArgument("classical_wv: " + why);
  std::vector<std::vector<double>> level_sums;
  out.transforms = haar_transforms(series);
  const auto& transforms = out.transforms;
  out.wvs = classical_wv(transforms, wv, &level_sums);
  out.wv_seconds = std::chrono::duration<double>(Clock::now() - wv_start).count();
  if (allan) {
    const auto allan_start = Clock::now();
    out.allan = allan_deviation(transforms, freq, *allan, level_sums);
    out.allan_seconds = std::chrono::duration<double>(Clock::now() - allan_start).count();
  }
  return out;
}

void require_regular(const io::SignalSet& set, const std::string& what) {
  if (set.missing.empty()) return;
  // The gaps of timestamps are joined by --gaps join; NaN rows (an array's) by dropping them.
  const bool stamps = set.timing && set.timing->gaps > 0;
  const std::string column = stamps ? " of the timestamps '" + set.timing->column + "'" : " (NaN rows)";
  throw InputError((set.path.empty() ? std::string() : set.path + ": ") + std::to_string(set.missing_samples()) +
                   " samples missing in " + std::to_string(set.missing.size()) + " gaps" + column + "; " + what +
                   " reads a regular record: " +
                   (stamps ? "give --gaps join to join the samples end to end"
                           : "drop the NaN rows to join the samples end to end"));
}

void check_simulated_grid(const io::SignalSet& set, const std::string& what) {
  if (set.missing.empty() || set.signals.empty()) return;
  const auto observed = static_cast<double>(set.signals.front().values.size());
  const double grid = observed + static_cast<double>(set.missing_samples());
  if (!(grid > kMaxSimulatedGridFactor * observed)) return;
  const MissingRun longest =
      *std::max_element(set.missing.begin(), set.missing.end(),
                        [](const MissingRun& a, const MissingRun& b) { return a.length < b.length; });
  throw InputError(
      (set.path.empty() ? std::string() : set.path + ": ") + what + " simulates the record's whole grid of " +
      significant(grid, 6) + " samples, " + significant(grid / observed, 3) + " times its " + significant(observed, 6) +
      " observed ones (at most " + significant(kMaxSimulatedGridFactor, 3) + "): cut the record at its longest gap (" +
      std::to_string(longest.length) + " samples missing from grid sample " + std::to_string(longest.start) +
      "), or give --gaps join to join the samples end to end");
}

namespace {

// The held-samples sentence a column's screening note says when its screen is off.
std::string held_screen_note(const RepeatedSamples& repeated) {
  return "spike screen off: " + significant(100.0 * repeated.held_share, 3) +
         "% of the samples copy the one before (held), and their steps of exactly zero deflate the level-1 "
         "robust scale the screen measures spikes against";
}

}  // namespace

std::unique_ptr<WvEstimator> draw_estimator(const std::vector<MissingRun>& missing,
                                            const std::optional<robust::RobustWvOptions>& robust) {
  if (robust && !missing.empty()) return std::make_unique<robust::GappyRobustWvEstimator>(*robust, missing);
  if (robust) return std::make_unique<robust::RobustWvEstimator>(*robust);
  if (!missing.empty()) return std::make_unique<GappyWvEstimator>(missing);
  return nullptr;
}

std::unique_ptr<WvEstimator> draw_estimator(const io::SignalSet& set,
                                            const std::optional<robust::RobustWvOptions>& robust) {
  return draw_estimator(set.missing, robust);
}

WaveletVariance gappy_wv_of(std::span<const double> observed, const std::vector<MissingRun>& missing,
                            const RepeatedSamples* repeated, const WvOptions& wv,
                            const robust::RobustWvOptions* robust) {
  WaveletVariance out;
  if (!robust) {
    out = classical_wv_with_gaps(observed, missing, wv);
    drop_incomplete_levels(out);
    return out;
  }
  robust::RobustWvOptions o = *robust;
  o.progress = nullptr;
  const bool held = robust->screen_spikes && repeated && repeated->held();
  if (held) o.screen_spikes = false;
  out = robust::robust_wv_with_gaps(observed, missing, o);
  drop_incomplete_levels(out);
  if (held) out.screening = held_screen_note(*repeated);
  return out;
}

ColumnWvs gappy_column_wvs(const io::SignalSet& set, const WvOptions& wv, const std::optional<AllanOptions>& allan) {
  using Clock = std::chrono::steady_clock;
  ColumnWvs out;
  out.wvs.resize(set.signals.size());
  if (allan) out.allan.resize(set.signals.size());
  const auto start = Clock::now();
  gmwm::parallel_for(std::size_t{0}, set.signals.size(), [&](std::size_t k) {
    out.wvs[k] = gappy_wv_of(set.signals[k].values, set.missing, nullptr, wv, nullptr);
  });
  out.wv_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (allan) {
    const auto allan_start = Clock::now();
    gmwm::parallel_for(std::size_t{0}, set.signals.size(), [&](std::size_t k) {
      out.allan[k] = allan_deviation_with_gaps(set.signals[k].values, set.missing, set.freq, *allan);
    });
    out.allan_seconds = std::chrono::duration<double>(Clock::now() - allan_start).count();
  }
  return out;
}

std::vector<WaveletVariance> robust_wvs_of(const std::vector<std::span<const double>>& series,
                                           const std::vector<const RepeatedSamples*>& repeated,
                                           const robust::RobustWvOptions& options,
                                           const std::vector<std::unique_ptr<HaarModwt>>& transforms) {
  const auto held = [&](std::size_t k) {
    return options.screen_spikes && k < repeated.size() && repeated[k] && repeated[k]->held();
  };
  std::vector<std::span<const double>> screened, unscreened;
  for (std::size_t k = 0; k < series.size(); ++k) (held(k) ? unscreened : screened).push_back(series[k]);
  if (unscreened.empty()) return robust::robust_wv(series, options, transforms);
  // The held series without the screen, the others with it (each group's series and levels
  // in parallel); their own transforms are rebuilt (a held record only).
  robust::RobustWvOptions off = options;
  off.screen_spikes = false;
  std::vector<WaveletVariance> a =
      screened.empty() ? std::vector<WaveletVariance>() : robust::robust_wv(screened, options);
  std::vector<WaveletVariance> b = robust::robust_wv(unscreened, off);
  std::vector<WaveletVariance> out;
  std::size_t ia = 0, ib = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    if (!held(k)) {
      out.push_back(std::move(a[ia++]));
      continue;
    }
    WaveletVariance w = std::move(b[ib++]);
    w.screening = held_screen_note(*repeated[k]);
    out.push_back(std::move(w));
  }
  return out;
}

namespace {

// robust_wv_with_gaps of every column (in parallel), cut to its consecutive levels with a
// usable window as the classical one; the screen off for held columns as robust_wvs_of.
std::vector<WaveletVariance> gappy_robust_wvs(const io::SignalSet& set, const robust::RobustWvOptions& options) {
  std::vector<WaveletVariance> out(set.signals.size());
  std::atomic<int> done{0};
  const auto total = static_cast<int>(set.signals.size());
  gmwm::parallel_for(std::size_t{0}, set.signals.size(), [&](std::size_t k) {
    const io::Signal& s = set.signals[k];
    out[k] = gappy_wv_of(s.values, set.missing, &s.repeated, {}, &options);
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  });
  return out;
}

}  // namespace

std::vector<WaveletVariance> robust_column_wvs(const io::SignalSet& set, const robust::RobustWvOptions& options,
                                               const std::vector<std::unique_ptr<HaarModwt>>& transforms) {
  if (!set.missing.empty()) return gappy_robust_wvs(set, options);
  std::vector<std::span<const double>> series;
  std::vector<const RepeatedSamples*> repeated;
  for (const io::Signal& s : set.signals) {
    series.emplace_back(s.values);
    repeated.push_back(&s.repeated);
  }
  return robust_wvs_of(series, repeated, options, transforms);
}

ColumnWvs column_wvs_for_fit(const io::SignalSet& set, const WvOptions& wv,
                             const std::optional<robust::RobustWvOptions>& robust, double alpha) {
  if (!set.missing.empty()) {
    if (robust) {
      // The robust WVs the fits read, the classical ones beside them (the report's
      // comparison), both from the windows without a gap.
      const auto start = std::chrono::steady_clock::now();
      ColumnWvs out = gappy_column_wvs(set, wv, std::nullopt);
      out.classical = std::move(out.wvs);
      out.wvs = robust_column_wvs(set, *robust);
      out.wv_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return out;
    }
    std::optional<AllanOptions> allan;
    if (set.freq_known) {
      allan.emplace();
      allan->alpha = alpha;
    }
    return gappy_column_wvs(set, wv, allan);
  }
  std::vector<std::span<const double>> series;
  for (const auto& s : set.signals) series.emplace_back(s.values);
  if (robust) {
    const auto start = std::chrono::steady_clock::now();
    ColumnWvs out;
    // One transform per column for both estimates (the robust one reuses it where its
    // spike screen replaces nothing).
    out.transforms = haar_transforms(series);
    out.wvs = robust_column_wvs(set, *robust, out.transforms);
    out.wv_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.classical = classical_wv(out.transforms, wv);
    out.transforms.clear();  // the fits do not read them: 16 bytes a sample, freed now
    return out;
  }
  std::optional<AllanOptions> allan;
  if (set.freq_known) {
    allan.emplace();
    allan->alpha = alpha;
  }
  ColumnWvs out = classical_column_wvs(series, wv, set.freq, allan);
  out.transforms.clear();  // the fits do not read them: 16 bytes a sample, freed now
  return out;
}

}  // namespace gmwm::pipeline::detail
