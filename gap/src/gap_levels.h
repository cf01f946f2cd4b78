#pragma once
// Per-level map and gap bands of the gap diagnosis (docs/gap.md, method note 2), internal to gap.cc.
#include <vector>

#include <Eigen/Core>

#include "gap_reference.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

/// The level (tau = 2^level samples) of the map's first entry: 1, or the first level a
/// diagnosis of a WV that drop_fine_levels cut compares (GapResult::first_level). A band's
/// first_level and last_level are levels, so levels[level - levels_from(levels)] is its entry.
int levels_from(const std::vector<GapLevel>& levels);

/// Runs of levels with |z| above z_threshold and |ratio - 1| above min_effect, of one sign.
std::vector<GapBand> find_bands(const std::vector<GapLevel>& levels, double z_threshold, double min_effect);

/// The levels' map of nuhat against a reference whose log mean is shifted by `shift`
/// (the reference of the base with added effects: replicates rescaled by nu_new / nu_base).
std::vector<GapLevel> map_levels(const WaveletVariance& wv, const Eigen::VectorXd& nuhat, const Reference& ref,
                                 const Eigen::VectorXd& nu_model, const Eigen::VectorXd& shift, double alpha);

/// RMS of log(nuhat_j / nu_j) over the bands' levels (0 without bands); nuhat and nu start
/// at level `first`.
double rms_log_ratio(const Eigen::VectorXd& nuhat, const Eigen::VectorXd& nu, const std::vector<GapBand>& bands,
                     int first);

}  // namespace gmwm::gap::detail
