#pragma once
// The noise figures consumers read (IEEE Std 952-1997, Annex C): the white noise density
// N, the random walk K, the bias instability B, the quantization noise Q and the rate ramp
// R, read off an Allan deviation curve, the data's or a fitted model's as a whole.
//
//   N: on the slope -1/2 (ADEV = N / sqrt(tau)), N = ADEV(1 s) on that line;
//   K: on the slope +1/2 (ADEV = K sqrt(tau / 3)), K = ADEV(3 s) on that line;
//   B: at the flat minimum, B = min ADEV / sqrt(2 ln 2 / pi) = min ADEV / 0.664;
//   Q: on the slope -1 (ADEV = sqrt(3) Q / tau), Q = ADEV(sqrt(3) s) on that line;
//   R: on the slope +1 (ADEV = R tau / sqrt(2)), R = ADEV(sqrt(2) s) on that line.
//
// A slope region is a run of (at least two) points whose local log-log slope (least
// squares over one octave) is within `slope_tolerance` of the slope's value, among the
// points with at least `min_edf` equivalent degrees of freedom; the figure is read at the
// region's point nearest the IEEE tau (status kRead when the region spans that tau, else
// kExtrapolated along the line). N is read on the longest -1/2 region, K on the +1/2 one
// nearest 3 s; Q only on a -1 region starting at the curve's first point and R only on a
// +1 region ending at its last (quantization shows at the shortest taus, a ramp at the
// longest: a -1 fall after a bump, or a +1 rise before one, is a tone or a correlated
// term). Without such a region the curve still bounds the figure (kBound): a white
// noise's ADEV N / sqrt(tau) never exceeds the total, so N <= min_tau ADEV(tau) sqrt(tau),
// and likewise K <= min ADEV(tau) sqrt(3 / tau), Q <= min ADEV(tau) tau / sqrt(3),
// R <= min ADEV(tau) sqrt(2) / tau. B is not read when the curve has no interior minimum
// (still falling at its last usable point: B <= that value / 0.664).
//
// For a model the read-offs use its implied curve on the data's grid (so that both read
// at the same taus); a fast AR1 then adds to N and a slow one to B, whatever the
// components are called. `sources` names the components making up the curve where each
// figure was read. One rule for every command (docs/noise-figures.md): a figure is read
// where the data show it, and the model's value there is used only where its Allan
// deviation agrees with the data's at that same tau (noise_figure_report).
//
//   const auto data = gmwm::read_noise_figures(gmwm::allan_deviation(x, f));
//   const auto model = gmwm::model_noise_figures(fit.model, fit.theta, adev, &fit.covariance);

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/kalman.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

enum class ReadoffStatus {
  kRead,          ///< on its slope, in a region holding the IEEE tau
  kExtrapolated,  ///< on its slope's line, from the region's point nearest the IEEE tau
  kBound,         ///< no such slope (or no minimum): an upper bound from the curve
};
const char* to_string(ReadoffStatus s);
/// The inverse of to_string (nullopt for any other name).
std::optional<ReadoffStatus> parse_readoff_status(const std::string& name);

struct Readoff {
  double value = NAN;            ///< in the data's unit pattern (N: U/sqrt(Hz), K: U/s/sqrt(Hz), B: U, Q: U*s, R: U/s)
  double low = NAN, high = NAN;  ///< interval at 1 - alpha (NaN when unknown; a bound has low NaN)
  ReadoffStatus status = ReadoffStatus::kBound;
  double tau = NAN;                           ///< where it was read, in seconds
  double region_from = NAN, region_to = NAN;  ///< the slope region (flat region for B), seconds
  std::string how;                            ///< one line, e.g. "on the -1/2 slope over 0.08-20 s, at 1 s"
  /// Model read-offs: the components making up the Allan variance at tau, with their share.
  std::vector<std::pair<std::string, double>> sources;
  /// N only: a bump (a tone, a fast correlated term) that lifts the curve above the white
  /// floor's -1/2 line near the IEEE tau, one line ("" when none); a model's names the
  /// component making it. It is not counted in N, and the figure's note says so.
  std::string bends;
  bool available() const { return std::isfinite(value); }
};

