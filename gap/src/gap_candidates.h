#pragma once
// The candidate effects of the gap diagnosis (docs/gap.md, method note 3), internal to gap.cc: the
// catalogue, each candidate's fit on top of the current base (fixed, or re-estimated with
// it), its threshold calibrated on the base's own replicates, and its bootstrap intervals.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

/// The finest levels where outliers show first (docs/gap.md, method note 3: robust/classical
/// ratio at tau = 2..8).
inline constexpr int kOutlierLevels = 3;

/// One gap effect as every part of gap reads it (the names, the attribution's candidates,
/// gap-check's injections): its name as to_string writes it, the latent process the WV
/// attribution adds for it (nullptr: none) and whether the attribution tries it.
struct EffectEntry {
  GapEffect effect;
  const char* name;
  const char* process;
  bool wv_candidate;
};
/// Every effect once, in GapEffect's order (the attribution tries the candidates in it).
std::span<const EffectEntry> effect_table();
/// e's entry in effect_table().
const EffectEntry& effect_entry(GapEffect e);

struct CandidateSpec {
  GapEffect effect;
  const char* process;  ///< added process (nullptr: REPARAMETERISE)
};

/// The base as the candidates see it: its family, its values and its WV.
struct Base {
  Model model;
  Eigen::VectorXd theta;
  Eigen::VectorXd nu;
};

struct Step {
  std::vector<GapCandidate> scored;
  int best = -1;  ///< index into scored, -1 when nothing cleared
};

/// True when a component of m plays role r (ProcessRole: asked of the process).
bool has_role(const Model& m, ProcessRole r);

/// The candidates tried against `base` (see gap_candidates.cc).
std::vector<CandidateSpec> candidates_for(const Model& base, const GapOptions& o);

/// (target - nu)' omega (target - nu).
double objective(const Eigen::VectorXd& target, const Eigen::VectorXd& nu, const Eigen::MatrixXd& omega);

/// Scores every candidate on the data and calibrates it on the replicates (rows of `reps`,
/// data from the base alone).
Step score_step(const std::vector<CandidateSpec>& specs, const Base& base, const Eigen::VectorXd& nuhat,
                const Eigen::MatrixXd& reps, const WaveletVariance& like, const Eigen::MatrixXd& omega,
                const GapOptions& o);

/// Percentile intervals of the effect chosen at a step (fills fit.se, ci_low, ci_high).
void effect_intervals(const CandidateSpec& spec, const Base& base, const Eigen::MatrixXd& reps_augmented,
                      const WaveletVariance& like, const Eigen::MatrixXd& omega, const GapOptions& o,
                      const FitResult& chosen, FitResult& fit);

/// The base's family re-estimated on `target` (REPARAMETERISE's fit: from the base's values
/// and the family's sub-models, the objective's weights `omega`).
FitResult refit_family(const Base& base, const Eigen::VectorXd& target, const WaveletVariance& like,
                       const Eigen::MatrixXd& omega, const GapOptions& o);

/// The added effect's component of a refitted augmented model (base family + effect).
FitResult effect_part(const FitResult& augmented, const Base& base);

}  // namespace gmwm::gap::detail
