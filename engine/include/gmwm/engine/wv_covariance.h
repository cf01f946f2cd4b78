#pragma once
// Model-based covariance of the empirical classical WV of a Gaussian process
// (docs/statistics.md section 5), by the exact finite-N sums
//   Cov(nuhat_i, nuhat_j) = (2 / (M_i M_j)) sum_h n_ij(h) c_ij(h)^2
//                           + (4 d_i d_j / (M_i M_j)) sum_h n_ij(h) c_ij(h),
// where c_ij(h) = Cov(W_{i,t}, W_{j,t+h}) for the stochastic components, n_ij(h) counts
// the coefficient pairs at lag h, and d_j is the deterministic components' (constant)
// Haar coefficient at level j (DR: omega tau_j / 4; the second term is the cross product
// 2 d_j S_{j,t} inside (d_j + S_{j,t})^2, absent without a deterministic component);
// and by parametric bootstrap with any WV estimator.

#include <cstdint>
#include <functional>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

/// J x J covariance of the classical WV of levels 1..levels for a series of length n.
Eigen::MatrixXd model_wv_covariance(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int levels);

/// The same for the classical WV `wv` as it was estimated: wv.n samples, wv.levels() levels
/// and, where samples were missing (classical_wv_with_gaps), M_j^c = wv.coefficients[j]
/// complete windows of the M_j = n - 2^j + 1. The exact sums then count the pairs of
/// complete windows at each lag; to first order in the share of windows lost, a pair of
/// levels (i, j) keeps the share r_ij = min(M_i^c / M_i, M_j^c / M_j) of its pairs at every
/// lag the covariance reaches (the coarser level's windows, which hold the finer ones), so
///   Cov^c(i, j) = Cov(i, j) (M_i M_j / (M_i^c M_j^c)) r_ij,
/// and a level's variance grows as M_j / M_j^c. Against 4000 simulated WVs read through the
/// same gaps (WvCovariance.FollowsTheCompleteWindowsOfARecordWithGaps): within the Monte
/// Carlo's error where the windows are at most a quarter of the typical segment between
/// gaps; beyond, conservative (20% above it where a window is a quarter to all of a
/// segment, since pairs of complete windows thin out with the lag). Equal to
/// model_wv_covariance(model, theta, n, levels) without gaps. A level read from
/// near-complete windows (each half missing at most a tenth, gappy_wv.h) counts them in
/// M_j^c as complete ones: validated for complete windows only, and it leaves out the up to
/// 1.11 times larger white-noise term of a window missing its whole tenth (small at the long
/// levels where such windows are read).
Eigen::MatrixXd model_wv_covariance(const Model& model, const Eigen::VectorXd& theta, const WaveletVariance& wv);

/// Cov(nuhat) of `wv` under (model, theta): the WV's own covariance when it carries one
/// (stacked replicates, a bootstrap), else model_wv_covariance inflated by 1 / efficiency
/// for a robust WV (spec s.2). The V a goodness of fit of (model, theta) is measured with,
/// by fit and by every row of a selection alike (issue 43, item 4).
Eigen::MatrixXd wv_covariance_at(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta);

/// Sample covariance of the WV of `replicates` series simulated from (model, theta),
/// with stream seeds derived from `seed`; deterministic whatever the thread count.
/// `progress` (draws done, replicates) after each draw; it may throw gmwm::Cancelled.
Eigen::MatrixXd bootstrap_wv_covariance(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int levels,
                                        int replicates, std::uint64_t seed, const WvEstimator& estimator,
                                        double alpha = 0.05, const std::function<void(int, int)>& progress = {});

}  // namespace gmwm
