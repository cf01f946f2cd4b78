#pragma once
// The Jacobian of a model's WV without the parameters of some components: the goodness of
// fit of a selection's row leaves out the optimism's boundary components (select.cc), the
// selection over replicates does the same on the reduced WV (replicate_select.cc).
#include <algorithm>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm::selection::detail {

/// d nu / d theta at `tau`, the columns of the components listed in `dropped` left out.
inline Eigen::MatrixXd active_jacobian(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau,
                                       const std::vector<int>& dropped) {
  const Eigen::MatrixXd full = model.jacobian(theta, tau);
  std::vector<Eigen::Index> keep;
  for (int c = 0; c < model.num_components(); ++c) {
    if (std::find(dropped.begin(), dropped.end(), c) != dropped.end()) continue;
    for (int k = 0; k < model.components()[static_cast<std::size_t>(c)].process->size(); ++k)
      keep.push_back(model.offset(c) + k);
  }
  Eigen::MatrixXd A(full.rows(), static_cast<Eigen::Index>(keep.size()));
  for (Eigen::Index a = 0; a < A.cols(); ++a) A.col(a) = full.col(keep[static_cast<std::size_t>(a)]);
  return A;
}

}  // namespace gmwm::selection::detail
