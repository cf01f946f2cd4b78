#pragma once
// Samples that do not measure anew (issue 47 item 2): a driver that fills a faster stream
// by copying the last sample (held samples) or by joining two samples with a straight line
// (interpolated samples), as RealSense's unite_imu_method does when it puts a 200 Hz
// accelerometer on a 400 Hz gyroscope's stamps. Both leave the long scales alone and
// smooth the fine ones: the Haar WV of white noise held or interpolated p-fold falls short
// of the measured one by about c p / tau at scale tau samples (c = 0.75 held, 1.1
// interpolated), so a fit that weighs the fine scales reads N too low.
//
// Held samples: a step x_t - x_{t-1} of exactly zero. Rounding to a quantum q makes some
// of those on its own; with the steps' continuous part Gaussian of sd s (in quanta) and the
// rounding errors uniform, a step of k quanta has probability
//   P_k(s) = G(k + 1) - 2 G(k) + G(k - 1),  G(x) = x Phi(x / s) + s phi(x / s)
// (the Gaussian smoothed by the triangle of two rounding errors). s is read from the steps
// of one quantum among the non-zero ones (P_1 / (1 - P_0), which held samples leave
// alone), and the held share is the zero steps beyond P_0: h = (z - P_0) / (1 - P_0).
//
// Interpolated samples: a sample that is an exact linear combination of its neighbours.
// Three samples on one straight segment (linear interpolation by more than 2x) have a
// second difference of exactly zero; below 3x a sample is a fixed combination of its four
// nearest neighbours in every P-th position (the pattern's period: 2 for 200 -> 400 Hz,
// 8 for 250 -> 400 Hz), found by least squares per position within blocks of the record.
// A combination that holds in every position at period 1 is a smooth signal, not an
// interpolation (a sensor filtered far below its rate), and is not claimed.

#include <cstdint>
#include <string>

#include "gmwm/engine/wavelet_variance.h"

#include "gmwm/engine/quantization.h"

namespace gmwm {

struct RepeatedSamples {
  /// Held: the share of samples that copy the one before beyond what rounding explains
  /// (zero steps observed, and expected from rounding alone).
  double held_share = 0.0;
  double zero_step_share = 0.0;
  double expected_zero_step_share = 0.0;
  /// Interpolated: the share of samples that are an exact linear combination of their
  /// neighbours (held ones apart), and the period of their pattern (0: none; 1: three on
  /// a line, no fixed period).
  double interpolated_share = 0.0;
  int period = 0;
  /// Where: the first and last 0-based samples of the stretches found held or interpolated.
  std::int64_t first = 0;
  std::int64_t last = 0;
  /// The samples per measured sample at most (p above): what the fine scales' bias follows.
  double samples_per_measurement = 1.0;
  /// The finest Haar level (tau = 2^level samples) whose WV of white noise the repetition
  /// biases by less than kAffectedWvBias; 1 when nothing was found.
  int first_clean_level = 1;

  bool held() const { return held_share >= kMinRepeatedShare + kRoundingModelError * expected_zero_step_share; }
  bool interpolated() const { return interpolated_share >= kMinRepeatedShare; }
  bool detected() const { return held() || interpolated(); }

  /// A share claimed only from 5% of the samples, and held samples only beyond the rounding
  /// model's error besides: kRoundingModelError of the zero steps it explains. On the three
  /// ADIS16405 units, whose accelerometer noise is about one quantum (0.25-0.37 of their steps
  /// are zero), the observed zero steps exceed P_0 by up to 0.032, 0.093 of P_0; 0.25 leaves
  /// 2.7x (RepeatedSamplesReading.NoColumnOfTheShippedRecordingsIsHeldOrInterpolated).
  static constexpr double kMinRepeatedShare = 0.05;
  static constexpr double kRoundingModelError = 0.25;
  /// The fine scales are "affected" while white noise's WV departs by more than 5% (2.5% of
  /// a deviation) from the measured one's.
  static constexpr double kAffectedWvBias = 0.05;
  /// A fit's first level leaves a bias of at most this share of the level's own standard
  /// error sqrt(2 / eta_j): the fitted white noise, weighted mostly to its first two levels,
  /// then moves by about 0.24 of its own standard error, and a 95% interval covers at least
  /// 94% (Phi(1.96 - 0.24) - Phi(-1.96 - 0.24)). kAffectedWvBias alone left N 3% low with
  /// an interval of +-1.1% at 2^17 samples (tests/engine/first_level_test.cc).
  static constexpr double kFitBiasOfStandardError = 0.25;
};

/// Held and interpolated samples in x (n values, in time order), read against the values'
/// own rounding (detect_quantization). The shares come from 16 blocks of 2048 samples spread
/// over a longer record, where they are from the record.
RepeatedSamples detect_repeated_samples(const double* x, std::int64_t n);

/// The relative shortfall 1 - nu_held^2 / nu^2 of the Haar WV at scale tau (samples) of
/// white noise held (interpolated = false) or linearly interpolated p-fold (p >= 1, whole),
/// averaged over the p phases: the exact filter sum, O(p tau).
double repetition_wv_shortfall(int p, std::int64_t tau, bool interpolated);

/// The first level a fit of `wv` (the WV of the series r was read from) takes: 1 when
/// nothing repeats, else the finest level from r.first_clean_level on whose white-noise
/// shortfall is within kFitBiasOfStandardError of its standard error sqrt(2 / eta_j); the
/// WV's last level when none is.
int first_fit_level(const RepeatedSamples& r, const WaveletVariance& wv);

/// "accel_x: 50% of the samples copy the one before (held; 200 of 400 Hz measured), from
/// sample 0 to 65535: the WV below tau = 16 samples is smoothed (levels 1-3)"; "" when
/// nothing was found. `name` is the column, `freq` the rate (0: unknown, scales in samples).
std::string repeated_samples_text(const RepeatedSamples& r, const std::string& name, double freq);

}  // namespace gmwm