/// The figures in the order every face shows them, with their symbol, JSON key, name and
/// unit pattern (physical.h: "U" is the data's unit; a gyro in deg/s has Q in deg, the
/// angle quantum, and R in deg/s^2).
struct FigureName {
  char symbol;               ///< 'N'
  const char* key;           ///< the JSON key: "white"
  const char* name;          ///< "white noise"
  const char* unit_pattern;  ///< "U/sqrt(Hz)"
};
inline constexpr int kFigureCount = 5;
inline constexpr FigureName kFigureNames[kFigureCount] = {
    {'N', "white", "white noise", "U/sqrt(Hz)"},
    {'K', "walk", "random walk", "U/s/sqrt(Hz)"},
    {'B', "instability", "bias instability", "U"},
    {'Q', "quantization", "quantization noise", "U*s"},
    {'R', "ramp", "rate ramp", "U/s"},
};

struct NoiseFigures {
  Readoff white;         ///< N: white noise density (angle / velocity random walk), U/sqrt(Hz)
  Readoff walk;          ///< K: random walk (rate / acceleration random walk), U/s/sqrt(Hz)
  Readoff instability;   ///< B: bias instability, U
  Readoff quantization;  ///< Q: quantization noise, U*s (a gyro in deg/s: deg, the angle quantum)
  Readoff ramp;          ///< R: rate ramp, U/s (a gyro in deg/s: deg/s^2)
  /// The figure k in kFigureNames' order (N, K, B, Q, R).
  const Readoff& operator[](int k) const { return *std::array{&white, &walk, &instability, &quantization, &ramp}[k]; }
  Readoff& operator[](int k) { return *std::array{&white, &walk, &instability, &quantization, &ramp}[k]; }
};

/// sqrt(2 ln 2 / pi): the flat part of a flicker-floor ADEV in units of B (IEEE 952 C.1).
inline constexpr double kBiasInstabilityFactor = 0.6642824702679600;

struct ReadoffOptions {
  /// How far a point's local slope may be from -1/2, +1/2 or 0 and still be on it: the
  /// tolerance an engineer's ruler allows (a white noise plus a tenth of a flicker floor
  /// at the same tau bends the slope by ~0.05).
  double slope_tolerance = 0.1;
  /// Points with fewer equivalent degrees of freedom decide nothing: their ADEV is
  /// uncertain by a factor ~2 or more (chi-square with 4 df: 95% interval 0.35-1.5).
  double min_edf = 4.0;
  double alpha = 0.05;
  std::string Validate() const;
};

/// The read-offs of the data's own Allan deviation, with intervals from its chi-square
/// ones. Throws InputError for invalid options.
NoiseFigures read_noise_figures(const AllanDeviation& adev, const ReadoffOptions& options = {});

/// The read-offs of the model's Allan deviation on `grid`'s averaging factors and usable
/// points; intervals by the delta method when `covariance` (of theta) is given and finite;
/// `sources` per figure. With `at` (the data's read-offs on the same grid), each figure the
/// data show is read on the model's curve at the data's read point instead (a figure is
/// read where the data show it); the others on the model's own curve. Throws InputError
/// for invalid options.
NoiseFigures model_noise_figures(const Model& model, const Eigen::VectorXd& theta, const AllanDeviation& grid,
                                 const Eigen::MatrixXd* covariance, const ReadoffOptions& options = {},
                                 const NoiseFigures* at = nullptr);

/// Where a figure to use comes from (choose_noise_figures).
enum class FigureSource {
  kModel,  ///< the model's read-off: the model matches the data's Allan deviation there
  kData,   ///< the data's read-off: the model misses the data where the figure is read
  kBound,  ///< neither shows the slope: the smaller upper bound
};
const char* to_string(FigureSource s);
/// The inverse of to_string (nullopt for any other name).
std::optional<FigureSource> parse_figure_source(const std::string& name);

struct ChosenFigure {
  Readoff figure;  ///< the value to use (and where it was read)
  FigureSource source = FigureSource::kBound;
  std::string note;     ///< one line: why this one
  Readoff model, data;  ///< both read-offs, as they are
};

struct ChosenFigures {
  ChosenFigure white, walk, instability, quantization, ramp;
  /// The figure k in kFigureNames' order (N, K, B, Q, R).
  const ChosenFigure& operator[](int k) const {
    return *std::array{&white, &walk, &instability, &quantization, &ramp}[k];
  }
  ChosenFigure& operator[](int k) { return *std::array{&white, &walk, &instability, &quantization, &ramp}[k]; }
};

