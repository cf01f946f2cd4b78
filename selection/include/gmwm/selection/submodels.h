#pragma once
// The candidate models of a selection (docs/statistics.md section 6): every non-empty
// multiset of a maximal model's components. Components of the same process (same name
// and structure) are interchangeable slots, so 3*AR1+WN+RW+QN+DR has 4 x 2^4 - 1 = 63
// sub-models and 4*AR1+WN+RW has 5 x 2 x 2 - 1 = 19.
//
//   const gmwm::Model full = gmwm::parse_model("3*AR1+WN+RW+QN+DR");
//   const gmwm::selection::SubModelSet set = gmwm::selection::enumerate_submodels(full);
//   for (const auto& m : set.models) ... m.model, m.parents (one component fewer)
//
// Order: by number of components, then by the counts per process in canonical order
// (more of an earlier process first). It is fixed by the maximal model alone, so fits
// scheduled bottom-up in this order (each warm-started from its parents) give the same
// result whatever the thread count.

#include <string>
#include <vector>

#include "gmwm/engine/model.h"

namespace gmwm::selection {

/// One distinct process of the maximal model and how many slots it has.
struct ProcessGroup {
  Component prototype;  ///< the first such component of the maximal model (its given values)
  int slots = 0;
};

struct SubModel {
  Model model;              ///< canonical order
  std::vector<int> counts;  ///< per group of SubModelSet::groups, how many slots are used
  int size = 0;             ///< number of components
  /// Indices (into SubModelSet::models) of the sub-models with one component fewer
  /// (empty for single-component models). All precede this model in the order.
  std::vector<int> parents;
};

struct SubModelSet {
  std::vector<ProcessGroup> groups;  ///< canonical order of the maximal model
  std::vector<SubModel> models;      ///< ordered as described above; the last is the maximal model
  /// Index of the model with these counts, or -1.
  int find(const std::vector<int>& counts) const;
};

/// Every non-empty sub-model of `maximal`. Throws InvalidArgument for an empty model.
SubModelSet enumerate_submodels(const Model& maximal);

/// The smallest model containing every one of `models` (the non-nested mode: per
/// process, the largest number of slots any of them uses), canonical. Throws
/// InvalidArgument for an empty list.
Model common_supermodel(const std::vector<Model>& models);

/// The components of `m` that `sub` lacks, as "WN+QN" (for messages), given that sub is
/// nested in m.
std::string difference(const SubModelSet& set, int model, int sub);

}  // namespace gmwm::selection
