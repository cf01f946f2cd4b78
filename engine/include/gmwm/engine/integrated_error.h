#pragma once
// Predicted integrated-error growth of a noise model (docs/gap.md, method note 4: "what it means
// for navigation, e.g. attitude error after 60 s"): the error of the integral of the
// noise over a horizon, S = (1/f) (x_1 + ... + x_K), K = round(horizon * f) samples at the
// sampling rate f. Gyro noise in deg/s integrates to an attitude error in deg,
// accelerometer noise in m/s^2 to a velocity error in m/s: results are in U*s for data in
// U (physical.h: render_unit("U*s", unit)).
//
// The non-stationary components start at 0 at time 0 (RW: x_t = e_1 + ... + e_t; DR:
// x_t = omega t), as an integration started with a known bias does. Components are
// independent, so the variances of their sums add (Process::sum_moments); a DR adds a
// deterministic error omega K (K + 1) / (2 f) (in magnitude: its sign is not
// identifiable), reported apart from the random part.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm {

struct IntegratedError {
  double horizon_seconds = 0.0;
  std::int64_t samples = 0;                         ///< K = round(horizon_seconds * freq)
  double sd_random = 0.0;                           ///< sd of S from the stochastic components
  double deterministic = 0.0;                       ///< |mean of S| (the drift's integral)
  double total_rms = 0.0;                           ///< sqrt(sd_random^2 + deterministic^2)
  std::vector<double> per_component_sd;             ///< per component, model order
  std::vector<double> per_component_deterministic;  ///< per component (DR only non-zero)
};

/// Largest K accepted: the stationary components need their autocovariance at K lags
/// (8 bytes each), so this caps the memory at 512 MiB (e.g. 93 h at 200 Hz).
inline constexpr std::int64_t kMaxIntegratedSamples = std::int64_t{1} << 26;

/// The integrated error at one horizon. O(K) per stationary component, O(1) for RW and DR.
/// Throws InvalidArgument (check.h) naming the argument for freq or horizon_seconds not
/// positive and finite, a horizon under half a sample or over kMaxIntegratedSamples
/// samples, a theta invalid for the model ("integrated_error: component 1 (WN): ..."),
/// or a freq differing from the rate a component was built with (when known).
IntegratedError integrated_error(const Model& model, const Eigen::VectorXd& theta, double freq, double horizon_seconds);

/// The same at several horizons (any order; results in the order given), sharing one
/// autocovariance per component: O(max K) in all.
std::vector<IntegratedError> integrated_error(const Model& model, const Eigen::VectorXd& theta, double freq,
                                              std::span<const double> horizons_seconds);

/// integrated_error(...).sd_random: the standard deviation of the random part of S.
double integrated_error_sd(const Model& model, const Eigen::VectorXd& theta, double freq, double horizon_seconds);

}  // namespace gmwm