/// The figures to put in a filter: the model's read-off where the model's Allan deviation
/// lies inside the data's interval at the tau the data's figure is read (or the data show
/// no such slope, and the model's figure stays below the data's bound); else the data's
/// read-off, saying by how much the model misses. A figure neither curve shows is the
/// smaller of the two upper bounds. model_adev: the model's curve on data_adev's grid;
/// `model` read at the data's read points (model_noise_figures with `at` = &data), so that
/// the model's value is the one checked.
ChosenFigures choose_noise_figures(const NoiseFigures& model, const NoiseFigures& data, const AllanDeviation& data_adev,
                                   std::span<const double> model_adev, const ReadoffOptions& options = {});

/// A first-order Gauss-Markov process's Allan deviation peaks at 0.6174 sigma at
/// tau = 1.8926 T (the maximum of (2x - 3 + 4e^-x - e^-2x) / x^2, x = tau / T; IEEE 952
/// Annex C, the Markov noise term).
inline constexpr double kGaussMarkovPeakTau = 1.8926;
inline constexpr double kGaussMarkovPeakAdev = 0.61736;

/// The Kalman-filter terms of the figures at filter_rate Hz (kalman.h conventions):
/// white measurement noise R = N^2 f_k from N; a bias random-walk state Q_d = K^2 / f_k
/// from K; when B was read at an interior minimum tau_B, a Gauss-Markov bias state
/// whose Allan deviation peaks there at the flat level 0.664 B (T = tau_B / 1.8926,
/// sigma = 0.664 B / 0.6174), an approximation of a flicker floor; and, when Q was read (not
/// a bound), the quantization's measurement noise R = 2 Q^2 f_k^2 (the rate averaged over
/// 1 / f_k: the difference of two roundings of the integral, QN's own term). R (the rate
/// ramp) gives none: a ramp is deterministic over the record, no process noise (a filter that
/// follows it carries a drift-rate state, DR's own Kalman term). Each term's note says where
/// its figure came from.
std::vector<KalmanTerm> kalman_terms(const ChosenFigures& figures, double filter_rate);

/// Everything about one column's noise figures: the data's Allan deviation, the model's
/// on the same grid, both read-offs and the figures to use.
struct FigureReport {
  AllanDeviation adev;
  std::vector<double> model_adev;
  NoiseFigures data, model;
  ChosenFigures chosen;
};

/// The noise-figure report of series x (freq Hz) and its fitted (model, theta), with the
/// fit's covariance for the model's intervals (nullptr or empty: none).
FigureReport noise_figure_report(std::span<const double> x, double freq, const Model& model,
                                 const Eigen::VectorXd& theta, const Eigen::MatrixXd* covariance,
                                 const AllanOptions& allan = {}, const ReadoffOptions& readoff = {});

/// The same from the data's Allan deviation already computed (allan_deviation of the
/// series' transforms, shared with its WV).
FigureReport noise_figure_report(AllanDeviation adev, const Model& model, const Eigen::VectorXd& theta,
                                 const Eigen::MatrixXd* covariance, const ReadoffOptions& readoff = {});

/// As noise_figure_report, with the data's Allan deviation taken from a WV (octave
/// points: AVAR(m = tau_j / 2) = 2 nu_j^2, its interval from the WV's): for a robust WV,
/// whose ADEV is the one to trust on contaminated data (the classical one carries the
/// contamination).
FigureReport noise_figure_report_from_wv(const WaveletVariance& wv, double freq, const Model& model,
                                         const Eigen::VectorXd& theta, const Eigen::MatrixXd* covariance,
                                         const ReadoffOptions& readoff = {});

/// The data's figures alone (no model; model_adev empty): each figure the data's read-off
/// (source kData) or its bound (kBound).
FigureReport data_figure_report(std::span<const double> x, double freq, const AllanOptions& allan = {},
                                const ReadoffOptions& readoff = {});
/// The same from the data's Allan deviation already computed.
FigureReport data_figure_report(AllanDeviation adev, const ReadoffOptions& readoff = {});

/// The model's figures alone, on the averaging factors of a record of n samples at freq
/// (when the data are not at hand, e.g. exporting a saved fit, or when several recordings
/// share the model): each figure from the model (source kModel) or its bound (kBound),
/// with delta-method intervals when `covariance` (of theta) is given; `why` is the notes'
/// reason for reading the model alone.
ChosenFigures model_only_figures(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                 const ReadoffOptions& readoff = {}, const Eigen::MatrixXd* covariance = nullptr,
                                 const std::string& why = "the model's Allan deviation (the data were not at hand)");

}  // namespace gmwm
