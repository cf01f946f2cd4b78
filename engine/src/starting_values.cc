#include "starting_values.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>

#include <Eigen/Dense>

namespace gmwm::detail {
namespace {

enum class Placement { kFinest, kCoarsest, kSpread };

Placement placement_of(const Process& p) {
  if (p.deterministic()) return Placement::kCoarsest;  // DR
  if (p.linear()) {
    // Linear processes whose WV decreases with scale (WN, QN) sit at the finest scale,
    // the others (RW) at the coarsest.
    const double tau[2] = {2.0, 4.0};
    double out[2];
    std::vector<double> theta(static_cast<std::size_t>(p.size()), 1.0);
    p.wv(theta, tau, out);
    return out[1] < out[0] ? Placement::kFinest : Placement::kCoarsest;
  }
  return Placement::kSpread;
}

// Number of grid positions (log2 scale) for the placement of scale-bearing components.
constexpr int kGridPositions = 12;
// Cap on the placements evaluated (C(12, 3) = 220 for three AR1s).
constexpr int kMaxPlacements = 2000;
// Floor of a component's size relative to the data's WV when the least-squares size
// is zero: keeps log-parameters finite and gradients alive.
constexpr double kSizeFloor = 1e-8;

// How a component's WV scales: parameter k multiplies it linearly or, for DR's omega,
// through its square. Found numerically, so no process names are involved.
struct ScaleParam {
  int index = -1;
  bool squared = false;
};

// `base` receives p's WV at theta (the reference the probes are compared with; solve_sizes
// uses it as its column instead of evaluating it again).
ScaleParam find_scale_param(const Process& p, const std::vector<double>& theta, std::span<const double> tau,
                            std::vector<double>& base) {
  base.resize(tau.size());
  std::vector<double> probe(tau.size());
  p.wv(theta, tau, base);
  for (int k = p.size() - 1; k >= 0; --k) {
    if (p.parameters()[static_cast<std::size_t>(k)].transform != Transform::kLog) continue;
    for (bool squared : {false, true}) {
      std::vector<double> t(theta);
      t[static_cast<std::size_t>(k)] *= squared ? std::sqrt(2.0) : 2.0;
      if (!p.validate(t).empty()) continue;
      p.wv(t, tau, probe);
      bool ok = true;
      for (std::size_t j = 0; j < tau.size() && ok; ++j)
        ok = std::abs(probe[j] - 2.0 * base[j]) <= 1e-9 * std::abs(2.0 * base[j]) + 1e-300;
      if (ok) return {k, squared};
    }
  }
  return {};
}

// Non-negative weighted least squares min (y - F s)' W (y - F s), s >= 0, by the
// active-set method of Lawson & Hanson (1974), for the handful of columns here.
Eigen::VectorXd nnls(const Eigen::MatrixXd& F, const Eigen::VectorXd& y, const Eigen::MatrixXd& W) {
  const int p = static_cast<int>(F.cols());
  std::vector<bool> free(static_cast<std::size_t>(p), true);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(p);
  for (int iter = 0; iter < 3 * p + 3; ++iter) {
    std::vector<int> idx;
    for (int k = 0; k < p; ++k)
      if (free[static_cast<std::size_t>(k)]) idx.push_back(k);
    if (idx.empty()) break;
    Eigen::MatrixXd Fa(F.rows(), static_cast<Eigen::Index>(idx.size()));
    for (std::size_t a = 0; a < idx.size(); ++a) Fa.col(static_cast<Eigen::Index>(a)) = F.col(idx[a]);
    // Jacobi scaling: the components' WVs differ by many decades (a WN's 1/tau against a
    // random walk's tau/6 at tau = 2^16, under weights of 1e15), and the rank-revealing
    // solve would otherwise read the small column as null and drop it.
    const Eigen::MatrixXd G = Fa.transpose() * W * Fa;
    const Eigen::VectorXd d = G.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd Gs = d.asDiagonal() * G * d.asDiagonal();
    const Eigen::VectorXd sa =
        d.cwiseProduct(Gs.completeOrthogonalDecomposition().solve(d.cwiseProduct(Fa.transpose() * W * y)));
    int worst = -1;
    double most_negative = 0.0;
    for (std::size_t a = 0; a < idx.size(); ++a)
      if (sa(static_cast<Eigen::Index>(a)) < most_negative) {
        most_negative = sa(static_cast<Eigen::Index>(a));
        worst = idx[a];
      }
    if (worst < 0) {
      s.setZero();
      for (std::size_t a = 0; a < idx.size(); ++a) s(idx[a]) = sa(static_cast<Eigen::Index>(a));
      return s;
    }
    free[static_cast<std::size_t>(worst)] = false;
  }
  return s;
}

void next_combination(std::vector<int>& c, int n, bool& done) {
  const int k = static_cast<int>(c.size());
  int i = k - 1;
  while (i >= 0 && c[static_cast<std::size_t>(i)] == n - k + i) --i;
  if (i < 0) {
    done = true;
    return;
  }
  ++c[static_cast<std::size_t>(i)];
  for (int j = i + 1; j < k; ++j) c[static_cast<std::size_t>(j)] = c[static_cast<std::size_t>(j - 1)] + 1;
}

}  // namespace

namespace {

// Component c's WV is "collapsed" when it is below this share of the data's WV at every
// level: it then explains nothing, and the optimiser cannot bring it back (its
// log-size gradient is ~ its share). 1e-6 is far below any share a fitted component
// contributes on the shared ADIS and Xsens recordings (smallest seen: ~1e-3) and far above
// the 1e-12 share given to absent components by warm starts.
constexpr double kCollapsedShare = 1e-6;

}  // namespace

namespace {

// One component's shape as solve_sizes sees it: the parameter that scales its WV and its
// WV at the shape (the column of the least-squares problem).
struct SizeColumn {
  ScaleParam sp;
  std::vector<double> f;
};

SizeColumn size_column(const WaveletVariance& wv, const Model& model, int c, const Eigen::VectorXd& theta) {
  const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
  std::vector<double> g(theta.data() + model.offset(c), theta.data() + model.offset(c) + p.size());
  SizeColumn col;
  col.sp = find_scale_param(p, g, wv.tau, col.f);
  return col;
}

// solve_sizes on the components' columns at theta's shapes (columns[c] for component c).
bool solve_sizes_on(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega,
                    const std::vector<const SizeColumn*>& columns, Eigen::VectorXd& theta, double& objective) {
  const int J = wv.levels();
  const int C = model.num_components();
  Eigen::VectorXd y = wv.values();
  for (int j = 0; j < J; ++j)
    if (!(y(j) > 0.0) || !std::isfinite(y(j))) y(j) = 0.0;
  const double level = std::max(y.maxCoeff(), 1e-300);
  auto column = [&](int c) {
    return Eigen::Map<const Eigen::VectorXd>(columns[static_cast<std::size_t>(c)]->f.data(), J);
  };
  // Components without a free scale parameter keep their size: move them to y.
  Eigen::VectorXd yy = y;
  std::vector<int> cols;
  for (int c = 0; c < C; ++c) {
    const ScaleParam& s = columns[static_cast<std::size_t>(c)]->sp;
    const bool given =
        s.index >= 0 &&
        !std::isnan(model.components()[static_cast<std::size_t>(c)].given[static_cast<std::size_t>(s.index)]);
    if (s.index < 0 || given)
      yy -= column(c);
    else
      cols.push_back(c);
  }
  if (!cols.empty()) {
    Eigen::MatrixXd Fa(J, static_cast<Eigen::Index>(cols.size()));
    for (std::size_t a = 0; a < cols.size(); ++a) Fa.col(static_cast<Eigen::Index>(a)) = column(cols[a]);
    const Eigen::VectorXd s = nnls(Fa, yy, omega);
    for (std::size_t a = 0; a < cols.size(); ++a) {
      const int c = cols[a];
      const ScaleParam& spc = columns[static_cast<std::size_t>(c)]->sp;
      const double fmax = std::max(column(c).cwiseAbs().maxCoeff(), 1e-300);
      const double factor = std::max(s(static_cast<Eigen::Index>(a)), kSizeFloor * level / fmax);
      double& v = theta(model.offset(c) + spc.index);
      v *= spc.squared ? std::sqrt(factor) : factor;
    }
  }
  if (!model.validate(theta).empty()) return false;
  const Eigen::VectorXd r = wv.values() - model.wv(theta, wv.tau);
  objective = r.dot(omega * r);
  return std::isfinite(objective);
}

}  // namespace

bool solve_sizes(const WaveletVariance& wv, const Model& model, const Eigen::MatrixXd& omega, Eigen::VectorXd& theta,
                 double& objective) {
  const int C = model.num_components();
  std::vector<SizeColumn> owned;
  owned.reserve(static_cast<std::size_t>(C));
  std::vector<const SizeColumn*> columns;
  for (int c = 0; c < C; ++c) columns.push_back(&owned.emplace_back(size_column(wv, model, c, theta)));
  return solve_sizes_on(wv, model, omega, columns, theta, objective);
}

namespace {

// The WV's range of log2 scales: the log2 of its first and last scale when they increase
// (a record's dyadic levels: [first level, last level], exactly; a curve's scales, curve.h:
// any, several to an octave, whose count is no number of octaves); else (replicates' WVs
// stacked, joint_fit.h) [first level, first level + levels - 1].
std::pair<double, double> log_scale_range(const WaveletVariance& wv) {
  if (!wv.tau.empty() && wv.tau.front() >= 2.0 && std::is_sorted(wv.tau.begin(), wv.tau.end(), std::less_equal<>()))
    return {std::log2(wv.tau.front()), std::log2(wv.tau.back())};
  const auto first = static_cast<double>(first_level(wv));
  return {first, first + std::max(wv.levels(), 1) - 1.0};
}

// Log-spaced scale grid over the WV's range (the placement positions).
std::vector<double> placement_grid(const WaveletVariance& wv) {
  const int J = wv.levels();
  const auto [lo, hi] = log_scale_range(wv);
  const int G = std::min(kGridPositions, std::max(J, 1));
  std::vector<double> grid(static_cast<std::size_t>(G));
  for (int g = 0; g < G; ++g)
    grid[static_cast<std::size_t>(g)] = std::exp2(G > 1 ? lo + (hi - lo) * g / (G - 1.0) : lo);
  return grid;
}

double hint_for(Placement pl, const WaveletVariance& wv, double spread_hint) {
  switch (pl) {
    case Placement::kFinest:
      return wv.tau.front();
    case Placement::kCoarsest:
      return wv.tau.back();
    case Placement::kSpread:
      return spread_hint;
  }
  return spread_hint;
}

// Component c's parameters: initial_guess at the hint, given values kept.
void place_component(const WaveletVariance& wv, const Model& model, int c, double hint,
                     const std::vector<double>& target, Eigen::VectorXd& theta) {
  const Component& comp = model.components()[static_cast<std::size_t>(c)];
  const Process& p = *comp.process;
  GuessContext ctx{wv.tau, target, hint};
  std::vector<double> g = p.initial_guess(ctx);
  for (int i = 0; i < p.size(); ++i) {
    const double given = comp.given[static_cast<std::size_t>(i)];
    if (!std::isnan(given)) g[static_cast<std::size_t>(i)] = given;
  }
  theta.segment(model.offset(c), p.size()) = Eigen::Map<Eigen::VectorXd>(g.data(), p.size());
}

struct Scored {
  double value;
  Eigen::VectorXd theta;
};

std::vector<Eigen::VectorXd> best_of(std::vector<Scored> scored, int count) {
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.value < b.value; });
  std::vector<Eigen::VectorXd> out;
  for (std::size_t i = 0; i < scored.size() && static_cast<int>(i) < count; ++i) out.push_back(scored[i].theta);
  return out;
}

