#include "gmwm/selection/gap.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <oneapi/tbb/parallel_for.h>

#include "gap_events.h"
#include "gap_levels.h"
#include "gap_reference.h"
#include "gap_summary.h"
#include "gap_windows.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/robust/contamination.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"

namespace gmwm::selection {
namespace {

// Local optimisations per candidate fit: the effects have one or two parameters, whose
// shape-based starts (engine/src/starting_values.cc) place scale-bearing ones on a grid.
constexpr int kCandidateStarts = 4;
// --fit mode (and after REPARAMETERISE) each calibration replicate costs two refits of
// the family per candidate: half as many replicates (the threshold's two-moment
// chi-square fit stays stable: the mean and variance of 50 drops).
constexpr int kRefitCalibrationReplicates = 50;
// Shape-based starts of the --fit mode calibration refits (besides the warm starts).
constexpr int kRefitCalibrationStarts = 1;
// Reference replicates used to calibrate each candidate's threshold (each costs one fit
// per candidate and step); the threshold comes from a scaled chi-square matched to their
// drops' mean and variance (Satterthwaite 1946), so 100 give a stable tail quantile.
constexpr int kCalibrationReplicates = 100;
// The finest levels where outliers show first (GAP.md: robust/classical ratio at tau = 2..8).
constexpr int kOutlierLevels = 3;
// Stream offset of the reference replicates of each forward step's shifted reference is
// not needed (the reference is simulated once); the replicate streams are (seed, b).

struct CandidateSpec {
  GapEffect effect;
  const char* process;  // added process (nullptr: REPARAMETERISE)
};

constexpr CandidateSpec kCatalogue[] = {
    {GapEffect::kWN, "WN"},          {GapEffect::kQN, "QN"},   {GapEffect::kRW, "RW"},
    {GapEffect::kDR, "DR"},          {GapEffect::kAR1, "AR1"}, {GapEffect::kFlicker, "FLICKER"},
    {GapEffect::kSin, "SIN"},        {GapEffect::kReparameterise, nullptr},
};

bool has_process(const Model& m, const std::string& name) {
  for (const auto& c : m.components())
    if (c.process->name() == name) return true;
  return false;
}

// The candidates tried against `base`: the requested ones (all by default), without
// a single-instance term the base already has (adding it is a re-sizing, i.e.
// REPARAMETERISE, GAP.md s.5), and without REPARAMETERISE when the base is refitted anyway.
std::vector<CandidateSpec> candidates_for(const Model& base, const GapOptions& o) {
  std::vector<CandidateSpec> out;
  for (const auto& c : kCatalogue) {
    if (!o.candidates.empty() && std::find(o.candidates.begin(), o.candidates.end(), c.effect) == o.candidates.end())
      continue;
    if (c.process == nullptr) {
      if (!o.refit_baseline) out.push_back(c);
      continue;
    }
    const std::string p = c.process;
    if ((p == "WN" || p == "QN" || p == "RW" || p == "DR") && has_process(base, p)) continue;
    out.push_back(c);
  }
  return out;
}

WaveletVariance with_values(const WaveletVariance& like, const Eigen::VectorXd& v) {
  WaveletVariance w = like;
  w.wv.assign(v.data(), v.data() + v.size());
  return w;
}

double objective(const Eigen::VectorXd& target, const Eigen::VectorXd& nu, const Eigen::MatrixXd& omega) {
  const Eigen::VectorXd r = target - nu;
  return r.dot(omega * r);
}

FitOptions candidate_fit_options(const GapOptions& o, const Eigen::MatrixXd& omega) {
  FitOptions fo = o.fit;
  fo.omega_matrix = omega;
  fo.inference = false;
  fo.nested_starts = false;
  fo.multistarts = kCandidateStarts;
  fo.log_not_converged = false;
  return fo;
}

// The baseline as the candidates see it: its family, its values and its WV.
struct Base {
  Model model;
  Eigen::VectorXd theta;
  Eigen::VectorXd nu;
};

// The objective left by `spec` on `target` (baseline fixed: the effect is fitted to the
// residual; refit: the family and the effect together, started from the base's values)
// and the fit behind it. REPARAMETERISE: the base's family with free values.
double fit_candidate(const CandidateSpec& spec, const Base& base, const Eigen::VectorXd& target,
                     const WaveletVariance& like, const Eigen::MatrixXd& omega, const GapOptions& o, FitResult* out,
                     const FitResult* warm = nullptr) {
  FitOptions fo = candidate_fit_options(o, omega);
  FitResult r;
  // Calibration refits of --fit mode (family + effect on each replicate) start from the
  // data's fit and one shape-based start: they cost the most, and the replicates lie
  // close to the base.
  if (warm && o.refit_baseline && spec.process != nullptr) fo.multistarts = kRefitCalibrationStarts;
  if (spec.process == nullptr) {
    fo.starts = {base.theta};
    r = fit_gmwm(with_values(like, target), base.model, fo);
  } else if (!o.refit_baseline) {
    r = fit_gmwm(with_values(like, target - base.nu), parse_model(spec.process, o.context), fo);
  } else {
    const Model m = base.model + parse_model(spec.process, o.context);
    const WaveletVariance w = with_values(like, target);
    fo.starts = {embed_start(base.model, base.theta, m, w)};
    if (warm && warm->status != FitStatus::kFailed) fo.starts.push_back(embed_start(warm->model, warm->theta, m, w));
    r = fit_gmwm(w, m, fo);
  }
  const double g = r.status == FitStatus::kFailed ? std::numeric_limits<double>::infinity() : r.objective;
  if (out) *out = std::move(r);
  return g;
}

// The objective of the base itself on `target`: fixed, or refitted (--fit mode).
double base_objective(const Base& base, const Eigen::VectorXd& target, const WaveletVariance& like,
                      const Eigen::MatrixXd& omega, const GapOptions& o) {
  if (!o.refit_baseline) return objective(target, base.nu, omega);
  FitOptions fo = candidate_fit_options(o, omega);
  fo.multistarts = kRefitCalibrationStarts;
  fo.starts = {base.theta};
  const FitResult r = fit_gmwm(with_values(like, target), base.model, fo);
  return r.status == FitStatus::kFailed ? objective(target, base.nu, omega) : r.objective;
}

// (1 - level) quantile of a scaled chi-square a chi2_d matched to the drops' mean and variance.
double calibrated_threshold(const std::vector<double>& drops, double level) {
  double mean = 0.0, var = 0.0;
  for (double d : drops) mean += d;
  mean /= static_cast<double>(drops.size());
  for (double d : drops) var += (d - mean) * (d - mean);
  var /= static_cast<double>(drops.size() - 1);
  const double biggest = *std::max_element(drops.begin(), drops.end());
  if (!(mean > 0.0) || !(var > 0.0)) return std::max(biggest, 0.0);
  const double a = var / (2.0 * mean), d = 2.0 * mean * mean / var;
  return a * boost::math::quantile(boost::math::complement(boost::math::chi_squared(d), level));
}

FitResult effect_part(const FitResult& augmented, const Base& base);

// Percentile intervals of the effect chosen at a step: the effect refitted on
// replicates of the augmented model (the base's reference rescaled level by level to it),
// exactly as it was fitted on the data. Fills fit.se, ci_low, ci_high.
void effect_intervals(const CandidateSpec& spec, const Base& base, const Eigen::MatrixXd& reps_augmented,
                      const WaveletVariance& like, const Eigen::MatrixXd& omega, const GapOptions& o,
                      const FitResult& chosen, FitResult& fit) {
  const int R = std::min<int>(o.refit_baseline ? kRefitCalibrationReplicates : kCalibrationReplicates,
                              static_cast<int>(reps_augmented.rows()));
  const Eigen::Index p = fit.theta.size();
  Eigen::MatrixXd draws = Eigen::MatrixXd::Constant(R, p, std::numeric_limits<double>::quiet_NaN());
  oneapi::tbb::parallel_for(0, R, [&](int b) {
    FitResult r;
    const double left = fit_candidate(spec, base, reps_augmented.row(b).transpose(), like, omega, o, &r, &chosen);
    if (!std::isfinite(left)) return;
    const FitResult e = o.refit_baseline ? effect_part(r, base) : r;
    if (e.theta.size() == p) draws.row(b) = e.theta.transpose();
  });
  fit.se.resize(p);
  fit.ci_low.resize(p);
  fit.ci_high.resize(p);
  for (Eigen::Index k = 0; k < p; ++k) {
    std::vector<double> v;
    for (int b = 0; b < R; ++b)
      if (std::isfinite(draws(b, k))) v.push_back(draws(b, k));
    if (v.size() < 2) {
      fit.se(k) = fit.ci_low(k) = fit.ci_high(k) = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    std::sort(v.begin(), v.end());
    double mean = 0.0, var = 0.0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    for (double x : v) var += (x - mean) * (x - mean);
    fit.se(k) = std::sqrt(var / static_cast<double>(v.size() - 1));
    auto q = [&](double level) { return v[static_cast<std::size_t>(std::lround(level * static_cast<double>(v.size() - 1)))]; };
    fit.ci_low(k) = q(o.alpha / 2.0);
    fit.ci_high(k) = q(1.0 - o.alpha / 2.0);
  }
}

struct Step {
  std::vector<GapCandidate> scored;
  int best = -1;  // index into scored, -1 when nothing cleared
};

// Scores every candidate on the data and calibrates it on the replicates (rows of `reps`,
// data from the base alone).
Step score_step(const std::vector<CandidateSpec>& specs, const Base& base, const Eigen::VectorXd& nuhat,
                const Eigen::MatrixXd& reps, const WaveletVariance& like, const Eigen::MatrixXd& omega,
                const GapOptions& o) {
  const std::size_t K = specs.size();
  const int R = std::min<int>(o.refit_baseline ? kRefitCalibrationReplicates : kCalibrationReplicates,
                              static_cast<int>(reps.rows()));
  Step s;
  s.scored.resize(K);
  std::vector<std::vector<double>> drops(K, std::vector<double>(static_cast<std::size_t>(R), 0.0));
  const double g_data = base_objective(base, nuhat, like, omega, o);
  // The base's own objective on each replicate, once (a refit in --fit mode).
  std::vector<double> g_base(static_cast<std::size_t>(R));
  oneapi::tbb::parallel_for(0, R, [&](int b) {
    g_base[static_cast<std::size_t>(b)] =
        base_objective(base, reps.row(b).transpose(), like, omega, o);
  });
  // The data's fits first (the replicates' refits start from them).
  oneapi::tbb::parallel_for(std::size_t{0}, K, [&](std::size_t c) {
    GapCandidate& g = s.scored[c];
    g.effect = specs[c].effect;
    const double left = fit_candidate(specs[c], base, nuhat, like, omega, o, &g.fit);
    g.improvement = std::isfinite(left) ? g_data - left : 0.0;
    if (g.fit.status != FitStatus::kFailed) g.model = g.fit.model.to_string(g.fit.theta);
  });
  oneapi::tbb::parallel_for(std::size_t{0}, K * static_cast<std::size_t>(R), [&](std::size_t k) {
    const std::size_t c = k % K, b = k / K;
    const Eigen::VectorXd t = reps.row(static_cast<Eigen::Index>(b)).transpose();
    const double left = fit_candidate(specs[c], base, t, like, omega, o, nullptr, &s.scored[c].fit);
    drops[c][b] = std::isfinite(left) ? g_base[b] - left : 0.0;
  });
  // Cleared candidates rank by how far their drop exceeds their own null threshold (a
  // flexible candidate pays for its flexibility through a higher threshold).
  double best_margin = 0.0;
  for (std::size_t c = 0; c < K; ++c) {
    GapCandidate& g = s.scored[c];
    g.threshold = calibrated_threshold(drops[c], o.alpha / static_cast<double>(K));
    for (double d : drops[c]) g.optimism += d;
    g.optimism /= static_cast<double>(drops[c].size());
    g.wvic_confirmed = g.improvement > 2.0 * g.optimism;
    g.cleared = g.fit.status != FitStatus::kFailed && g.improvement > g.threshold && g.wvic_confirmed;
    if (g.cleared && g.improvement - g.threshold > best_margin) {
      best_margin = g.improvement - g.threshold;
      s.best = static_cast<int>(c);
    }
  }
  // Parsimony (GAP.md s.3, "parsimony"): a candidate with more parameters must beat
  // every cleared simpler one by more than its own threshold, else the simpler one that
  // explains the most is kept (a SIN near Nyquist has QN's slope; an AR1 with a long
  // correlation time a FLICKER's plateau over a few octaves).
  if (s.best >= 0 && specs[static_cast<std::size_t>(s.best)].process != nullptr) {
    const GapCandidate& b = s.scored[static_cast<std::size_t>(s.best)];
    int simpler = -1;
    for (std::size_t c = 0; c < K; ++c) {
      const GapCandidate& g = s.scored[c];
      if (!g.cleared || specs[c].process == nullptr || g.fit.theta.size() >= b.fit.theta.size()) continue;
      if (b.improvement - g.improvement > b.threshold) continue;
      if (simpler < 0 || g.improvement > s.scored[static_cast<std::size_t>(simpler)].improvement)
        simpler = static_cast<int>(c);
    }
    if (simpler >= 0) s.best = simpler;
  }
  return s;
}

// The added effect's component of a refitted augmented model (base family + effect),
// as a fit of that component alone: every base component is matched, greedily, to the
// augmented component of the same process whose values are closest (relative); the one
// left over is the effect.
FitResult effect_part(const FitResult& augmented, const Base& base) {
  const Model& m = augmented.model;
  std::vector<char> used(static_cast<std::size_t>(m.num_components()), 0);
  for (int b = 0; b < base.model.num_components(); ++b) {
    const Process& pb = *base.model.components()[static_cast<std::size_t>(b)].process;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int c = 0; c < m.num_components(); ++c) {
      const Process& pc = *m.components()[static_cast<std::size_t>(c)].process;
      if (used[static_cast<std::size_t>(c)] || pc.name() != pb.name() || pc.size() != pb.size()) continue;
      double d = 0.0;
      for (int k = 0; k < pc.size(); ++k) {
        const double x = augmented.theta(m.offset(c) + k), y = base.theta(base.model.offset(b) + k);
        d += std::pow((x - y) / std::max({std::abs(x), std::abs(y), 1e-300}), 2);
      }
      if (d < best_d) {
        best_d = d;
        best = c;
      }
    }
    if (best >= 0) used[static_cast<std::size_t>(best)] = 1;
  }
  FitResult out = augmented;
  for (int c = 0; c < m.num_components(); ++c) {
    if (used[static_cast<std::size_t>(c)]) continue;
    const auto& comp = m.components()[static_cast<std::size_t>(c)];
    out.model = Model({comp});
    out.theta = augmented.theta.segment(m.offset(c), comp.process->size());
    out.se.resize(0);
    out.ci_low.resize(0);
    out.ci_high.resize(0);
    break;
  }
  return out;
}

}  // namespace

const char* to_string(GapEffect e) {
  switch (e) {
    case GapEffect::kNone: return "none";
    case GapEffect::kWN: return "WN";
    case GapEffect::kQN: return "QN";
    case GapEffect::kRW: return "RW";
    case GapEffect::kDR: return "DR";
    case GapEffect::kAR1: return "AR1";
    case GapEffect::kFlicker: return "FLICKER";
    case GapEffect::kSin: return "SIN";
    case GapEffect::kOutliers: return "OUTLIERS";
    case GapEffect::kStep: return "STEP";
    case GapEffect::kTransient: return "TRANSIENT";
    case GapEffect::kTemperature: return "TEMPERATURE";
    case GapEffect::kReparameterise: return "REPARAMETERISE";
  }
  return "none";
}

std::optional<GapEffect> parse_gap_effect(const std::string& name) {
  for (int e = static_cast<int>(GapEffect::kNone); e <= static_cast<int>(GapEffect::kReparameterise); ++e)
    if (name == to_string(static_cast<GapEffect>(e))) return static_cast<GapEffect>(e);
  return std::nullopt;
}

std::string GapOptions::Validate() const {
  std::ostringstream os;
  if (replicates < 20 || replicates > 100000) os << "replicates must be in [20, 100000], got " << replicates;
  else if (!(alpha > 0.0 && alpha < 0.5)) os << "alpha must be in (0, 0.5), got " << alpha;
  else if (!(min_effect >= 0.0)) os << "min_effect must be >= 0, got " << min_effect;
  else if (max_steps < 0) os << "max_steps must be >= 0, got " << max_steps;
  return os.str();
}

GapResult diagnose_gap(const WaveletVariance& wv, const Model& baseline, const Eigen::VectorXd& theta,
                       const GapOptions& options, const WaveletVariance* robust, const std::vector<double>* x,
                       const std::vector<double>* temperature) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("gap: " + why);
  if (const std::string why = baseline.validate(theta); !why.empty()) throw InputError("gap: baseline " + why);
  const Eigen::VectorXd nuhat = wv.values();
  for (int j = 0; j < wv.levels(); ++j)
    if (!(nuhat(j) > 0.0) || !std::isfinite(nuhat(j)))
      throw InputError("gap: the WV at level " + std::to_string(j + 1) + " is not positive (" +
                       std::to_string(nuhat(j)) + "); a gap is measured on log scales");
  if (temperature && (!x || temperature->size() != x->size()))
    throw InputError("gap: the temperature channel has " + std::to_string(temperature->size()) +
                     " samples, the signal " + std::to_string(x ? x->size() : 0));
  const ClassicalWvEstimator classical;
  const WvEstimator& estimator = options.estimator ? *options.estimator : classical;
  const Eigen::VectorXd nu_base = baseline.wv(theta, wv.tau);
  detail::SeriesStatistic series_statistic;
  if (x)
    series_statistic = [&](const std::vector<double>& s) {
      return detail::series_statistics(s, temperature, nu_base);
    };
  const detail::Reference ref =
      detail::build_reference(baseline, theta, wv.n, wv.levels(), options.replicates, options.seed, estimator,
                              wv.alpha, options.progress, series_statistic);
  const int J = wv.levels();
  GapResult g;
  g.baseline = baseline;
  g.baseline_theta = theta;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(J);
  g.levels = detail::map_levels(wv, nuhat, ref, ref.nu, zero, options.alpha);
  g.statistic = detail::distance(ref, nuhat, zero);
  g.p_value = detail::p_value(ref, g.statistic);
  const double z_bonferroni =
      boost::math::quantile(boost::math::complement(boost::math::normal(), options.alpha / (2.0 * J)));
  g.bands = detail::find_bands(g.levels, z_bonferroni, options.min_effect);
  g.detected = g.p_value < options.alpha && !g.bands.empty();
  if (x) {
    detail::map_windows(*x, baseline, theta, options, g);
    detail::split_halves(*x, options.alpha, g);
  }
  // Time-domain tests (Bonferroni over them and the WV candidates): a significant event or
  // temperature coupling is a departure from the baseline even where the WV shows none.
  detail::TimeFindings time;
  if (x) {
    const double K = static_cast<double>(candidates_for(baseline, options).size()) + 1.0 + (temperature ? 1.0 : 0.0);
    time = detail::run_time_tests(*x, temperature, nu_base, ref.series_stats, options.alpha / K, options.alpha, g);
    if ((time.event || time.coupling || time.trend) && !g.detected) {
      g.detected = true;
      if (g.bands.empty()) g.bands = detail::event_bands(time, g.levels);
      if (g.bands.empty() && time.trend) g.bands = detail::drift_band(g.trend->omega, wv, nu_base, options.context, g.levels);
    }
  }

