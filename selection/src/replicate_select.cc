#include "gmwm/selection/replicate_select.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <Eigen/Cholesky>
#include <boost/random/uniform_int_distribution.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm::selection {
namespace {

// C(12, 6) = 924 training splits, each a full selection: the most this runs.
constexpr int kMaxReplicates = 12;
// A paired mean excess below this share of the chosen model's CV-WVIC is no excess: the
// optimiser's own tolerance (1e-10 relative per fit, summed over splits and levels) makes
// models that are the same in effect differ by ~1e-8 of the loss.
constexpr double kEquivalenceTolerance = 1e-6;

Eigen::MatrixXd block_diagonal(const std::vector<const Eigen::MatrixXd*>& blocks) {
  Eigen::Index n = 0;
  for (const auto* b : blocks) n += b->rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index at = 0;
  for (const auto* b : blocks) {
    out.block(at, at, b->rows(), b->cols()) = *b;
    at += b->rows();
  }
  return out;
}

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
  for (const auto& wv : wvs) {
    Eigen::MatrixXd v = model_wv_covariance(pilot.joint.model, pilot.joint.theta, wv.n, wv.levels()) /
                        wv.efficiency.value_or(1.0);
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

// Stage 2: the selection (every sub-model, warm-started along the representation order)
// on the stacked WV of `members`, under their fixed Omega_k and V_k.
Selection select_on(std::span<const WaveletVariance> wvs, const std::vector<int>& members, const Weights& w,
                    const Model& maximal, const ReplicateSelectOptions& o) {
  std::vector<WaveletVariance> part;
  std::vector<const Eigen::MatrixXd*> v, omega;
  for (int k : members) {
    part.push_back(wvs[static_cast<std::size_t>(k)]);
    v.push_back(&w.v[static_cast<std::size_t>(k)]);
    omega.push_back(&w.omega[static_cast<std::size_t>(k)]);
  }
  WaveletVariance stacked = stack_wv(part);
  stacked.covariance = block_diagonal(v);
  SelectOptions so = o.select;
  so.optimism = OptimismMethod::kAnalytic;
  so.penalty = Penalty::kWvic;
  so.fit.omega_matrix = block_diagonal(omega);
  return select_models({stacked}, maximal, so).front();
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
  if (K > kMaxReplicates)
    throw InputError("select by replicates: at most " + std::to_string(kMaxReplicates) + " replicates (C(K, K/2) "
                     "training splits, each a full selection), got " + std::to_string(K));
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
  out.training = subsets(K, (K + 1) / 2);
  std::vector<int> all(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) all[static_cast<std::size_t>(k)] = k;
  const Selection whole = select_on(wvs, all, w, maximal, options);

  std::map<std::string, double> analytic;  // candidate -> its effective model's WVIC
  for (const auto& row : whole.ranking)
    for (const auto& m : row.members) analytic[m] = row.criterion;
  for (const auto& c : whole.candidates) {
    CvCandidate r;
    r.model = c.model;
    r.parameters = c.fit.model.num_parameters();
    r.objective = c.fit.objective;
    r.analytic_wvic = analytic.count(c.model) ? analytic[c.model] : std::numeric_limits<double>::quiet_NaN();
    out.ranking.push_back(std::move(r));
  }
  for (const auto& training : out.training) {
    const Selection sel = select_on(wvs, training, w, maximal, options);
    for (std::size_t i = 0; i < sel.candidates.size(); ++i)
      out.ranking[i].split_loss.push_back(held_out_loss(wvs, training, w, sel.candidates[i].fit));
  }
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
  std::vector<std::size_t> by_analytic(out.ranking.size());
  for (std::size_t i = 0; i < by_analytic.size(); ++i) by_analytic[i] = i;
  std::stable_sort(by_analytic.begin(), by_analytic.end(), [&](std::size_t a, std::size_t b) {
    return before(out.ranking[a].analytic_wvic, out.ranking[b].analytic_wvic, out.ranking[a].parameters,
                  out.ranking[b].parameters);
  });
  for (std::size_t k = 0; k < by_analytic.size(); ++k) out.ranking[by_analytic[k]].rank_analytic = static_cast<int>(k) + 1;
  out.chosen_analytic = out.ranking[by_analytic.front()].model;
  std::stable_sort(out.ranking.begin(), out.ranking.end(), [&](const CvCandidate& a, const CvCandidate& b) {
    return before(a.cv_wvic, b.cv_wvic, a.parameters, b.parameters);
  });
  for (std::size_t k = 0; k < out.ranking.size(); ++k) out.ranking[k].rank = static_cast<int>(k) + 1;
  out.chosen = out.ranking.front().model;
  equivalence(out.ranking, options);
  const CvCandidate* rec = &out.ranking.front();
  for (const auto& r : out.ranking)
    if (r.equivalent && (r.parameters < rec->parameters || (r.parameters == rec->parameters && r.cv_wvic < rec->cv_wvic)))
      rec = &r;
  out.recommended = rec->model;
  return out;
}

}  // namespace gmwm::selection
