#pragma once
// Which models can represent which (beyond nesting), and starting points that follow.
//
// A model M represents a model S when every component of S can be taken by a distinct
// component of M (Process::represent: the same process, or one that contains it exactly
// or in a limit, such as AR1 with phi = 0 for WN, AR1 with phi -> 1 for RW, MA1 with
// theta -> -1 for QN), the components of M left over vanishing. M's best objective is
// then never above S's, so a fit of M is warm-started from S's optimum mapped into M
// (represent_start), and a model-selection run orders its fits along this relation
// (representation_covers), not only along nesting.
//
//   if (auto start = gmwm::represent_start(super, sub_fit.model, sub_fit.theta, wv)) options.starts.push_back(*start);

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {

/// For each component of `sub`, the component of `super` that takes it, with that
/// component's parameters; nullopt when `super` cannot represent `sub` at `theta_sub`.
/// Same-process assignments are preferred, so a nested model maps onto itself.
struct Representation {
  std::vector<int> slot;                   ///< per component of sub: a component of super
  std::vector<std::vector<double>> theta;  ///< per component of sub: the slot's parameters
};
std::optional<Representation> representation(const Model& super, const Model& sub, const Eigen::VectorXd& theta_sub);

/// Whether `super` can represent `sub` for typical parameter values (structure only).
bool represents(const Model& super, const Model& sub);

/// A starting point for `super` reproducing the fit (sub, theta_sub): the represented
/// components take their mapped parameters, the others a negligible size (1e-12 of the
/// data's WV). nullopt when super cannot represent sub there.
std::optional<Eigen::VectorXd> represent_start(const Model& super, const Model& sub, const Eigen::VectorXd& theta_sub,
                                               const WaveletVariance& wv);

/// Models one step below `model` in the representation order: one component removed,
/// or one component replaced by a simpler process it represents (AR1 -> WN, RW; MA1 ->
/// WN, QN; ...). Distinct, canonical, in a fixed order.
std::vector<Model> representation_neighbours(const Model& model);

/// rep[i][k]: models[i] represents models[k] (i != k, and not both ways: a model listed
/// twice orders nothing). O(K^2) structural checks.
std::vector<std::vector<bool>> representation_matrix(const std::vector<Model>& models);

/// For each i, the indices k that models[i] represents with nothing in between (no m
/// with rep[i][m] and rep[m][k]). Only i's covers need warm-starting i: the rest are
/// represented through them. Acyclic, so fits can run along it.
std::vector<std::vector<int>> representation_covers(const std::vector<std::vector<bool>>& rep);

}  // namespace gmwm
