#include "gmwm/selection/select.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <span>
#include <numeric>
#include <optional>
#include <sstream>

#include <Eigen/Cholesky>
#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/parallel_for.h>
#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/selection/submodels.h"

namespace gmwm::selection {
namespace {

// Relative tolerance of the nesting check (issue 4: "relative tolerance 1e-9").
constexpr double kNestingTolerance = 1e-9;
// Criteria this close (relative) are tied. A model whose extra components collapsed to
// the boundary repeats its sub-model's objective up to the optimiser's precision, which
// on real data reaches ~1e-8 relative (cont_imu1's robust WV: 3*AR1+WN came out 1e-8
// below 2*AR1); one parameter's worth of penalty (~1-2 in absolute terms) is above 3e-5
// relative even at criteria of 3e4 (the ADIS gyro_z).
constexpr double kTieTolerance = 1e-6;

// Replicate streams are (signal, model, replicate) packed as
// ((signal * models) + model) * kMaxReplicates + replicate.
constexpr int kMaxReplicates = 100000;

struct BootstrapResult {
  double value = 0.0, se = 0.0;
  int failed = 0, not_converged = 0;
};

// Parametric-bootstrap optimism of one fitted model (STATISTICS.md section 6): B series
// simulated from the fit, their WV by the same estimator, refits warm-started from the
// fit under the same Omega; optimism = 2 tr(Omega C), C the sample cross-covariance of
// nu(theta*) and nuhat*. Its Monte-Carlo s.e. from the per-replicate terms
// 2 (nu(theta*_b) - mean)' Omega (nuhat*_b - mean) (their mean, times B/(B-1), is the
// estimate).
BootstrapResult bootstrap_optimism(const WaveletVariance& wv, const FitResult& fit, const Eigen::MatrixXd& omega,
                                   const SelectOptions& options, std::uint64_t stream_base) {
  const int B = options.bootstrap_replicates;
  const Eigen::Index J = wv.levels();
  const ClassicalWvEstimator classical;
  const WvEstimator& estimator = options.estimator ? *options.estimator : classical;
  std::vector<Eigen::VectorXd> implied(static_cast<std::size_t>(B)), empirical(static_cast<std::size_t>(B));
  std::vector<char> ok(static_cast<std::size_t>(B), 0), converged(static_cast<std::size_t>(B), 0);
  oneapi::tbb::parallel_for(0, B, [&](int b) {
    const std::vector<double> x =
        simulate(fit.model, fit.theta, wv.n, options.seed, stream_base + static_cast<std::uint64_t>(b));
    const WaveletVariance w = estimator.compute(x.data(), wv.n, static_cast<int>(J), wv.alpha);
    if (!w.values().allFinite()) return;
    FitOptions fo = options.fit;
    fo.omega_matrix = omega;
    fo.nested_starts = false;
    fo.inference = false;
    fo.multistarts = 1;
    fo.starts = {fit.theta};
    fo.log_not_converged = false;  // counted and reported once per model below
    const FitResult r = fit_gmwm(w, fit.model, fo);
    if (r.status == FitStatus::kFailed) return;
    converged[static_cast<std::size_t>(b)] = r.status == FitStatus::kConverged;
    implied[static_cast<std::size_t>(b)] = r.implied_wv;
    empirical[static_cast<std::size_t>(b)] = w.values();
    ok[static_cast<std::size_t>(b)] = 1;
  });
  BootstrapResult out;
  Eigen::VectorXd mi = Eigen::VectorXd::Zero(J), me = Eigen::VectorXd::Zero(J);
  int n = 0;
  for (int b = 0; b < B; ++b)
    if (ok[static_cast<std::size_t>(b)]) {
      mi += implied[static_cast<std::size_t>(b)];
      me += empirical[static_cast<std::size_t>(b)];
      ++n;
    }
  out.failed = B - n;
  for (int b = 0; b < B; ++b)
    if (ok[static_cast<std::size_t>(b)] && !converged[static_cast<std::size_t>(b)]) ++out.not_converged;
  if (out.failed > 0 || out.not_converged > 0)
    spdlog::warn("bootstrap optimism of {}: {} of {} refits failed (left out), {} stopped before convergence (kept)",
                 fit.model.to_string(), out.failed, B, out.not_converged);
  if (n < 2) {
    out.value = out.se = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  mi /= n;
  me /= n;
  std::vector<double> terms;
  for (int b = 0; b < B; ++b)
    if (ok[static_cast<std::size_t>(b)])
      terms.push_back(2.0 * (implied[static_cast<std::size_t>(b)] - mi).dot(omega * (empirical[static_cast<std::size_t>(b)] - me)));
  double sum = 0.0, sum2 = 0.0;
  for (double t : terms) sum += t;
  const double mean = sum / n;
  for (double t : terms) sum2 += (t - mean) * (t - mean);
  out.value = sum / (n - 1);
  out.se = std::sqrt(sum2 / (n - 1)) / std::sqrt(static_cast<double>(n)) * n / (n - 1);
  return out;
}

struct SignalWork {
  const WaveletVariance* wv = nullptr;
  Eigen::MatrixXd omega;
  OmegaSource omega_source = OmegaSource::kData;
  std::optional<FitResult> pilot;  // the maximal model's fit under the data's Omega (kModel)
  Eigen::MatrixXd v;               // model-based Cov(nuhat) at the pilot (kModel), else empty
  std::vector<FitResult> fits;     // per sub-model, in SubModelSet order

  // Cov(nuhat) for the optimism and GoF: at the pilot when there is one (it is the
  // maximal model's fit too, and its V formed Omega), else at `full`.
  Eigen::MatrixXd covariance(const FitResult& full) const {
    if (v.size() > 0) return v;
    Eigen::MatrixXd c = model_wv_covariance(full.model, full.theta, wv->n, wv->levels());
    if (wv->efficiency) c /= *wv->efficiency;  // robust WV: variance inflated by 1/eff
    return c;
  }
};

bool nested_in(const std::vector<int>& sub, const std::vector<int>& super) {
  for (std::size_t g = 0; g < sub.size(); ++g)
    if (sub[g] > super[g]) return false;
  return true;
}

// V^-1 for the model-based V when `full` and V is positive definite, else diag(1 / V_jj)
// (a level where V_jj is not positive and finite keeps the data's weight).
Eigen::MatrixXd model_omega(const Eigen::MatrixXd& v, const Eigen::MatrixXd& data_omega, bool full) {
  if (full) {
    const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (v + v.transpose()));
    if (llt.info() == Eigen::Success) {
      Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(v.rows(), v.cols()));
      if (inv.allFinite()) return 0.5 * (inv + inv.transpose());
    }
    spdlog::warn("select: the model-based V is not positive definite; using diag 1 / V_jj");
  }
  Eigen::VectorXd d = data_omega.diagonal();
  for (Eigen::Index j = 0; j < d.size(); ++j)
    if (v(j, j) > 0.0 && std::isfinite(v(j, j))) d(j) = 1.0 / v(j, j);
  return d.asDiagonal();
}

// Per signal: its WV, its one Omega (the caller's; the data's diag Omega; or the model
// Omega at a pilot fit of `maximal`) and room for K fits.
std::vector<SignalWork> make_work(const std::vector<WaveletVariance>& wvs, std::size_t K, const Model& maximal,
                                  const SelectOptions& options) {
  std::vector<SignalWork> work(wvs.size());
  oneapi::tbb::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    SignalWork& w = work[s];
    w.wv = &wvs[s];
    w.fits.resize(K);
    if (options.fit.omega_matrix) {
      w.omega = *options.fit.omega_matrix;
      return;
    }
    w.omega = diagonal_omega(wvs[s]);
    if (options.omega == OmegaSource::kData) return;
    FitOptions fo = options.fit;
    fo.omega_matrix = w.omega;
    fo.inference = false;
    fo.nested_starts = false;
    FitResult pilot = fit_gmwm(wvs[s], maximal, fo);
    if (pilot.status == FitStatus::kFailed) {
      spdlog::warn("select: the pilot fit of {} failed ({}); using the data's Omega", maximal.to_string(),
                   pilot.message);
      return;
    }
    w.pilot = std::move(pilot);
    w.v = w.covariance(*w.pilot);
    const bool full = options.omega == OmegaSource::kModelFull;
    w.omega = model_omega(w.v, w.omega, full);
    w.omega_source = full && !w.omega.isDiagonal(0.0) ? OmegaSource::kModelFull : OmegaSource::kModel;
  });
  return work;
}

