#pragma once
// The curve fit study: one model fitted by GMWM to each given Allan-deviation, Allan-variance
// or wavelet-variance curve (engine/curve.h, docs/curve-fit.md), the taus of --exclude-taus
// left out, and the noise figures (N, K, B) read off the curve and the model. What `gmwm fit
// --curve` and Python's gmwm.fit_curve both run; report::curve_fit_document writes it.
//
//   const std::vector<gmwm::GivenCurve> curves = gmwm::io::read_curves("adev.csv", {});
//   gmwm::pipeline::CurveFitStudyOptions o;
//   o.model = "WN+RW+AR1";
//   const gmwm::pipeline::CurveFitStudy s = gmwm::pipeline::study_curve_fit(curves, o);
//   // s.columns[k].fit.theta, s.columns[k].figures->chosen ...

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/curve.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::pipeline {

/// A range of taus in seconds, both ends included.
struct TauRange {
  double from = 0.0;
  double to = std::numeric_limits<double>::infinity();
  bool holds(double tau) const { return tau >= from && tau <= to; }
};

/// --exclude-taus: comma-separated ranges of taus in seconds, "A:B" (an end left empty is
/// open: ":0.05", "100:") or one tau "T". InputError naming `option` ("found '1:x', expected
/// ...") for anything else, a negative or non-finite end, or an end below the start.
std::vector<TauRange> parse_tau_ranges(const std::string& text, const std::string& option = "--exclude-taus");

/// The ranges as --exclude-taus writes them ("0:0.05,100:"), for the documents.
std::string tau_ranges_text(const std::vector<TauRange>& ranges);

struct CurveFitStudyOptions {
  /// The model ("WN+RW+AR1": checked when assigned), bound at each curve's rate.
  ModelSpec model;
  /// The rate (Hz) of the data behind the curves, which the parameters are per sample at;
  /// nullopt: each curve's own (curve_rate: its finest tau one sample).
  std::optional<double> freq;
  /// Taus (the curve's own, in seconds) left out of the fit and of the data's read-offs.
  std::vector<TauRange> exclude;
  /// The weights' settings: record_seconds, confidence, omega (model or diag) and the fit's
  /// alpha, max_evaluations and seed.
  CurveFitOptions fit;
  /// Empty when valid, else what is wrong.
  std::string Validate() const;
};

struct CurveFitColumn {
  GivenCurve curve;          ///< as given
  WaveletVariance wv;        ///< every point as a WV at `freq` (curve_wv)
  std::vector<bool> fitted;  ///< per point: not left out by --exclude-taus
  CurveWeights weights = CurveWeights::kShortestRecord;
  double freq = 1.0;          ///< Hz: given, or the curve's own (curve_rate)
  bool whole_samples = true;  ///< every tau a whole number of samples at freq
  /// The fit of the fitted points, its implied_wv at every point and its misfits' levels
  /// the points' (1-based, counting the points left out).
  FitResult fit;
  /// The curve's and the model's Allan deviations on the fitted points and the figures
  /// chosen from them; absent for a failed fit.
  std::optional<FigureReport> figures;
};

struct CurveFitStudy {
  std::string model_spec;
  std::uint64_t seed = 0;
  OmegaKind omega = OmegaKind::kModel;
  bool freq_given = false;
  std::vector<TauRange> exclude;
  double confidence = 0.95;     ///< of the given intervals
  double record_seconds = 0.0;  ///< as given (0: none)
  std::vector<CurveFitColumn> columns;
  double fit_seconds = 0.0;
};

/// Runs the study on every curve. Throws InputError (one line naming the curve's file and
/// line where it applies) for invalid options, an unusable curve (engine curve_problem), a
/// tau below one sample at the rate, fewer points fitted than the model has parameters, a
/// process that needs whole scales (ARMA) on taus that are not whole numbers of samples; a
/// fit that fails is reported in its FitResult (status kFailed), not thrown.
CurveFitStudy study_curve_fit(const std::vector<GivenCurve>& curves, const CurveFitStudyOptions& options);

}  // namespace gmwm::pipeline
