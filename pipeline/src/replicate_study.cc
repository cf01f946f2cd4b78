// Studies over replicates: per group, the replicates' WVs, then the joint analysis
// (analyse_replicates) or the selection over replicates (select_by_replicates).
#include "gmwm/pipeline/replicate_study.h"

#include <memory>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::pipeline {
namespace {

std::vector<std::span<const double>> spans_of(const ReplicateGroup& g) { return {g.series.begin(), g.series.end()}; }

std::unique_ptr<robust::RobustWvEstimator> estimator_for(const std::optional<robust::RobustWvOptions>& robust) {
  return robust ? std::make_unique<robust::RobustWvEstimator>(*robust) : nullptr;
}

}  // namespace

std::vector<WaveletVariance> replicate_wvs(const ReplicateGroup& group, const Model& model, const WvOptions& options,
                                           const std::optional<robust::RobustWvOptions>& robust) {
  const std::vector<std::span<const double>> series = spans_of(group);
  std::vector<WaveletVariance> wvs = robust ? robust::robust_wv(series, *robust) : classical_wv(series, options);
  for (std::size_t k = 0; k < wvs.size(); ++k) {
    try {
      check_model_fits_levels(model, wvs[k].levels());
    } catch (const InputError& e) {
      throw InputError(group.sources[k] + " (" + std::to_string(group.series[k].size()) + " samples): " + e.what());
    }
  }
  return wvs;
}

std::string JointFitStudyOptions::Validate() const {
  if (model.empty()) return "the model is empty";
  if (fit.estimator) return "leave FitOptions::estimator null: the study sets it";
  if (fit.omega == OmegaKind::kBootstrap) return "the joint fit takes Omega diag or full";
  if (std::string why = fit.Validate(); !why.empty()) return why;
  ReplicateTestOptions t;
  t.bootstrap = test_draws;
  if (std::string why = t.Validate(); !why.empty()) return "--replicates: " + why;
  return wv.Validate();
}

JointFitStudy study_joint_fit(const std::vector<ReplicateGroup>& groups, const ProcessContext& context,
                              const JointFitStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  const Model model = parse_model(options.model, context);
  // The joint fit's bootstrap and the test's draws get the data's WV estimator.
  const auto estimator = estimator_for(options.robust);
  JointAnalysisOptions ao;
  ao.fit = options.fit;
  ao.fit.estimator = estimator.get();
  ao.test.bootstrap = options.test_draws;
  ao.test.seed = options.seed;
  ao.test.estimator = estimator.get();
  ao.bootstrap_draws = kReplicateBootstrapDraws;
  JointFitStudy study{options.model, options.seed, options.robust.has_value(), options.fit.omega, {}};
  for (const ReplicateGroup& g : groups) {
    JointFitGroupStudy s;
    s.wvs = replicate_wvs(g, model, options.wv, options.robust);
    const std::vector<std::span<const double>> series = spans_of(g);
    s.analysis = analyse_replicates(s.wvs, series, model, ao);
    study.groups.push_back(std::move(s));
  }
  return study;
}

std::string JointSelectStudyOptions::Validate() const {
  if (model.empty()) return "the model is empty";
  if (select.select.estimator) return "leave SelectOptions::estimator null: the study sets it";
  if (std::string why = select.Validate(); !why.empty()) return why;
  if (recommended_test_draws > 0) {
    ReplicateTestOptions t;
    t.bootstrap = recommended_test_draws;
    if (std::string why = t.Validate(); !why.empty()) return why;
  }
  return wv.Validate();
}

JointSelectStudy study_joint_select(const std::vector<ReplicateGroup>& groups, const ProcessContext& context,
                                    const JointSelectStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  const Model maximal = parse_model(options.model, context);
  const auto estimator = estimator_for(options.robust);
  selection::ReplicateSelectOptions ro = options.select;
  ro.select.estimator = estimator.get();
  JointSelectStudy study;
  study.model_spec = options.model;
  study.seed = options.select.seed;
  study.robust = options.robust.has_value();
  study.all_optimisms = options.select.select.optimism == selection::OptimismMethod::kBoth;
  for (const ReplicateGroup& g : groups) study.wvs.push_back(replicate_wvs(g, maximal, options.wv, options.robust));
  study.results = selection::select_by_replicates(study.wvs, maximal, ro);
  if (options.recommended_test_draws > 0) {
    // The recommended model of each axis fitted jointly, with its shared-theta test and
    // replicate-t intervals.
    JointAnalysisOptions ao;
    ao.fit = options.select.select.fit;
    ao.test.bootstrap = options.recommended_test_draws;
    ao.test.seed = options.select.seed;
    ao.test.estimator = estimator.get();
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const std::vector<std::span<const double>> series = spans_of(groups[i]);
      study.recommended.push_back(
          analyse_replicates(study.wvs[i], series, parse_model(study.results[i].recommended, context), ao));
    }
  }
  return study;
}

}  // namespace gmwm::pipeline
