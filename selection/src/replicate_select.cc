#include "gmwm/selection/replicate_select.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <set>

#include <Eigen/Cholesky>
#include <boost/random/uniform_int_distribution.hpp>

#include "active_jacobian.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm::selection {
namespace {

// Up to this many replicates every training subset of s = ceil(K/2) replicates is a split:
// C(12, 6) = 924 of them, each a full selection, the most the exhaustive cross-validation
// runs.
constexpr int kExhaustiveReplicates = 12;
// Beyond, kRandomSplits distinct half-splits drawn at random (repeated random sub-sampling,
// "Monte Carlo cross-validation": Shao 1993, "Linear model selection by cross-validation",
// JASA 88:486, and Xu & Liang 2001, "Monte Carlo cross validation", Chemometr. Intell. Lab.
// 56:1), as many as the exhaustive scheme's largest case, so that a fleet costs what 12
// replicates did: the CV-WVIC is then a mean over 924 of the C(K, s) splits, whose
// Monte-Carlo standard error is 1 / sqrt(924) = 3.3% of the split-to-split standard deviation
// of the held-out loss (the paired differences the equivalence test resamples likewise).
constexpr int kRandomSplits = 924;
static_assert(kRandomSplits >= 1);
// A paired mean excess below this share of the chosen model's CV-WVIC is no excess: the
// optimiser's own tolerance (1e-10 relative per fit, summed over splits and levels) makes
// models that are the same in effect differ by ~1e-8 of the loss.
constexpr double kEquivalenceTolerance = 1e-6;
// Bootstrap streams of the stacked draw: replicate k of draw `stream` is simulated on
// stream * max(K, kStreamsPerDraw) + k: distinct for every K, and for K <= 16 the layout the
// exhaustive scheme always had (stream * 16 + k).
constexpr std::uint64_t kStreamsPerDraw = 16;
// A model is rejected when its goodness-of-fit p-value is below this (select.cc's level).
constexpr double kRejectionLevel = 0.05;

// Stage 1: each replicate's V_k and Omega_k at a pilot joint fit of the maximal model.
struct Weights {
  std::vector<Eigen::MatrixXd> v, omega;
};
Weights pilot_weights(std::span<const WaveletVariance> wvs, const Model& maximal, const ReplicateSelectOptions& o) {
  FitOptions fo = o.select.fit;
  fo.omega = OmegaKind::kDiag;
  fo.inference = false;
  const JointFitResult pilot = fit_gmwm_joint(wvs, maximal, fo);
  if (pilot.joint.status == FitStatus::kFailed)
    throw InputError("select by replicates: the pilot joint fit of " + maximal.to_string() +
                     " failed: " + pilot.joint.message);
  Weights w;
  const bool full = o.select.omega == OmegaSource::kModelFull;
  // Replicates of one length, levels and efficiency share V_k: computed once for them.
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    const WaveletVariance& wv = wvs[k];
    std::size_t same = k;
    for (std::size_t i = 0; i < k && same == k; ++i)
      if (wvs[i].n == wv.n && wvs[i].levels() == wv.levels() && wvs[i].coefficients == wv.coefficients &&
          wvs[i].efficiency.value_or(1.0) == wv.efficiency.value_or(1.0))
        same = i;
    Eigen::MatrixXd v = same < k ? w.v[same]
                                 : Eigen::MatrixXd(model_wv_covariance(pilot.joint.model, pilot.joint.theta, wv) /
                                                   wv.efficiency.value_or(1.0));
    Eigen::MatrixXd omega = diagonal_omega(wv);
    if (o.select.omega == OmegaSource::kData) {
      // the data's own weights
    } else if (full && Eigen::LLT<Eigen::MatrixXd>(v).info() == Eigen::Success) {
      omega = v.llt().solve(Eigen::MatrixXd::Identity(v.rows(), v.cols()));
      omega = 0.5 * (omega + omega.transpose());
    } else {
      for (Eigen::Index j = 0; j < v.rows(); ++j)
        if (v(j, j) > 0.0 && std::isfinite(v(j, j))) omega(j, j) = 1.0 / v(j, j);
    }
    w.v.push_back(std::move(v));
    w.omega.push_back(std::move(omega));
  }
  return w;
}