std::vector<double> positive_target(const WaveletVariance& wv) {
  std::vector<double> target(wv.wv);
  for (double& v : target)
    if (!(v > 0.0) || !std::isfinite(v)) v = 0.0;
  return target;
}

}  // namespace

std::vector<Eigen::VectorXd> candidate_starts(const WaveletVariance& wv, const Model& model,
                                              const Eigen::MatrixXd& omega, int count) {
  const int C = model.num_components();
  const std::vector<double> target = positive_target(wv);
  std::vector<Placement> place(static_cast<std::size_t>(C));
  std::vector<int> spread;
  for (int c = 0; c < C; ++c) {
    place[static_cast<std::size_t>(c)] = placement_of(*model.components()[static_cast<std::size_t>(c)].process);
    if (place[static_cast<std::size_t>(c)] == Placement::kSpread) spread.push_back(c);
  }
  const int k = static_cast<int>(spread.size());
  const std::vector<double> grid = placement_grid(wv);
  const auto [lo, hi] = log_scale_range(wv);
  const int G = static_cast<int>(grid.size());

  std::vector<Scored> scored;
  std::vector<int> comb(static_cast<std::size_t>(k));
  std::iota(comb.begin(), comb.end(), 0);
  bool done = k > G;
  if (done) comb.clear();  // more placed components than grid points: spread them evenly
  int evaluated = 0;
  // A component placed at a hint has the same shape and WV column in every combination
  // that places it there (a spread component takes at most G hints, the others one): each
  // is formed once, not once per combination (the columns' WV probes were 40% of
  // candidate_starts; issue 44).
  struct Placed {
    Eigen::VectorXd shape;
    SizeColumn column;
  };
  std::map<std::pair<int, double>, Placed> placed;
  std::vector<const SizeColumn*> columns(static_cast<std::size_t>(C));
  do {
    Eigen::VectorXd theta(model.num_parameters());
    int si = 0;
    for (int c = 0; c < C; ++c) {
      double spread_hint = wv.tau.front();
      if (place[static_cast<std::size_t>(c)] == Placement::kSpread) {
        spread_hint = comb.empty() ? std::exp2(lo + (hi - lo) * (si + 0.5) / k)
                                   : grid[static_cast<std::size_t>(comb[static_cast<std::size_t>(si)])];
        ++si;
      }
      const double hint = hint_for(place[static_cast<std::size_t>(c)], wv, spread_hint);
      auto [it, fresh] = placed.try_emplace({c, hint});
      if (fresh) {
        Eigen::VectorXd t(model.num_parameters());
        place_component(wv, model, c, hint, target, t);
        it->second.shape = t.segment(model.offset(c), model.components()[static_cast<std::size_t>(c)].process->size());
        it->second.column = size_column(wv, model, c, t);
      }
      theta.segment(model.offset(c), it->second.shape.size()) = it->second.shape;
      columns[static_cast<std::size_t>(c)] = &it->second.column;
    }
    double q = 0.0;
    if (solve_sizes_on(wv, model, omega, columns, theta, q)) scored.push_back({q, theta});
    ++evaluated;
    if (!comb.empty())
      next_combination(comb, G, done);
    else
      done = true;
  } while (!done && evaluated < kMaxPlacements);
  return best_of(std::move(scored), count);
}