  // The objective's weights: the baseline's own spread of nuhat (raw scale).
  const Eigen::MatrixXd omega = ref.var.cwiseInverse().asDiagonal();
  double null_mean = 0.0;
  for (Eigen::Index b = 0; b < ref.wv.rows(); ++b) null_mean += objective(ref.wv.row(b).transpose(), ref.nu, omega);
  null_mean /= static_cast<double>(ref.wv.rows());

  GapShrinkage& s = g.shrinkage;
  s.objective_before = objective(nuhat, ref.nu, omega);
  s.null_mean = null_mean;
  s.rms_log_ratio_before = detail::rms_log_ratio(nuhat, ref.nu, g.bands);
  for (const auto& l : g.levels) s.levels_outside_before += l.outside;
  s.p_value_before = g.p_value;
  g.final_model = baseline;
  g.final_theta = theta;
  g.navigation.rms_without = g.navigation.rms_with = detail::navigation_rms(baseline, theta, options.context, g.notes);
  auto finish_unchanged = [&] {
    s.objective_after = s.objective_before;
    s.rms_log_ratio_after = s.rms_log_ratio_before;
    s.levels_outside_after = s.levels_outside_before;
    s.p_value_after = s.p_value_before;
  };
  if (!g.detected) {
    g.notes.push_back(g.p_value >= options.alpha ? "the global test does not reject the baseline"
                                                 : "no band of levels passes both the multiplicity-corrected z "
                                                   "threshold and the effect-size threshold");
    finish_unchanged();
    return g;
  }

