#pragma once
// The baseline's reference distribution of the WV (docs/gap.md, method note 2), internal to gap.cc.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

/// Shrinkage of the log-WV covariance towards its diagonal before inversion (B ~ 100
/// replicates for J ~ 20 levels leave the sample covariance noisy; Ledoit & Wolf 2004
/// motivate a fixed convex combination, 0.2 keeps it well conditioned).
inline constexpr double kCovarianceShrinkage = 0.2;

struct Reference {
  Eigen::MatrixXd wv;                ///< B x J: the replicates' WV
  Eigen::VectorXd nu;                ///< the baseline's theoretical WV
  Eigen::VectorXd mean_log, sd_log;  ///< per level, over all replicates
  Eigen::VectorXd var;               ///< per level variance of nuhat (raw scale), over all replicates
  // The global test uses two halves: its mean and (shrunk) covariance from half A, the
  // null distribution of the distance from half B (exchangeable with the data).
  Eigen::VectorXd mean_log_a;
  Eigen::MatrixXd precision_a;
  std::vector<double> null_distance;  ///< half B's distances, sorted
  /// Per replicate (same rows as wv): the series statistic, when one was requested.
  Eigen::MatrixXd series_stats;
};

/// A statistic of each simulated series besides its WV (the time-domain tests).
/// It gets the series and its Haar transform (built once per replicate, shared with the WV,
/// which is computed after it: the statistic may keep levels' squares for the WV to reuse).
using SeriesStatistic = std::function<Eigen::VectorXd(const std::vector<double>&, HaarModwt&)>;

/// Simulates `replicates` series of length n from (model, theta) with streams
/// (seed, stream_base + b), computes their WV with `estimator` (`levels` levels from
/// `first_level` on: a FromLevelEstimator when first_level > 1), and summarises them.
/// Throws InputError if fewer than 8 replicates give a finite WV.
Reference build_reference(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int first_level, int levels,
                          int replicates, std::uint64_t seed, const WvEstimator& estimator, double alpha,
                          const std::function<void(int, int)>& progress, const SeriesStatistic& series_statistic = {});

/// What makes two references the same draw: the model and its values (bit for bit), the
/// record length, the levels (first and count), replicates, seed (stream family included), the replicate
/// estimator (nullptr: the classical one; another by its identity), the WV's CI level and
/// what the series statistic reads (`statistic`: a description of its inputs, empty when
/// there is none).
std::string reference_key(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int first_level, int levels,
                          int replicates, std::uint64_t seed, const WvEstimator* estimator, double alpha,
                          const std::string& statistic);

/// The reference under `key` from `cache`, built by `build` the first time (no cache: built).
std::shared_ptr<const Reference> cached_reference(ReferenceCache* cache, const std::string& key,
                                                  const std::function<Reference()>& build);

/// Mahalanobis distance of log(nuhat) - shift from the half-A reference.
double distance(const Reference& ref, const Eigen::VectorXd& nuhat, const Eigen::VectorXd& log_shift);

/// Monte-Carlo p-value of a distance against half B: (1 + #{null >= d}) / (1 + B/2).
double p_value(const Reference& ref, double d);

}  // namespace gmwm::gap::detail

namespace gmwm::gap {
class ReferenceCache {
 public:
  mutable std::mutex mutex;
  std::map<std::string, std::shared_ptr<const detail::Reference>> kept;
};
}  // namespace gmwm::gap