// Runs f(t) for t in [0, n) in parallel and rethrows the lowest-index task's exception,
// so that which message the user sees does not depend on which thread failed first.
template <typename F>
void parallel_in_order(std::size_t n, F f) {
  std::vector<std::exception_ptr> errors(n);
  gmwm::parallel_for(std::size_t{0}, n, [&](std::size_t t) {
    try {
      f(t);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

// Every subset of size s of {0, ..., K-1}, in lexicographic order.
std::vector<std::vector<int>> subsets(int K, int s) {
  std::vector<std::vector<int>> out;
  std::vector<int> idx(static_cast<std::size_t>(s));
  for (int i = 0; i < s; ++i) idx[static_cast<std::size_t>(i)] = i;
  while (true) {
    out.push_back(idx);
    int i = s - 1;
    while (i >= 0 && idx[static_cast<std::size_t>(i)] == K - s + i) --i;
    if (i < 0) break;
    ++idx[static_cast<std::size_t>(i)];
    for (int k = i + 1; k < s; ++k) idx[static_cast<std::size_t>(k)] = idx[static_cast<std::size_t>(k - 1)] + 1;
  }
  return out;
}

// The training splits: every subset of s = ceil(K/2) replicates up to kExhaustiveReplicates,
// else kRandomSplits distinct ones drawn from one stream of the seed (in order, before any
// parallel work: the same splits whatever the thread count), each sorted.
std::vector<std::vector<int>> training_splits(int K, std::uint64_t seed) {
  const int s = (K + 1) / 2;
  if (K <= kExhaustiveReplicates) return subsets(K, s);
  Rng rng = make_stream(seed, {0x7370u});
  std::set<std::vector<int>> seen;
  std::vector<std::vector<int>> out;
  std::vector<int> pool(static_cast<std::size_t>(K));
  while (static_cast<int>(out.size()) < kRandomSplits) {
    for (int k = 0; k < K; ++k) pool[static_cast<std::size_t>(k)] = k;
    for (int i = 0; i < s; ++i) {  // a partial Fisher-Yates shuffle: s distinct replicates
      boost::random::uniform_int_distribution<int> pick(i, K - 1);
      std::swap(pool[static_cast<std::size_t>(i)], pool[static_cast<std::size_t>(pick(rng))]);
    }
    std::vector<int> split(pool.begin(), pool.begin() + s);
    std::sort(split.begin(), split.end());
    if (seen.insert(split).second) out.push_back(std::move(split));
  }
  return out;
}

// The replicates `members` of `wvs` with their V_k and Omega_k, reduced to one WV on their
// common levels (joint_fit.h: the stacked problem's exact reduction).
struct Part {
  std::vector<WaveletVariance> wvs;
  std::vector<Eigen::MatrixXd> v, omega;
  std::vector<const WvEstimator*> estimators;  // the members' own, when each replicate has one
  ReducedReplicates reduced;
};
Part part_of(std::span<const WaveletVariance> wvs, const std::vector<int>& members, const Weights& w,
             const ReplicateSelectOptions& o) {
  Part p;
  for (int k : members) {
    if (!o.estimators.empty()) p.estimators.push_back(o.estimators[static_cast<std::size_t>(k)]);
    p.wvs.push_back(wvs[static_cast<std::size_t>(k)]);
    p.v.push_back(w.v[static_cast<std::size_t>(k)]);
    p.omega.push_back(w.omega[static_cast<std::size_t>(k)]);
  }
  p.reduced = reduce_replicates(p.wvs, p.omega, p.v);
  return p;
}

// The parametric-bootstrap draw of the part's reduced WV: every member replicate simulated
// from the fitted model at its own length, its WV by its estimator (its own, else the
// selection's) at its own levels, reduced under the same Omega_k (the stacked draw's reduction).
SelectOptions::BootstrapDraw reduced_draw(const Part& part, const ReplicateSelectOptions& o) {
  return
      [wvs = part.wvs, omega = part.omega, estimators = part.estimators, estimator = o.select.estimator, seed = o.seed](
          const WaveletVariance&, const Model& model, const Eigen::VectorXd& theta, std::uint64_t stream) {
        const ClassicalWvEstimator classical;
        const std::uint64_t per_draw = std::max<std::uint64_t>(kStreamsPerDraw, wvs.size());
        std::vector<WaveletVariance> draws;
        for (std::size_t k = 0; k < wvs.size(); ++k) {
          const WvEstimator& e = replicate_estimator(estimators, k, estimator, classical);
          const std::vector<double> x = simulate(model, theta, wvs[k].n, seed, stream * per_draw + k);
          draws.push_back(e.compute(x.data(), wvs[k].n, static_cast<int>(wvs[k].levels()), wvs[k].alpha));
        }
        return reduce_replicates(draws, omega).wv;
      };
}

// The selection on the reduced WV as the stacked problem's: every objective plus C, and
// each row's goodness of fit (and so all_rejected) with the stacked degrees of freedom and
// Satterthwaite traces (the stacked selection's Omega was the caller's, not V^-1).
// best_fit, which the selection over replicates does not use, stays the reduced problem's.
void as_stacked(Selection& sel, const ReducedReplicates& r) {
  for (auto& c : sel.candidates)
    if (c.fit.status != FitStatus::kFailed) c.fit.objective += r.within;
  for (auto& row : sel.ranking) {
    for (double& o : row.member_objectives) o += r.within;
    if (row.fit.status == FitStatus::kFailed) continue;
    row.fit.objective += r.within;
    row.objective += r.within;
    row.criterion += r.within;
    const Model& m = row.effective.model;
    row.gof = stacked_goodness_of_fit(
        r, detail::active_jacobian(m, row.effective.theta, r.wv.tau, row.analytic.boundary_components), row.objective,
        static_cast<double>(r.stacked_levels - row.parameters), false);
  }
  sel.all_rejected = std::all_of(sel.ranking.begin(), sel.ranking.end(), [](const RankedModel& row) {
    return !std::isfinite(row.gof.p_value) || row.gof.p_value < kRejectionLevel;
  });
}

// Stage 2: the selection (every sub-model, warm-started along the representation order)
// on the reduced WV of `members`, under their fixed Omega_k and V_k; with the
// parametric-bootstrap optimism beside the analytic one when `bootstrap` is set.
Selection select_on(std::span<const WaveletVariance> wvs, const std::vector<int>& members, const Weights& w,
                    const Model& maximal, const ReplicateSelectOptions& o, bool bootstrap) {
  const Part part = part_of(wvs, members, w, o);
  SelectOptions so = o.select;
  so.optimism = bootstrap ? OptimismMethod::kBoth : OptimismMethod::kAnalytic;
  so.penalty = Penalty::kWvic;
  so.fit.omega_matrix = part.reduced.weight;
  if (bootstrap) so.bootstrap_draw = reduced_draw(part, o);
  Selection sel = select_models({part.reduced.wv}, maximal, so).front();
  as_stacked(sel, part.reduced);
  return sel;
}

// Held-out loss of a candidate fitted on a split.
double held_out_loss(std::span<const WaveletVariance> wvs, const std::vector<int>& training, const Weights& w,
                     const FitResult& fit) {
  if (fit.status == FitStatus::kFailed) return std::numeric_limits<double>::quiet_NaN();
  double loss = 0.0;
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    if (std::find(training.begin(), training.end(), static_cast<int>(k)) != training.end()) continue;
    const Eigen::VectorXd r = wvs[k].values() - fit.model.wv(fit.theta, wvs[k].tau);
    loss += r.dot(w.omega[k] * r);
  }
  return loss;
}

// Stage 4: the bootstrap over the splits of each candidate's paired loss difference to the
// chosen one: the share of resamples whose mean difference is <= 0.
void equivalence(std::vector<CvCandidate>& rows, const ReplicateSelectOptions& o) {
  const CvCandidate& best = rows.front();
  const std::size_t S = best.split_loss.size();
  Rng rng = make_stream(o.seed, {0x7265u});
  boost::random::uniform_int_distribution<std::size_t> pick(0, S - 1);
  std::vector<std::vector<std::size_t>> draws(static_cast<std::size_t>(o.split_bootstrap), std::vector<std::size_t>(S));
  for (auto& d : draws)
    for (auto& i : d) i = pick(rng);
  for (auto& r : rows) {
    if (!std::isfinite(r.cv_wvic)) continue;
    int not_worse = 0;
    for (const auto& d : draws) {
      double sum = 0.0;
      double scale = 0.0;
      for (std::size_t i : d) {
        sum += r.split_loss[i] - best.split_loss[i];
        scale += best.split_loss[i];
      }
      not_worse += sum <= kEquivalenceTolerance * std::abs(scale);
    }
    r.p_not_worse = static_cast<double>(not_worse) / static_cast<double>(draws.size());
    r.equivalent = r.p_not_worse > o.equivalence_level;
  }
}

}  // namespace

std::string ReplicateSelectOptions::Validate() const {
  if (split_bootstrap < 100) return "split_bootstrap must be at least 100, got " + std::to_string(split_bootstrap);
  if (!(equivalence_level > 0.0 && equivalence_level < 0.5))
    return "equivalence_level must be in (0, 0.5), got " + std::to_string(equivalence_level);
  return select.Validate();
}

ReplicateSelection select_by_replicates(std::span<const WaveletVariance> wvs, const Model& maximal,
                                        const ReplicateSelectOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("select by replicates: " + why);
  const int K = static_cast<int>(wvs.size());
  if (K < 2)
    throw InputError("select by replicates: the replicate-based optimism needs at least 2 replicates, got " +
                     std::to_string(K));
  check_replicate_estimators("select by replicates", options.estimators, wvs.size());
  for (int k = 0; k < K; ++k) {
    try {
      check_model_fits_levels(maximal, wvs[static_cast<std::size_t>(k)].levels());
    } catch (const InputError& e) {
      throw InputError("replicate " + std::to_string(k + 1) + ": " + e.what());
    }
  }
  const Weights w = pilot_weights(wvs, maximal, options);

  ReplicateSelection out;
  out.full_model = maximal.canonical().to_string();
  out.training = training_splits(K, options.seed);
  std::vector<int> all(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) all[static_cast<std::size_t>(k)] = k;
  // The selection on all replicates (task 0) and on every training split, as one parallel
  // loop (each selection parallel inside over its models); each task writes its own slot.
  const bool bootstrap = options.select.optimism != OptimismMethod::kAnalytic;
  const std::size_t S = out.training.size();
  std::vector<Selection> sel(S + 1);
  // Progress: the selections done out of S + 1, reported when each ends and, as the
  // cancellation point, whenever one of them reports its own (the same count again).
  std::atomic<int> done{0};
  ReplicateSelectOptions inner = options;
  if (options.select.progress)
    inner.select.progress = [&](int, int) { options.select.progress(done.load(), static_cast<int>(S + 1)); };
  parallel_in_order(S + 1, [&](std::size_t t) {
    sel[t] = t == 0 ? select_on(wvs, all, w, maximal, inner, bootstrap)
                    : select_on(wvs, out.training[t - 1], w, maximal, inner, false);
    const int d = ++done;
    if (options.select.progress) options.select.progress(d, static_cast<int>(S + 1));
  });
  const Selection& whole = sel.front();
  out.all_rejected = whole.all_rejected;

  std::map<std::string, const RankedModel*> row_of;  // candidate -> its effective model's row
  for (const auto& row : whole.ranking)
    for (const auto& m : row.members) row_of[m] = &row;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& c : whole.candidates) {
    CvCandidate r;
    r.model = c.model;
    r.parameters = c.fit.model.num_parameters();
    r.effective = row_of.count(c.model) ? row_of[c.model]->model : c.model;
    r.objective = c.fit.objective;
    const RankedModel* row = row_of.count(c.model) ? row_of[c.model] : nullptr;
    r.analytic_wvic = row ? row->objective + row->optimism_analytic.value_or(nan) : nan;
    if (row && row->optimism_bootstrap) {
      r.bootstrap_wvic = row->objective + *row->optimism_bootstrap;
      r.bootstrap_se = row->optimism_bootstrap_se.value_or(nan);
    }
    out.ranking.push_back(std::move(r));
  }
  for (std::size_t t = 1; t <= S; ++t)
    for (std::size_t i = 0; i < sel[t].candidates.size(); ++i)
      out.ranking[i].split_loss.push_back(held_out_loss(wvs, out.training[t - 1], w, sel[t].candidates[i].fit));
  for (auto& r : out.ranking) {
    double sum = 0.0;
    for (double l : r.split_loss) sum += l;
    r.cv_wvic = sum / static_cast<double>(r.split_loss.size());
  }
  // Ranks: by CV-WVIC (NaN last; equal values to the smaller model), and by the analytic WVIC.
  // A strict weak order: NaN last, then by value, then by size.
  const auto before = [](double a, double b, int pa, int pb) {
    if (std::isnan(a) != std::isnan(b)) return std::isnan(b);
    if (!std::isnan(a) && a != b) return a < b;
    return pa < pb;
  };
  // Ranks under another criterion; returns the first-ranked model (empty when every value is NaN).
  const auto rank_by = [&](double CvCandidate::*value, int CvCandidate::*rank) {
    std::vector<std::size_t> order(out.ranking.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return before(out.ranking[a].*value, out.ranking[b].*value, out.ranking[a].parameters, out.ranking[b].parameters);
    });
    for (std::size_t k = 0; k < order.size(); ++k) out.ranking[order[k]].*rank = static_cast<int>(k) + 1;
    return std::isnan(out.ranking[order.front()].*value) ? std::string() : out.ranking[order.front()].model;
  };
  out.chosen_analytic = rank_by(&CvCandidate::analytic_wvic, &CvCandidate::rank_analytic);
  if (bootstrap) out.chosen_bootstrap = rank_by(&CvCandidate::bootstrap_wvic, &CvCandidate::rank_bootstrap);
  std::stable_sort(out.ranking.begin(), out.ranking.end(), [&](const CvCandidate& a, const CvCandidate& b) {
    return before(a.cv_wvic, b.cv_wvic, a.parameters, b.parameters);
  });
  for (std::size_t k = 0; k < out.ranking.size(); ++k) out.ranking[k].rank = static_cast<int>(k) + 1;
  out.chosen = out.ranking.front().model;
  equivalence(out.ranking, options);
  const CvCandidate* rec = &out.ranking.front();
  for (const auto& r : out.ranking)
    if (r.equivalent &&
        (r.parameters < rec->parameters || (r.parameters == rec->parameters && r.cv_wvic < rec->cv_wvic)))
      rec = &r;
  out.recommended = rec->model;
  return out;
}

std::vector<ReplicateSelection> select_by_replicates(std::span<const std::vector<WaveletVariance>> axes,
                                                     const Model& maximal, const ReplicateSelectOptions& options) {
  std::vector<ReplicateSelection> out(axes.size());
  parallel_in_order(axes.size(), [&](std::size_t a) { out[a] = select_by_replicates(axes[a], maximal, options); });
  return out;
}

}  // namespace gmwm::selection
