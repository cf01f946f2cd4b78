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
#include <spdlog/spdlog.h>

#include "active_jacobian.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_relations.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/engine/choice.h"
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

// A model is rejected when its goodness-of-fit p-value is below this (the 5% of issue 13).
constexpr double kRejectionLevel = 0.05;

// Replicate streams are (signal, model, replicate) packed as
// ((signal * models) + model) * kMaxReplicates + replicate.
constexpr int kMaxReplicates = 100000;

struct BootstrapResult {
  double value = 0.0, se = 0.0;
  int failed = 0, not_converged = 0;
};

/// The bootstrap optimism of a row's own fit when it is no candidate (row index given for
/// its streams); empty function: none.
using RowBootstrap = std::function<std::optional<BootstrapResult>(const FitResult&, std::size_t row)>;

// Parametric-bootstrap optimism of one fitted model (docs/statistics.md section 6): B series
// simulated from the fit, their WV by the same estimator, refits warm-started from the
// fit under the same Omega; optimism = 2 tr(Omega C), C the sample cross-covariance of
// nu(theta*) and nuhat*. Its Monte-Carlo s.e. from the per-replicate terms
// 2 (nu(theta*_b) - mean)' Omega (nuhat*_b - mean) (their mean, times B/(B-1), is the
// estimate).
BootstrapResult bootstrap_optimism(const WaveletVariance& wv, const FitResult& fit, const Eigen::MatrixXd& omega,
                                   const SelectOptions& options, std::uint64_t stream_base,
                                   const std::function<void()>& tick) {
  const int B = options.bootstrap_replicates;
  const Eigen::Index J = wv.levels();
  const ClassicalWvEstimator classical;
  // A WV cut by drop_fine_levels (a fit above the smoothed scales): its own levels.
  const FromLevelEstimator estimator(options.estimator ? *options.estimator : classical, first_level(wv));
  std::vector<Eigen::VectorXd> implied(static_cast<std::size_t>(B)), empirical(static_cast<std::size_t>(B));
  std::vector<char> ok(static_cast<std::size_t>(B), 0), converged(static_cast<std::size_t>(B), 0);
  gmwm::parallel_for(0, B, [&](int b) {
    tick();  // progress, and the cancellation point, before each draw's work
    const std::uint64_t stream = stream_base + static_cast<std::uint64_t>(b);
    const WaveletVariance w = [&] {
      if (options.bootstrap_draw) return options.bootstrap_draw(wv, fit.model, fit.theta, stream);
      const std::vector<double> x = simulate(fit.model, fit.theta, wv.n, options.seed, stream);
      return estimator.compute(x.data(), wv.n, static_cast<int>(J), wv.alpha);
    }();
    if (w.levels() != J) return;
    if (!w.values().allFinite()) return;
    FitOptions fo = options.fit;
    fo.omega_matrix = omega;
    fo.nested_starts = false;
    fo.inference = false;
    fo.multistarts = 0;  // from the fit alone: bench_bootstrap_refit_starts
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
      terms.push_back(
          2.0 * (implied[static_cast<std::size_t>(b)] - mi).dot(omega * (empirical[static_cast<std::size_t>(b)] - me)));
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
    Eigen::MatrixXd c = model_wv_covariance(full.model, full.theta, *wv);
    if (wv->efficiency) c /= *wv->efficiency;  // robust WV: variance inflated by 1/eff
    return c;
  }
  // The model WV that covariance(full) is the Cov(nuhat) of; none when the caller gave V.
  std::optional<Eigen::VectorXd> covariance_wv(const FitResult& full) const {
    if (wv->covariance) return std::nullopt;
    const FitResult& at = pilot ? *pilot : full;
    if (at.status == FitStatus::kFailed || at.implied_wv.size() != wv->levels()) return std::nullopt;
    return at.implied_wv;
  }
};

// The bootstrap optimism of a row that is no candidate (its own fit), when the selection
// asked for bootstrap optimism: streams after every candidate's of every signal.
RowBootstrap row_bootstrap(const SignalWork& w, std::size_t signal, std::size_t signals, std::size_t K,
                           const SelectOptions& options) {
  if (options.optimism == OptimismMethod::kAnalytic) return {};
  return [&w, signal, signals, K, &options](const FitResult& f, std::size_t row) -> std::optional<BootstrapResult> {
    const auto base =
        static_cast<std::uint64_t>(signals * K + signal * K + row) * static_cast<std::uint64_t>(kMaxReplicates);
    return bootstrap_optimism(*w.wv, f, w.omega, options, base, [] {});
  };
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
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    SignalWork& w = work[s];
    w.wv = &wvs[s];
    w.fits.resize(K);
    if (wvs[s].covariance) {
      // The caller's V (stacked replicates): Omega from it as for kModel / kModelFull.
      w.v = *wvs[s].covariance;
      if (options.fit.omega_matrix) {
        w.omega = *options.fit.omega_matrix;
        return;
      }
      const bool full = options.omega == OmegaSource::kModelFull;
      w.omega =
          options.omega == OmegaSource::kData ? diagonal_omega(wvs[s]) : model_omega(w.v, diagonal_omega(wvs[s]), full);
      w.omega_source = options.omega == OmegaSource::kData ? OmegaSource::kData
                       : full && !w.omega.isDiagonal(0.0)  ? OmegaSource::kModelFull
                                                           : OmegaSource::kModel;
      return;
    }
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
                                           const SelectOptions& options, const std::function<void()>& tick) {
  std::vector<BootstrapResult> boot(work.size() * K);
  gmwm::parallel_for(std::size_t{0}, boot.size(), [&](std::size_t k) {
    const FitResult& f = work[k / K].fits[k % K];
    if (f.status == FitStatus::kFailed) {
      boot[k].value = boot[k].se = std::numeric_limits<double>::quiet_NaN();
      boot[k].failed = options.bootstrap_replicates;
      for (int b = 0; b < options.bootstrap_replicates; ++b) tick();  // no draws: counted as done
      return;
    }
    boot[k] = bootstrap_optimism(*work[k / K].wv, f, work[k / K].omega, options,
                                 static_cast<std::uint64_t>(k) * static_cast<std::uint64_t>(kMaxReplicates), tick);
  });
  return boot;
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

// Scores one candidate's fit as its effective model: the analytic optimism and the GoF
// at the effective parameters (boundary components left out of A), the bootstrap
// optimism of the candidate as fitted, and the criterion objective + penalty.
RankedModel score_candidate(const WaveletVariance& wv, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v,
                            const CandidateFit& c, const BootstrapResult* boot, bool omega_is_v_inverse,
                            const SelectOptions& options) {
  RankedModel r;
  r.fit = c.fit;
  r.effective = c.effective;
  r.model = c.effective.model.to_string();
  r.members = {c.model};
  r.parameters = c.effective.parameters();
  r.objective = c.fit.objective;
  if (c.fit.status != FitStatus::kFailed) {
    const Model& m = c.effective.model;
    r.analytic = analytic_optimism(m, c.effective.theta, wv.tau, wv.values(), omega, v);
    if (r.analytic.status != OptimismStatus::kFailed) r.optimism_analytic = r.analytic.value;
    // The GoF is measured with Cov(nuhat) at the row's own estimate, as fit measures its
    // own (one rule): with the maximal pilot's V, a true WN+QN+RW was rejected in 22.5% of
    // series at 5% (issue 43, item 4; tools/bench/bench_gof_level). The shared Omega is
    // not that V's inverse, so the test is Satterthwaite's unless the WV carries its own V.
    // The pilot's V rescaled to the row's WV (D V D, D = nu_row / nu_pilot) would cost
    // nothing but is not calibrated (9.0% and 10.1% on the first two truths): the
    // correlation of a level's coefficients depends on the row's spectral shape. The exact
    // V costs select 1.33x (6 x 63 models on adis_16405_imu1: 3.27 s against 2.48 s), to be
    // won back in model_wv_covariance itself (issue 44).
    r.gof =
        goodness_of_fit(detail::active_jacobian(m, c.effective.theta, wv.tau, r.analytic.boundary_components),
                        r.objective, static_cast<double>(wv.levels() - r.parameters), omega,
                        wv_covariance_at(wv, m, c.effective.theta), omega_is_v_inverse && wv.covariance.has_value());
  }
  if (boot) {
    if (std::isfinite(boot->value)) {
      r.optimism_bootstrap = boot->value;
      r.optimism_bootstrap_se = boot->se;
    }
    r.bootstrap_failed = boot->failed;
    r.bootstrap_not_converged = boot->not_converged;
  }
  if (options.penalty == Penalty::kWvic)
    r.optimism = (options.optimism == OptimismMethod::kBootstrap ? r.optimism_bootstrap : r.optimism_analytic)
                     .value_or(std::numeric_limits<double>::quiet_NaN());
  else
    r.optimism = r.parameters * std::log(static_cast<double>(wv.n));
  r.criterion =
      c.fit.status == FitStatus::kFailed ? std::numeric_limits<double>::quiet_NaN() : r.objective + r.optimism;
  return r;
}

// A row's own fit: its displayed model fitted alone, started from every member's
// effective parameters and from its own candidate fit when it is a candidate; the better
// of that refit and the candidate's fit. A row used to keep its best member's fit, so
// "AR1+WN" showed the objective and GoF of the 3*AR1+WN+QN+RW+DR it had been reduced from
// (issue 27).
FitResult own_fit(const WaveletVariance& wv, const Eigen::MatrixXd& omega, const Model& model,
                  const std::vector<const CandidateFit*>& members, const FitResult* exact,
                  const SelectOptions& options) {
  FitOptions fo = options.fit;
  fo.omega_matrix = omega;
  fo.nested_starts = false;
  fo.inference = false;
  if (exact) fo.starts.push_back(exact->theta);
  for (const CandidateFit* c : members)
    if (c->fit.status != FitStatus::kFailed && c->effective.theta.size() == model.num_parameters())
      fo.starts.push_back(c->effective.theta);
  FitResult r = fit_gmwm(wv, model, fo);
  if (exact && (r.status == FitStatus::kFailed || exact->objective <= r.objective)) return *exact;
  return r;
}

// The model as fitted, in canonical order, as its own effective form (nothing reduced).
EffectiveModel as_fitted(const FitResult& f) {
  EffectiveModel e;
  Eigen::VectorXd th = f.theta;
  e.model = f.model.canonical(&th);
  e.theta = th;
  e.labels.assign(static_cast<std::size_t>(e.model.num_components()), "");
  return e;
}

// The rows of a ranking. `group`: one per distinct effective model, the candidates that
// fell onto it listed as members (the model itself first when it is a candidate, then by
// their own objectives); else one per listed model. Every row's numbers are its own
// model's fit (own_fit); the reductions shown are how its best member fell onto it.
std::vector<RankedModel> ranking_rows(const WaveletVariance& wv, const Eigen::MatrixXd& omega, const Eigen::MatrixXd& v,
                                      const std::vector<CandidateFit>& cands,
                                      const std::vector<const BootstrapResult*>& boot, bool group,
                                      bool omega_is_v_inverse, const SelectOptions& options,
                                      const RowBootstrap& row_bootstrap) {
  std::vector<std::string> keys;
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const std::string key = group ? cands[i].effective.model.to_string() : cands[i].model;
    const auto it = std::find(keys.begin(), keys.end(), key);
    if (it == keys.end()) {
      keys.push_back(key);
      groups.push_back({i});
    } else {
      groups[static_cast<std::size_t>(it - keys.begin())].push_back(i);
    }
  }
  std::vector<RankedModel> rows(keys.size());
  gmwm::parallel_for(std::size_t{0}, keys.size(), [&](std::size_t g) {
    std::vector<std::size_t> idx = groups[g];
    // The row's model as a candidate itself, wherever its own fit's effective form put it
    // (AR1+WN+RW whose RW collapsed is "AR1+WN" in effect, yet its fit is still the best of
    // the row AR1+WN+RW that other members fell onto).
    std::optional<std::size_t> exact;
    for (std::size_t i = 0; i < cands.size(); ++i)
      if (cands[i].model == keys[g] && cands[i].fit.status != FitStatus::kFailed) exact = i;
    // Members: the model itself first, then by their own objectives (failed fits last).
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
      if (exact && (a == *exact) != (b == *exact)) return a == *exact;
      const double x = cands[a].fit.status == FitStatus::kFailed ? INFINITY : cands[a].fit.objective;
      const double y = cands[b].fit.status == FitStatus::kFailed ? INFINITY : cands[b].fit.objective;
      return x < y;
    });
    std::vector<const CandidateFit*> members;
    for (std::size_t i : idx) members.push_back(&cands[i]);
    const bool any = std::any_of(members.begin(), members.end(),
                                 [](const CandidateFit* c) { return c->fit.status != FitStatus::kFailed; });
    CandidateFit row{keys[g], cands[idx.front()].fit, {}};
    if (!any) {
      row.effective = cands[idx.front()].effective;
    } else {
      const Model& model = group ? members.front()->effective.model : members.front()->fit.model;
      row.fit = group ? own_fit(wv, omega, model, members, exact ? &cands[*exact].fit : nullptr, options)
                      : cands[idx.front()].fit;
      row.effective = as_fitted(row.fit);
    }
    const BootstrapResult* b = exact ? boot[*exact] : (group ? nullptr : boot[idx.front()]);
    std::optional<BootstrapResult> extra;
    if (!b && any && row_bootstrap) {
      extra = row_bootstrap(row.fit, g);
      if (extra) b = &*extra;
    }
    RankedModel r = score_candidate(wv, omega, v, row, b, omega_is_v_inverse, options);
    r.model = keys[g];
    r.members.clear();
    for (const CandidateFit* c : members) {
      r.members.push_back(c->model);
      r.member_objectives.push_back(c->fit.status == FitStatus::kFailed ? std::numeric_limits<double>::quiet_NaN()
                                                                        : c->fit.objective);
    }
    // How the members fell onto the row's model: the reductions of its best-fitting member.
    for (const CandidateFit* c : members)
      if (c->effective.reduced()) {
        r.effective.reductions = c->effective.reductions;
        r.reduced_member = c->model;
        break;
      }
    rows[g] = std::move(r);
  });
  return rows;
}

