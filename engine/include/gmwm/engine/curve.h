#pragma once
// A model fitted to a given curve instead of raw data (docs/curve-fit.md): an Allan
// deviation or variance, or a Haar wavelet variance, at averaging times in seconds, with or
// without each point's interval or equivalent degrees of freedom: digitised from a
// datasheet, exported by another tool (allantools, Stable32) or by `gmwm wv --adev-csv`.
//
// The curve becomes the WaveletVariance the GMWM estimator takes (curve_wv): at a sampling
// rate f an averaging time T is m = T f samples and AVAR(T) = 2 nu^2(2m) (statistics.md
// section 1); a WV's scale tau (s, the Haar filter's width as `gmwm wv` writes it) is
// tau f samples. m need not be whole: the processes continue their closed forms between
// whole scales (process.h). Each point's precision is a chi-square with eta degrees of
// freedom, eta from the given edf, else from the given interval (the eta whose chi-square
// interval at the given confidence has the interval's ratio high / low), else from the
// record's length (the engine's own eta = max((N - 2m + 1) / (2m), 1), statistics.md
// section 1), else from the shortest record that reaches the curve's longest averaging time
// (N = twice it, where every tool's grid stops): its points' relative weights are any
// record's, and its intervals, the widest any record gives, bound the real ones from above.
//
//   gmwm::GivenCurve c;  // tau, value (and low, high or edf)
//   c.quantity = gmwm::CurveQuantity::kAdev;
//   const double f = gmwm::curve_rate(c);
//   gmwm::CurveFitOptions o;
//   const gmwm::WaveletVariance wv = gmwm::curve_wv(c, f, o);
//   const gmwm::FitResult r = gmwm::fit_curve(wv, model, o);
//
// Limits: without the data there is no bootstrap and no goodness-of-fit test (the points'
// correlation across taus is unknown: the fit's p-value is null); the points are taken as
// independent, so the parameters' intervals of a dense curve (many points an octave, whose
// overlapping estimates are correlated) are too narrow.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

/// What a curve's values are: the Allan deviation (squared to the variance), the Allan
/// variance, or the Haar wavelet variance nu^2.
enum class CurveQuantity { kAdev, kAvar, kWv };
/// "adev", "avar", "wv".
const char* to_string(CurveQuantity q);
std::optional<CurveQuantity> parse_curve_quantity(const std::string& name);
/// The names parse_curve_quantity takes: adev, avar, wv (choice.h).
std::vector<std::string> curve_quantity_names();

/// Where a curve's precision (its weights and the parameters' intervals) comes from.
enum class CurveWeights {
  kEdf,        ///< each point's equivalent degrees of freedom, as given
  kIntervals,  ///< each point's interval, as given (at CurveFitOptions::confidence)
  kRecord,     ///< the record's length (CurveFitOptions::record_seconds): the engine's eta
  /// nothing: the engine's eta of the shortest record reaching the longest averaging time
  /// (twice it): any record's relative weights, intervals as wide as any record's can be
  kShortestRecord,
};
/// "edf", "intervals", "record", "shortest-record".
const char* to_string(CurveWeights w);

/// One column of a curve as given: its name and, in a file, its 1-based column (0: none).
struct CurveField {
  std::string name;
  int column = 0;
};

/// A curve as given. tau, value, and low/high or edf when present, one entry per point.
struct GivenCurve {
  std::string name;    ///< the curve's name (a file's `column` field, else its value column's)
  std::string source;  ///< the file it was read from, or what the caller names it ("curve")
  CurveQuantity quantity = CurveQuantity::kAdev;
  std::vector<double> tau;        ///< s: the averaging time (adev, avar) or the Haar scale (wv)
  std::vector<double> value;      ///< adev: a deviation; avar, wv: a variance (the data's unit)
  std::vector<double> low, high;  ///< the value's interval, the same quantity (empty: none)
  std::vector<double> edf;        ///< each point's equivalent degrees of freedom (empty: none)
  /// Each point's line in its file (empty: not from a file; messages then name "field[k]").
  std::vector<std::int64_t> line;
  CurveField tau_field{"tau"}, value_field{"value"}, low_field{"low"}, high_field{"high"}, edf_field{"edf"};
  std::size_t size() const { return tau.size(); }
};

/// Where point k's `field` is, for a message: "FILE:LINE:COLUMN: " from a file, else
/// "SOURCE: NAME[k]: " (k 0-based, as the caller's arrays are).
std::string curve_place(const GivenCurve& curve, std::size_t k, const CurveField& field);

/// The first thing that makes the curve unusable, as one line naming where it is and what
/// was expected; empty when it is usable. Refused: fields of different lengths, no point,
/// a tau or value that is not finite and positive, taus that do not increase (a repeated tau
/// named with the line it repeats), a variance outside [kMinFittableWv, kMaxFittableWv], an
/// interval given on one side only, not finite, below 0, without width or not holding its
/// value, an edf not above 0 or beyond kMaxCurveEdf.
std::string curve_problem(const GivenCurve& curve);

