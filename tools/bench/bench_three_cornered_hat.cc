// The three-cornered hat's intervals against an oracle (issue 48, item 7;
// stability/three_cornered_hat.h): three independent simulated sensors of known noise levels
// (white FM, random-walk FM, or one of each), many seeds; at each averaging factor, how often
// the known true deviation of each sensor lies inside its interval (the score interval the
// library gives, and for comparison the chi-square interval with the moment-matched
// Satterthwaite edf read at the estimate), how often the separated variance is negative and
// how often no interval is given. The truth of a kind at factor m is the expectation of its
// squared estimator: for white FM of unit variance the trace of its quadratic form, the sum of
// its values on the N unit impulses; for random-walk FM the sum on the N unit steps.
//
//   bench_three_cornered_hat [SEEDS] [N]   (defaults 1000, 4096)
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

#include "bench_common.h"
#include "gmwm/stability/confidence.h"
#include "gmwm/stability/deviation.h"
#include "gmwm/stability/three_cornered_hat.h"

namespace {

using gmwm::stability::DeviationCurve;
using gmwm::stability::DeviationIntervals;
using gmwm::stability::DeviationKind;

// A sensor: white FM of standard deviation `white` plus random-walk FM of step `walk`.
struct Sensor {
  double white = 0.0, walk = 0.0;
};
struct Config {
  std::string name;
  std::array<Sensor, 3> sensors;
};

std::vector<double> simulate(const Sensor& s, std::size_t n, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double level = 0.0;
  for (double& v : y) {
    level += s.walk * g(rng);
    v = s.white * g(rng) + level;
  }
  return y;
}

// The expected squared deviation of `kind` at `m` for unit white FM (impulses) or unit
// random-walk FM (steps): the trace of the quadratic form.
std::vector<double> unit_truth(DeviationKind kind, std::size_t n, const std::vector<std::int64_t>& m, bool walk) {
  std::vector<double> sum(m.size(), 0.0);
  std::vector<double> y(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    std::fill(y.begin(), y.end(), 0.0);
    for (std::size_t i = k; i < (walk ? n : k + 1); ++i) y[i] = 1.0;
    const DeviationCurve c = gmwm::stability::deviation(kind, gmwm::stability::phase_from_frequency(y, 1.0), 1.0, m);
    for (std::size_t i = 0; i < m.size(); ++i) sum[i] += c.value[i] * c.value[i];
  }
  return sum;
}

// The chi-square interval of a separated variance with the moment-matched edf read at the
// estimate (the rule the library does not use): NaN where the estimate is not positive.
std::array<double, 2> plug_in_chi_square(double v, double others_sum, double others_product, double edf, double p) {
  if (!(v > 0.0) || !std::isfinite(edf)) return {NAN, NAN};
  // nu = edf 2 v^2 / (2 v^2 + v S + P): the separated variance's edf, read at the estimate.
  const double own =
      edf * 2.0 * v * v / gmwm::stability::separated_variance_variance(v, others_sum, others_product, 1.0);
  const boost::math::chi_squared_distribution<double> chi2(own);
  return {v * own / boost::math::quantile(chi2, (1.0 + p) / 2.0),
          v * own / boost::math::quantile(chi2, (1.0 - p) / 2.0)};
}

struct Tally {
  std::vector<double> covered, given, negative, plug_covered, plug_given, edf;
};

void run(const Config& config, DeviationKind kind, std::size_t n, int seeds, double confidence) {
  const auto m = gmwm::stability::factors(gmwm::stability::TauSet::kOctave, kind, static_cast<std::int64_t>(n) + 1);
  const std::vector<double> white = unit_truth(kind, n, m, false), walk = unit_truth(kind, n, m, true);
  Tally t{std::vector<double>(m.size()), std::vector<double>(m.size()), std::vector<double>(m.size()),
          std::vector<double>(m.size()), std::vector<double>(m.size()), std::vector<double>(m.size())};
  gmwm::stability::IntervalOptions options;
  options.confidence = confidence;
  options.method = gmwm::stability::IntervalMethod::kExact;
  for (int seed = 0; seed < seeds; ++seed) {
    std::mt19937_64 rng(1000003ULL * static_cast<unsigned>(seed) + 17);
    std::array<std::vector<double>, 3> y;
    for (std::size_t s = 0; s < 3; ++s) y[s] = simulate(config.sensors[s], n, rng);
    std::array<DeviationCurve, 3> pairs;
    std::array<DeviationIntervals, 3> ci;
    for (std::size_t k = 0; k < 3; ++k) {
      std::vector<double> d(n);
      for (std::size_t i = 0; i < n; ++i) d[i] = y[k][i] - y[(k + 1) % 3][i];
      const std::vector<double> x = gmwm::stability::phase_from_frequency(d, 1.0);
      pairs[k] = gmwm::stability::deviation(kind, x, 1.0, m);
      ci[k] = gmwm::stability::deviation_intervals(pairs[k], x, options);
    }
    const auto hat = gmwm::stability::three_cornered_hat(pairs, ci);
    for (std::size_t i = 0; i < m.size(); ++i) {
      t.edf[i] += hat.edf[i] / seeds;
      for (std::size_t s = 0; s < 3; ++s) {
        const Sensor& sensor = config.sensors[s];
        const double truth = std::sqrt(sensor.white * sensor.white * white[i] + sensor.walk * sensor.walk * walk[i]);
        const auto& h = hat.sensors[s];
        t.negative[i] += h.negative[i];
        if (std::isfinite(h.low[i])) {
          t.given[i] += 1;
          t.covered[i] += h.low[i] <= truth && truth <= h.high[i];
        }
        const double b = std::max(hat.sensors[(s + 1) % 3].variance[i], 0.0);
        const double c = std::max(hat.sensors[(s + 2) % 3].variance[i], 0.0);
        const double opposite = std::pow(pairs[(s + 1) % 3].value[i], 2);
        const auto plug = plug_in_chi_square(h.variance[i], opposite, b * c, hat.edf[i], confidence);
        if (std::isfinite(plug[0])) {
          t.plug_given[i] += 1;
          t.plug_covered[i] += plug[0] <= truth * truth && truth * truth <= plug[1];
        }
      }
    }
  }
  std::printf("\n%s, %s, N = %zu, %d seeds, confidence %.4f\n", config.name.c_str(),
              std::string(gmwm::stability::deviation_name(kind)).c_str(), n, seeds, confidence);
  std::printf("%6s %8s %10s %10s %10s %12s\n", "m", "edf", "score", "given", "negative", "chi2 plug-in");
  double covered = 0, given = 0, all = 0, plug = 0, plug_all = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double total = 3.0 * seeds;
    std::printf("%6lld %8.1f %10.3f %10.3f %10.3f %12.3f\n", static_cast<long long>(m[i]), t.edf[i],
                t.covered[i] / std::max(t.given[i], 1.0), t.given[i] / total, t.negative[i] / total,
                t.plug_covered[i] / std::max(t.plug_given[i], 1.0));
    covered += t.covered[i];
    given += t.given[i];
    all += total;
    plug += t.plug_covered[i];
    plug_all += t.plug_given[i];
  }
  std::printf("pooled: score %.3f of %.0f%% given; chi2 plug-in %.3f\n", covered / given, 100.0 * given / all,
              plug / plug_all);
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 1000;
  const std::size_t n = argc > 2 ? static_cast<std::size_t>(std::atoll(argv[2])) : 4096;
  gmwm::bench::Stopwatch clock;
  const std::vector<Config> configs = {
      {"white FM 1, 1, 1", {{{1, 0}, {1, 0}, {1, 0}}}},
      {"white FM 1, 2, 3", {{{1, 0}, {2, 0}, {3, 0}}}},
      {"white FM 1, 3, 10", {{{1, 0}, {3, 0}, {10, 0}}}},
      {"random-walk FM 1, 2, 3 (x 0.01)", {{{0, 0.01}, {0, 0.02}, {0, 0.03}}}},
      {"mixed: white 1 | walk 0.01 | white 1 + walk 0.01", {{{1, 0}, {0, 0.01}, {1, 0.01}}}},
  };
  for (const double p : {gmwm::stability::kStable32Confidence, 0.95})
    for (const Config& c : configs)
      for (const DeviationKind kind : {DeviationKind::kOadev, DeviationKind::kMdev, DeviationKind::kTotdev})
        run(c, kind, n, seeds, p);
  std::printf("\n%.1f s\n", clock.seconds());
  return 0;
}
