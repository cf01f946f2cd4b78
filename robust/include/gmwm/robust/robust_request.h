#pragma once
// The robust WV as every face asks for it: the command line's --robust, --eff, --estimator
// and --no-spike-screen, the web app's fields and Python's keywords of the same names fill
// one RobustRequest, checked by one function whose messages name the CLI options (each face
// rewords them: io::option_wording). Issue 45: the three faces checked these on their own,
// with three sets of messages, and Python's robust WV ignored `levels`.

#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::robust {

struct RobustRequest {
  bool robust = false;                   ///< --robust
  std::optional<double> eff;             ///< --eff E: the target Gaussian efficiency, in (0, 1)
  std::optional<std::string> estimator;  ///< --estimator NAME (robust_kind_names)
  bool no_spike_screen = false;          ///< --no-spike-screen
};

/// huber, bisquare: the names parse_robust_kind takes, in RobustKind's order.
std::vector<std::string> robust_kind_names();

/// The robust WV settings of `request` with the classical WV's levels and alpha, or nullopt
/// without --robust. Throws InputError naming the option: "--eff 0.8: only meaningful with
/// --robust", "--eff: found 1.5, expected a Gaussian efficiency strictly between 0 and 1
/// (e.g. 0.6)", "--estimator: found 'tukey', expected huber or bisquare".
std::optional<RobustWvOptions> robust_wv_options(const RobustRequest& request, const WvOptions& wv);

}  // namespace gmwm::robust
