#pragma once
// The selection over replicates' ranking as a reader sees it (HTML and terminal): each
// effective model once, at its best-ranked candidate, with the candidates that fell onto
// it (a maximal model of six terms has 63 candidates and far fewer distinct models).
#include <string>
#include <vector>

#include "gmwm/selection/replicate_select.h"

namespace gmwm::report::detail {

struct FoldedRow {
  const selection::CvCandidate* best = nullptr;       ///< the best-ranked candidate of its effective model
  std::vector<const selection::CvCandidate*> others;  ///< the other candidates that fell onto it, by rank
  bool chosen = false, recommended = false;           ///< one of its candidates is the chosen / recommended one
};

/// The ranking (already by CV-WVIC) folded by effective model, in rank order.
inline std::vector<FoldedRow> fold_by_effective(const selection::ReplicateSelection& s) {
  std::vector<FoldedRow> rows;
  for (const selection::CvCandidate& c : s.ranking) {
    const std::string& key = c.effective.empty() ? c.model : c.effective;
    FoldedRow* row = nullptr;
    for (FoldedRow& r : rows)
      if ((r.best->effective.empty() ? r.best->model : r.best->effective) == key) row = &r;
    if (row)
      row->others.push_back(&c);
    else
      rows.push_back({&c, {}, false, false});
    FoldedRow& r = row ? *row : rows.back();
    r.chosen = r.chosen || c.model == s.chosen;
    r.recommended = r.recommended || c.model == s.recommended;
  }
  return rows;
}

/// The row's effective model, with its best candidate when that is another model:
/// "AR1+WN (best as 2*AR1+WN)".
inline std::string folded_name(const FoldedRow& r) {
  const std::string& e = r.best->effective.empty() ? r.best->model : r.best->effective;
  return e == r.best->model ? e : e + " (best as " + r.best->model + ")";
}

}  // namespace gmwm::report::detail
