#include "gmwm/engine/simulate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "processes/process_util.h"

namespace gmwm {

std::vector<double> simulate(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, std::uint64_t seed,
                             std::uint64_t signal) {
  check_at_least("simulate", "n", static_cast<double>(n), 1.0);
  const std::string why = model.validate(theta);
  if (!why.empty()) throw InvalidArgument("simulate: " + why);
  std::vector<double> x(static_cast<std::size_t>(n), 0.0);
  auto add = [&](int c) {
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    Rng rng = make_stream(seed, {signal, static_cast<std::uint64_t>(c)});
    p.simulate({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, rng, x);
  };
  // Consecutive components that are AR1 paths (AR1, GM) are added in one interleaved pass:
  // each sample gets their values in component order, as one pass each would add them.
  for (int c = 0; c < model.num_components();) {
    std::vector<internal::Ar1Path> paths;
    std::vector<Rng> streams;
    int e = c;
    for (; e < model.num_components(); ++e) {
      const auto& p = *model.components()[static_cast<std::size_t>(e)].process;
      const auto* source = dynamic_cast<const internal::Ar1PathSource*>(&p);
      if (!source) break;
      paths.push_back(source->ar1_path({theta.data() + model.offset(e), static_cast<std::size_t>(p.size())}));
      streams.push_back(make_stream(seed, {signal, static_cast<std::uint64_t>(e)}));
    }
    if (e - c >= 2) {
      internal::simulate_ar1_paths(paths, streams, x);
      c = e;
    } else {
      add(c++);
    }
  }
  // A value a double cannot hold is never returned: a drift's omega t passes 1.8e308
  // (DR(omega=1e305) after 1800 samples), or a sum of components does. The processes
  // keep their own intermediates in range for any valid theta (stochastic values stay
  // below ~1e163), so the component that crossed is named. Each component adds its path
  // (Process::simulate), and a sum that is not finite stays so, so one check of the total
  // finds any crossing; only then are the components added again one at a time, from the
  // same streams, to name the first that crossed (a check after each component was a pass
  // over the series per component: 3-8% of a bootstrap draw, issue 44).
  auto not_finite = [&] { return std::find_if(x.begin(), x.end(), [](double v) { return !std::isfinite(v); }); };
  if (not_finite() == x.end()) return x;
  std::fill(x.begin(), x.end(), 0.0);
  for (int c = 0; c < model.num_components(); ++c) {
    add(c);
    const auto bad = not_finite();
    if (bad == x.end()) continue;
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    char at[96];
    std::snprintf(at, sizeof at, "%lld of %lld", static_cast<long long>(bad - x.begin()), static_cast<long long>(n));
    throw InputError("component " + std::to_string(c + 1) + " (" + p.name() +
                     ") takes the simulated series beyond the largest double (1.8e308) at sample " + at);
  }
  throw InputError("simulate: the simulated series is not finite");  // the streams are fixed: not reached
}

std::vector<std::vector<double>> simulate_many(const Model& model, const Eigen::VectorXd& theta, std::int64_t n,
                                               int signals, std::uint64_t seed) {
  check_at_least("simulate_many", "signals", signals, 1.0);
  std::vector<std::vector<double>> out(static_cast<std::size_t>(signals));
  gmwm::parallel_for(0, signals, [&](int k) {
    out[static_cast<std::size_t>(k)] = simulate(model, theta, n, seed, static_cast<std::uint64_t>(k));
  });
  return out;
}

}  // namespace gmwm
