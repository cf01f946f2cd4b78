#pragma once
// Model selection over replicates of a sensor (the multi-signal GMWM's cross-validation):
// every sub-model of a maximal model is fitted jointly on each training subset S of
// s = ceil(K/2) replicates and scored by its loss on the held-out replicates,
//
//   loss(m, S) = sum_{k not in S} (nuhat_k - nu_m(theta_hat_S; tau_k))' Omega_k (...),
//   CV-WVIC(m) = mean over S of loss(m, S),
//
// with each replicate's Omega_k fixed for every model and split (model-based at a pilot
// joint fit of the maximal model, as in single-signal selection). The training subsets are
// all C(K, s) of them up to K = 12 (924 for K = 12); beyond, 924 distinct ones drawn at
// random from the seed (repeated random sub-sampling, "Monte Carlo cross-validation":
// Shao 1993, JASA 88:486; Xu & Liang 2001, Chemometr. Intell. Lab. 56:1), so a fleet of
// any size costs what 12 replicates did. Each split's selection runs on the exact
// reduction of its stacked WV to one WV on the common levels (joint_fit.h,
// reduce_replicates): O(K J^2) to set up, then a single signal's cost per fit. Beside it:
// the analytic WVIC of the joint fit on all replicates (the stacked problem with
// V = blockdiag(V_k), through the same reduction). The model with the smallest CV-WVIC is
// chosen; the models whose paired loss difference to it over the splits is not
// significantly positive (bootstrap over the splits) are "equivalent", and the smallest
// equivalent model is recommended.
//
//   gmwm::selection::ReplicateSelectOptions o;
//   auto r = gmwm::selection::select_by_replicates(wvs, gmwm::parse_model("3*AR1+WN+RW"), o);
//   r.recommended, r.ranking[0].cv_wvic ...

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/selection/select.h"

namespace gmwm::selection {

struct ReplicateSelectOptions {
  /// The selection of each split (penalty WVIC, Omega source kModel or kModelFull, fit
  /// settings, progress). Its optimism: kAnalytic, or kBootstrap / kBoth for the
  /// parametric-bootstrap optimism of the joint fit on all replicates beside the analytic
  /// one (every replicate simulated at its own length from the candidate's joint fit,
  /// bootstrap_replicates draws per candidate, its WV by `select.estimator`, streams from
  /// this struct's `seed`, not select.seed); the splits
  /// are always scored by their held-out loss.
  SelectOptions select;
  /// Per replicate, the WV estimator of its simulated series when the replicates are read
  /// differently (each through its own gaps); empty: `select.estimator` for all. Its size
  /// must be the replicates' (InputError otherwise). Over several axes, replicate k of
  /// every axis takes estimators[k] (one recording's columns share its gaps).
  std::vector<const WvEstimator*> estimators;
  int split_bootstrap = 2000;       ///< resamples of the splits for the equivalence test
  double equivalence_level = 0.05;  ///< a model is equivalent unless its excess loss is significant at this level
  /// Streams of the random splits (beyond 12 replicates), of the equivalence test's
  /// resamples and of the bootstrap WVIC's draws.
  std::uint64_t seed = 0;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

struct CvCandidate {
  std::string model;  ///< the candidate (canonical, without values)
  /// The effective model its fit on all replicates falls onto (select.h's ranking rows: a
  /// 2*AR1+WN whose second AR1 vanished is AR1+WN); the candidate itself when nothing reduces.
  /// A report lists each effective model once, with the candidates that fell onto it.
  std::string effective;
  int parameters = 0;
  double cv_wvic = 0.0;            ///< mean held-out loss over the splits
  std::vector<double> split_loss;  ///< per split, in ReplicateSelection::training order
  double objective = 0.0;          ///< joint objective on all replicates
  double analytic_wvic = 0.0;      ///< objective + analytic optimism on all replicates
  /// objective + parametric-bootstrap optimism on all replicates, and the optimism's
  /// Monte-Carlo s.e. (NaN unless asked for)
  double bootstrap_wvic = std::numeric_limits<double>::quiet_NaN();
  double bootstrap_se = std::numeric_limits<double>::quiet_NaN();
  int rank = 0;            ///< by CV-WVIC (ties: fewer parameters)
  int rank_analytic = 0;   ///< by the analytic WVIC
  int rank_bootstrap = 0;  ///< by the bootstrap WVIC (0 unless asked for)
  /// Bootstrap probability (over the splits) that its mean loss is not above the chosen
  /// model's; equivalent when above equivalence_level. The splits share replicates, so
  /// their losses are not independent: with few replicates this probability is coarse
  /// (3 splits for K = 3) and errs towards calling a model worse.
  double p_not_worse = 1.0;
  bool equivalent = false;
};

struct ReplicateSelection {
  std::string full_model;
  std::vector<std::vector<int>> training;  ///< each split's training replicates (0-based, sorted)
  std::vector<CvCandidate> ranking;        ///< by CV-WVIC
  std::string chosen;                      ///< smallest CV-WVIC
  std::string recommended;                 ///< smallest equivalent model (ties: lower CV-WVIC)
  std::string chosen_analytic;             ///< smallest analytic WVIC on all replicates
  std::string chosen_bootstrap;            ///< smallest bootstrap WVIC (empty unless asked for)
  /// Every candidate's joint fit on all replicates is rejected by its goodness-of-fit test
  /// at 5%: no sub-model describes the recordings, and the ranking compares misfits.
  bool all_rejected = false;
};

/// Throws InputError for fewer than 2 replicates, invalid options, or a replicate with
/// fewer levels than the maximal model has parameters (naming it, 1-based). Any K beyond:
/// memory grows as K J^2 (the replicates' Omega_k and V_k; 97 MB in all for 495 units of
/// 2^18 samples) and time as K only in the pilot's single fits and the reductions.
/// The split selections and the one on all replicates run as one parallel loop; the
/// splits are drawn before it, so the result does not depend on the thread count.
ReplicateSelection select_by_replicates(std::span<const WaveletVariance> wvs, const Model& maximal,
                                        const ReplicateSelectOptions& options = {});

/// Every axis at once (each axis its own replicates' WVs): axes x splits x models in one
/// TBB task tree; result i is select_by_replicates(axes[i], ...), bit for bit. When several
/// fail, the first axis's (then first split's) error is thrown, whatever the thread timing.
std::vector<ReplicateSelection> select_by_replicates(std::span<const std::vector<WaveletVariance>> axes,
                                                     const Model& maximal, const ReplicateSelectOptions& options = {});

}  // namespace gmwm::selection
