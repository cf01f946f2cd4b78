#pragma once
// The selection study of a signal set: every sub-model of a maximal model (or the models of
// a list, fitted under their common supermodel's Omega) ranked by WVIC or BIC on each
// column's (classical or robust) WV, the best fit's drift oriented by the series' slope,
// and its noise figures. What `gmwm select` and Python's gmwm.select both run;
// report::select_document writes it.
//
//   gmwm::pipeline::SelectStudyOptions o;
//   o.models = {"3*AR1+WN+RW+QN+DR"};
//   const gmwm::pipeline::SelectStudy s = gmwm::pipeline::study_select(set, o);
//   // s.columns[k].selection.best_model ...

#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/first_level.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/selection/select.h"

namespace gmwm::pipeline {

struct SelectStudyOptions {
  /// One maximal model (every sub-model is ranked), or, `listed`, the models to rank as
  /// given.
  std::vector<ModelSpec> models;
  bool listed = false;
  /// Optimism, Omega, penalty, replicates, seed, the fits' options, progress. Its
  /// `estimator` is set by the study (the robust WV's) and must be left null.
  selection::SelectOptions select;
  /// Levels and alpha of the classical WV.
  WvOptions wv;
  /// The robust WV instead of the classical one.
  std::optional<robust::RobustWvOptions> robust;
  /// The first level every model is fitted from (first_level.h; FitStudyOptions::first_level).
  int first_level = 1;

  /// Empty when valid, else what is wrong.
  std::string Validate() const;
};

struct SelectColumnStudy {
  std::string name;
  WaveletVariance wv;
  selection::Selection selection;
  /// The best fit's noise figures; absent without a known rate or a usable fit.
  std::optional<FigureReport> figures;
  /// With a robust `wv`: the classical WV of the same series, for comparison (not fitted).
  std::optional<WaveletVariance> classical;
  /// The first level fitted: `wv` holds every level, the models took first_level.. (the
  /// best fit's implied_wv covers every level of `wv`).
  int first_level = 1;
  /// Why the finer levels were left out (empty when first_level is 1): one sentence.
  std::string first_level_reason;
};

struct SelectStudy {
  /// False when every sub-model of models[0] was ranked; true for a list.
  bool listed = false;
  /// The models ranked: the maximal model, or the list's models each once (in the list's
  /// order, the first entry of each model kept).
  std::vector<ModelSpec> models;
  /// A list's entries that repeat an earlier entry's model (the same components in any
  /// order: "RW+WN" is "WN+RW") and were dropped, one line each ("entry 7 'RW+WN' is entry 1
  /// 'WN+RW'"); for the caller to say. Each model is fitted and ranked once.
  std::vector<std::string> duplicates;
  selection::SelectOptions options;  // as run (without the estimator and progress)
  std::vector<SelectColumnStudy> columns;
  /// Stage times: the WV, the data's Allan deviation from the same transforms (0 without a
  /// known rate or with the robust WV), the selection.
  double wv_seconds = 0.0, allan_seconds = 0.0, select_seconds = 0.0;
};

/// The models a request names, the one rule of every face (issue 45: the ';' split was the
/// CLI's alone): `model`, whose every sub-model is ranked, or `models`, a list "SPEC1;SPEC2;..."
/// split at ';' and ranked as given; exactly one of the two. Sets options.models and
/// options.listed. Throws InputError naming --model / --models (each face says them in its
/// own words, io::option_wording) for neither or both, or an empty entry of the list.
void set_select_models(SelectStudyOptions& options, const std::string& model, const std::string& models);

/// Runs the study on every column of `set`. Throws InputError for invalid options, a model
/// that does not parse, a list of more than selection::kMaxListedModels distinct models, or
/// a maximal model with more parameters than a column's WV has levels.
SelectStudy study_select(const io::SignalSet& set, const SelectStudyOptions& options);

}  // namespace gmwm::pipeline