// Scores the fitted candidates of one signal, ranks their rows (ranking_rows), and refits
// the best with inference. v: Cov(nuhat), model-based at the maximal model's fit.
void score_and_rank(Selection& sel, const WaveletVariance& wv, const Eigen::MatrixXd& omega, Eigen::MatrixXd v,
                    const std::optional<Eigen::VectorXd>& v_at, const std::vector<FitResult>& fits,
                    const std::vector<std::string>& names, const std::vector<const BootstrapResult*>& boot, bool group,
                    const SelectOptions& options, const RowBootstrap& row_bootstrap) {
  const std::size_t K = fits.size();
  sel.models = static_cast<int>(K);
  sel.omega = omega;
  sel.v = std::move(v);
  sel.candidates.clear();
  sel.not_converged = sel.failed = 0;
  for (std::size_t i = 0; i < K; ++i) {
    CandidateFit c{names[i], fits[i], {}};
    if (fits[i].status == FitStatus::kFailed) {
      ++sel.failed;
      c.effective.model = fits[i].model.canonical();
      c.effective.theta = fits[i].theta;
    } else {
      if (fits[i].status == FitStatus::kNotConverged) ++sel.not_converged;
      EffectiveOptions eo;
      eo.covariance = sel.v;    // the exact Cov(nuhat) the optimism and GoF use
      eo.covariance_wv = v_at;  // ... at this WV: each reduction is tested at its own levels
      c.effective = effective_model(wv, fits[i].model, fits[i].theta, eo);
    }
    sel.candidates.push_back(std::move(c));
  }
  std::vector<RankedModel> rows = ranking_rows(wv, omega, sel.v, sel.candidates, boot, group,
                                               sel.omega_source == OmegaSource::kModelFull, options, row_bootstrap);
  const std::size_t R = rows.size();
  // Ranks under each optimism (WVIC): by objective + that optimism, same tie rule.
  auto with = [](const std::optional<double>& o, double objective) {
    return o ? objective + *o : std::numeric_limits<double>::quiet_NaN();
  };
  if (options.penalty == Penalty::kWvic) {
    const auto a = rank_order(rows, [&](const RankedModel& r) { return with(r.optimism_analytic, r.objective); });
    for (std::size_t k = 0; k < R; ++k)
      if (rows[a[k]].optimism_analytic) rows[a[k]].rank_analytic = static_cast<int>(k) + 1;
    if (options.optimism != OptimismMethod::kAnalytic) {
      const auto b = rank_order(rows, [&](const RankedModel& r) { return with(r.optimism_bootstrap, r.objective); });
      for (std::size_t k = 0; k < R; ++k)
        if (rows[b[k]].optimism_bootstrap) rows[b[k]].rank_bootstrap = static_cast<int>(k) + 1;
    }
  }
  const auto order = rank_order(rows, [](const RankedModel& r) { return r.criterion; });
  sel.ranking.clear();
  for (std::size_t k = 0; k < R; ++k) {
    sel.ranking.push_back(std::move(rows[order[k]]));
    sel.ranking.back().rank = static_cast<int>(k) + 1;
  }
  // The best effective model with inference (same Omega), from its effective parameters
  // and, when it is a candidate itself, from that candidate's optimum.
  const RankedModel& top = sel.ranking.front();
  FitOptions fo = options.fit;
  fo.omega_matrix = omega;
  fo.nested_starts = false;
  fo.inference = true;
  fo.starts = {top.effective.theta};
  sel.best_fit = fit_gmwm(wv, top.effective.model, fo);
  // One verdict: the first row's test is its refit's, the GoF every face prints beside the
  // chosen model (the same rule, at the same Omega; the refit's estimate is the final one).
  if (sel.best_fit.status != FitStatus::kFailed && std::isfinite(sel.best_fit.gof.p_value))
    sel.ranking.front().gof = sel.best_fit.gof;
  sel.all_rejected = std::all_of(sel.ranking.begin(), sel.ranking.end(), [](const RankedModel& r) {
    return !std::isfinite(r.gof.p_value) || r.gof.p_value < kRejectionLevel;
  });
}

