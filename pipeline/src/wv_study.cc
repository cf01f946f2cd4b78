// The WV study as named stages: wavelet variances and, with --adev, the Allan deviations
// from the same transforms (robust: with the classical one, the rounding check and the
// contamination diagnostic) -> noise figures.
#include "gmwm/engine/parallel.h"
#include "gmwm/pipeline/wv_study.h"
#include "column_wvs.h"
#include "usable_wv.h"

#include <chrono>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::pipeline {

std::string WvStudyOptions::Validate() const {
  if (std::string why = wv.Validate(); !why.empty()) return why;
  if (allan)
    if (std::string why = allan->Validate(); !why.empty()) return why;
  return {};
}

WvStudy study_wv(const io::SignalSet& set, const WvStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  if (options.allan && !set.freq_known)
    throw InputError(set.path + ": the Allan deviation needs the sampling rate: give --freq HZ or a timestamp column");
  WvStudy study;
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::span<const double>> series;
  for (const auto& s : set.signals) series.emplace_back(s.values);
  detail::ColumnWvs curves = set.missing.empty()
                                 ? detail::classical_column_wvs(series, options.wv, set.freq, options.allan)
                                 : detail::gappy_column_wvs(set, options.wv, options.allan);
  std::vector<WaveletVariance>& classical = curves.wvs;
  detail::check_usable_wvs(set, classical, false);
  if (options.robust) {
    std::vector<WaveletVariance> robust_wvs = detail::robust_column_wvs(set, *options.robust, curves.transforms);
    const robust::Tuning tuning = robust::tune(options.robust->estimator, options.robust->efficiency);
    for (std::size_t k = 0; k < set.signals.size(); ++k) {
      const auto& x = set.signals[k].values;
      const auto n = static_cast<std::int64_t>(x.size());
      RobustWvView view;
      view.quantization = robust::detect_quantization(x.data(), n);
      view.diagnostic = set.missing.empty()
                            ? robust::contamination_diagnostic(*curves.transforms[k], robust_wvs[k], classical[k],
                                                               view.quantization, tuning)
                            : robust::contamination_diagnostic_with_gaps(x, set.missing, robust_wvs[k], classical[k],
                                                                         view.quantization, tuning);
      view.classical = std::move(classical[k]);
      study.columns.push_back({set.signals[k].name, std::move(robust_wvs[k]), std::move(view), std::nullopt});
    }
  } else {
    for (std::size_t k = 0; k < set.signals.size(); ++k)
      study.columns.push_back({set.signals[k].name, std::move(classical[k]), std::nullopt, std::nullopt});
  }
  study.levels_asked = options.wv.levels;
  study.wv_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - curves.allan_seconds;
  study.allan_seconds = curves.allan_seconds;
  if (options.allan) {
    ReadoffOptions ro;
    ro.alpha = options.allan->alpha;
    gmwm::parallel_for(std::size_t{0}, set.signals.size(), [&](std::size_t k) {
      study.columns[k].allan = data_figure_report(std::move(curves.allan[k]), ro);
    });
  }
  return study;
}

}  // namespace gmwm::pipeline
