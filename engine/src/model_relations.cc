#include "gmwm/engine/model_relations.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

namespace gmwm {
namespace {

// The relative size, against the data's WV, given to a component of the super-model that
// takes no part in the represented fit: small enough not to change the objective
// noticeably, large enough to keep the log-parameters' gradients alive.
constexpr double kNegligibleShare = 1e-12;

std::span<const double> slice(const Eigen::VectorXd& theta, int off, int len) {
  return {theta.data() + off, static_cast<std::size_t>(len)};
}

/// A valid parameter vector of `p` away from every limit, for structural questions.
std::vector<double> typical_theta(const Process& p) {
  std::vector<double> t;
  for (const auto& s : p.parameters()) {
    switch (s.transform) {
      case Transform::kLog:
        t.push_back(1.0);
        break;
      case Transform::kAtanh:
        t.push_back(0.5);
        break;
      case Transform::kLogitHalf:
        t.push_back(0.1);
        break;
      case Transform::kIdentity:
        t.push_back(0.5);
        break;
    }
  }
  return t;
}

/// Depth-first assignment of sub's components (in `order`) to distinct super components.
bool assign(const Model& super, const Model& sub, const Eigen::VectorXd& theta_sub, const std::vector<int>& order,
            std::size_t next, std::vector<bool>& used, Representation& out) {
  if (next == order.size()) return true;
  const int c = order[next];
  const Process& q = *sub.components()[static_cast<std::size_t>(c)].process;
  const auto qt = slice(theta_sub, sub.offset(c), q.size());
  // Same process first (a nested model maps onto itself), then the containing ones.
  for (int pass = 0; pass < 2; ++pass) {
    for (int s = 0; s < super.num_components(); ++s) {
      if (used[static_cast<std::size_t>(s)]) continue;
      const Process& p = *super.components()[static_cast<std::size_t>(s)].process;
      if ((pass == 0) != same_process(p, q)) continue;
      auto mapped = p.represent(q, qt);
      if (!mapped || !p.validate(*mapped).empty()) continue;
      used[static_cast<std::size_t>(s)] = true;
      out.slot[static_cast<std::size_t>(c)] = s;
      out.theta[static_cast<std::size_t>(c)] = std::move(*mapped);
      if (assign(super, sub, theta_sub, order, next + 1, used, out)) return true;
      used[static_cast<std::size_t>(s)] = false;
    }
  }
  return false;
}

}  // namespace

std::optional<Representation> representation(const Model& super, const Model& sub, const Eigen::VectorXd& theta_sub) {
  if (sub.num_components() > super.num_components()) return std::nullopt;
  Representation r;
  r.slot.assign(static_cast<std::size_t>(sub.num_components()), -1);
  r.theta.resize(static_cast<std::size_t>(sub.num_components()));
  // Components with the fewest candidate slots first keeps the search short.
  std::vector<int> order(static_cast<std::size_t>(sub.num_components()));
  std::vector<int> options(order.size(), 0);
  for (int c = 0; c < sub.num_components(); ++c) {
    order[static_cast<std::size_t>(c)] = c;
    const Process& q = *sub.components()[static_cast<std::size_t>(c)].process;
    for (const auto& sc : super.components())
      if (sc.process->represent(q, slice(theta_sub, sub.offset(c), q.size()))) ++options[static_cast<std::size_t>(c)];
    if (options[static_cast<std::size_t>(c)] == 0) return std::nullopt;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return options[static_cast<std::size_t>(a)] < options[static_cast<std::size_t>(b)];
  });
  std::vector<bool> used(static_cast<std::size_t>(super.num_components()), false);
  if (!assign(super, sub, theta_sub, order, 0, used, r)) return std::nullopt;
  return r;
}

bool represents(const Model& super, const Model& sub) {
  Eigen::VectorXd theta(sub.num_parameters());
  for (int c = 0; c < sub.num_components(); ++c) {
    const auto t = typical_theta(*sub.components()[static_cast<std::size_t>(c)].process);
    for (std::size_t k = 0; k < t.size(); ++k) theta(sub.offset(c) + static_cast<int>(k)) = t[k];
  }
  return representation(super, sub, theta).has_value();
}