// Pairs (i, k) where models[i] represents models[k] (nested or through an equivalent
// form) and still ends above it (relative kNestingTolerance).
int count_representation_violations(const std::vector<std::vector<bool>>& rep, const std::vector<FitResult>& fits) {
  int n = 0;
  for (std::size_t i = 0; i < fits.size(); ++i)
    for (std::size_t k = 0; k < fits.size(); ++k)
      if (rep[i][k] && fits[i].status != FitStatus::kFailed && fits[k].status != FitStatus::kFailed &&
          fits[i].objective > fits[k].objective * (1.0 + kNestingTolerance))
        ++n;
  return n;
}

/// Fits `models` on every signal of `work` along the representation order: a model's
/// node runs once the nodes of the models it covers are done and starts from their
/// optima mapped into it (represent_start), in the covers' fixed order, so the result
/// does not depend on the thread count. `with_own_starts`: each fit also starts from its
/// own representation neighbours (the non-nested mode, where they are not in the list).
void fit_along_representation(std::vector<SignalWork>& work, const std::vector<Model>& models,
                              const std::vector<std::vector<int>>& covers, const Model* maximal, bool with_own_starts,
                              const SelectOptions& options, int total, std::atomic<int>& done) {
  const std::size_t K = models.size();
  // One fit: signal s, model i, started from the fits of the models it covers.
  auto fit_one = [&](std::size_t s, std::size_t i) {
    SignalWork& w = work[s];
    const Model& m = models[i];
    FitOptions fo = options.fit;
    fo.omega_matrix = w.omega;
    fo.nested_starts = with_own_starts;
    fo.inference = false;
    for (int k : covers[i]) {
      const FitResult& kf = w.fits[static_cast<std::size_t>(k)];
      if (kf.status == FitStatus::kFailed) continue;
      if (auto start = represent_start(m, kf.model, kf.theta, *w.wv)) fo.starts.push_back(std::move(*start));
    }
    if (w.pilot && maximal && m.to_string() == maximal->to_string())
      if (auto start = represent_start(m, w.pilot->model, w.pilot->theta, *w.wv))
        fo.starts.push_back(std::move(*start));
    w.fits[i] = fit_gmwm(*w.wv, m, fo);
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  };
#ifdef GMWM_THREAD_SANITIZER
  // Under ThreadSanitizer (gmwm/engine/parallel.h): the same fits in waves, each wave the
  // models whose covered models are all fitted, run by gmwm::parallel_for on std::threads.
  std::vector<char> fitted(K, 0);
  for (std::size_t left = K; left > 0;) {
    std::vector<std::size_t> wave;
    for (std::size_t i = 0; i < K; ++i)
      if (!fitted[i] && std::all_of(covers[i].begin(), covers[i].end(),
                                    [&](int k) { return fitted[static_cast<std::size_t>(k)] != 0; }))
        wave.push_back(i);
    if (wave.empty()) throw std::logic_error("fit_along_representation: the covers are not a DAG");
    gmwm::parallel_for(std::size_t{0}, wave.size() * work.size(),
                       [&](std::size_t t) { fit_one(t / wave.size(), wave[t % wave.size()]); });
    for (std::size_t i : wave) fitted[i] = 1;
    left -= wave.size();
  }
#else
  namespace flow = oneapi::tbb::flow;
  flow::graph g;
  using Node = flow::continue_node<flow::continue_msg>;
  std::vector<std::unique_ptr<Node>> nodes;
  nodes.reserve(work.size() * K);
  for (std::size_t s = 0; s < work.size(); ++s) {
    for (std::size_t i = 0; i < K; ++i)
      nodes.push_back(std::make_unique<Node>(g, [&, s, i](const flow::continue_msg&) { fit_one(s, i); }));
    for (std::size_t i = 0; i < K; ++i)
      for (int k : covers[i]) flow::make_edge(*nodes[s * K + static_cast<std::size_t>(k)], *nodes[s * K + i]);
  }
  for (std::size_t s = 0; s < work.size(); ++s)
    for (std::size_t i = 0; i < K; ++i)
      if (covers[i].empty()) nodes[s * K + i]->try_put(flow::continue_msg());
  g.wait_for_all();
#endif
}

}  // namespace

