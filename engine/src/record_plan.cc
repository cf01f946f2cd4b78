// How long to record: the GMWM's asymptotic covariance at a record length, carried to the
// noise figures by the delta method, and a bisection on the length (record_plan.h).
#include "gmwm/engine/record_plan.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include <Eigen/Dense>
#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/engine/number_text.h"

namespace gmwm {

std::string RecordPlanOptions::Validate() const {
  auto num = [](double x) { return significant(x); };
  if (!(precision > 0.0 && precision < 1.0))
    return "record plan: precision must be in (0, 1) (a relative half-width, 0.1 = +-10%), got " + num(precision);
  if (!(confidence > 0.0 && confidence < 1.0))
    return "record plan: confidence must be in (0, 1), got " + num(confidence);
  if (!(record_seconds >= 0.0 && std::isfinite(record_seconds)))
    return "record plan: record_seconds must be non-negative and finite (0: not asked), got " + num(record_seconds);
  if (max_samples < kMinSeriesLength || max_samples > kMaxPlannedSamples)
    return "record plan: max_samples must be in [" + std::to_string(kMinSeriesLength) + ", 2^34], got " +
           std::to_string(max_samples);
  for (const auto& t : targets)
    if (t.empty()) return "record plan: a target is empty (N, K, B or a parameter label such as WN[1].sigma2)";
  return {};
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// N and K are the figures of the model's own white-noise and random-walk terms
// (Process::physical: WN's sqrt(sigma2 / f), RW's sqrt(gamma2 f)), differentiated by
// central differences in the unconstrained parameters u (log of a variance), step
// kFigureStep * max(1, |u_k|): truncation error ~ step^2 (<= 1e-5 relative for
// |u| <= 30), rounding ~ 1e-16 / step, both far below the ~1% at which an se matters
// to a length.
constexpr double kFigureStep = 1e-4;
// The bisection stops when hi <= lo (1 + kLengthResolution): 1% in length is 0.5% in the
// se of an n^-1/2 estimate, below the Monte Carlo error of any check of it (a coverage
// over 200 records has a binomial se of 1.5 points).
constexpr double kLengthResolution = 0.01;
// H scaled to unit diagonal: an eigenvalue below this fraction of the largest is a flat
// direction, the parameters are not identified (the fit's own threshold, kFlatCurvature
// in engine/src/inference.cc).
constexpr double kFlatCurvature = 1e-10;

// A plan is never shorter than the model's resolution: the length at which the fit's
// intervals at the plan's confidence are all two-sided, every parameter's z se within its
// distance to the edge of its domain (a variance to 0, phi to +-1: the fit's own rule for
// a one-sided interval, docs/statistics.md section 5). Shorter, the estimate reaches where
// components vanish or merge (an AR1 of phi ~ 0 standing in for the white noise, one of
// phi ~ 1 for the random walk), which the sandwich at the model does not describe. 200
// fits each of AR1(0.99, 1e-4) + WN(1) + RW(1e-6) at 100 Hz: the WN term's N has a
// simulated sd 21x the planned se at 1000 samples, 9.6x at 10^4, 1.05x at 3 10^4; fits
// of a gyroscope's WN + RW + AR1(T = 10 s) put the AR1 in the white noise's place in 7%
// of records at 1.5 10^5 samples (the AR1's sigma2 one se from 0), and moved the walk
// into an AR1 of phi -> 1 (K more than 20% low) in 16% at 9.6 10^5 (1 - phi 1.6 se
// from 0) (tools/bench/bench_record_plan's truths).
double distance_to_edge(Transform t, double x) {
  switch (t) {
    case Transform::kLog:
      return std::abs(x);
    case Transform::kAtanh:
      return 1.0 - std::abs(x);
    case Transform::kLogitHalf:
      return std::min(x, 0.5 - x);
    case Transform::kIdentity:
      break;
  }
  return kInf;
}

enum class Kind { kN, kK, kB, kParameter };

struct Target {
  std::string name;
  Kind kind = Kind::kParameter;
  int parameter = -1;
};

bool shows(const Readoff& r) { return r.available() && r.status != ReadoffStatus::kBound; }
PhysicalKind term_kind(Kind kind) { return kind == Kind::kN ? PhysicalKind::kNoiseDensity : PhysicalKind::kRandomWalk; }

// The root sum of squares of the figure of `kind` over the components that state one
// (there is at most one WN and one RW: docs/statistics.md section 4); NaN when none does.
// By hypot: a figure's square leaves the doubles where the figure does not (K = 3e154).
double term_figure(const Model& model, const Eigen::VectorXd& theta, double freq, PhysicalKind kind) {
  double root = 0.0;
  bool any = false;
  for (int c = 0; c < model.num_components(); ++c) {
    const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
    const double q =
        quantity_of_kind(p.physical({theta.data() + model.offset(c), static_cast<std::size_t>(p.size())}, freq), kind);
    if (std::isfinite(q)) root = std::hypot(root, q), any = true;
  }
  return any ? root : std::numeric_limits<double>::quiet_NaN();
}

// N without a WN term (the white noise carried by a fast AR1, as select often chooses):
// N as the model's Allan deviation shows it (model_only_figures, the rule every face reads
// N by), sized by the delta method at its read point (issue 43, item 8).
bool white_on_curve(const Model& model, const Eigen::VectorXd& theta, double freq, Kind kind) {
  return kind == Kind::kN && !std::isfinite(term_figure(model, theta, freq, PhysicalKind::kNoiseDensity));
}

int levels_of(std::int64_t n) { return static_cast<int>(std::bit_width(static_cast<std::uint64_t>(n))) - 1; }

Target resolve(const Model& model, const std::string& name) {
  if (name == "N") return {name, Kind::kN, -1};
  if (name == "K") return {name, Kind::kK, -1};
  if (name == "B") return {name, Kind::kB, -1};
  std::string labels;
  for (int k = 0; k < model.num_parameters(); ++k) {
    if (model.parameter_label(k) == name) return {name, Kind::kParameter, k};
    labels += (k ? ", " : "") + model.parameter_label(k);
  }
  throw InputError("record plan: the model " + model.to_string() + " has no target '" + name +
                   "' (expected N, K, B or one of its parameters: " + labels + ")");
}

// The GMWM's covariance at the model for a record of n samples (natural parameters), or
// nullopt when the levels do not identify the parameters.
std::optional<Eigen::MatrixXd> sandwich(const Model& model, const Eigen::VectorXd& theta, std::int64_t n) {
  const int J = levels_of(n), p = model.num_parameters();
  if (J < p) return std::nullopt;
  std::vector<double> tau(static_cast<std::size_t>(J));
  for (int j = 0; j < J; ++j) tau[static_cast<std::size_t>(j)] = std::ldexp(1.0, j + 1);
  const Eigen::MatrixXd V = model_wv_covariance(model, theta, n, J);
  Eigen::VectorXd w(J);  // fit.cc's OmegaKind::kModel: diag(1 / V_jj), a level without a positive V_jj weighs 0
  for (int j = 0; j < J; ++j) w(j) = V(j, j) > 0.0 && std::isfinite(V(j, j)) ? 1.0 / V(j, j) : 0.0;
  // Relative variances (columns times |theta_k| for a log-transformed parameter, as the fit's
  // inference scales them): H on the scale of relative changes. A bounded parameter keeps
  // its own scale: phi = 1e-300 scaled by itself took H's diagonal below the doubles, and
  // the plan said "not resolved (: z se is inf%)" for a white AR1 (the normalised H below
  // does not depend on this scaling, only its range does).
  Eigen::VectorXd s = Eigen::VectorXd::Ones(p);
  for (int k = 0; k < p; ++k)
    if (model.spec_of(k).transform == Transform::kLog && std::abs(theta(k)) > 0.0) s(k) = std::abs(theta(k));
  const Eigen::MatrixXd A = model.jacobian(theta, tau) * s.asDiagonal();
  const Eigen::MatrixXd WA = w.asDiagonal() * A;
  const Eigen::MatrixXd H = A.transpose() * WA;
  const Eigen::VectorXd d = H.diagonal();
  if (!(d.minCoeff() > 0.0) || !d.allFinite()) return std::nullopt;
  const Eigen::VectorXd di = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Hn = di.asDiagonal() * H * di.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Hn, Eigen::EigenvaluesOnly);
  if (!(es.eigenvalues()(0) > kFlatCurvature * es.eigenvalues()(p - 1))) return std::nullopt;
  const Eigen::MatrixXd Hinv = di.asDiagonal() * Hn.ldlt().solve(Eigen::MatrixXd::Identity(p, p)) * di.asDiagonal();
  const Eigen::MatrixXd G = Hinv * WA.transpose();  // d theta_hat / d nuhat (relative)
  const Eigen::MatrixXd C = G * V * G.transpose();
  return Eigen::MatrixXd(s.asDiagonal() * C * s.asDiagonal());
}

struct Point {
  std::vector<double> rse;
  std::vector<std::string> note;
  double worst = kInf;      // the largest se / distance to the edge of the domain
  std::string worst_label;  // its label
};

Point evaluate(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
               const std::vector<Target>& targets) {
  const std::size_t T = targets.size();
  const int J = levels_of(n), p = model.num_parameters();
  Point pt;
  pt.rse.assign(T, kInf);
  pt.note.assign(T, "");
  const auto cov = n >= kMinSeriesLength ? sandwich(model, theta, n) : std::nullopt;
  if (!cov) {
    const std::string why = J < p || n < kMinSeriesLength
                                ? "too short: " + std::to_string(J) + " levels for " + std::to_string(p) + " parameters"
                                : "the parameters are not identified over " + std::to_string(J) + " levels";
    std::fill(pt.note.begin(), pt.note.end(), why);
    return pt;
  }
  pt.worst = 0.0;
  for (int k = 0; k < p; ++k) {
    const double r = std::sqrt(std::max((*cov)(k, k), 0.0)) / distance_to_edge(model.spec_of(k).transform, theta(k));
    if (!(r <= pt.worst)) pt.worst = r, pt.worst_label = model.parameter_label(k);
  }
  const std::string basis = "GMWM sandwich covariance at n = " + std::to_string(n) + " (" + std::to_string(J) +
                            " levels, model-based diagonal weights)";
  const bool minimum = std::any_of(targets.begin(), targets.end(), [](const Target& t) { return t.kind == Kind::kB; });
  const bool n_on_curve = std::any_of(targets.begin(), targets.end(),
                                      [&](const Target& t) { return white_on_curve(model, theta, freq, t.kind); });
  // N on the curve takes the read-off's delta-method interval at its read point (the
  // covariance is passed only then: B's gradient is formed below, and the plan's bisection
  // evaluates this at every length it tries).
  const ChosenFigures at = minimum || n_on_curve
                               ? model_only_figures(model, theta, freq, n, {}, n_on_curve ? &*cov : nullptr)
                               : ChosenFigures{};
  for (std::size_t i = 0; i < T; ++i) {
    const Target& t = targets[i];
    Eigen::VectorXd g = Eigen::VectorXd::Zero(p);
    double value = 0.0;
    std::string how;
    if (t.kind == Kind::kParameter) {
      g(t.parameter) = 1.0;
      value = theta(t.parameter);
    } else if (t.kind == Kind::kB) {
      const Readoff& r = at.instability.figure;
      if (!shows(r)) {
        pt.note[i] = "B is not read at n = " + std::to_string(n) + ": " + r.how;
        continue;
      }
      // B = sigma(m) / 0.664 at the read point m, sigma^2 = 2 nu^2(2m): dB = (d nu^2(2m) / sigma(m)) / 0.664.
      value = r.value;
      const double tau2[1] = {2.0 * std::round(r.tau * freq)};
      g = model.jacobian(theta, tau2).row(0).transpose() / (r.value * kBiasInstabilityFactor * kBiasInstabilityFactor);
      how = "; B " + r.how + " (delta method at the read point)";
    } else if (white_on_curve(model, theta, freq, t.kind)) {
      // The read-off's own delta method on log N at its read point m (fixed): its 1 - alpha
      // interval is N exp(+-z se_rel), se_rel = sqrt(g' C g), g = J(2m) / AVAR(m).
      const Readoff& r = at.white.figure;
      if (!shows(r) || !(r.low > 0.0 && r.high > r.low)) {
        pt.note[i] = "N is not read at n = " + std::to_string(n) + ": " + r.how;
        continue;
      }
      const double z = boost::math::quantile(boost::math::normal(), 1.0 - ReadoffOptions{}.alpha / 2.0);
      pt.rse[i] = std::log(r.high / r.low) / (2.0 * z);
      pt.note[i] = basis + "; no white noise term: N " + r.how + " (delta method at the read point)";
      continue;
    } else {
      const PhysicalKind kind = term_kind(t.kind);
      value = term_figure(model, theta, freq, kind);
      const Eigen::VectorXd u = model.to_unconstrained(theta), dtheta = model.dtheta_du(u);
      for (int k = 0; k < p; ++k) {
        const double h = kFigureStep * std::max(1.0, std::abs(u(k)));
        Eigen::VectorXd v = u;
        v(k) = u(k) + h;
        const double up = term_figure(model, model.from_unconstrained(v), freq, kind);
        v(k) = u(k) - h;
        const double down = term_figure(model, model.from_unconstrained(v), freq, kind);
        g(k) = dtheta(k) != 0.0 ? (up - down) / (2.0 * h) / dtheta(k) : 0.0;
      }
      how = t.kind == Kind::kN ? "; N = sqrt(sigma2 / f) of the white noise (delta method)"
                               : "; K = sqrt(gamma2 f) of the random walk (delta method)";
    }
    const double var = g.dot(*cov * g);
    pt.rse[i] = var >= 0.0 && value != 0.0 ? std::sqrt(var) / std::abs(value) : kInf;
    pt.note[i] = basis + how;
  }
  return pt;
}

// The plan depends on ratios of the parameters only: data times sqrt(c) have c times the
// WV, c^2 times its covariance, and the same relative standard errors, resolution and
// read points. So it is computed at the model's unit scale, the WV of its first level in
// [1, 4) (c a power of 4: sqrt(c) is a power of 2 and the scaling exact), the values
// shown at the model's own. At the given scale the WV's covariance (~ nu^2 / M) left the
// normal doubles where the WV is below ~1e-145 or above ~1e150 (at the 2^34-sample cap its
// levels underflowed to 0 or overflowed to inf: every target "unreachable" for
// WN(sigma2=1e-150)+RW(gamma2=1e-150), 1038/1512/293 samples at 1e-140), and the figures'
// difference steps (kFigureStep max(1, |log theta|)) grew with the scale's logarithm.
// A first level beyond the doubles (subnormal, or inf for variances near 1.8e308) is
// brought in by a first factor of at most 4^kMaxScaleStep, then scaled to unit. A model
// whose terms cannot share one scale (a variance would underflow to 0 or overflow) is
// refused: no double computation of its plan exists.
constexpr int kMaxScaleStep = 500;  // 4^500 = 2^1000: a factor a double holds

// theta for the model's data times 2^-exponent: a figure (in the data's unit) computed at
// it, times 2^exponent, is the model's own.
struct UnitScale {
  Eigen::VectorXd theta;
  int exponent = 0;
};

UnitScale at_unit_scale(const Model& model, const Eigen::VectorXd& theta) {
  const double first[1] = {2.0};
  UnitScale x{theta, 0};
  for (int pass = 0; pass < 3; ++pass) {
    const double nu = model.wv(x.theta, first)(0);
    if (nu >= 1.0 && nu < 4.0) return x;
    if (!(nu > 0.0)) return {theta, 0};  // no first level to scale by (or NaN): as given
    int k = kMaxScaleStep / 2;           // nu = inf: 4^-250 first
    if (std::isfinite(nu)) {
      int e = 0;
      std::frexp(nu, &e);  // nu in [2^(e-1), 2^e)
      k = std::clamp(static_cast<int>(std::floor(0.5 * (e - 1))), -kMaxScaleStep, kMaxScaleStep);
    }
    const Eigen::VectorXd y = model.scaled(x.theta, std::ldexp(1.0, -2 * k));
    for (int j = 0; j < y.size(); ++j)
      if (theta(j) != 0.0 && !(y(j) != 0.0 && std::isfinite(y(j))))
        throw InputError("record plan: the model " + model.to_string(theta) +
                         " spans more scales than a double holds (" + model.parameter_label(j) +
                         " leaves the doubles when its first level's wavelet variance is brought to 1): expected "
                         "values whose ratios a double holds");
    x.theta = y;
    x.exponent += k;
  }
  return model.validate(x.theta).empty() ? x : UnitScale{theta, 0};
}

// The targets asked (or the defaults the model has), their existence judged at the
// model's unit scale (`unit`; a figure's is scale-free), named with theta in messages.
std::vector<Target> resolve_all(const Model& model, const Eigen::VectorXd& theta, const Eigen::VectorXd& unit,
                                double freq, const RecordPlanOptions& options) {
  std::vector<Target> out;
  const bool defaults = options.targets.empty();
  const std::vector<std::string> names = defaults ? std::vector<std::string>{"N", "K", "B"} : options.targets;
  std::optional<ChosenFigures> top;
  for (const auto& name : names) {
    Target t = resolve(model, name);
    if (t.kind == Kind::kN || t.kind == Kind::kK) {
      if (!std::isfinite(term_figure(model, unit, freq, term_kind(t.kind)))) {
        // N without a WN term: read on the model's curve when it shows a -1/2 slope.
        if (t.kind == Kind::kN) {
          if (!top) top = model_only_figures(model, unit, freq, options.max_samples);
          if (shows(top->white.figure)) {
            out.push_back(t);
            continue;
          }
        }
        if (defaults) continue;
        throw InputError("record plan: the model " + model.to_string(theta) + " has no " +
                         (t.kind == Kind::kN
                              ? "white noise term (WN) and no -1/2 slope on its Allan deviation over " +
                                    std::to_string(options.max_samples) + " samples for the noise density N"
                              : std::string("random walk term (RW) for the random walk K")));
      }
    } else if (t.kind == Kind::kB) {
      if (!top) top = model_only_figures(model, unit, freq, options.max_samples);
      if (!shows(top->instability.figure)) {
        if (defaults) continue;
        throw InputError("record plan: the model " + model.to_string(theta) +
                         " has no bias instability B: its Allan deviation shows no minimum over " +
                         std::to_string(options.max_samples) + " samples (" + top->instability.figure.how + ")");
      }
    }
    out.push_back(t);
  }
  return out;
}

void check_input(const Model& model, const Eigen::VectorXd& theta, double freq) {
  if (!(freq > 0.0) || !std::isfinite(freq))
    throw InputError("record plan: the sampling rate must be positive and finite");
  if (theta.size() != model.num_parameters())
    throw InputError("record plan: theta has " + std::to_string(theta.size()) + " values, the model " +
                     model.to_string() + " has " + std::to_string(model.num_parameters()) + " parameters");
  if (const std::string why = model.validate(theta); !why.empty()) throw InputError("record plan: " + why);
}

std::string seconds_text(double s) {
  char buf[48];
  if (s < 120.0)
    std::snprintf(buf, sizeof buf, "%.3g s", s);
  else if (s < 7200.0)
    std::snprintf(buf, sizeof buf, "%.3g min", s / 60.0);
  else
    std::snprintf(buf, sizeof buf, "%.3g h", s / 3600.0);
  return buf;
}

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "+-%.3g%%", 100.0 * x);
  return buf;
}

}  // namespace