// The bootstrap optimism of every (signal, model) of `work` (K models per signal);
// replicate streams depend on (signal, model, replicate) only.
std::vector<BootstrapResult> bootstrap_all(const std::vector<SignalWork>& work, std::size_t K,
                                           const SelectOptions& options) {
  std::vector<BootstrapResult> boot(work.size() * K);
  oneapi::tbb::parallel_for(std::size_t{0}, boot.size(), [&](std::size_t k) {
    const FitResult& f = work[k / K].fits[k % K];
    if (f.status == FitStatus::kFailed) {
      boot[k].value = boot[k].se = std::numeric_limits<double>::quiet_NaN();
      boot[k].failed = options.bootstrap_replicates;
      return;
    }
    boot[k] = bootstrap_optimism(*work[k / K].wv, f, work[k / K].omega, options,
                                 static_cast<std::uint64_t>(k) * static_cast<std::uint64_t>(kMaxReplicates));
  });
  return boot;
}

// The Jacobian of nu at theta without the parameters of the listed components.
Eigen::MatrixXd active_jacobian(const Model& model, const Eigen::VectorXd& theta, std::span<const double> tau,
                                const std::vector<int>& dropped) {
  const Eigen::MatrixXd full = model.jacobian(theta, tau);
  std::vector<Eigen::Index> keep;
  for (int c = 0; c < model.num_components(); ++c) {
    if (std::find(dropped.begin(), dropped.end(), c) != dropped.end()) continue;
    for (int k = 0; k < model.components()[static_cast<std::size_t>(c)].process->size(); ++k)
      keep.push_back(model.offset(c) + k);
  }
  Eigen::MatrixXd A(full.rows(), static_cast<Eigen::Index>(keep.size()));
  for (Eigen::Index a = 0; a < A.cols(); ++a) A.col(a) = full.col(keep[static_cast<std::size_t>(a)]);
  return A;
}