const char* to_string(Penalty p) { return p == Penalty::kWvic ? "wvic" : "bic"; }

const char* to_string(OmegaSource o) {
  switch (o) {
    case OmegaSource::kData:
      return "data";
    case OmegaSource::kModel:
      return "model";
    case OmegaSource::kModelFull:
      return "full";
  }
  return "model";
}

const char* to_string(OptimismMethod m) {
  switch (m) {
    case OptimismMethod::kAnalytic:
      return "analytic";
    case OptimismMethod::kBootstrap:
      return "bootstrap";
    case OptimismMethod::kBoth:
      return "both";
  }
  return "analytic";
}

namespace {
// Each enum's names once, in the order a user reads them.
constexpr Penalty kPenalties[] = {Penalty::kWvic, Penalty::kBic};
constexpr OptimismMethod kOptimismMethods[] = {OptimismMethod::kAnalytic, OptimismMethod::kBootstrap,
                                               OptimismMethod::kBoth};
constexpr OmegaSource kOmegaSources[] = {OmegaSource::kModel, OmegaSource::kModelFull, OmegaSource::kData};
}  // namespace

std::optional<Penalty> parse_penalty(const std::string& name) { return parse_among(name, kPenalties); }
std::optional<OptimismMethod> parse_optimism_method(const std::string& name) {
  return parse_among(name, kOptimismMethods);
}
std::optional<OmegaSource> parse_omega_source(const std::string& name) { return parse_among(name, kOmegaSources); }

