#include "gap_candidates.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm::gap::detail {

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
// Stream offset of the reference replicates of each forward step's shifted reference is
// not needed (the reference is simulated once); the replicate streams are (seed, b).

// The attribution's cancellation point: the progress callback called again with the
// reference complete (the bar stays where it is; a Cancelled thrown there stops the work).
void checkpoint(const GapOptions& o) {
  if (o.progress) o.progress(o.replicates, o.replicates);
}

constexpr EffectEntry kEffects[] = {
    {GapEffect::kNone, "none", nullptr, false},
    {GapEffect::kWN, "WN", "WN", true},
    {GapEffect::kQN, "QN", "QN", true},
    {GapEffect::kRW, "RW", "RW", true},
    {GapEffect::kDR, "DR", "DR", true},
    {GapEffect::kAR1, "AR1", "AR1", true},
    {GapEffect::kFlicker, "FLICKER", "FLICKER", true},
    {GapEffect::kSin, "SIN", "SIN", true},
    {GapEffect::kOutliers, "OUTLIERS", nullptr, false},
    {GapEffect::kStep, "STEP", nullptr, false},
    {GapEffect::kTransient, "TRANSIENT", nullptr, false},
    {GapEffect::kTemperature, "TEMPERATURE", nullptr, false},
    {GapEffect::kReparameterise, "REPARAMETERISE", nullptr, true},
};
constexpr bool in_enum_order() {
  for (std::size_t k = 0; k < std::size(kEffects); ++k)
    if (static_cast<std::size_t>(kEffects[k].effect) != k) return false;
  return true;
}
static_assert(std::size(kEffects) == static_cast<std::size_t>(GapEffect::kReparameterise) + 1 && in_enum_order(),
              "every GapEffect has its entry, in the enum's order (effect_entry reads it by index)");

std::span<const EffectEntry> effect_table() { return kEffects; }

const EffectEntry& effect_entry(GapEffect e) { return kEffects[static_cast<std::size_t>(e)]; }

}  // namespace gmwm::gap::detail

namespace gmwm::gap {

std::vector<GapEffect> wv_candidate_effects() {
  std::vector<GapEffect> out;
  for (const auto& c : detail::effect_table())
    if (c.wv_candidate) out.push_back(c.effect);
  return out;
}

std::vector<GapEffect> parse_gap_candidates(const std::string& list, const std::string& option) {
  const std::vector<GapEffect> all = wv_candidate_effects();
  std::string known;
  for (const GapEffect e : all) known += (known.empty() ? "" : ", ") + std::string(to_string(e));
  std::vector<GapEffect> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    const auto e = parse_gap_effect(item);
    if (!e || std::find(all.begin(), all.end(), *e) == all.end())
      throw InputError(option + " '" + list + "': unknown effect '" + item + "', expected some of " + known);
    out.push_back(*e);
  }
  if (out.empty()) throw InputError(option + ": at least one effect is needed (" + known + ")");
  return out;
}

}  // namespace gmwm::gap

