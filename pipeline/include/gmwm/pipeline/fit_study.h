#pragma once
// The fit study of a signal set: one model fitted by GMWM to the (classical or robust) WV of
// every column, drifts oriented by the series' slope, and the noise figures (N, K, B) read
// off the data's and the model's Allan deviations. What `gmwm fit` and Python's gmwm.fit
// both run; report::fit_document writes it.
//
//   gmwm::pipeline::FitStudyOptions o;
//   o.model = "AR1+WN+RW";
//   const gmwm::pipeline::FitStudy s = gmwm::pipeline::study_fit(set, o);
//   // s.columns[k].fit.theta, s.columns[k].figures->chosen ...

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/first_level.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::pipeline {

struct FitStudyOptions {
  /// The model ("AR1+WN+RW": checked when assigned), bound at the data's rate.
  ModelSpec model;
  /// Omega, alpha, bootstrap replicates, seed, evaluation budget. Its `estimator` is set by
  /// the study (the robust WV's, for the bootstrap Omega) and must be left null.
  FitOptions fit;
  /// Levels and alpha of the classical WV.
  WvOptions wv;
  /// The robust WV instead of the classical one.
  std::optional<robust::RobustWvOptions> robust;
  /// The first level fitted (tau = 2^level samples): the finer ones are shown, not fitted
  /// (held or interpolated samples smooth them: repeated_samples.h). kAutoFirstLevel: each
  /// column's first_fit_level (repeated_samples.h), 1 where its samples do not repeat.
  int first_level = 1;

  /// Empty when valid, else what is wrong.
  std::string Validate() const;
};

struct FitColumnStudy {
  std::string name;
  WaveletVariance wv;
  FitResult fit;
  /// The data's and the model's Allan deviations and the figures chosen from them; absent
  /// without a known rate or a usable fit.
  std::optional<FigureReport> figures;
  /// With a robust `wv`: the classical WV of the same series, for comparison (not fitted).
  std::optional<WaveletVariance> classical;
  /// The first level fitted: `wv` holds every level, the fit took first_level.. (its
  /// implied_wv covers every level of `wv`, its misfits only the fitted ones).
  int first_level = 1;
  /// Why the finer levels were left out (empty when first_level is 1): one sentence.
  std::string first_level_reason;
};

struct FitStudy {
  std::string model_spec;
  std::uint64_t seed = 0;
  OmegaKind omega = OmegaKind::kDiag;
  Model model;
  std::vector<FitColumnStudy> columns;
  /// Stage times: the WV (its transforms included), the data's Allan deviation from the
  /// same transforms (0 without a known rate or with the robust WV), the fits.
  double wv_seconds = 0.0, allan_seconds = 0.0, fit_seconds = 0.0;
};

/// Runs the study on every column of `set`. Throws InputError for invalid options, a model
/// that does not parse, or one with more parameters than a column's WV has levels; a fit
/// that fails is reported in its FitResult (status kFailed), not thrown.
FitStudy study_fit(const io::SignalSet& set, const FitStudyOptions& options);

/// The noise figures of fitted columns (FitColumnStudy::figures), `fits[k]` on column k of
/// `set` with its WV `wvs[k]`: from the robust WV when the fit used one, else from the
/// data's Allan deviation `allan[k]` (computed from the series when `allan` is empty);
/// nothing without a known rate or for a failed fit. In parallel.
std::vector<std::optional<FigureReport>> noise_figures_of(const io::SignalSet& set,
                                                          const std::vector<const FitResult*>& fits,
                                                          const std::vector<WaveletVariance>& wvs,
                                                          const std::vector<AllanDeviation>& allan, double alpha);

}  // namespace gmwm::pipeline
