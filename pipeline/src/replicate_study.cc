// Studies over replicates: per group, the replicates' WVs, then the joint analysis
// (analyse_replicates) or the selection over replicates (select_by_replicates).
#include "gmwm/pipeline/replicate_study.h"
#include "column_wvs.h"
#include "usable_wv.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::pipeline {

std::vector<std::string> replicate_optimism_names() { return {"replicates", "all"}; }

namespace {

std::vector<std::span<const double>> spans_of(const ReplicateGroup& g) { return {g.series.begin(), g.series.end()}; }

std::unique_ptr<robust::RobustWvEstimator> estimator_for(const std::optional<robust::RobustWvOptions>& robust) {
  return robust ? std::make_unique<robust::RobustWvEstimator>(*robust) : nullptr;
}

std::string rate_text(double hz) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", hz);
  return buf;
}

}  // namespace

std::vector<ReplicateGroup> group_replicates(const io::SignalSet& primary, const std::string& primary_label,
                                             std::vector<ReplicateRecording> recordings) {
  std::vector<ReplicateGroup> groups;
  detail::require_regular(primary, "a fit of replicates");
  for (const ReplicateRecording& r : recordings) detail::require_regular(r.set, "a fit of replicates");
  for (const auto& s : primary.signals)
    groups.push_back({s.name, {primary.path + ":" + s.name}, {s.values}, {s.repeated}});
  for (ReplicateRecording& r : recordings) {
    const std::size_t expected = r.one_column ? 1 : groups.size();
    if (r.one_column && groups.size() != 1)
      throw InputError(r.label + ": one column, a replicate of one column, but " + primary_label + " has " +
                       std::to_string(groups.size()) + " columns");
    if (r.set.signals.size() != expected)
      throw InputError(r.label + ": has " + std::to_string(r.set.signals.size()) + " columns, expected " +
                       std::to_string(expected) + " (those of " + primary_label + ")");
    if (std::abs(r.set.freq / primary.freq - 1.0) > kReplicateRateTolerance)
      throw InputError(r.label + ": sampled at " + rate_text(r.set.freq) + " Hz, " + primary_label + " at " +
                       rate_text(primary.freq) + " Hz; replicates must share the rate");
    for (std::size_t k = 0; k < r.set.signals.size(); ++k) {
      ReplicateGroup& g = groups[r.one_column ? 0 : k];
      const std::string source = r.set.path + ":" + r.set.signals[k].name;
      for (std::size_t i = 0; i < g.series.size(); ++i)
        if (g.series[i] == r.set.signals[k].values)
          throw InputError(r.label + ": " + source + " is the same recording as " + g.sources[i] +
                           " (a replicate given twice)");
      g.sources.push_back(source);
      g.series.push_back(std::move(r.set.signals[k].values));  // the recording's copy is not kept
      g.repeated.push_back(r.set.signals[k].repeated);
    }
  }
  return groups;
}

std::optional<ChosenFigures> joint_noise_figures(const JointFitResult& fit, const ReplicateGroup& group,
                                                 const ProcessContext& context, double alpha) {
  const FitResult& j = fit.joint;
  if (!context.freq_known || group.series.empty() || j.status == FitStatus::kFailed ||
      j.theta.size() != j.model.num_parameters() || !j.theta.allFinite())
    return std::nullopt;
  ReadoffOptions ro;
  ro.alpha = alpha;
  const Eigen::MatrixXd* covariance = j.covariance.size() > 0 && j.covariance.allFinite() ? &j.covariance : nullptr;
  return model_only_figures(j.model, j.theta, context.freq, static_cast<std::int64_t>(group.series.front().size()), ro,
                            covariance, "the joint model's Allan deviation (the replicates share the model)");
}

std::vector<WaveletVariance> replicate_wvs(const ReplicateGroup& group, const Model& model, const WvOptions& options,
                                           const std::optional<robust::RobustWvOptions>& robust) {
  const std::vector<std::span<const double>> series = spans_of(group);
  std::vector<const RepeatedSamples*> repeated;
  for (const RepeatedSamples& r : group.repeated) repeated.push_back(&r);
  repeated.resize(series.size(), nullptr);
  std::vector<WaveletVariance> wvs =
      robust ? detail::robust_wvs_of(series, repeated, *robust) : classical_wv(series, options);
  for (std::size_t k = 0; k < wvs.size(); ++k)
    detail::check_usable_wv(group.sources[k] + ": ", wvs[k], series[k], true);
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
  const Model model = options.model.bind(context);
  // The joint fit's bootstrap and the test's draws get the data's WV estimator.
  const auto estimator = estimator_for(options.robust);
  JointAnalysisOptions ao;
  ao.fit = options.fit;
  ao.fit.estimator = estimator.get();
  ao.test.bootstrap = options.test_draws;
  ao.test.seed = options.seed;
  ao.test.estimator = estimator.get();
  ao.test.progress = options.progress;
  ao.bootstrap_draws = kReplicateBootstrapDraws;
  JointFitStudy study{options.model.text(), options.seed, options.robust.has_value(), options.fit.omega, {}};
  for (const ReplicateGroup& g : groups) {
    JointFitGroupStudy s;
    s.wvs = replicate_wvs(g, model, options.wv, options.robust);
    const std::vector<std::span<const double>> series = spans_of(g);
    s.analysis = analyse_replicates(s.wvs, series, model, ao);
    s.figures = joint_noise_figures(s.analysis.fit, g, context, options.fit.alpha);
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
  const Model maximal = options.model.bind(context);
  const auto estimator = estimator_for(options.robust);
  selection::ReplicateSelectOptions ro = options.select;
  ro.select.estimator = estimator.get();
  JointSelectStudy study;
  study.model_spec = options.model.text();
  study.seed = options.select.seed;
  study.robust = options.robust.has_value();
  study.all_optimisms = options.select.select.optimism == selection::OptimismMethod::kBoth;
  for (const ReplicateGroup& g : groups) study.wvs.push_back(replicate_wvs(g, maximal, options.wv, options.robust));
  study.results = selection::select_by_replicates(study.wvs, maximal, ro);
  // The recommended model of each axis fitted jointly (the values a consumer takes), with
  // its shared-theta test and replicate-t intervals when asked.
  JointAnalysisOptions ao;
  ao.fit = options.select.select.fit;
  ao.fit.estimator = estimator.get();
  ao.test.seed = options.select.seed;
  ao.test.estimator = estimator.get();
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const std::vector<std::span<const double>> series = spans_of(groups[i]);
    const Model recommended = parse_model(study.results[i].recommended, context);
    JointAnalysis a;
    if (options.recommended_test_draws > 0) {
      ao.test.bootstrap = options.recommended_test_draws;
      a = analyse_replicates(study.wvs[i], series, recommended, ao);
    } else {
      a.fit = fit_gmwm_joint(study.wvs[i], recommended, ao.fit);
      a.pooled_slope = orient_by_replicates(a.fit, series);
    }
    study.figures.push_back(joint_noise_figures(a.fit, groups[i], context, ao.fit.alpha));
    study.recommended.push_back(std::move(a));
  }
  return study;
}

}  // namespace gmwm::pipeline