  // OUTLIERS first: a fine-scale excess the robust WV does not show.
  Eigen::VectorXd data = nuhat;
  bool outliers = false;
  if (robust && x) {
    const robust::Quantization q = robust::detect_quantization(x->data(), static_cast<std::int64_t>(x->size()));
    const robust::Tuning tuning = robust::tune(
        robust::parse_robust_kind(robust->estimator).value_or(robust::RobustKind::kHuber),
        robust->efficiency.value_or(robust::kDefaultEfficiency));
    const auto diag = robust::contamination_diagnostic(x->data(), static_cast<std::int64_t>(x->size()), *robust, wv, q,
                                                       tuning);
    int flagged = 0;
    for (int j = 0; j < std::min(kOutlierLevels, J); ++j) flagged += diag[static_cast<std::size_t>(j)].contaminated;
    outliers = flagged > 0;
    if (flagged > 0) {
      g.steps.push_back(GapEffect::kOutliers);
      g.notes.push_back(std::to_string(flagged) + " of the finest " + std::to_string(kOutlierLevels) +
                        " levels flagged contaminated (robust WV below classical beyond what the data's rounding "
                        "explains, with an excess of far outliers): the robust WV is used from here on");
      bool usable = true;
      for (int j = 0; j < J; ++j) usable &= robust->wv[static_cast<std::size_t>(j)] > 0.0;
      if (usable) data = robust->values();
      g.step_drops.push_back(s.objective_before - objective(data, ref.nu, omega));
    }
  }

