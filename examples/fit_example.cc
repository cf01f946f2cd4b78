// Simulates a gyro's white noise and random walk, computes the Haar wavelet variance,
// fits the model and selects among the sub-models of AR1+WN+RW, with gmwm as an
// installed library. Prints the estimates; exits non-zero when the fit misses the truth
// by more than 5 standard errors (the test suite runs it against the installed tree).
#include <cmath>
#include <cstdio>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/selection/select.h"
#include "gmwm/version.h"

int main() {
  try {
    std::printf("gmwm headers %s, library %s\n", GMWM_VERSION_STRING, gmwm::library_version());
    const gmwm::Model truth = gmwm::parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-9)");
    const std::int64_t n = std::int64_t{1} << 17;
    const std::vector<double> x = gmwm::simulate(truth, truth.given_values(), n, /*seed=*/42, /*stream=*/0);
    const gmwm::WaveletVariance wv = gmwm::classical_wv(x.data(), n);

    const gmwm::FitResult fit = gmwm::fit_gmwm(wv, gmwm::parse_model("WN+RW"));
    std::printf("%s", fit.Report().c_str());
    const Eigen::VectorXd t = truth.given_values();
    for (Eigen::Index i = 0; i < t.size(); ++i)
      if (!(std::abs(fit.theta(i) - t(i)) <= 5.0 * fit.se(i))) {
        std::fprintf(stderr, "fit_example: parameter %ld is %g, truth %g, se %g\n", static_cast<long>(i), fit.theta(i),
                     t(i), fit.se(i));
        return 1;
      }

    const auto selection = gmwm::selection::select_models({wv}, gmwm::parse_model("AR1+WN+RW"));
    std::printf("selected: %s among %d sub-models\n", selection.front().ranking.front().model.c_str(),
                selection.front().models);
    return 0;
  } catch (const gmwm::InputError& e) {
    std::fprintf(stderr, "fit_example: %s\n", e.what());
    return 2;
  }
}