std::vector<std::string> penalty_names() { return names_among(kPenalties); }
std::vector<std::string> optimism_method_names() { return names_among(kOptimismMethods); }
std::vector<std::string> omega_source_names() { return names_among(kOmegaSources); }

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
  // Progress: every fit, then every bootstrap draw (a failed fit's draws count as done).
  const bool want_bootstrap = options.optimism != OptimismMethod::kAnalytic;
  const int total = static_cast<int>(wvs.size() * K * (1 + (want_bootstrap ? options.bootstrap_replicates : 0)));
  std::atomic<int> done{0};
  auto tick = [&] {
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  };
  std::vector<Model> models;
  for (const auto& m : set.models) models.push_back(m.model);
  const auto rep = representation_matrix(models);
  fit_along_representation(work, models, representation_covers(rep), &set.models.back().model, false, options, total,
                           done);

  // Bootstrap optimism of every (signal, model), when asked.
  const std::vector<BootstrapResult> boot =
      want_bootstrap ? bootstrap_all(work, K, options, tick) : std::vector<BootstrapResult>{};

  // Scoring and ranking, per signal.
  std::vector<Selection> out(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    const SignalWork& w = work[s];
    std::vector<std::string> names;
    for (const auto& m : set.models) names.push_back(m.model.to_string());
    std::vector<const BootstrapResult*> b(K, nullptr);
    if (want_bootstrap)
      for (std::size_t i = 0; i < K; ++i) b[i] = &boot[s * K + i];
    Selection& sel = out[s];
    sel.full_model = set.models.back().model.to_string();
    sel.omega_source = w.omega_source;
    score_and_rank(sel, *w.wv, w.omega, w.covariance(w.fits.back()), w.covariance_wv(w.fits.back()), w.fits, names, b,
                   true, options, row_bootstrap(w, s, wvs.size(), K, options));
    sel.representation_violations = count_representation_violations(rep, w.fits);
  });
  return out;
}

