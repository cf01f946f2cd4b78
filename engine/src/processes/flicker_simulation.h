#pragma once
// FLICKER's simulation (flicker.cc), exposed for its tests. Both draws are exact in law:
// the octaves' sum is the stationary Gaussian process with autocovariance
// s sum_{k = kmin..kmax} phi_k^h, phi_k = exp(-2^-k), each octave an AR1 of stationary
// variance s.
//
// The octave recursion draws one normal per octave and sample (41 per sample by default).
// The block bridge draws each octave's state only every D samples (its AR1 transition over
// D steps: phi^D, innovation variance s (1 - phi^2D)), and the D - 1 samples between two
// such states from their joint law given them: the octaves are independent Markov chains,
// so given every octave's state at both ends of a block the interior is Gaussian, with the
// mean sum_k (a_k(t) x_k(start) + b_k(t) x_k(end)) and the covariance sum_k C_k, the same
// for every block. For an AR1 bridge of length D (0 < t, i <= j < D):
//   a(t) = phi^t (1 - phi^(2(D - t))) / (1 - phi^(2D)),
//   b(t) = phi^(D - t) (1 - phi^(2t)) / (1 - phi^(2D)),
//   C(i, j) = s phi^(j - i) (1 - phi^(2i)) (1 - phi^(2(D - j))) / (1 - phi^(2D)),
// the Schur complement of the AR1's covariance on the block's ends (each factor 1 - phi^m
// formed as -expm1(-m L): no cancellation for octaves far beyond the record). One normal
// per interior sample (through the Cholesky factor of sum_k C_k) and K per block: 1 + K/D
// normals in place of K, and D/2 multiply-adds per sample for the Cholesky product plus
// r (2K + D - 1) / D for the mean, its map factored to its numerical rank r (18 of 82 by
// default; unfactored, 2K (D - 1) / D), the blocks in batches of kFlickerBatch as
// matrix-matrix products. The samples after
// the last whole block take the recursion from the states there. The scale is applied last
// (sqrt(s) times the unit draw), so a variance scaled by 4^k scales the series by exactly
// 2^k, as every process's draw does.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/random.h"

namespace gmwm::internal {

/// The block length of the bridge: 64 samples make the per-block octave states 0.64
/// normals per sample with the default 41 octaves, while the interior's Cholesky product
/// (D / 2 multiply-adds per sample) stays below the mean's 2K.
inline constexpr int kFlickerBlock = 64;
/// Blocks per matrix-matrix product of the bridge (simulate_flicker_bridge): 64 blocks of 64
/// samples, their 145 x 64 draws 74 KB, stay in the second-level cache.
inline constexpr int kFlickerBatch = 64;
/// Singular values of the mean map below this share of the largest are its rounding:
/// double's epsilon (2.2e-16).
inline constexpr double kBridgeRankTolerance = 2.220446049250313e-16;

/// The bridge's constants at unit variance (s = 1), for octaves kmin..kmax and blocks of D.
struct FlickerBridge {
  int block = 0;
  Eigen::VectorXd decay;      ///< phi_k^D
  Eigen::VectorXd step_sd;    ///< sqrt(1 - phi_k^(2D))
  Eigen::VectorXd phi;        ///< phi_k (the tail's recursion)
  Eigen::VectorXd sd;         ///< sqrt(1 - phi_k^2)
  Eigen::MatrixXd ends;       ///< (D - 1) x 2K: [a_k(t) b_k(t)]
  Eigen::MatrixXd chol;       ///< (D - 1) x (D - 1): lower Cholesky factor of sum_k C_k
  Eigen::MatrixXd mean_from;  ///< (D - 1) x r and
  Eigen::MatrixXd mean_of;    ///< r x 2K: ends = mean_from mean_of to its rounding (make_flicker_bridge)
  bool usable() const { return block > 1; }
};
/// The constants; not usable() when sum_k C_k is not numerically positive definite (never
/// seen: it is a sum of bridge covariances).
FlickerBridge make_flicker_bridge(long kmin, long kmax, int block = kFlickerBlock);

/// Adds the octave recursion's draw (stationary variance s per octave) to out.
void simulate_flicker_octaves(long kmin, long kmax, double s, Rng& rng, std::span<double> out);
/// Adds the block bridge's draw (stationary variance s per octave) to out.
void simulate_flicker_bridge(const FlickerBridge& bridge, double s, Rng& rng, std::span<double> out);

}  // namespace gmwm::internal
