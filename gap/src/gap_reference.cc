#include "gap_reference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include <Eigen/Cholesky>

#include "gmwm/engine/parallel.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/simulate.h"

namespace gmwm::gap::detail {
namespace {

// Fewer finite replicates than this cannot give a spread, let alone a covariance.
constexpr int kMinReplicates = 8;

Eigen::VectorXd column_mean(const Eigen::MatrixXd& m) { return m.colwise().mean().transpose(); }

}  // namespace

Reference build_reference(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int first_level, int levels,
                          int replicates, std::uint64_t seed, const WvEstimator& estimator, double alpha,
                          const std::function<void(int, int)>& progress, const SeriesStatistic& series_statistic) {
  std::vector<Eigen::VectorXd> rows(static_cast<std::size_t>(replicates)), stats(static_cast<std::size_t>(replicates));
  std::vector<char> ok(static_cast<std::size_t>(replicates), 0);
  std::atomic<int> done{0};
  gmwm::parallel_for(0, replicates, [&](int b) {
    const std::vector<double> x = simulate(model, theta, n, seed, static_cast<std::uint64_t>(b));
    HaarModwt transform(x.data(), n);
    Eigen::VectorXd statistic;
    if (series_statistic) statistic = series_statistic(x, transform);
    const WaveletVariance w = estimator.compute(transform, x.data(), n, levels, alpha);
    const Eigen::VectorXd v = w.values();
    if (v.size() == levels && v.allFinite() && (v.array() > 0.0).all()) {
      rows[static_cast<std::size_t>(b)] = v;
      stats[static_cast<std::size_t>(b)] = std::move(statistic);
      ok[static_cast<std::size_t>(b)] = 1;
    }
    const int d = ++done;
    if (progress) progress(d, replicates);
  });
  std::vector<Eigen::VectorXd> good, good_stats;
  for (int b = 0; b < replicates; ++b)
    if (ok[static_cast<std::size_t>(b)]) {
      good.push_back(rows[static_cast<std::size_t>(b)]);
      good_stats.push_back(stats[static_cast<std::size_t>(b)]);
    }
  const int B = static_cast<int>(good.size());
  if (B < kMinReplicates)
    throw InputError("gap: only " + std::to_string(B) + " of " + std::to_string(replicates) +
                     " reference replicates gave a positive, finite WV");
  Reference ref;
  ref.wv.resize(B, levels);
  for (int b = 0; b < B; ++b) ref.wv.row(b) = good[static_cast<std::size_t>(b)].transpose();
  if (series_statistic) {
    ref.series_stats.resize(B, good_stats.front().size());
    for (int b = 0; b < B; ++b) ref.series_stats.row(b) = good_stats[static_cast<std::size_t>(b)].transpose();
  }
  std::vector<double> tau;
  for (int j = first_level; j < first_level + levels; ++j) tau.push_back(std::ldexp(1.0, j));
  ref.nu = model.wv(theta, tau);
  const Eigen::MatrixXd L = ref.wv.array().log().matrix();
  ref.mean_log = column_mean(L);
  const Eigen::MatrixXd centred = L.rowwise() - ref.mean_log.transpose();
  ref.sd_log = (centred.array().square().colwise().sum() / (B - 1)).sqrt().transpose();
  const Eigen::VectorXd mean_raw = column_mean(ref.wv);
  ref.var = ((ref.wv.rowwise() - mean_raw.transpose()).array().square().colwise().sum() / (B - 1)).transpose();

  // Global test: half A (even replicates) for the mean and covariance, half B (odd) for
  // the null distribution of the distance.
  const int Ba = (B + 1) / 2, Bb = B / 2;
  Eigen::MatrixXd La(Ba, levels), Lb(Bb, levels);
  for (int b = 0; b < B; ++b) (b % 2 == 0 ? La.row(b / 2) : Lb.row(b / 2)) = L.row(b);
  ref.mean_log_a = column_mean(La);
  const Eigen::MatrixXd ca = La.rowwise() - ref.mean_log_a.transpose();
  Eigen::MatrixXd cov = ca.transpose() * ca / std::max(1, Ba - 1);
  const Eigen::VectorXd diag = cov.diagonal();
  cov = (1.0 - kCovarianceShrinkage) * cov;
  cov.diagonal() += kCovarianceShrinkage * diag;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(cov);
  ref.precision_a = ldlt.solve(Eigen::MatrixXd::Identity(levels, levels));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(levels);
  for (int b = 0; b < Bb; ++b)
    ref.null_distance.push_back(distance(ref, Lb.row(b).array().exp().matrix().transpose(), zero));
  std::sort(ref.null_distance.begin(), ref.null_distance.end());
  return ref;
}

std::string reference_key(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, int first_level, int levels,
                          int replicates, std::uint64_t seed, const WvEstimator* estimator, double alpha,
                          const std::string& statistic) {
  // The values as their bits (to_string's 17 digits name the model; the bits make equal
  // keys mean equal draws whatever the display).
  std::string key = model.to_string(theta) + "|";
  key.append(reinterpret_cast<const char*>(theta.data()), static_cast<std::size_t>(theta.size()) * sizeof(double));
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, "|n=%lld|L=%d|J=%d|B=%d|seed=%llu|alpha=%a|", static_cast<long long>(n),
                first_level, levels, replicates, static_cast<unsigned long long>(seed), alpha);
  // A caller's own estimator by its identity (its settings are not all in its name).
  const std::string by = estimator
                             ? estimator->name() + "@" + std::to_string(reinterpret_cast<std::uintptr_t>(estimator))
                             : std::string("classical");
  return key + numbers + by + "|" + statistic;
}

std::shared_ptr<const Reference> cached_reference(ReferenceCache* cache, const std::string& key,
                                                  const std::function<Reference()>& build) {
  if (!cache) return std::make_shared<const Reference>(build());
  {
    const std::lock_guard<std::mutex> lock(cache->mutex);
    if (const auto it = cache->kept.find(key); it != cache->kept.end()) return it->second;
  }
  // Built outside the lock (its replicates run in parallel); two threads asking for the
  // same key at once both build it, and the same draws give the same reference.
  auto built = std::make_shared<const Reference>(build());
  const std::lock_guard<std::mutex> lock(cache->mutex);
  return cache->kept.emplace(key, std::move(built)).first->second;
}

double distance(const Reference& ref, const Eigen::VectorXd& nuhat, const Eigen::VectorXd& log_shift) {
  const Eigen::VectorXd d = nuhat.array().log().matrix() - ref.mean_log_a - log_shift;
  return d.dot(ref.precision_a * d);
}

double p_value(const Reference& ref, double d) {
  const auto above = ref.null_distance.end() - std::lower_bound(ref.null_distance.begin(), ref.null_distance.end(), d);
  return (1.0 + static_cast<double>(above)) / (1.0 + static_cast<double>(ref.null_distance.size()));
}

}  // namespace gmwm::gap::detail

namespace gmwm::gap {

std::shared_ptr<ReferenceCache> make_reference_cache() { return std::make_shared<ReferenceCache>(); }

std::size_t cached_references(const ReferenceCache& cache) {
  const std::lock_guard<std::mutex> lock(cache.mutex);
  return cache.kept.size();
}

}  // namespace gmwm::gap
