#pragma once
// Where does contamination act? Per level, the robust and classical WVs side by side,
// whether their CIs are disjoint, and a contamination flag calibrated against what the
// data's rounding alone produces (docs/statistics.md section 2, "Quantized data").
//
// Rounding model: the sensor outputs x_t = q round(y_t / q) for a continuous Gaussian y
// whose position within a quantum is uniform. Then K = tau_j W_{j,t} / q is an integer
// equal to (the Haar sum of y) / q plus tau_j independent uniform rounding errors:
//   P(K = k) = integral phi_sigma(y) B_tau(k - y) dy,
// with B_tau the density of the sum of the errors (a triangle for tau = 2, the exact
// case at level 1; a Gaussian of variance tau/12 from tau = 4 on). sigma is matched to
// the level's classical WV, the robust equation solved on that lattice distribution, and
// the ratio of the two is what rounding alone makes of robust / classical.
// The rounding model is only approximate (the sensor's bias fixes where within a
// quantum a nearly constant signal sits, so the phase is not uniform: on the ADIS
// accelerometers the observed level-1 ratio departs from the model's by up to 10%).
// What rounding cannot produce is outliers: a lattice distribution keeps Gaussian tails.
// A level is therefore flagged when both
//   - its coefficients have an excess of far outliers: the share beyond kTailSd robust
//     standard deviations exceeds kTailExcess times the Gaussian share (and 3 / eta_j,
//     three effectively independent windows), and
//   - the robust CI, divided by the rounding ratio (less a tolerance), lies entirely
//     below the classical CI: contamination inflates the classical WV.

#include <cstdint>
#include <span>
#include <vector>

#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/quantization.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust {

// The rounding step (engine/quantization.h), read here against the robust estimators.
using gmwm::detect_quantization;
using gmwm::Quantization;

/// What rounding alone makes of robust / classical at a level of scale tau whose
/// classical WV is classical_wv, for the quantum q (1 when q is 0 or negligible).
double rounding_ratio(const Tuning& tuning, double classical_wv, double tau, double quantum);

struct LevelDiagnostic {
  double classical_wv = 0.0;
  double robust_to_classical = 0.0;  ///< NaN where the robust WV is undefined
  double expected_ratio = 1.0;       ///< robust / classical from rounding alone
  double tail_share = 0.0;           ///< share of coefficients beyond kTailSd robust sd
  bool ci_disjoint = false;
  bool contaminated = false;
};

/// Per level of `robust` (its classical counterpart: `classical`, same levels), for the
/// series x both were computed from.
std::vector<LevelDiagnostic> contamination_diagnostic(const double* x, std::int64_t n, const WaveletVariance& robust,
                                                      const WaveletVariance& classical,
                                                      const Quantization& quantization, const Tuning& tuning);
/// The same from x's Haar transform (the classical WV's, which the caller already holds).
std::vector<LevelDiagnostic> contamination_diagnostic(const HaarModwt& transform, const WaveletVariance& robust,
                                                      const WaveletVariance& classical,
                                                      const Quantization& quantization, const Tuning& tuning);
/// The same for a record with missing samples, whose WVs came from the windows
/// classical_wv_with_gaps reads (robust_wv_with_gaps, classical_wv_with_gaps): the tails are
/// counted among those windows' coefficients (GappyWindows).
std::vector<LevelDiagnostic> contamination_diagnostic_with_gaps(std::span<const double> observed,
                                                                std::span<const MissingRun> missing,
                                                                const WaveletVariance& robust,
                                                                const WaveletVariance& classical,
                                                                const Quantization& quantization, const Tuning& tuning);

}  // namespace gmwm::robust
