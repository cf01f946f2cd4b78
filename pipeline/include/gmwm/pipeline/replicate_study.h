#pragma once
// Studies over replicates (several recordings of one sensor): the joint fit of one model per
// axis (MGMWM with the shared-theta test and replicate-t intervals) and the selection over
// replicates (cross-validated WVIC, with the joint fit's analytic and bootstrap WVIC beside
// it). What `gmwm fit --joint` and `gmwm select --joint` run; report::joint_fit_document and
// report::joint_select_document write them.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/joint_fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/samples.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/selection/replicate_select.h"

namespace gmwm::pipeline {

/// One axis and its replicates, the primary recording's column first.
struct ReplicateGroup {
  std::string axis;                  ///< the primary recording's column name
  std::vector<std::string> sources;  ///< "FILE:COLUMN" per replicate
  std::vector<Samples> series;       ///< per replicate (in memory or in temporary files, as read)
  /// Per replicate, its held and interpolated samples as reading found them (empty: none
  /// known): a held replicate's robust WV goes without the spike screen.
  std::vector<RepeatedSamples> repeated = {};
  /// Per replicate, the samples its timestamps (or NaN rows) show missing, on its grid
  /// (io::SignalSet::missing; empty: none): its WV reads the windows without a gap, and its
  /// simulated series (the shared-theta test, the bootstrap WVIC) are read through the same
  /// gaps. Empty, or one per replicate.
  std::vector<std::vector<MissingRun>> missing = {};

  /// The estimators of the replicates' simulated series, each read through its own gaps
  /// (robust when `robust` is given): empty when no replicate has gaps (every replicate then
  /// takes the study's one estimator).
  std::vector<std::unique_ptr<WvEstimator>> draw_estimators(const std::optional<robust::RobustWvOptions>& robust) const;
  /// Replicate k's missing samples (the sum of its runs' lengths) and gaps (its runs); 0 without.
  std::int64_t missing_samples(std::size_t k) const;
  std::int64_t gaps(std::size_t k) const {
    return k < missing.size() ? static_cast<std::int64_t>(missing[k].size()) : 0;
  }
};

/// Raw pointers to `owned` (ReplicateTestOptions::estimators, ReplicateSelectOptions::estimators).
std::vector<const WvEstimator*> estimator_pointers(const std::vector<std::unique_ptr<WvEstimator>>& owned);

/// A recording of the same sensor given as replicates: `set`'s columns are replicates of
/// the primary recording's columns of the same names, in order (`one_column` false), or its
/// single column is a replicate of the primary's single column (`one_column` true).
/// `label` names it in messages ("--joint run2.csv", "replicates[1]").
struct ReplicateRecording {
  std::string label;
  io::SignalSet set;
  bool one_column = false;
};

/// Rates that differ by less than this (relative) are the same rate: timestamps jitter,
/// and two recordings' estimated rates differ in their last digits (io's rate estimate).
inline constexpr double kReplicateRateTolerance = 1e-6;

/// The groups: per column of `primary` (named `primary_label` in messages), its series
/// then each recording's column, sources "PATH:COLUMN", each with its recording's gaps.
/// Throws InputError (one line naming the recording) when a recording's rate differs from
/// the primary's, its column count does not match, a series is given twice (the same
/// samples as another replicate), or a recording's grid is too long to simulate
/// (check_simulated_grid: the shared-theta test simulates it).
std::vector<ReplicateGroup> group_replicates(const io::SignalSet& primary, const std::string& primary_label,
                                             std::vector<ReplicateRecording> recordings);

/// Resamples of the replicates for the replicate-t intervals when they are too many to fit
/// every distinct one (C(2K-1, K) > 200 from K = 6 on).
inline constexpr int kReplicateBootstrapDraws = 200;

/// The WVs of a group's replicates (classical, or robust when `robust` is given), each
/// checked against `model`'s parameter count (InputError naming the replicate's source and
/// length).
std::vector<WaveletVariance> replicate_wvs(const ReplicateGroup& group, const Model& model, const WvOptions& options,
                                           const std::optional<robust::RobustWvOptions>& robust);

struct JointFitStudyOptions {
  ModelSpec model;
  /// The joint fit's settings (Omega diag or full, alpha, seed ...); `estimator` is set by
  /// the study and must be left null.
  FitOptions fit;
  WvOptions wv;
  std::optional<robust::RobustWvOptions> robust;
  /// Draws of the shared-theta test's parametric bootstrap, and its seed.
  int test_draws = ReplicateTestOptions{}.bootstrap;
  std::uint64_t seed = 0;
  /// (draws done, total) of the shared-theta test's bootstrap, per group; may throw
  /// gmwm::Cancelled to stop the study (error.h).
  std::function<void(int, int)> progress;

