// The selection study as named stages: models -> wavelet variances and the data's Allan
// deviations (one transform per column) -> selection (drifts oriented) -> the best fits'
// noise figures.
#include "gmwm/pipeline/select_study.h"
#include "column_wvs.h"
#include "first_level.h"
#include "usable_wv.h"

#include <chrono>
#include <map>
#include <memory>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/selection/submodels.h"

namespace gmwm::pipeline {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void set_select_models(SelectStudyOptions& options, const std::string& model, const std::string& models) {
  const auto blank = [](const std::string& t) { return t.find_first_not_of(" \t") == std::string::npos; };
  if (blank(model) == blank(models))
    throw InputError("select: give either --model SPEC (every sub-model) or --models \"SPEC1;SPEC2;...\"");
  options.models.clear();
  options.listed = !blank(models);
  if (!options.listed) {
    options.models.emplace_back(model);
    return;
  }
  std::string cur;
  for (char ch : models + ";") {
    if (ch != ';') {
      cur += ch;
      continue;
    }
    if (blank(cur)) throw InputError("--models \"" + models + "\": empty model in the list");
    options.models.emplace_back(cur);
    cur.clear();
  }
}

std::string SelectStudyOptions::Validate() const {
  if (models.empty()) return "no model given";
  if (!listed && models.size() != 1) return "give one maximal model (or set listed for a list of models)";
  for (const ModelSpec& m : models)
    if (m.text().find_first_not_of(" \t") == std::string::npos) return "an empty model";
  if (select.estimator) return "leave SelectOptions::estimator null: the study sets it";
  if (std::string why = select.Validate(); !why.empty()) return why;
  if (std::string why = first_level_problem(first_level); !why.empty()) return why;
  return wv.Validate();
}

SelectStudy study_select(const io::SignalSet& set, const SelectStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  SelectStudy study;
  study.listed = options.listed;
  study.models = options.models;
  study.options = options.select;
  study.options.progress = nullptr;

  // The models at the data's rate, a list's each once (a repeated model was fitted again,
  // each copy warm-started from every copy of the models it covers: 900 entries of six
  // models took 4.5 s, 1800 took 17 s); a list is fitted under its common supermodel's Omega.
  const ProcessContext ctx{set.freq, set.freq_known};
  std::vector<Model> models;
  study.models.clear();
  std::map<std::string, std::size_t> first;  // a model's canonical form -> its first entry
  for (std::size_t i = 0; i < options.models.size(); ++i) {
    Model m = options.models[i].bind(ctx);
    if (study.listed) {
      const auto [at, fresh] = first.emplace(m.canonical().to_string(), i);
      if (!fresh) {
        study.duplicates.push_back("entry " + std::to_string(i + 1) + " '" + options.models[i].text() + "' is entry " +
                                   std::to_string(at->second + 1) + " '" + options.models[at->second].text() + "'");
        continue;
      }
    }
    models.push_back(std::move(m));
    study.models.push_back(options.models[i]);
  }
  const Model maximal = !study.listed ? models.front() : selection::common_supermodel(models);

  detail::ColumnWvs curves = detail::column_wvs_for_fit(set, options.wv, options.robust, options.select.fit.alpha);
  std::vector<WaveletVariance>& wvs = curves.wvs;
  study.wv_seconds = curves.wv_seconds;
  study.allan_seconds = curves.allan_seconds;
  detail::check_usable_wvs(set, wvs, true);
  for (const auto& w : wvs) check_model_fits_levels(maximal, w.levels());

  // Bootstrap draws get the data's WV estimator.
  selection::SelectOptions so = options.select;
  if (so.fit.omega == OmegaKind::kBootstrap) detail::check_simulated_grid(set, "--omega bootstrap");
  if (so.optimism != selection::OptimismMethod::kAnalytic) detail::check_simulated_grid(set, "the bootstrap optimism");
  const std::unique_ptr<WvEstimator> estimator = detail::draw_estimator(set, options.robust);
  if (estimator) so.estimator = estimator.get();
  // Each column's fitted levels: every level, or those above the smoothed scales.
  const std::vector<detail::FittedLevels> levels = detail::fitted_levels(set, wvs, maximal, options.first_level);
  const std::vector<WaveletVariance> fitted = detail::fitted_wvs(wvs, levels);
  const auto select_start = std::chrono::steady_clock::now();
  std::vector<selection::Selection> result =
      !study.listed ? selection::select_models(fitted, maximal, so) : selection::select_among(fitted, models, so);
  for (std::size_t k = 0; k < result.size(); ++k) detail::restore_levels(result[k].best_fit, wvs[k], levels[k]);
  // A drift's sign is not in the WV: the series' own slope gives it.
  for (std::size_t k = 0; k < result.size(); ++k)
    if (has_sign_from_series(result[k].best_fit)) orient_by_series(result[k].best_fit, set.signals[k].values);
  study.select_seconds = seconds_since(select_start);

  std::vector<const FitResult*> best;
  for (const auto& s : result) best.push_back(&s.best_fit);
  std::vector<std::optional<FigureReport>> figures =
      noise_figures_of(set, best, wvs, curves.allan, options.select.fit.alpha);
  for (std::size_t k = 0; k < result.size(); ++k)
    study.columns.push_back({set.signals[k].name, std::move(wvs[k]), std::move(result[k]), std::move(figures[k]),
                             k < curves.classical.size() ? std::optional(curves.classical[k]) : std::nullopt,
                             levels[k].first, levels[k].reason});
  return study;
}

}  // namespace gmwm::pipeline