// Indices of `ranking` sorted by crit (NaN last); criteria within kTieTolerance
// (relative) of a run's first are ordered by fewer parameters.
template <class Crit>
std::vector<std::size_t> rank_order(const std::vector<RankedModel>& ranking, Crit crit) {
  const std::size_t K = ranking.size();
  std::vector<std::size_t> order(K);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double x = crit(ranking[a]), y = crit(ranking[b]);
    const bool xn = std::isnan(x), yn = std::isnan(y);
    if (xn != yn) return yn;
    if (!xn && x != y) return x < y;
    return ranking[a].parameters < ranking[b].parameters;
  });
  // A model whose extra components sit at the boundary repeats its sub-model's criterion.
  for (std::size_t a = 0; a < K;) {
    std::size_t b = a + 1;
    const double ca = crit(ranking[order[a]]);
    while (b < K && std::abs(crit(ranking[order[b]]) - ca) <= kTieTolerance * std::abs(ca)) ++b;
    std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(a), order.begin() + static_cast<std::ptrdiff_t>(b),
                     [&](std::size_t x, std::size_t y) { return ranking[x].parameters < ranking[y].parameters; });
    a = b;
  }
  return order;
}

// Scores the fitted candidates of one signal (optimism, criterion), ranks them, and
// refits the best with inference. v: Cov(nuhat), model-based at the maximal model's fit.
void score_and_rank(Selection& sel, const WaveletVariance& wv, const Eigen::MatrixXd& omega, Eigen::MatrixXd v,
                    const std::vector<FitResult>& fits, const std::vector<std::string>& names,
                    const std::vector<const BootstrapResult*>& boot, const SelectOptions& options) {
  const std::size_t K = fits.size();
  sel.models = static_cast<int>(K);
  sel.omega = omega;
  sel.v = std::move(v);
  const Eigen::VectorXd nuhat = wv.values();
  std::vector<RankedModel> scored;
  for (std::size_t i = 0; i < K; ++i) {
    RankedModel r;
    r.fit = fits[i];
    r.model = names[i];
    r.parameters = r.fit.model.num_parameters();
    r.objective = r.fit.objective;
    if (r.fit.status != FitStatus::kFailed) {
      r.analytic = analytic_optimism(r.fit.model, r.fit.theta, wv.tau, nuhat, omega, sel.v);
      if (r.analytic.status != OptimismStatus::kFailed) r.optimism_analytic = r.analytic.value;
      r.gof = goodness_of_fit(active_jacobian(r.fit.model, r.fit.theta, wv.tau, r.analytic.boundary_components),
                              r.objective, static_cast<double>(wv.levels() - r.parameters), omega, sel.v,
                              sel.omega_source == OmegaSource::kModelFull);
    }
    if (boot[i]) {
      if (std::isfinite(boot[i]->value)) {
        r.optimism_bootstrap = boot[i]->value;
        r.optimism_bootstrap_se = boot[i]->se;
      }
      r.bootstrap_failed = boot[i]->failed;
      r.bootstrap_not_converged = boot[i]->not_converged;
    }
    if (options.penalty == Penalty::kWvic)
      r.optimism = (options.optimism == OptimismMethod::kBootstrap ? r.optimism_bootstrap : r.optimism_analytic)
                       .value_or(std::numeric_limits<double>::quiet_NaN());
    else
      r.optimism = r.parameters * std::log(static_cast<double>(wv.n));
    r.criterion = r.objective + r.optimism;
    scored.push_back(std::move(r));
  }
  // Ranks under each optimism (WVIC): by objective + that optimism, same tie rule.
  auto with = [](const std::optional<double>& o, double objective) {
    return o ? objective + *o : std::numeric_limits<double>::quiet_NaN();
  };
  if (options.penalty == Penalty::kWvic) {
    const auto a = rank_order(scored, [&](const RankedModel& r) { return with(r.optimism_analytic, r.objective); });
    for (std::size_t k = 0; k < K; ++k)
      if (scored[a[k]].optimism_analytic) scored[a[k]].rank_analytic = static_cast<int>(k) + 1;
    if (options.optimism != OptimismMethod::kAnalytic) {
      const auto b = rank_order(scored, [&](const RankedModel& r) { return with(r.optimism_bootstrap, r.objective); });
      for (std::size_t k = 0; k < K; ++k)
        if (scored[b[k]].optimism_bootstrap) scored[b[k]].rank_bootstrap = static_cast<int>(k) + 1;
    }
  }
  const auto order = rank_order(scored, [](const RankedModel& r) { return r.criterion; });
  sel.ranking.clear();
  for (std::size_t k = 0; k < K; ++k) {
    sel.ranking.push_back(std::move(scored[order[k]]));
    sel.ranking.back().rank = static_cast<int>(k) + 1;
  }
  // The best model with inference (same Omega, started from its own optimum).
  FitOptions fo = options.fit;
  fo.omega_matrix = omega;
  fo.nested_starts = false;
  fo.inference = true;
  fo.starts = {sel.ranking.front().fit.theta};
  sel.best_fit = fit_gmwm(wv, sel.ranking.front().fit.model, fo);
}