std::vector<double> record_target_values(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                         const std::vector<std::string>& targets) {
  check_input(model, theta, freq);
  if (n < kMinSeriesLength)
    throw InputError("record plan: a record of " + std::to_string(n) + " samples has no wavelet variance (at least " +
                     std::to_string(kMinSeriesLength) + ")");
  // The figures at the unit scale, brought back by 2^exponent: the model's own Allan
  // variance overflows where its variances are near 1.8e308 (B then missing).
  const UnitScale unit = at_unit_scale(model, theta);
  std::vector<double> out;
  std::optional<ChosenFigures> figures;
  for (const auto& name : targets) {
    const Target t = resolve(model, name);
    const bool curve = white_on_curve(model, unit.theta, freq, t.kind);
    if ((t.kind == Kind::kB || curve) && !figures) figures = model_only_figures(model, unit.theta, freq, n);
    double v = 0.0;
    if (t.kind == Kind::kParameter)
      v = theta(t.parameter);
    else if (t.kind == Kind::kB)
      v = std::ldexp(figures->instability.figure.value, unit.exponent);
    else if (curve)  // N on the model's curve: its read-off, NaN where it only bounds N
      v = shows(figures->white.figure) ? std::ldexp(figures->white.figure.value, unit.exponent)
                                       : std::numeric_limits<double>::quiet_NaN();
    else
      v = std::ldexp(term_figure(model, unit.theta, freq, term_kind(t.kind)), unit.exponent);
    out.push_back(v);
  }
  return out;
}

