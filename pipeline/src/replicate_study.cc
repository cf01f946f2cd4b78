// Studies over replicates: per group, the replicates' WVs, then the joint analysis
// (analyse_replicates) or the selection over replicates (select_by_replicates).
#include "gmwm/pipeline/replicate_study.h"
#include "column_wvs.h"
#include "usable_wv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <span>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"

namespace gmwm::pipeline {

std::vector<std::string> replicate_optimism_names() { return {"replicates", "all"}; }

namespace {

std::vector<std::span<const double>> spans_of(const ReplicateGroup& g) { return {g.series.begin(), g.series.end()}; }

std::unique_ptr<robust::RobustWvEstimator> estimator_for(const std::optional<robust::RobustWvOptions>& robust) {
  return robust ? std::make_unique<robust::RobustWvEstimator>(*robust) : nullptr;
}

// What simulates a replicate's grid, in check_simulated_grid's refusal.
constexpr const char* kJointTestName = "the shared-theta test of replicates";

bool has_gaps(const ReplicateGroup& g) {
  return std::any_of(g.missing.begin(), g.missing.end(), [](const auto& m) { return !m.empty(); });
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
  // The shared-theta test simulates each replicate over its whole grid (observed and missing).
  detail::check_simulated_grid(primary, kJointTestName);
  for (const ReplicateRecording& r : recordings) detail::check_simulated_grid(r.set, kJointTestName);
  for (const auto& s : primary.signals)
    groups.push_back({s.name, {primary.path + ":" + s.name}, {s.values}, {s.repeated}, {primary.missing}});
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
      g.missing.push_back(r.set.missing);
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
  // On the first replicate's grid (its observed and missing samples: the span its WV reads).
  const std::int64_t grid = static_cast<std::int64_t>(group.series.front().size()) + group.missing_samples(0);
  return model_only_figures(j.model, j.theta, context.freq, grid, ro, covariance,
                            "the joint model's Allan deviation (the replicates share the model)");
}

std::vector<std::unique_ptr<WvEstimator>> ReplicateGroup::draw_estimators(
    const std::optional<robust::RobustWvOptions>& robust) const {
  std::vector<std::unique_ptr<WvEstimator>> out;
  if (!has_gaps(*this)) return out;
  for (std::size_t k = 0; k < series.size(); ++k)
    out.push_back(detail::draw_estimator(k < missing.size() ? missing[k] : std::vector<MissingRun>{}, robust));
  return out;
}

std::int64_t ReplicateGroup::missing_samples(std::size_t k) const {
  return k < missing.size() ? gmwm::missing_samples(missing[k]) : 0;
}

std::vector<const WvEstimator*> estimator_pointers(const std::vector<std::unique_ptr<WvEstimator>>& owned) {
  std::vector<const WvEstimator*> out;
  for (const auto& e : owned) out.push_back(e.get());
  return out;
}

namespace {

// The WVs of a group's replicates: regular ones together (classical_wv, robust_wvs_of), each
// one with gaps from its windows without a gap (gappy_wv_of).
std::vector<WaveletVariance> wvs_of(const ReplicateGroup& group, const WvOptions& options,
                                    const std::optional<robust::RobustWvOptions>& robust) {
  const std::vector<std::span<const double>> series = spans_of(group);
  const auto gappy = [&](std::size_t k) { return k < group.missing.size() && !group.missing[k].empty(); };
  const auto repeated_of = [&](std::size_t k) { return k < group.repeated.size() ? &group.repeated[k] : nullptr; };
  std::vector<std::span<const double>> regular;
  std::vector<const RepeatedSamples*> repeated;
  for (std::size_t k = 0; k < series.size(); ++k)
    if (!gappy(k)) {
      regular.push_back(series[k]);
      repeated.push_back(repeated_of(k));
    }
  std::vector<WaveletVariance> done = regular.empty() ? std::vector<WaveletVariance>()
                                      : robust        ? detail::robust_wvs_of(regular, repeated, *robust)
                                                      : classical_wv(regular, options);
  std::vector<WaveletVariance> wvs(series.size());
  std::size_t next = 0;
  gmwm::parallel_for(std::size_t{0}, series.size(), [&](std::size_t k) {
    if (gappy(k))
      wvs[k] = detail::gappy_wv_of(series[k], group.missing[k], repeated_of(k), options, robust ? &*robust : nullptr);
  });
  for (std::size_t k = 0; k < series.size(); ++k)
    if (!gappy(k)) wvs[k] = std::move(done[next++]);
  return wvs;
}

}  // namespace

std::vector<WaveletVariance> replicate_wvs(const ReplicateGroup& group, const Model& model, const WvOptions& options,
                                           const std::optional<robust::RobustWvOptions>& robust) {
  const std::vector<std::span<const double>> series = spans_of(group);
  std::vector<WaveletVariance> wvs = wvs_of(group, options, robust);
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
    const auto own = g.draw_estimators(options.robust);  // each replicate's gaps
    ao.test.estimators = estimator_pointers(own);
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
  // Each replicate's simulated series read through its own gaps (its recording's, the same
  // on every axis); none when no replicate has gaps.
  const auto own =
      groups.empty() ? std::vector<std::unique_ptr<WvEstimator>>() : groups.front().draw_estimators(options.robust);
  ro.estimators = estimator_pointers(own);
  study.results = selection::select_by_replicates(study.wvs, maximal, ro);
  // The recommended model of each axis fitted jointly (the values a consumer takes), with
  // its shared-theta test and replicate-t intervals when asked.
  JointAnalysisOptions ao;
  ao.fit = options.select.select.fit;
  ao.fit.estimator = estimator.get();
  ao.test.seed = options.select.seed;
  ao.test.estimator = estimator.get();
  ao.test.estimators = ro.estimators;
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