std::vector<Selection> select_among(const std::vector<WaveletVariance>& wvs, const std::vector<Model>& models,
                                    const SelectOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("select: " + why);
  if (models.empty()) throw InputError("select: no models given");
  if (models.size() > kMaxListedModels)
    throw InputError("select: found a list of " + std::to_string(models.size()) + " models, expected at most " +
                     std::to_string(kMaxListedModels) + " (a maximal model ranks its sub-models without a list)");
  const Model super = common_supermodel(models);
  std::vector<std::string> names;
  for (const Model& m : models) names.push_back(m.canonical().to_string());
  for (const auto& wv : wvs) check_model_fits_levels(super, wv.levels());
  const std::size_t K = models.size();
  std::vector<SignalWork> work = make_work(wvs, K, super, options);
  const bool want_bootstrap = options.optimism != OptimismMethod::kAnalytic;
  const int total = static_cast<int>(wvs.size() * (K + 1 + (want_bootstrap ? K * options.bootstrap_replicates : 0)));
  std::atomic<int> done{0};
  auto tick = [&] {
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  };
  // The listed models along the representation order among them, each also with its own
  // representation neighbours (they are not in the list): nested_starts as the caller set it.
  const auto rep = representation_matrix(models);
  fit_along_representation(work, models, representation_covers(rep), nullptr, options.fit.nested_starts, options, total,
                           done);
  std::vector<FitResult> full(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    FitOptions fo = options.fit;
    fo.omega_matrix = work[s].omega;
    fo.inference = false;
    fo.nested_starts = false;
    for (const FitResult& f : work[s].fits)
      if (f.status != FitStatus::kFailed)
        if (auto start = represent_start(super, f.model, f.theta, *work[s].wv)) fo.starts.push_back(std::move(*start));
    if (work[s].pilot)
      if (auto start = represent_start(super, work[s].pilot->model, work[s].pilot->theta, *work[s].wv))
        fo.starts.push_back(std::move(*start));
    full[s] = fit_gmwm(*work[s].wv, super, fo);
    tick();
  });
  // Bootstrap optimism of every (signal, model), when asked.
  const std::vector<BootstrapResult> boot =
      want_bootstrap ? bootstrap_all(work, K, options, tick) : std::vector<BootstrapResult>{};
  std::vector<Selection> out(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t s) {
    std::vector<const BootstrapResult*> b(K, nullptr);
    if (want_bootstrap)
      for (std::size_t i = 0; i < K; ++i) b[i] = &boot[s * K + i];
    Selection& sel = out[s];
    sel.full_model = super.to_string();
    sel.omega_source = work[s].omega_source;
    score_and_rank(sel, *work[s].wv, work[s].omega, work[s].covariance(full[s]), work[s].covariance_wv(full[s]),
                   work[s].fits, names, b, false, options, {});
    sel.representation_violations = count_representation_violations(rep, work[s].fits);
  });
  return out;
}

}  // namespace gmwm::selection
