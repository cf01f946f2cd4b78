#pragma once
// The joint (multi-signal GMWM) model of a fleet's group: per axis, its units taken as
// replicates of one sensor (docs/multi-signal.md). The selection over replicates over the
// study's maximal model (cross-validated WVIC; random half-splits beyond 12 units) gives the
// recommended model, fitted jointly on every unit's WV, with the shared-theta test (do the
// units share one theta, or does each differ beyond its own noise?) and the replicate-t
// intervals (the units resampled). Its N, K, B are the figures of the group's typical unit:
// what a simulator of the whole fleet would take, with intervals that say how well the fleet
// pins them. It runs on the records' WVs alone (no series), so a cached or remote record
// serves as well.
//
//   o.joint.enabled = true;  // gmwm fleet --joint
//   const FleetStudy s = study_fleet(manifest, o);  // s.joint[k].recommended, .test, .figures

#include <vector>

#include "gmwm/fleet/fleet_study.h"

namespace gmwm::fleet {

/// The joint model of every group's axis with at least 2 units whose rows are "ok" (from
/// `study`'s rows and curves), under `options` (its maximal model, selection and fit
/// settings, seed, joint.test_draws). A group's axis that cannot have one (fewer than 2
/// units, units at different rates) is a model with its status, never an exception; the
/// result does not depend on the thread count. May throw gmwm::Cancelled through
/// options.progress.
std::vector<FleetJointModel> fleet_joint_models(const FleetStudy& study, const FleetStudyOptions& options);

}  // namespace gmwm::fleet