std::vector<int> collapsed_components(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta) {
  std::vector<int> out;
  const std::vector<double> target = positive_target(wv);
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> f(wv.tau.size());
    p.wv({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, wv.tau, f);
    bool collapsed = true;
    for (std::size_t j = 0; j < f.size() && collapsed; ++j) collapsed = !(std::abs(f[j]) > kCollapsedShare * target[j]);
    if (collapsed) out.push_back(c);
  }
  return out;
}

std::vector<Eigen::VectorXd> revival_starts(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                                            const Eigen::MatrixXd& omega, int count) {
  const std::vector<double> target = positive_target(wv);
  const std::vector<double> grid = placement_grid(wv);
  std::vector<Scored> scored;
  for (int c : collapsed_components(wv, model, theta)) {
    const Placement pl = placement_of(*model.components()[static_cast<std::size_t>(c)].process);
    const std::vector<double> hints = pl == Placement::kSpread ? grid : std::vector<double>{hint_for(pl, wv, 0.0)};
    for (double h : hints) {
      Eigen::VectorXd t = theta;
      place_component(wv, model, c, h, target, t);
      double q = 0.0;
      if (solve_sizes(wv, model, omega, t, q)) scored.push_back({q, t});
    }
  }
  return best_of(std::move(scored), count);
}

int linear_scale_parameter(const Process& p, const std::vector<double>& theta, std::span<const double> tau) {
  std::vector<double> base;
  const ScaleParam sp = find_scale_param(p, theta, tau, base);
  return sp.squared ? -1 : sp.index;
}

}  // namespace gmwm::detail