std::optional<Eigen::VectorXd> represent_start(const Model& super, const Model& sub, const Eigen::VectorXd& theta_sub,
                                               const WaveletVariance& wv) {
  const auto r = representation(super, sub, theta_sub);
  if (!r) return std::nullopt;
  Eigen::VectorXd theta(super.num_parameters());
  std::vector<bool> taken(static_cast<std::size_t>(super.num_components()), false);
  for (std::size_t c = 0; c < r->slot.size(); ++c) {
    const int s = r->slot[c];
    taken[static_cast<std::size_t>(s)] = true;
    for (std::size_t k = 0; k < r->theta[c].size(); ++k) theta(super.offset(s) + static_cast<int>(k)) = r->theta[c][k];
  }
  std::vector<double> small(wv.wv);
  for (double& v : small) v = std::max(v, 1e-300) * kNegligibleShare;
  for (int s = 0; s < super.num_components(); ++s) {
    if (taken[static_cast<std::size_t>(s)]) continue;
    const Process& p = *super.components()[static_cast<std::size_t>(s)].process;
    const GuessContext ctx{wv.tau, small, wv.tau[wv.tau.size() / 2]};
    const auto g = p.initial_guess(ctx);
    for (int i = 0; i < p.size(); ++i) theta(super.offset(s) + i) = g[static_cast<std::size_t>(i)];
  }
  return theta;
}

std::vector<Model> representation_neighbours(const Model& model) {
  std::vector<Model> out;
  std::set<std::string> seen;
  const auto& comps = model.components();
  auto add = [&](std::vector<Component> kept) {
    if (kept.empty()) return;
    Model m = Model(std::move(kept)).canonical();
    if (seen.insert(m.to_string()).second) out.push_back(std::move(m));
  };
  for (std::size_t c = 0; c < comps.size(); ++c) {
    std::vector<Component> kept;
    for (std::size_t k = 0; k < comps.size(); ++k)
      if (k != c) kept.push_back(comps[k]);
    add(kept);
  }
  for (std::size_t c = 0; c < comps.size(); ++c) {
    const Process& p = *comps[c].process;
    for (const SimplerForm& f : p.simpler_forms(typical_theta(p))) {
      if (!p.represent(*f.process, f.theta)) continue;
      // Two of a linear process (WN, QN, RW) are one: that neighbour is the removal above.
      const bool duplicate = std::any_of(
          comps.begin(), comps.end(), [&](const Component& other) { return same_process(*other.process, *f.process); });
      if (duplicate && f.process->linear()) continue;
      std::vector<Component> kept;
      for (std::size_t k = 0; k < comps.size(); ++k) kept.push_back(k == c ? Component{f.process, {}} : comps[k]);
      add(kept);
    }
  }
  return out;
}

std::vector<std::vector<bool>> representation_matrix(const std::vector<Model>& models) {
  const std::size_t K = models.size();
  std::vector<std::vector<bool>> rep(K, std::vector<bool>(K, false));
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t k = 0; k < K; ++k)
      rep[i][k] =
          i != k && models[i].num_components() >= models[k].num_components() && represents(models[i], models[k]);
  // Strict: two equally expressive models (the same multiset listed twice) order nothing.
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (rep[i][k] && rep[k][i]) rep[i][k] = rep[k][i] = false;
  return rep;
}

std::vector<std::vector<int>> representation_covers(const std::vector<std::vector<bool>>& rep) {
  const std::size_t K = rep.size();
  std::vector<std::vector<int>> covers(K);
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t k = 0; k < K; ++k) {
      if (!rep[i][k]) continue;
      bool between = false;
      for (std::size_t m = 0; m < K && !between; ++m) between = rep[i][m] && rep[m][k];
      if (!between) covers[i].push_back(static_cast<int>(k));
    }
  return covers;
}

}  // namespace gmwm
