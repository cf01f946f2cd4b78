// The joint model of each group's axis (fleet_joint.h): members (one rate, one unit) ->
// selection over replicates -> the recommended model's joint fit -> the shared-theta test and
// the replicate-t intervals -> the joint model's N, K, B.
#include "gmwm/fleet/fleet_joint.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>

#include "gmwm/engine/error.h"
#include "gmwm/engine/gappy_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/selection/replicate_select.h"

namespace gmwm::fleet {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Stage 1: a group's axis's units as replicates: their WVs in one unit (the data unit they
// share, else SI: a WV scales with the unit squared, its variance with the fourth power).
struct Members {
  std::vector<WaveletVariance> wvs;
  // Per unit, its simulated series read through its own gaps; empty when no unit has gaps.
  std::vector<std::unique_ptr<WvEstimator>> estimators;
  std::vector<std::string> left_out;  // the units that stand out on this axis
  std::string unit;
  double freq = NAN;
  std::int64_t n = 0;
  std::string why;  // non-empty: no joint model
};

double per_si(const FleetRow& r) {
  if (r.data_unit.empty()) return 1.0;
  try {
    return io::parse_any_unit(r.data_unit).second.per_si;
  } catch (const std::exception&) {
    return 1.0;
  }
}

WaveletVariance scaled(WaveletVariance wv, double factor) {
  const double f2 = factor * factor;
  for (auto* v : {&wv.wv, &wv.ci_low, &wv.ci_high})
    for (double& x : *v) x *= f2;
  for (double& x : wv.variance) x *= f2 * f2;
  return wv;
}

Members members(const FleetStudy& study, const std::string& group, const std::string& axis) {
  Members m;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < study.rows.size(); ++i) {
    const FleetRow& r = study.rows[i];
    if (r.group != group || r.axis != axis || r.status != "ok" || study.curves[i].wv.wv.empty()) continue;
    if (!r.flags.empty())
      m.left_out.push_back(r.unit);  // the typical unit's model is not the outliers'
    else
      rows.push_back(i);
  }
  if (rows.size() < 2) {
    m.why = "a joint model needs 2 units or more with a result, found " + std::to_string(rows.size());
    return m;
  }
  m.freq = study.rows[rows.front()].freq;
  bool same_unit = true;
  for (std::size_t i : rows) {
    const FleetRow& r = study.rows[i];
    if (!(std::abs(r.freq - m.freq) <= pipeline::kReplicateRateTolerance * m.freq)) {
      m.why = "the units' rates differ (" + study.rows[rows.front()].unit + " " + std::to_string(m.freq) + " Hz, " +
              r.unit + " " + std::to_string(r.freq) + " Hz): one model of the group would mix their scales";
      return m;
    }
    same_unit = same_unit && r.data_unit == study.rows[rows.front()].data_unit;
    m.n = std::max(m.n, r.n + missing_samples(study.curves[i].missing));  // the grid the WV read
  }
  m.unit = study.rows[rows.front()].data_unit;
  if (!same_unit) {
    try {
      m.unit = io::si_unit(io::sensor_kind_of_column(axis)).name;
    } catch (const std::exception&) {
      m.why = "the units declare different units and the column's name tells no sensor kind to convert them to";
      return m;
    }
  }
  for (std::size_t i : rows)
    m.wvs.push_back(same_unit ? study.curves[i].wv : scaled(study.curves[i].wv, 1.0 / per_si(study.rows[i])));
  if (std::any_of(rows.begin(), rows.end(), [&](std::size_t i) { return !study.curves[i].missing.empty(); }))
    for (std::size_t i : rows)
      m.estimators.push_back(
          study.curves[i].missing.empty() ? nullptr : std::make_unique<GappyWvEstimator>(study.curves[i].missing));
  return m;
}

// Stages 2-5 for one group's axis.
void analyse(FleetJointModel& out, const Members& m, const FleetStudyOptions& o) {
  ProcessContext context;
  context.freq = m.freq;
  context.freq_known = true;
  const Model maximal = o.model.bind(context);
  // Stage 2: the selection over the units (its own streams from the study's seed).
  selection::ReplicateSelectOptions so;
  so.select = o.select;
  so.select.progress = o.select.progress;
  so.seed = o.select.seed;
  std::vector<const WvEstimator*> own;  // each unit's gaps (null: the classical WV of a regular unit)
  for (const auto& e : m.estimators) own.push_back(e.get());
  so.estimators = own;
  const selection::ReplicateSelection sel = selection::select_by_replicates(m.wvs, maximal, so);
  out.recommended = sel.recommended;
  out.chosen = sel.chosen;
  // Stage 3: the recommended model's joint fit.
  FitOptions fo = o.select.fit;
  out.fit = fit_gmwm_joint(m.wvs, parse_model(sel.recommended, context), fo);
  const FitResult& j = out.fit.joint;
  if (j.status == FitStatus::kFailed || !j.theta.allFinite()) {
    out.status = "the joint fit of " + sel.recommended + " failed" + (j.message.empty() ? "" : ": " + j.message);
    return;
  }
  // Stage 4: do the units share one theta? (bootstrap for small groups, chi-square beyond)
  ReplicateTestOptions to;
  to.seed = o.select.seed;
  to.fit = fo;
  to.fit.inference = false;
  to.bootstrap = o.joint.test_draws;
  to.estimators = own;
  to.calibration =
      out.units <= kMaxBootstrapTestUnits ? ReplicateCalibration::kBootstrap : ReplicateCalibration::kChiSquare;
  out.test = replicate_test(m.wvs, out.fit, to);
  out.intervals = replicate_bootstrap(m.wvs, out.fit, fo.alpha, kJointIntervalDraws, o.select.seed, to.fit);
  // Stage 5: the joint model's figures, on the averaging factors of the longest unit.
  ReadoffOptions ro;
  ro.alpha = fo.alpha;
  const Eigen::MatrixXd* covariance = j.covariance.size() > 0 && j.covariance.allFinite() ? &j.covariance : nullptr;
  out.figures = model_only_figures(j.model, j.theta, m.freq, m.n, ro, covariance,
                                   "the joint model's Allan deviation (the group's units share the model)");
}

}  // namespace

std::vector<FleetJointModel> fleet_joint_models(const FleetStudy& study, const FleetStudyOptions& options) {
  std::vector<std::pair<std::string, std::string>> keys;
  for (const FleetRow& r : study.rows)
    if (!r.axis.empty() && std::find(keys.begin(), keys.end(), std::pair{r.group, r.axis}) == keys.end())
      keys.emplace_back(r.group, r.axis);
  std::vector<FleetJointModel> out;
  for (const auto& [group, axis] : keys) {
    const auto t = std::chrono::steady_clock::now();
    FleetJointModel jm;
    jm.group = group;
    jm.axis = axis;
    const Members m = members(study, group, axis);
    jm.units = static_cast<int>(m.wvs.size());
    jm.left_out = m.left_out;
    jm.unit = m.unit;
    jm.freq = m.freq;
    jm.n = m.n;
    if (!m.why.empty()) {
      jm.status = m.why;
    } else {
      try {
        analyse(jm, m, options);
      } catch (const Cancelled&) {
        throw;
      } catch (const std::exception& e) {
        jm.status = printable_line(e.what());
      }
    }
    jm.seconds = seconds_since(t);
    out.push_back(std::move(jm));
  }
  return out;
}

}  // namespace gmwm::fleet