// Models whose objective exceeds that of a model nested in them (kNestingTolerance).
int count_nesting_violations(const SubModelSet& set, const std::vector<FitResult>& fits,
                             const std::vector<int>* members = nullptr) {
  int n = 0;
  const std::size_t K = fits.size();
  auto counts = [&](std::size_t i) -> const std::vector<int>& {
    return set.models[static_cast<std::size_t>(members ? (*members)[i] : static_cast<int>(i))].counts;
  };
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t k = 0; k < K; ++k)
      if (k != i && nested_in(counts(k), counts(i)) && fits[i].objective > fits[k].objective * (1.0 + kNestingTolerance))
        ++n;
  return n;
}

}  // namespace

const char* to_string(Penalty p) { return p == Penalty::kWvic ? "wvic" : "bic"; }

const char* to_string(OmegaSource o) {
  switch (o) {
    case OmegaSource::kData: return "data";
    case OmegaSource::kModel: return "model";
    case OmegaSource::kModelFull: return "full";
  }
  return "model";
}

const char* to_string(OptimismMethod m) {
  switch (m) {
    case OptimismMethod::kAnalytic: return "analytic";
    case OptimismMethod::kBootstrap: return "bootstrap";
    case OptimismMethod::kBoth: return "both";
  }
  return "analytic";
}