  std::string Validate() const;
};

struct JointFitGroupStudy {
  std::vector<WaveletVariance> wvs;  ///< per replicate
  JointAnalysis analysis;
  /// N, K, B of the joint model (joint_noise_figures); none when the rate is not known or
  /// the fit failed.
  std::optional<ChosenFigures> figures;
};

/// The noise figures of a group's joint model: read off the model's Allan deviation on the
/// averaging factors of the group's first recording (model_only_figures; the replicates
/// share the model, not one data curve). nullopt when the rate is unknown or the joint fit
/// has no finite estimate.
std::optional<ChosenFigures> joint_noise_figures(const JointFitResult& fit, const ReplicateGroup& group,
                                                 const ProcessContext& context, double alpha);

struct JointFitStudy {
  std::string model_spec;
  std::uint64_t seed = 0;
  bool robust = false;
  OmegaKind omega = OmegaKind::kDiag;
  std::vector<JointFitGroupStudy> groups;  ///< per ReplicateGroup
};

/// The joint analysis of each group (analyse_replicates) at the rate of `context`. Throws
/// InputError for invalid options, a model that does not parse, or a replicate too short.
JointFitStudy study_joint_fit(const std::vector<ReplicateGroup>& groups, const ProcessContext& context,
                              const JointFitStudyOptions& options);

/// The optimisms of a selection over replicates (select --joint, Python's select_joint), listed
/// once: replicates (the cross-validated WVIC) and all (the joint fit's analytic and bootstrap
/// WVIC beside it). A single recording's selection takes selection::optimism_method_names().
std::vector<std::string> replicate_optimism_names();

struct JointSelectStudyOptions {
  /// The maximal model: every sub-model is ranked.
  ModelSpec model;
  /// The selection's settings; select.optimism kBoth adds the joint fit's bootstrap WVIC
  /// ("all"), kAnalytic gives the cross-validated and the analytic WVIC. select.estimator
  /// is set by the study and must be left null.
  selection::ReplicateSelectOptions select;
  WvOptions wv;
  std::optional<robust::RobustWvOptions> robust;
  /// The recommended model of each axis is always fitted jointly (the result's values);
  /// > 0: with its shared-theta test of that many draws (what a report draws); 0: without.
  int recommended_test_draws = 0;

  std::string Validate() const;
};

struct JointSelectStudy {
  std::string model_spec;
  std::uint64_t seed = 0;
  bool robust = false;
  bool all_optimisms = false;
  std::vector<std::vector<WaveletVariance>> wvs;       ///< per group, per replicate
  std::vector<selection::ReplicateSelection> results;  ///< per group
  /// Per group: the recommended model fitted jointly on all replicates, oriented; its
  /// shared-theta test and replicate-t intervals only when recommended_test_draws > 0.
  std::vector<JointAnalysis> recommended;
  std::vector<std::optional<ChosenFigures>> figures;  ///< per group, of `recommended` (joint_noise_figures)
};

JointSelectStudy study_joint_select(const std::vector<ReplicateGroup>& groups, const ProcessContext& context,
                                    const JointSelectStudyOptions& options);

}  // namespace gmwm::pipeline
