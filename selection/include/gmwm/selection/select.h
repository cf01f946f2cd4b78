#pragma once
// Automatic model selection (docs/statistics.md section 6): every sub-model of a maximal model
// fitted on each signal, bottom-up by size, each warm-started from the fits of the
// models nested in it (its parents: one component fewer), all with the signal's one
// Omega; then scored by WVIC = objective + optimism and ranked.
//
//   gmwm::selection::SelectOptions o;                       // analytic optimism
//   auto results = gmwm::selection::select_models(wvs, gmwm::parse_model("3*AR1+WN+RW+QN+DR"), o);
//   results[s].ranking[0]                                    // the best model of signal s
//
// Scheduling: a TBB flow graph over signals x models; a model's node runs once its
// parents' nodes are done, and takes their fits as starts in the parents' fixed order,
// so the result does not depend on the thread count. A super-model's fit starts from its
// parents' optima (embedded), so its objective is never above theirs.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/effective_model.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/selection/optimism.h"

namespace gmwm::selection {

enum class Penalty {
  kWvic,  ///< objective + optimism (prediction)
  kBic,   ///< objective + p log(N) (consistent)
};
const char* to_string(Penalty p);

/// How the WVIC's optimism is computed: analytic (delta method), parametric bootstrap,
/// or both side by side (the criterion then uses the analytic one).
enum class OptimismMethod { kAnalytic, kBootstrap, kBoth };
const char* to_string(OptimismMethod m);

/// The Omega all models of a signal share (docs/statistics.md section 4: "from the data's WV,
/// or from the maximal model's fit").
enum class OmegaSource {
  /// diag(1 / Var(nuhat_j)) from the chi-square variance 2 nuhat_j^4 / eta_j: the data
  /// alone. Its weights at the coarsest levels (eta ~ 1) follow the noise of nuhat_j
  /// (the weight is ~ 1 / nuhat_j^2), which adds optimism the delta method does not see.
  kData,
  /// diag(1 / V_jj), V the model-based Cov(nuhat) at a pilot fit of the maximal model
  /// (under the data's Omega): a smooth function of all levels, so the analytic
  /// optimism's fixed-Omega assumption holds (bench_optimism). The default.
  kModel,
  /// V^-1 (full), V as for kModel: the objective is then chi-square scaled, so that the
  /// objective differences of nested models are too (the levels of long-memory
  /// components are strongly correlated, which a diagonal Omega ignores).
  kModelFull,
};
const char* to_string(OmegaSource o);
/// The inverses of to_string (nullopt for any other name): the one spelling the CLI and
/// Python parse with.
std::optional<Penalty> parse_penalty(const std::string& name);
std::optional<OptimismMethod> parse_optimism_method(const std::string& name);
std::optional<OmegaSource> parse_omega_source(const std::string& name);
/// The names each parser takes, in the order a user reads them (choice.h: every face's check
/// and refusal): wvic, bic; analytic, bootstrap, both; model, full, data.
std::vector<std::string> penalty_names();
std::vector<std::string> optimism_method_names();
std::vector<std::string> omega_source_names();

struct SelectOptions {
  Penalty penalty = Penalty::kWvic;
  OmegaSource omega = OmegaSource::kModel;
  OptimismMethod optimism = OptimismMethod::kAnalytic;
  /// Bootstrap optimism: replicates per model (issue 4 default 50), their seed, and the
  /// WV estimator of the simulated series (nullptr: classical; a robust selection passes
  /// its robust estimator so the replicates use the same WV).
  int bootstrap_replicates = 50;
  std::uint64_t seed = 0;
  const WvEstimator* estimator = nullptr;
  /// The WV of one bootstrap series drawn from a fitted model: given the signal's WV, the
  /// model, its theta and a stream number distinct per (signal, model, replicate). Empty:
  /// one series of the signal's length simulated with (seed, stream), its WV by
  /// `estimator`. The selection over replicates sets it to draw every replicate at its own
  /// length and stack their WVs.
  using BootstrapDraw = std::function<WaveletVariance(const WaveletVariance& wv, const Model& model,
                                                      const Eigen::VectorXd& theta, std::uint64_t stream)>;
  BootstrapDraw bootstrap_draw;
  /// Fit settings shared by every model (omega_matrix, inference, nested_starts and
  /// starts are set per signal/model by the selection).
  FitOptions fit;
  /// Called after each model fit and each bootstrap draw of the optimism with (done, total),
  /// from worker threads; may throw gmwm::Cancelled to stop the selection (error.h).
  std::function<void(int, int)> progress;
  /// Empty when valid, else one line.
  std::string Validate() const;
};

/// One candidate of a selection as fitted, and what it is in effect.
struct CandidateFit {
  std::string model;         ///< the candidate (canonical string, without values)
  FitResult fit;             ///< no inference
  EffectiveModel effective;  ///< its effective form (effective_model.h)
};

/// One row of a ranking: a distinct effective model (select_models; e.g. 3*AR1, 2*AR1+WN
/// and 2*AR1+WN+QN all being "2*AR1+WN" in effect), or one listed model (select_among).
/// Every number of a row is its own model's fit: the model fitted alone, from its members'
/// effective parameters and its own candidate fit (the better of the two); the members are
/// listed with their own objectives.
struct RankedModel {
  std::string model;  ///< the row's model (canonical string, without values)
  /// Candidates that fell onto it: the model itself first when it is a candidate, then by
  /// their own objectives; member_objectives[k] is members[k]'s own objective (NaN: failed).
  std::vector<std::string> members;
  std::vector<double> member_objectives;
  FitResult fit;  ///< the row model's own fit (no inference; see Selection::best_fit)
  /// The row model as fitted (model, theta); `reductions` are how `reduced_member` (its
  /// best-fitting member that was reduced) fell onto it, empty when none was.
  EffectiveModel effective;
  std::string reduced_member;
  int parameters = 0;  ///< the row model's parameters
  double objective = 0.0;
  double optimism = 0.0;   ///< the penalty added (analytic optimism or p log N)
  double criterion = 0.0;  ///< objective + optimism
  std::optional<double> optimism_analytic;
  Optimism analytic;                                                ///< its status and dropped components
  std::optional<double> optimism_bootstrap, optimism_bootstrap_se;  ///< and its Monte-Carlo s.e.
  int bootstrap_failed = 0;                                         ///< replicates whose refit failed (left out)
  int bootstrap_not_converged = 0;  ///< replicates whose refit stopped before convergence (kept)
  /// Goodness of fit under the selection's shared Omega and V (Satterthwaite),
  /// boundary components left out of A as for the optimism.
  GoodnessOfFit gof;
  int rank = 0;                                      ///< 1-based, under `criterion`
  std::optional<int> rank_analytic, rank_bootstrap;  ///< under each optimism (WVIC only)
};

struct Selection {
  std::string full_model;
  /// One row per distinct effective model, sorted by criterion (criteria within 1e-6
  /// relative are tied, and ties go to the smaller effective model).
  std::vector<RankedModel> ranking;
  std::vector<CandidateFit> candidates;  ///< every candidate as fitted, in the enumeration order
  int not_converged = 0;                 ///< candidates whose fit stopped before converging
  /// True when every ranked model is rejected by its goodness-of-fit test at 5%: no
  /// candidate describes the data (best_fit.worst_levels() says where the chosen one misses).
  bool all_rejected = false;
  int failed = 0;  ///< candidates whose fit failed (ranked last, criterion NaN)
  /// The first-ranked effective model refitted with inference (from its effective
  /// parameters; and from its own candidate fit when it is a candidate).
  FitResult best_fit;
  Eigen::MatrixXd omega;                          ///< shared by all models
  OmegaSource omega_source = OmegaSource::kData;  ///< how `omega` was formed (kData also when the caller gave it)
  Eigen::MatrixXd
      v;  ///< Cov(nuhat) for the optimism and GoF: model-based at the maximal model's fit (the pilot's with OmegaSource::kModel)
  int models = 0;
  /// Fit-quality check: pairs of candidates where one represents the other (nested, or
  /// through an equivalent form: model_relations.h) and still ends above it (relative
  /// tolerance 1e-9); 0 by construction.
  int representation_violations = 0;
};

/// The most distinct models a list may hold (select_among; `gmwm select --models`). Fitting
/// is linear in the list (one fit each, ~25 ms for a model of a few components on this
/// machine's cores), but the representation order among the models is a pairwise relation,
/// ~1 us a pair (representation_matrix: 0.56 s for 767 models): at 1000 models the pairs
/// take ~1 s against >= 25 s of fits. A longer list is better written as a maximal model,
/// whose sub-models select_models enumerates itself.
inline constexpr std::size_t kMaxListedModels = 1000;

/// Selection on each signal's WV. Throws InputError for invalid options or a maximal
/// model with more parameters than levels.
std::vector<Selection> select_models(const std::vector<WaveletVariance>& wvs, const Model& maximal,
                                     const SelectOptions& options = {});

/// The non-nested mode: only `models` are fitted and ranked (each with nested starts of
/// its own), on each signal; their smallest common super-model (common_supermodel) is
/// fitted too, warm-started from them, for the covariance V of the optimism, and is
/// Selection::full_model. Throws InputError for an empty list, more than kMaxListedModels
/// models, invalid options or a model with more parameters than levels. Each model should be
/// listed once (pipeline::study_select drops a repeated one): a copy is fitted again.
std::vector<Selection> select_among(const std::vector<WaveletVariance>& wvs, const std::vector<Model>& models,
                                    const SelectOptions& options = {});

}  // namespace gmwm::selection