std::string SelectOptions::Validate() const {
  if (optimism != OptimismMethod::kAnalytic && !(bootstrap_replicates >= 2 && bootstrap_replicates <= kMaxReplicates))
    return "bootstrap replicates must be in [2, " + std::to_string(kMaxReplicates) + "], got " +
           std::to_string(bootstrap_replicates);
  FitOptions f = fit;
  f.omega_matrix.reset();
  return f.Validate();
}

std::vector<Selection> select_models(const std::vector<WaveletVariance>& wvs, const Model& maximal,
                                     const SelectOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("select: " + why);
  const SubModelSet set = enumerate_submodels(maximal);
  const std::size_t K = set.models.size();
  for (const auto& wv : wvs) check_model_fits_levels(set.models.back().model, wv.levels());

  std::vector<SignalWork> work = make_work(wvs, K, maximal, options);
  const int total = static_cast<int>(wvs.size() * K);
  std::atomic<int> done{0};

  // One node per (signal, model); edges from each parent model's node.
  namespace flow = oneapi::tbb::flow;
  flow::graph g;
  using Node = flow::continue_node<flow::continue_msg>;
  std::vector<std::unique_ptr<Node>> nodes;
  nodes.reserve(wvs.size() * K);
  for (std::size_t s = 0; s < wvs.size(); ++s) {
    for (std::size_t i = 0; i < K; ++i) {
      nodes.push_back(std::make_unique<Node>(g, [&, s, i](const flow::continue_msg&) {
        SignalWork& w = work[s];
        const SubModel& m = set.models[i];
        FitOptions fo = options.fit;
        fo.omega_matrix = w.omega;
        fo.nested_starts = false;
        fo.inference = false;
        for (int p : m.parents) {
          const FitResult& pf = w.fits[static_cast<std::size_t>(p)];
          if (pf.status != FitStatus::kFailed) fo.starts.push_back(embed_start(pf.model, pf.theta, m.model, *w.wv));
        }
        if (i + 1 == K && w.pilot) fo.starts.push_back(embed_start(w.pilot->model, w.pilot->theta, m.model, *w.wv));
        w.fits[i] = fit_gmwm(*w.wv, m.model, fo);
        const int d = ++done;
        if (options.progress) options.progress(d, total);
      }));
    }
    for (std::size_t i = 0; i < K; ++i)
      for (int p : set.models[i].parents)
        flow::make_edge(*nodes[s * K + static_cast<std::size_t>(p)], *nodes[s * K + i]);
  }
  for (std::size_t s = 0; s < wvs.size(); ++s)
    for (std::size_t i = 0; i < K; ++i)
      if (set.models[i].parents.empty()) nodes[s * K + i]->try_put(flow::continue_msg());
  g.wait_for_all();

  // Bootstrap optimism of every (signal, model), when asked.
  const bool want_bootstrap = options.optimism != OptimismMethod::kAnalytic;
  const std::vector<BootstrapResult> boot = want_bootstrap ? bootstrap_all(work, K, options) : std::vector<BootstrapResult>{};

  // Scoring and ranking, per signal.
  std::vector<Selection> out(wvs.size());
  oneapi::tbb::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    const SignalWork& w = work[s];
    std::vector<std::string> names;
    for (const auto& m : set.models) names.push_back(m.model.to_string());
    std::vector<const BootstrapResult*> b(K, nullptr);
    if (want_bootstrap)
      for (std::size_t i = 0; i < K; ++i) b[i] = &boot[s * K + i];
    Selection& sel = out[s];
    sel.full_model = set.models.back().model.to_string();
    sel.omega_source = w.omega_source;
    score_and_rank(sel, *w.wv, w.omega, w.covariance(w.fits.back()), w.fits, names, b, options);
    sel.nesting_violations = count_nesting_violations(set, w.fits);
  });
  return out;
}

