#include "gmwm/engine/simulate.h"

#include "gmwm/engine/check.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"

namespace gmwm {

std::vector<double> simulate(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, std::uint64_t seed,
                             std::uint64_t signal) {
  check_at_least("simulate", "n", static_cast<double>(n), 1.0);
  const std::string why = model.validate(theta);
  if (!why.empty()) throw InvalidArgument("simulate: " + why);
  std::vector<double> x(static_cast<std::size_t>(n), 0.0);
  for (int c = 0; c < model.num_components(); ++c) {
    const auto& p = *model.components()[static_cast<std::size_t>(c)].process;
    Rng rng = make_stream(seed, {signal, static_cast<std::uint64_t>(c)});
    p.simulate({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, rng, x);
  }
  return x;
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
