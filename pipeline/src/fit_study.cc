// The fit study as named stages: wavelet variances and the data's Allan deviations (one
// transform per column) -> fits (in parallel, drifts oriented) -> noise figures.
#include "gmwm/engine/parallel.h"
#include "gmwm/pipeline/fit_study.h"
#include "column_wvs.h"
#include "first_level.h"
#include "usable_wv.h"

#include <chrono>
#include <memory>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::pipeline {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::string FitStudyOptions::Validate() const {
  if (model.empty()) return "the model is empty";
  if (fit.estimator) return "leave FitOptions::estimator null: the study sets it";
  if (std::string why = fit.Validate(); !why.empty()) return why;
  if (std::string why = first_level_problem(first_level); !why.empty()) return why;
  return wv.Validate();
}

std::vector<std::optional<FigureReport>> noise_figures_of(const io::SignalSet& set,
                                                          const std::vector<const FitResult*>& fits,
                                                          const std::vector<WaveletVariance>& wvs,
                                                          const std::vector<AllanDeviation>& allan, double alpha) {
  std::vector<std::optional<FigureReport>> out(fits.size());
  if (!set.freq_known) return out;
  gmwm::parallel_for(std::size_t{0}, fits.size(), [&](std::size_t k) {
    const FitResult& f = *fits[k];
    if (f.status == FitStatus::kFailed || f.theta.size() != f.model.num_parameters() || !f.theta.allFinite()) return;
    AllanOptions ao;
    ao.alpha = alpha;
    ReadoffOptions ro;
    ro.alpha = alpha;
    if (k < wvs.size() && wvs[k].estimator != "classical")
      out[k] = noise_figure_report_from_wv(wvs[k], set.freq, f.model, f.theta, &f.covariance, ro);
    else if (k < allan.size())
      out[k] = noise_figure_report(allan[k], f.model, f.theta, &f.covariance, ro);
    else
      out[k] = noise_figure_report(set.signals[k].values, set.freq, f.model, f.theta, &f.covariance, ao, ro);
  });
  return out;
}

FitStudy study_fit(const io::SignalSet& set, const FitStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  FitStudy study;
  study.model_spec = options.model.text();
  study.seed = options.fit.seed;
  study.omega = options.fit.omega;
  study.model = options.model.bind(ProcessContext{set.freq, set.freq_known});

  detail::ColumnWvs curves = detail::column_wvs_for_fit(set, options.wv, options.robust, options.fit.alpha);
  std::vector<WaveletVariance>& wvs = curves.wvs;
  study.wv_seconds = curves.wv_seconds;
  study.allan_seconds = curves.allan_seconds;
  detail::check_usable_wvs(set, wvs, true);
  for (const auto& w : wvs) check_model_fits_levels(study.model, w.levels());

  // The bootstrap Omega recomputes the same WV on simulated series.
  FitOptions fo = options.fit;
  if (fo.omega == OmegaKind::kBootstrap) detail::check_simulated_grid(set, "--omega bootstrap");
  const std::unique_ptr<WvEstimator> estimator = detail::draw_estimator(set, options.robust);
  if (estimator) fo.estimator = estimator.get();
  // Each column's fitted levels: every level, or those above the smoothed scales.
  const std::vector<detail::FittedLevels> levels = detail::fitted_levels(set, wvs, study.model, options.first_level);
  const std::vector<WaveletVariance> fitted = detail::fitted_wvs(wvs, levels);
  const auto fit_start = std::chrono::steady_clock::now();
  std::vector<FitResult> fits(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t k) {
    fits[k] = fit_gmwm(fitted[k], study.model, fo);
    detail::restore_levels(fits[k], wvs[k], levels[k]);
  });
  // A drift's sign is not in the WV: the series' own slope gives it.
  for (std::size_t k = 0; k < fits.size(); ++k)
    if (has_sign_from_series(fits[k])) orient_by_series(fits[k], set.signals[k].values);
  study.fit_seconds = seconds_since(fit_start);

  std::vector<const FitResult*> ptrs;
  for (const auto& f : fits) ptrs.push_back(&f);
  std::vector<std::optional<FigureReport>> figures = noise_figures_of(set, ptrs, wvs, curves.allan, options.fit.alpha);
  for (std::size_t k = 0; k < fits.size(); ++k)
    study.columns.push_back({set.signals[k].name, std::move(wvs[k]), std::move(fits[k]), std::move(figures[k]),
                             k < curves.classical.size() ? std::optional(curves.classical[k]) : std::nullopt,
                             levels[k].first, levels[k].reason});
  return study;
}

}  // namespace gmwm::pipeline