std::vector<Selection> select_among(const std::vector<WaveletVariance>& wvs, const std::vector<Model>& models,
                                    const SelectOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("select: " + why);
  if (models.empty()) throw InputError("select: no models given");
  const Model super = common_supermodel(models);
  const SubModelSet set = enumerate_submodels(super);
  // Each listed model's place among the super-model's sub-models (for the nesting check).
  std::vector<int> members;
  std::vector<std::string> names;
  for (const Model& m : models) {
    std::vector<int> counts(set.groups.size(), 0);
    for (const Component& c : m.components())
      for (std::size_t g = 0; g < set.groups.size(); ++g)
        if (set.groups[g].prototype.process->name() == c.process->name() &&
            set.groups[g].prototype.process->structure() == c.process->structure())
          ++counts[g];
    members.push_back(set.find(counts));
    names.push_back(m.canonical().to_string());
  }
  for (const auto& wv : wvs) {
    check_model_fits_levels(super, wv.levels());
  }
  const std::size_t K = models.size();
  std::vector<SignalWork> work = make_work(wvs, K, super, options);
  const int total = static_cast<int>(wvs.size() * (K + 1));
  std::atomic<int> done{0};
  auto tick = [&] {
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  };
  oneapi::tbb::parallel_for(std::size_t{0}, wvs.size() * K, [&](std::size_t k) {
    const std::size_t s = k / K, i = k % K;
    FitOptions fo = options.fit;
    fo.omega_matrix = work[s].omega;
    fo.inference = false;  // nested_starts as the caller set it (default on)
    work[s].fits[i] = fit_gmwm(*work[s].wv, models[i], fo);
    tick();
  });
  std::vector<FitResult> full(wvs.size());
  oneapi::tbb::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    FitOptions fo = options.fit;
    fo.omega_matrix = work[s].omega;
    fo.inference = false;
    fo.nested_starts = false;
    for (const FitResult& f : work[s].fits)
      if (f.status != FitStatus::kFailed) fo.starts.push_back(embed_start(f.model, f.theta, super, *work[s].wv));
    if (work[s].pilot) fo.starts.push_back(embed_start(work[s].pilot->model, work[s].pilot->theta, super, *work[s].wv));
    full[s] = fit_gmwm(*work[s].wv, super, fo);
    tick();
  });
  // Bootstrap optimism of every (signal, model), when asked.
  const bool want_bootstrap = options.optimism != OptimismMethod::kAnalytic;
  const std::vector<BootstrapResult> boot = want_bootstrap ? bootstrap_all(work, K, options) : std::vector<BootstrapResult>{};
  std::vector<Selection> out(wvs.size());
  oneapi::tbb::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    std::vector<const BootstrapResult*> b(K, nullptr);
    if (want_bootstrap)
      for (std::size_t i = 0; i < K; ++i) b[i] = &boot[s * K + i];
    Selection& sel = out[s];
    sel.full_model = super.to_string();
    sel.omega_source = work[s].omega_source;
    score_and_rank(sel, *work[s].wv, work[s].omega, work[s].covariance(full[s]), work[s].fits, names, b, options);
    sel.nesting_violations = count_nesting_violations(set, work[s].fits, &members);
  });
  return out;
}

}  // namespace gmwm::selection
