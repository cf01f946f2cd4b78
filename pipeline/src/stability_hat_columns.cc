// The three-cornered hat's rule on the record (stability_study.h): three columns.
#include "gmwm/engine/error.h"
#include "gmwm/pipeline/stability_study.h"

namespace gmwm::pipeline {

void require_hat_columns(const io::SignalSet& set) {
  if (set.signals.size() == stability::kHatSensors) return;
  std::string names;
  for (const io::Signal& s : set.signals) names += (names.empty() ? "" : ", ") + s.name;
  throw InputError((set.path.empty() ? std::string() : set.path + ": ") +
                   "--hat: the three-cornered hat reads three columns recorded together (--columns A,B,C), found " +
                   std::to_string(set.signals.size()) + (names.empty() ? std::string() : " (" + names + ")"));
}

}  // namespace gmwm::pipeline