/// A whole number of samples m within this relative distance of one is that number: the
/// taus of a table printed to 6 significant digits (Stable32's) miss it by up to 5e-7.
inline constexpr double kWholeScaleTolerance = 1e-6;
/// The finest tau in samples when a curve's taus are no whole multiples of it and no rate is
/// given: the averaging times are then whole to within 0.5% where the noise figures read the
/// model's Allan deviation (at whole averaging factors, noise_figures.h), and that moves a
/// white noise's deviation by at most 0.25%, below a digitised curve's reading error.
inline constexpr double kDigitisedFinestSamples = 100.0;
/// The edf an interval gives is kept within [kMinCurveEdf, kMaxCurveEdf]: 1 is the engine's
/// own floor (statistics.md section 1; an interval reaching 0, such as allantools' +-1 sigma
/// with one term, or wider than 1 degree's); 1e12 is beyond any record (the finest level of
/// 2^40 samples has 5e11), an interval of no visible width.
inline constexpr double kMinCurveEdf = 1.0;
inline constexpr double kMaxCurveEdf = 1e12;

/// The rate a curve is read at when none is given: the one at which its finest tau is one
/// sample (adev, avar: m = 1; wv: tau = 2 samples), when every tau is then a whole number
/// of samples (kWholeScaleTolerance); else kDigitisedFinestSamples times that.
double curve_rate(const GivenCurve& curve);

struct CurveFitOptions {
  /// The length in seconds of the record behind the curve (0: unknown, the shortest that
  /// reaches its longest averaging time): the points' eta when the curve gives neither edf
  /// nor intervals.
  double record_seconds = 0.0;
  /// The level of the given intervals (allantools' and Stable32's +-1 sigma bars: 0.683).
  double confidence = 0.95;
  /// kModel (default): diag(eta_k / (2 nu_k^4)) at a pilot fit weighed by the curve's own
  /// values; kDiag: the curve's own values' weights (1 / Var(nuhat_k^2)). No other.
  OmegaKind omega = OmegaKind::kModel;
  /// alpha (the parameters' intervals), max_evaluations, multistarts; its omega,
  /// omega_matrix, starts and inference are the curve fit's own.
  FitOptions fit;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// The curve as the WV the estimator takes at `freq` Hz (curve_problem checked first): per
/// point the scale tau = 2m samples, nu^2 (adev^2 / 2, avar / 2 or wv), its interval (the
/// given one converted, else the chi-square one at options.fit.alpha), eta and Var(nuhat^2) =
/// 2 nu^4 / eta, coefficients 0, estimator "curve", n the record's samples (record_seconds f,
/// else the shortest record's: twice the longest averaging time). `weights`
/// (when given) receives where eta came from. Throws InputError for an unusable curve, a tau
/// below one sample (two for a WV) at freq, a record shorter than the longest averaging
/// window, or invalid options.
WaveletVariance curve_wv(const GivenCurve& curve, double freq, const CurveFitOptions& options,
                         CurveWeights* weights = nullptr);

/// The eta of a chi-square whose interval at `confidence` has the ratio high / low (low may
/// be 0: kMinCurveEdf), within [kMinCurveEdf, kMaxCurveEdf]. Throws InvalidArgument unless
/// 0 <= low < high and 0 < confidence < 1.
double interval_edf(double low, double high, double confidence);

/// The GMWM fit of `model` to a curve's WV (curve_wv's, points left out already removed): a
/// pilot weighed by the curve's own values (diag(eta / (2 nuhat^4)), each nuhat^2 guarded as
/// diagonal_omega guards a record's levels), then with options.omega kModel the refit under
/// diag(eta / (2 nu^4)) at the pilot; the inference (sandwich, delta-method intervals) with
/// Var(nuhat_k^2) = 2 nu_k^4(theta_hat) / eta_k. The goodness of fit has no p-value (its
/// method says why). Throws InputError for invalid options or a model
/// with more parameters than the WV has points.
FitResult fit_curve(const WaveletVariance& wv, const Model& model, const CurveFitOptions& options);

/// The model's Allan variance 2 nu^2(theta; 2 T f) at averaging times T (s) at freq Hz, T f
/// >= 1 samples, whole or not (a process that needs_whole_scales() needs whole ones).
std::vector<double> model_allan_variance(const Model& model, const Eigen::VectorXd& theta,
                                         std::span<const double> tau_seconds, double freq);

/// A curve's WV (curve_wv's, at wv.n samples and freq Hz) as the data's Allan deviation the
/// noise figures read (noise_figures.h), on the points `keep` marks (all when empty): tau =
/// the averaging time, m its whole number of samples nearest (at least 1), the deviation
/// and its interval from the WV's, edf eta.
AllanDeviation curve_allan_deviation(const WaveletVariance& wv, double freq, const std::vector<bool>& keep = {});

}  // namespace gmwm
