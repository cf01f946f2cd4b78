#pragma once
// Small-sample bias correction of the robust scale estimate of one wavelet level
// (internal to robust/; docs/statistics.md section 2 "Small samples").
//
// The root s of mean chi(W_t^2 / s) = a(c) is Fisher-consistent (a(c)) but, with M
// strongly correlated coefficients, biased at order 1 / eta: +0.98 / n on n i.i.d.
// Gaussian coefficients at Huber eff 0.6, +0.35 / eta on white-noise wavelet levels
// (eta = M / tau; 4000 replicates, levels 7-10 of N = 24000; the estimate below averages
// +0.35 / eta there too, and +0.93 / n on 46 i.i.d. values).
// A second-order expansion of the estimating equation around the truth gives the bias
// (t = s / nu^2, u_t = W_t^2 / nu^2, p_t = chi(u_t), q_t = chi'(u_t) u_t):
//
//   E[t - 1] = -Cov(pbar, qbar) / slope^2 + curvature Var(pbar) / (2 slope^3)
//
// with slope and curvature the Gaussian constants of tuning.h. Var(pbar) and
// Cov(pbar, qbar) are long-run (co)variances of the level's coefficients, which carry
// the level's correlation structure (white noise, random walk, ...): they are estimated
// from the data by overlapping batch means. The corrected estimate is s / (1 + bias).

#include <cstdint>
#include <span>

#include "gmwm/robust/tuning.h"

namespace gmwm::robust::internal {

/// Above this eta_j = M_j / tau_j the bias (at most ~1 / eta: 3e-4 here) is below 2% of
/// the estimate's own standard error (sqrt(2 / (eff eta)) >= 2.6%) and is not computed
/// (this also keeps the extra pass off the fine levels, which dominate the cost).
inline constexpr double kSmallSampleMaxEta = 3000.0;
/// Batch length of the long-run (co)variance estimates, in units of tau_j: the
/// coefficients of a finite-memory process at level j are correlated over ~tau_j lags,
/// and overlapping batch means of length b underestimate a long-run variance by about
/// (sum_k |k| gamma_k) / (b sum_k gamma_k) ~ tau_j / (4 b) = 6% here; at eta = 46 this
/// is a 0.07% error on a 1.1% correction.
inline constexpr double kBatchScales = 4.0;
/// ... but at least this many batches' worth of coefficients (the coarse levels).
inline constexpr double kMinBatches = 4.0;
/// The (co)variances are computed on every (tau_j / kSamplesPerScale)-th coefficient.
/// The level's autocovariance is that of a length-tau_j filter's output: piecewise
/// smooth on the scale tau_j / 2 (the Haar filter's autocorrelation is piecewise linear
/// with kinks at 0, tau/2 and tau; the input's own correlation only smooths it). The mean
/// of a stride-st subsample then has the variance of the full mean up to the error of a
/// trapezoidal rule with step st, O((st / tau)^2) ~ 0.4% relative: negligible on a
/// correction of ~1 / eta, and it takes the extra pass off the robust WV's cost.
inline constexpr double kSamplesPerScale = 16.0;

/// The relative bias E[s / nu^2 - 1] of the root `scale` of the level's coefficients w,
/// tau = 2^j. Returns 0 when the level is too short to estimate it (fewer than 8
/// coefficients in the subsample).
double small_sample_bias(std::span<const double> w, const Tuning& t, double scale, double tau);

}  // namespace gmwm::robust::internal