std::vector<double> record_relative_se(const Model& model, const Eigen::VectorXd& theta, double freq, std::int64_t n,
                                       const std::vector<std::string>& targets) {
  check_input(model, theta, freq);
  std::vector<Target> ts;
  for (const auto& name : targets) ts.push_back(resolve(model, name));
  return evaluate(model, at_unit_scale(model, theta).theta, freq, n, ts).rse;
}

RecordPlan plan_record_length(const Model& model, const Eigen::VectorXd& theta, double freq,
                              const RecordPlanOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_input(model, theta, freq);
  const UnitScale unit = at_unit_scale(model, theta);
  const std::vector<Target> targets = resolve_all(model, theta, unit.theta, freq, options);
  RecordPlan plan;
  plan.freq = freq;
  plan.z = boost::math::quantile(boost::math::normal(), 0.5 * (1.0 + options.confidence));
  std::map<std::int64_t, Point> cache;
  auto at = [&](std::int64_t n) -> const Point& {
    auto it = cache.find(n);
    if (it == cache.end()) it = cache.emplace(n, evaluate(model, unit.theta, freq, n, targets)).first;
    return it->second;
  };
  // The shortest record with a level per parameter (and the WV's own minimum).
  const int p = model.num_parameters();
  const std::int64_t shortest =
      std::min(options.max_samples,
               std::max<std::int64_t>(kMinSeriesLength, p < 62 ? std::int64_t{1} << p : options.max_samples));
  const std::int64_t cap = options.max_samples;
  // The smallest n in [shortest, cap] where ok(n) holds, by bisection on log2 n (ok is
  // taken to hold from some length on); nullopt when it fails at the cap.
  auto first_passing = [&](const auto& ok) -> std::optional<std::int64_t> {
    if (!ok(cap)) return std::nullopt;
    std::int64_t lo = shortest, hi = cap;
    if (ok(lo)) return lo;
    while (static_cast<double>(hi) > static_cast<double>(lo) * (1.0 + kLengthResolution)) {
      const auto mid =
          static_cast<std::int64_t>(std::llround(std::sqrt(static_cast<double>(lo) * static_cast<double>(hi))));
      if (mid <= lo || mid >= hi) break;
      (ok(mid) ? hi : lo) = mid;
    }
    return hi;
  };
  const auto resolved = first_passing([&](std::int64_t n) { return plan.z * at(n).worst <= 1.0; });
  plan.resolved_samples = resolved.value_or(cap);
  plan.resolved_seconds = static_cast<double>(plan.resolved_samples) / freq;
  plan.resolved_by = at(plan.resolved_samples).worst_label;
  const double record_n = std::floor(std::min(options.record_seconds * freq, static_cast<double>(kMaxPlannedSamples)));
  for (std::size_t i = 0; i < targets.size(); ++i) {
    RecordTarget r;
    r.name = targets[i].name;
    const auto own = first_passing([&](std::int64_t n) { return plan.z * at(n).rse[i] <= options.precision; });
    // B is a figure of the whole curve, whichever components make it up: no floor.
    const bool whole_curve = targets[i].kind == Kind::kB;
    const std::int64_t floor = whole_curve ? shortest : resolved.value_or(cap);
    r.own_samples = own.value_or(0);
    r.reachable = own && (resolved || whole_curve);
    r.samples = r.reachable ? std::max(*own, floor) : cap;
    r.seconds = static_cast<double>(r.samples) / freq;
    r.relative_se = at(r.samples).rse[i];
    const std::string within = "unreachable within " + std::to_string(cap) + " samples (" +
                               seconds_text(static_cast<double>(cap) / freq) + "): ";
    if (!resolved && !whole_curve)
      r.basis = within +
                (plan.resolved_by.empty()  // no covariance at all there: the note says why
                     ? at(cap).note[i]
                     : "the model is not resolved there (" + plan.resolved_by + ": z se is " +
                           percent(plan.z * at(cap).worst).substr(2) + " of its distance to the edge of its domain)");
    else if (!own)
      r.basis =
          within + (std::isfinite(r.relative_se) ? percent(plan.z * r.relative_se) + " there; " : "") + at(cap).note[i];
    else
      r.basis =
          at(r.samples).note[i] + (floor > *own ? "; set by the model's resolution (" + plan.resolved_by +
                                                      "'s interval inside its domain): " + percent(options.precision) +
                                                      " already at n = " + std::to_string(*own)
                                                : "");
    r.precision_at_record = std::numeric_limits<double>::quiet_NaN();
    if (options.record_seconds > 0.0) {
      const bool fits = record_n >= static_cast<double>(std::max(kMinSeriesLength, floor)) && (resolved || whole_curve);
      r.precision_at_record = fits ? plan.z * at(static_cast<std::int64_t>(record_n)).rse[i] : kInf;
      // Why a record of that length promises no precision.
      if (!fits && record_n < static_cast<double>(kMinSeriesLength))
        r.record_basis = "a record of " + std::to_string(static_cast<std::int64_t>(record_n)) +
                         " samples has no wavelet variance (at least " + std::to_string(kMinSeriesLength) + ")";
      else if (!fits && !resolved)
        r.record_basis = "the model is not resolved within " + std::to_string(cap) + " samples: " +
                         (plan.resolved_by.empty() ? at(cap).note[i]
                                                   : plan.resolved_by + "'s interval reaches the edge of its domain");
      else if (!fits)
        r.record_basis = "the model is resolved only from " + std::to_string(floor) + " samples (" +
                         seconds_text(static_cast<double>(floor) / freq) + "; last " + plan.resolved_by +
                         "): a shorter record's fit may trade components, and no precision of a term's figure can be "
                         "promised";
      else if (!std::isfinite(r.precision_at_record))
        r.record_basis = at(static_cast<std::int64_t>(record_n)).note[i];
    }
    plan.targets.push_back(std::move(r));
  }
  // Values under the model (B at its planned length: its read point moves with it).
  for (std::size_t i = 0; i < targets.size(); ++i)
    plan.targets[i].value = record_target_values(model, theta, freq, plan.targets[i].samples, {targets[i].name})[0];
  return plan;
}

}  // namespace gmwm