  // Then the time-domain effects: the series corrected for them, its WV the data from here on.
  bool time_explained = false;
  if (time.event || time.coupling || time.trend) {
    const std::size_t first_time_step = g.steps.size();
    const double g_before_time = objective(data, ref.nu, omega);
    const std::vector<double> corrected = detail::apply_time_effects(*x, temperature, time, g);
    if (g.event) g.bands = detail::merge_event_band(g.bands, time, g.levels, g.event->effect);
    WaveletVariance w;
    if (outliers) {
      robust::RobustWvOptions ro;
      ro.estimator = robust::parse_robust_kind(robust->estimator).value_or(robust::RobustKind::kHuber);
      ro.efficiency = robust->efficiency.value_or(robust::kDefaultEfficiency);
      ro.levels = J;
      w = robust::robust_wv(corrected.data(), wv.n, ro);
    } else {
      w = estimator.compute(corrected.data(), wv.n, J, wv.alpha);
    }
    const Eigen::VectorXd v = w.values();
    if (v.allFinite() && (v.array() > 0.0).all()) data = v;
    time_explained = detail::p_value(ref, detail::distance(ref, data, zero)) >= options.alpha;
    // The time effects' drop together, credited to the first of them.
    for (std::size_t k = first_time_step; k < g.steps.size(); ++k)
      g.step_drops.push_back(k == first_time_step ? g_before_time - objective(data, ref.nu, omega) : 0.0);
  }

