#include "gmwm/robust/robust_request.h"

#include "gmwm/engine/choice.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::robust {

namespace {
constexpr RobustKind kRobustKinds[] = {RobustKind::kHuber, RobustKind::kBisquare};
}  // namespace

std::vector<std::string> robust_kind_names() { return names_among(kRobustKinds); }

std::optional<RobustWvOptions> robust_wv_options(const RobustRequest& request, const WvOptions& wv) {
  if (!request.robust) {
    if (request.eff) throw InputError("--eff " + significant(*request.eff) + ": only meaningful with --robust");
    if (request.estimator) throw InputError("--estimator " + *request.estimator + ": only meaningful with --robust");
    if (request.no_spike_screen) throw InputError("--no-spike-screen: only meaningful with --robust");
    return std::nullopt;
  }
  RobustWvOptions o;
  o.levels = wv.levels;
  o.alpha = wv.alpha;
  o.screen_spikes = !request.no_spike_screen;
  if (request.eff) {
    if (!(*request.eff > 0.0 && *request.eff < 1.0))
      throw InputError("--eff: found " + significant(*request.eff) +
                       ", expected a Gaussian efficiency strictly between 0 and 1 (e.g. 0.6)");
    o.efficiency = *request.eff;
  }
  if (request.estimator) {
    const auto kind = parse_robust_kind(*request.estimator);
    if (!kind) throw InputError("--estimator: " + unknown_choice(*request.estimator, robust_kind_names()));
    o.estimator = *kind;
  }
  if (const std::string why = o.Validate(); !why.empty()) throw InputError("--robust: " + why);
  return o;
}

}  // namespace gmwm::robust
