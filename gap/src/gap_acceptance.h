#pragma once
// The gap diagnosis' yardstick (docs/gap.md, "The acceptance rule", "The objective and the
// share removed"): the objective's weights, a model's fitness on the data (objective, its
// null mean, levels outside, global test), the acceptance of a move, and the assessor that
// keeps the yardstick for other models (the corrected configuration's gap left).
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gap_reference.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/gap/gap.h"

namespace gmwm::gap::detail {

// What every stage after the reference shares.
struct Context {
  const WaveletVariance& wv;
  const GapOptions& options;
  const detail::Reference& ref;
  const WaveletVariance* robust;
  const std::vector<double>* x;
  const std::vector<double>* temperature;
  /// The objective's weights (objective_weights).
  Eigen::MatrixXd omega;
  /// A record with gaps (options.missing): its observed samples, which only the
  /// contamination screen reads (x is then null: the time-domain stages need a regular series).
  const std::vector<double>* observed = nullptr;
};

// How well a model describes the current data: the objective, the levels outside its
// reference band (the baseline's reference shifted to the model) and the global p.
struct Fitness {
  double objective = 0.0;
  double null_mean = 0.0;  ///< E_m[G]: the objective's mean on data from the model itself
  int outside = 0;
  double distance = 0.0;  ///< the global test's statistic against the model's reference
  double p = 1.0;
  /// The model's excess X = max(G - E_m[G], 0) (docs/gap.md, "The objective and the share removed").
  double excess() const { return std::max(objective - null_mean, 0.0); }
};

/// Whether a level carries enough independent coefficients to decide anything alone.
bool decides(const WaveletVariance& wv, double tau, const GapOptions& o);

/// The weights 1 / Var(nuhat_j) under the model with WV `nu` (the reference's variance
/// rescaled to it), at the data's level where the data lie below that model.
/// objective_weights(wv, nuhat, ref, ref.nu, o) is the objective's (the baseline's).
Eigen::MatrixXd objective_weights(const WaveletVariance& wv, const Eigen::VectorXd& nuhat, const Reference& ref,
                                  const Eigen::VectorXd& nu, const GapOptions& o);

/// E[G] of a model (WV nu) on data from itself.
double null_mean(const Context& c, const Eigen::VectorXd& nu);

/// log(nu / nu_baseline): the reference shifted to a model.
Eigen::VectorXd log_shift(const Context& c, const Eigen::VectorXd& nu);

/// A model's fitness (WV nu) on `data`.
Fitness fitness(const Context& c, const Eigen::VectorXd& data, const Eigen::VectorXd& nu);

/// A move is taken when it lowers G - E_m[G] (see the definition's comment).
bool lowers(const Fitness& after, const Fitness& before);

/// One line for a refused move, with both fitnesses.
std::string refusal(const std::string& what, const Fitness& before, const Fitness& after);

/// The bands resting on at least one deciding level.
std::vector<GapBand> deciding_bands(const WaveletVariance& wv, std::vector<GapBand> bands, const GapOptions& o);

/// The two-sided Bonferroni z over `levels` levels at the options' alpha.
double bonferroni_z(const GapOptions& o, int levels);

/// The yardstick kept for other models: copies of what the stages shared, `data` the WV the
/// diagnosis compared last.
std::shared_ptr<GapAssessor> make_assessor(const Context& c, Eigen::VectorXd data);

}  // namespace gmwm::gap::detail