  Base base{baseline, theta, ref.nu};
  Eigen::MatrixXd reps = ref.wv;
  std::vector<FitResult> added;
  // After a REPARAMETERISE step the baseline's values are the data's, not the sim's:
  // later candidates re-estimate them together with the effect (as in --fit mode).
  GapOptions step_options = options;
  for (int step = 0; step < options.max_steps && !time_explained; ++step) {
    const auto specs = candidates_for(base.model, step_options);
    if (specs.empty()) break;
    Step st = score_step(specs, base, data, reps, wv, omega, step_options);
    if (step == 0) g.candidates = st.scored;
    // Disambiguation (GAP.md s.3, candidate 0): a new effect must beat re-sizing the
    // baseline's own terms by more than its own null threshold; otherwise the answer is
    // REPARAMETERISE (an AR1 with phi ~ 0 is a white noise, a FLICKER over few octaves
    // a re-sized random walk, ...).
    int pick = st.best;
    for (std::size_t c = 0; c < specs.size(); ++c) {
      const GapCandidate& re = st.scored[c];
      if (specs[c].effect != GapEffect::kReparameterise || !re.cleared) continue;
      if (pick < 0 || st.scored[static_cast<std::size_t>(pick)].improvement - re.improvement <=
                          st.scored[static_cast<std::size_t>(pick)].threshold)
        pick = static_cast<int>(c);
    }
    if (pick < 0) break;
    const GapCandidate& chosen = st.scored[static_cast<std::size_t>(pick)];
    g.steps.push_back(chosen.effect);
    const double g_before_step = objective(data, base.nu, omega);
    // The new base: the chosen fit (REPARAMETERISE or refit: the whole model; else
    // base + the effect at its fitted values).
    Base next;
    if (chosen.effect == GapEffect::kReparameterise || step_options.refit_baseline) {
      next.model = chosen.fit.model;
      next.theta = chosen.fit.theta;
      if (chosen.effect != GapEffect::kReparameterise) added.push_back(effect_part(chosen.fit, base));
    } else {
      next.model = base.model + chosen.fit.model;
      next.theta.resize(base.theta.size() + chosen.fit.theta.size());
      next.theta << base.theta, chosen.fit.theta;
      added.push_back(chosen.fit);
    }
    next.nu = next.model.wv(next.theta, wv.tau);
    // Replicates of the new base: the old ones rescaled level by level.
    const Eigen::VectorXd scale = (next.nu.array() / base.nu.array()).matrix();
    const Eigen::MatrixXd reps_next = reps * scale.asDiagonal();
    if (chosen.effect != GapEffect::kReparameterise && added.size() == 1)
      effect_intervals(specs[static_cast<std::size_t>(pick)], base, reps_next, wv, omega, step_options, chosen.fit,
                       added.front());
    reps = reps_next;
    base = std::move(next);
    g.step_drops.push_back(g_before_step - objective(data, base.nu, omega));
    const Eigen::VectorXd shift = (base.nu.array() / ref.nu.array()).log().matrix();
    if (detail::p_value(ref, detail::distance(ref, data, shift)) >= options.alpha) break;
    if (chosen.effect == GapEffect::kReparameterise) step_options.refit_baseline = true;
  }
  // The top candidate: the first step (OUTLIERS, then the time-domain effects, then the
  // WV candidates by calibrated margin), except that a drift, step or transient found in
  // the time domain yields to a later step that removed more of the gap (a strong slow
  // AR1 or flicker moves the end segments and concentrates coarse coefficients too).
  g.effect = g.steps.empty() ? GapEffect::kNone : g.steps.front();
  const auto time_domain = [](GapEffect e) {
    return e == GapEffect::kDR || e == GapEffect::kStep || e == GapEffect::kTransient;
  };
  if (!g.steps.empty() && time_domain(g.steps.front()))
    for (std::size_t k = 1; k < g.steps.size(); ++k)
      if (g.step_drops[k] > g.step_drops[0] && g.steps[k] != GapEffect::kReparameterise) {
        g.effect = g.steps[k];
        break;
      }
  if (g.steps.empty())
    g.notes.push_back("no candidate effect clears its calibrated threshold: no unmodelled effect found");
  g.final_model = base.model.canonical(&base.theta);
  g.final_theta = base.theta;
  if (!added.empty()) g.final_fit = added.front();
  const bool drift = std::find(g.steps.begin(), g.steps.end(), GapEffect::kDR) != g.steps.end() && g.trend &&
                     g.trend->significant;
  if (drift && (g.effect == GapEffect::kDR || added.empty())) g.final_fit = detail::drift_fit(*g.trend, options);

  const Eigen::VectorXd shift = (base.nu.array() / ref.nu.array()).log().matrix();
  const auto after = detail::map_levels(wv, data, ref, base.nu, shift, options.alpha);
  s.objective_after = objective(data, base.nu, omega);
  const double excess = s.objective_before - s.null_mean;
  s.excess_removed = excess > 0.0 ? (s.objective_before - s.objective_after) / excess : 0.0;
  s.rms_log_ratio_after = detail::rms_log_ratio(data, base.nu, g.bands);
  s.levels_outside_after = 0;
  for (const auto& l : after) s.levels_outside_after += l.outside;
  s.p_value_after = detail::p_value(ref, detail::distance(ref, data, shift));
  if (drift && !has_process(g.final_model, "DR")) {
    // The drift removed in the time domain belongs to the final model too.
    const FitResult d = detail::drift_fit(*g.trend, options);
    Eigen::VectorXd th(g.final_theta.size() + 1);
    th << g.final_theta, d.theta;
    g.final_model = (g.final_model + d.model).canonical(&th);
    g.final_theta = th;
  }
  g.navigation.rms_with = detail::navigation_rms(g.final_model, g.final_theta, options.context, g.notes);
  return g;
}

}  // namespace gmwm::selection