namespace gmwm::gap::detail {

bool has_role(const Model& m, ProcessRole r) {
  for (const auto& c : m.components())
    if (c.process->role() == r) return true;
  return false;
}

// The candidates tried against `base`: the requested ones (all by default), without a
// process of a role the base already has and a model holds once (single_per_model: adding
// it is a re-sizing, i.e. REPARAMETERISE, docs/gap.md, method note 5), and without
// REPARAMETERISE when the base is refitted anyway.
std::vector<CandidateSpec> candidates_for(const Model& base, const GapOptions& o) {
  std::vector<CandidateSpec> out;
  for (const auto& c : effect_table()) {
    if (!c.wv_candidate) continue;
    if (!o.candidates.empty() && std::find(o.candidates.begin(), o.candidates.end(), c.effect) == o.candidates.end())
      continue;
    if (c.process == nullptr) {
      if (!o.refit_baseline) out.push_back({c.effect, nullptr});
      continue;
    }
    const ProcessRole role = make_process(c.process, ProcessContext{})->role();
    if (single_per_model(role) && has_role(base, role)) continue;
    out.push_back({c.effect, c.process});
  }
  return out;
}

static WaveletVariance with_values(const WaveletVariance& like, const Eigen::VectorXd& v) {
  WaveletVariance w = like;
  w.wv.assign(v.data(), v.data() + v.size());
  return w;
}

double objective(const Eigen::VectorXd& target, const Eigen::VectorXd& nu, const Eigen::MatrixXd& omega) {
  const Eigen::VectorXd r = target - nu;
  return r.dot(omega * r);
}

static FitOptions candidate_fit_options(const GapOptions& o, const Eigen::MatrixXd& omega) {
  FitOptions fo = o.fit;
  fo.omega_matrix = omega;
  fo.inference = false;
  fo.nested_starts = false;
  fo.multistarts = kCandidateStarts;
  fo.log_not_converged = false;
  return fo;
}

// The family of a model without its given values: a refit's starting values must not be
// anchored to the baseline's sizes (the starting-value search keeps given sizes fixed).
static Model family_of(const Model& m) {
  std::vector<Component> cs = m.components();
  for (auto& c : cs) std::fill(c.given.begin(), c.given.end(), std::numeric_limits<double>::quiet_NaN());
  return Model(std::move(cs));
}

// The objective left by `spec` on `target` (baseline fixed: the effect is fitted to the
// residual; refit: the family and the effect together, started from the base's values)
// and the fit behind it. REPARAMETERISE: the base's family with free values.
static double fit_candidate(const CandidateSpec& spec, const Base& base, const Eigen::VectorXd& target,
                            const WaveletVariance& like, const Eigen::MatrixXd& omega, const GapOptions& o,
                            FitResult* out, const FitResult* warm = nullptr) {
  FitOptions fo = candidate_fit_options(o, omega);
  FitResult r;
  // Calibration refits of --fit mode (family + effect on each replicate) start from the
  // data's fit and one shape-based start: they cost the most, and the replicates lie
  // close to the base.
  if (warm && o.refit_baseline && spec.process != nullptr) fo.multistarts = kRefitCalibrationStarts;
  // The data's own refits (REPARAMETERISE, --fit mode) also start from the family's
  // sub-models: from a baseline far from the data (a datasheet white noise 200x too
  // high) the shape-based starts alone can end with the white noise collapsed on a
  // boundary (objective 32704 where 292 exists). The replicates' refits warm-start from
  // the data's fit instead.
  if (!warm && (spec.process == nullptr || o.refit_baseline)) fo.nested_starts = true;
  if (spec.process == nullptr) {
    fo.starts = {base.theta};
    r = fit_gmwm(with_values(like, target), family_of(base.model), fo);
  } else if (!o.refit_baseline) {
    r = fit_gmwm(with_values(like, target - base.nu), parse_model(spec.process, o.context), fo);
  } else {
    const Model m = family_of(base.model) + parse_model(spec.process, o.context);
    const WaveletVariance w = with_values(like, target);
    fo.starts = {embed_start(base.model, base.theta, m, w)};
    if (warm && warm->status != FitStatus::kFailed) fo.starts.push_back(embed_start(warm->model, warm->theta, m, w));
    r = fit_gmwm(w, m, fo);
  }
  const double g = r.status == FitStatus::kFailed ? std::numeric_limits<double>::infinity() : r.objective;
  if (out) *out = std::move(r);
  return g;
}

FitResult refit_family(const Base& base, const Eigen::VectorXd& target, const WaveletVariance& like,
                       const Eigen::MatrixXd& omega, const GapOptions& o) {
  FitResult r;
  fit_candidate(CandidateSpec{GapEffect::kReparameterise, nullptr}, base, target, like, omega, o, &r);
  return r;
}

// The objective of the base itself on `target`: fixed, or refitted (--fit mode).
static double base_objective(const Base& base, const Eigen::VectorXd& target, const WaveletVariance& like,
                             const Eigen::MatrixXd& omega, const GapOptions& o) {
  if (!o.refit_baseline) return objective(target, base.nu, omega);
  FitOptions fo = candidate_fit_options(o, omega);
  fo.multistarts = kRefitCalibrationStarts;
  fo.starts = {base.theta};
  const FitResult r = fit_gmwm(with_values(like, target), family_of(base.model), fo);
  return r.status == FitStatus::kFailed ? objective(target, base.nu, omega) : r.objective;
}

// (1 - level) quantile of a scaled chi-square a chi2_d matched to the drops' mean and variance.
static double calibrated_threshold(const std::vector<double>& drops, double level) {
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
  gmwm::parallel_for(0, R, [&](int b) {
    checkpoint(o);
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
    auto q = [&](double level) {
      return v[static_cast<std::size_t>(std::lround(level * static_cast<double>(v.size() - 1)))];
    };
    fit.ci_low(k) = q(o.alpha / 2.0);
    fit.ci_high(k) = q(1.0 - o.alpha / 2.0);
  }
}

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
  gmwm::parallel_for(0, R, [&](int b) {
    checkpoint(o);
    g_base[static_cast<std::size_t>(b)] = base_objective(base, reps.row(b).transpose(), like, omega, o);
  });
  // The data's fits first (the replicates' refits start from them).
  gmwm::parallel_for(std::size_t{0}, K, [&](std::size_t c) {
    checkpoint(o);
    GapCandidate& g = s.scored[c];
    g.effect = specs[c].effect;
    const double left = fit_candidate(specs[c], base, nuhat, like, omega, o, &g.fit);
    g.improvement = std::isfinite(left) ? g_data - left : 0.0;
    if (g.fit.status != FitStatus::kFailed) g.model = g.fit.model.to_string(g.fit.theta);
  });
  gmwm::parallel_for(std::size_t{0}, K * static_cast<std::size_t>(R), [&](std::size_t k) {
    checkpoint(o);
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
  // Parsimony (docs/gap.md, method note 3, "parsimony"): a candidate with more parameters must beat
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

}  // namespace gmwm::gap::detail
