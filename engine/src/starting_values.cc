#include "starting_values.h"

#include <algorithm>
#include <cmath>

#include <boost/random/uniform_real_distribution.hpp>

#include "gmwm/engine/random.h"

namespace gmwm::detail {
namespace {

enum class Placement { kFinest, kCoarsest, kSpread };

Placement placement_of(const Process& p) {
  if (p.deterministic()) return Placement::kCoarsest;                       // DR
  if (p.linear()) return p.name() == "RW" ? Placement::kCoarsest : Placement::kFinest;
  return Placement::kSpread;
}

// Stream identifier of the starting-value jitter (distinct from simulation streams).
constexpr std::uint64_t kStartStream = 0x5354415254ULL;  // "START"

}  // namespace

std::vector<Eigen::VectorXd> candidate_starts(const WaveletVariance& wv, const Model& model,
                                              int count, std::uint64_t seed) {
  const int J = wv.levels();
  std::vector<double> target(wv.wv);
  for (double& v : target)
    if (!(v > 0.0) || !std::isfinite(v)) v = 1e-300;
  std::vector<int> spread;
  for (int c = 0; c < model.num_components(); ++c)
    if (placement_of(*model.components()[static_cast<std::size_t>(c)].process) == Placement::kSpread) spread.push_back(c);
  const int k = static_cast<int>(spread.size());
  Rng rng = make_stream(seed, {kStartStream});
  boost::random::uniform_real_distribution<double> unif(0.0, 1.0);

  std::vector<Eigen::VectorXd> out;
  for (int v = 0; v < std::max(count, 1); ++v) {
    // Variant 0: evenly spread scales, equal shares. Later variants: jittered scales
    // (log2 positions) and shares drawn in [0.05, 1].
    std::vector<double> pos(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) {
      double frac = (i + 0.5) / k;
      if (v > 0) frac = std::clamp(frac + (unif(rng) - 0.5) / std::max(k, 1), 0.0, 1.0);
      pos[static_cast<std::size_t>(i)] = 1.0 + frac * (J - 1);
    }
    std::sort(pos.begin(), pos.end());
    Eigen::VectorXd theta(model.num_parameters());
    int spread_index = 0;
    for (int c = 0; c < model.num_components(); ++c) {
      const Component& comp = model.components()[static_cast<std::size_t>(c)];
      const Process& p = *comp.process;
      const double share = (v == 0) ? 1.0 / model.num_components() : 0.05 + 0.95 * unif(rng);
      std::vector<double> part(target);
      for (double& x : part) x *= share;
      GuessContext ctx{wv.tau, part, wv.tau.front()};
      switch (placement_of(p)) {
        case Placement::kFinest: ctx.tau_hint = wv.tau.front(); break;
        case Placement::kCoarsest: ctx.tau_hint = wv.tau.back(); break;
        case Placement::kSpread: ctx.tau_hint = std::exp2(pos[static_cast<std::size_t>(spread_index++)]); break;
      }
      std::vector<double> g = p.initial_guess(ctx);
      for (int i = 0; i < p.size(); ++i) {
        const double given = comp.given[static_cast<std::size_t>(i)];
        theta(model.offset(c) + i) = std::isnan(given) ? g[static_cast<std::size_t>(i)] : given;
      }
    }
    if (model.validate(theta).empty()) out.push_back(theta);
  }
  return out;
}

}  // namespace gmwm::detail
