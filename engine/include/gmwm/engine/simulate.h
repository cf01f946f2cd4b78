#pragma once
// Simulation of a model (docs/statistics.md section 7): components are summed, each drawing
// from its own seeded stream make_stream(seed, {signal, component}), so a signal does
// not depend on how many other signals are simulated or on the thread count.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/model.h"

namespace gmwm {

/// One series of length n for signal index `signal`. Throws InputError naming the
/// component when a value would leave the doubles (a drift whose omega (n - 1) passes
/// 1.8e308): no returned value is inf or NaN.
std::vector<double> simulate(const Model& model, const Eigen::VectorXd& theta, std::int64_t n, std::uint64_t seed,
                             std::uint64_t signal = 0);

/// `signals` series (in parallel), signal k equal to simulate(model, theta, n, seed, k).
std::vector<std::vector<double>> simulate_many(const Model& model, const Eigen::VectorXd& theta, std::int64_t n,
                                               int signals, std::uint64_t seed);

}  // namespace gmwm
