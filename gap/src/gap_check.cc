#include "gmwm/gap/gap_check.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <string_view>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include <boost/random/uniform_01.hpp>
#include <Eigen/Cholesky>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/robust/robust_wv.h"
#include "gap_candidates.h"

namespace gmwm::gap {
namespace {

// The base of the check (docs/gap.md, method note 5: "base model WN+RW"): white noise and random walk
// crossing near tau ~ sqrt(12 sigma2 / gamma2) ~ 3500 samples, inside every record.
constexpr const char* kBase = "WN(sigma2=1e-4)+RW(gamma2=1e-10)";
// Spikes: 0.1% of the samples (issue 5's real-data check uses the same share).
constexpr double kSpikeShare = 1e-3;
// The base's parameters off by this factor on the null side (docs/gap.md, method note 5: +-20%).
constexpr double kOffFactor = 0.2;
// Calibration draws come from another seed family than the evaluation data.
constexpr std::uint64_t kCalibrationSeedOffset = 0x5eedca1bULL;
// Nuisance ranges: AR1 correlation times log-uniform in [2^2, N / 2^3] samples (inside
// the record, so that the AR1 is not a random walk over it); SIN frequencies
// log-uniform in [2^3 / N, 0.45] cycles/sample (at least 8 cycles per record, below Nyquist).
constexpr double kAr1MinLog2T = 2.0;
constexpr double kAr1RecordShare = 1.0 / 8.0;
constexpr double kSinMinCycles = 8.0;
constexpr double kSinMaxF = 0.45;
// STEP times uniform over the record but this share of it from either end (a step at the
// very end is a few samples of offset); TRANSIENT time constants log-uniform in
// [2^kTransientMinLog2T, 2^kTransientMaxLog2T] samples (0.64 s to 41 s at 100 Hz).
constexpr double kStepEdgeShare = 1.0 / 16.0;
constexpr double kTransientMinLog2T = 6.0;
constexpr double kTransientMaxLog2T = 12.0;
// Levels whose effect/base ratio is at least this share of the largest count as the
// effect's dominant scales.
constexpr double kDominantShare = 0.5;

// The oracle's one-sided test at size 5%: z_0.95 of the standard normal.
constexpr double kZ95 = 1.6448536269514722;
// A family's "strength at 90% power" (issue 14, item 7).
constexpr double kTargetPower = 0.9;

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

std::vector<double> dyadic(int J) {
  std::vector<double> t;
  for (int j = 1; j <= J; ++j) t.push_back(std::ldexp(1.0, j));
  return t;
}

struct Injection {
  Model model;  // the effect (empty for OUTLIERS, STEP, TRANSIENT and the null side)
  Eigen::VectorXd theta;
  std::vector<double> signal;    // STEP, TRANSIENT: the deterministic signal added
  std::vector<int> dominant;     // 0-based levels
  double truth_parameter = 0.0;  // SIN f, AR1 or TRANSIENT T (samples), STEP time (sample)
};

// A deterministic effect (STEP, TRANSIENT) scaled to `strength`: the relative excess its
// WV causes at the level where it is largest (docs/gap.md, method note 5; the cross terms with the noise
// have mean zero).
void scale_signal(Injection& in, double strength, const Model& base, const Eigen::VectorXd& base_theta) {
  const auto n = static_cast<std::int64_t>(in.signal.size());
  const WaveletVariance w = classical_wv(in.signal.data(), n);
  const Eigen::VectorXd ratio = w.values().cwiseQuotient(base.wv(base_theta, w.tau));
  const double peak = ratio.maxCoeff();
  const double a = std::sqrt(strength / peak);
  for (double& v : in.signal) v *= a;
  for (int j = 0; j < w.levels(); ++j)
    if (ratio(j) >= kDominantShare * peak) in.dominant.push_back(j);
}

// The effect of `family` at `strength` (ratio of its WV to the base's at the level where
// that ratio peaks), with nuisance parameters drawn from rng.
Injection make_injection(GapEffect family, double strength, const Model& base, const Eigen::VectorXd& base_theta,
                         std::int64_t n, Rng& rng, const ProcessContext& ctx) {
  const int J = static_cast<int>(std::floor(std::log2(static_cast<double>(n))));
  const auto tau = dyadic(J);
  boost::random::uniform_01<double> u;
  Injection in;
  const char* spec = detail::effect_entry(family).process;
  Eigen::VectorXd unit;
  switch (family) {
    case GapEffect::kQN:
      unit = Eigen::VectorXd::Ones(1);
      break;
    case GapEffect::kDR:
      unit = Eigen::VectorXd::Ones(1);
      break;
    case GapEffect::kFlicker:
      unit = Eigen::VectorXd::Ones(1);
      break;
    case GapEffect::kAR1: {
      const double hi = std::log2(static_cast<double>(n) * kAr1RecordShare);
      const double T = std::exp2(kAr1MinLog2T + u(rng) * (hi - kAr1MinLog2T));
      in.truth_parameter = T;
      unit = (Eigen::VectorXd(2) << std::exp(-1.0 / T), 1.0).finished();
      break;
    }
    case GapEffect::kSin: {
      const double lo = std::log(kSinMinCycles / static_cast<double>(n)), hi = std::log(kSinMaxF);
      const double f = std::exp(lo + u(rng) * (hi - lo));
      in.truth_parameter = f;
      unit = (Eigen::VectorXd(2) << 1.0, f).finished();
      break;
    }
    case GapEffect::kStep: {
      const double t0 = std::floor((kStepEdgeShare + u(rng) * (1.0 - 2.0 * kStepEdgeShare)) * static_cast<double>(n));
      in.truth_parameter = t0;
      in.signal.assign(static_cast<std::size_t>(n), 0.0);
      for (auto t = static_cast<std::size_t>(t0); t < in.signal.size(); ++t) in.signal[t] = 1.0;
      scale_signal(in, strength, base, base_theta);
      return in;
    }
    case GapEffect::kTransient: {
      const double T = std::exp2(kTransientMinLog2T + u(rng) * (kTransientMaxLog2T - kTransientMinLog2T));
      in.truth_parameter = T;
      in.signal.resize(static_cast<std::size_t>(n));
      for (std::size_t t = 0; t < in.signal.size(); ++t) in.signal[t] = std::exp(-static_cast<double>(t) / T);
      scale_signal(in, strength, base, base_theta);
      return in;
    }
    default:
      return in;
  }
  in.model = parse_model(spec, ctx);
  const Eigen::VectorXd nu_base = base.wv(base_theta, tau), nu_unit = in.model.wv(unit, tau);
  const Eigen::VectorXd ratio = nu_unit.cwiseQuotient(nu_base);
  const double peak = ratio.maxCoeff();
  // Every effect's WV is linear in its size parameter (AR1: sigma2, the second; the
  // others: the first), except DR's (omega^2).
  const double scale = strength / peak;
  in.theta = unit;
  const Eigen::Index size_index = family == GapEffect::kAR1 ? 1 : 0;
  in.theta(size_index) = family == GapEffect::kDR ? std::sqrt(scale) : scale;
  for (int j = 0; j < J; ++j)
    if (ratio(j) >= kDominantShare * peak) in.dominant.push_back(j);
  return in;
}

bool overlaps(const GapResult& g, const std::vector<int>& dominant) {
  for (const auto& b : g.bands)
    for (int j : dominant)
      if (j + 1 >= b.first_level && j + 1 <= b.last_level) return true;
  return false;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Plan {
  GapEffect truth;
  double strength;
};

// dnu' V0^-1 dnu.
double noncentrality(const Eigen::LLT<Eigen::MatrixXd>& v0, const Eigen::VectorXd& dnu) {
  return dnu.dot(v0.solve(dnu));
}

// m' Sigma^-1 m for a mean m_t added to WN(sigma2) + RW(gamma2) (the RW's first step
// included, as simulate() draws it), in the coordinates y_0 = x_0, y_t = x_t - x_{t-1}
// (unit Jacobian, so the non-centrality is unchanged) where Sigma is tridiagonal:
// diagonal gamma2 + sigma2 (t = 0) and gamma2 + 2 sigma2, off-diagonal -sigma2. Solved by
// the Thomas algorithm (the matrix is diagonally dominant).
double series_noncentrality(const std::vector<double>& m, double sigma2, double gamma2) {
  const std::size_t n = m.size();
  if (n == 0) return 0.0;
  std::vector<double> y(n), c(n), d(n);
  for (std::size_t t = 0; t < n; ++t) y[t] = t == 0 ? m[0] : m[t] - m[t - 1];
  const double off = -sigma2;
  double denom = gamma2 + sigma2;
  c[0] = off / denom;
  d[0] = y[0] / denom;
  for (std::size_t t = 1; t < n; ++t) {
    denom = gamma2 + 2.0 * sigma2 - off * c[t - 1];
    c[t] = off / denom;
    d[t] = (y[t] - off * d[t - 1]) / denom;
  }
  double nc = 0.0, v = 0.0;
  for (std::size_t t = n; t-- > 0;) {
    v = d[t] - (t + 1 < n ? c[t] * v : 0.0);
    nc += y[t] * v;
  }
  return nc;
}

// The strength at which the mean oracle power over the cases' non-centralities is 90%
// (bisection in log strength; the mean is increasing in the strength). `series`: the
// time-domain oracle, whose z grows as sqrt(strength) (GapCheckCase::oracle_time_domain).
double oracle_strength(const std::vector<double>& nc, bool series) {
  auto power = [&](double s) {
    double sum = 0.0;
    for (double q : nc) sum += normal_cdf((series ? std::sqrt(s * q) : s * std::sqrt(q)) - kZ95);
    return sum / static_cast<double>(nc.size());
  };
  double lo = std::log(1e-8), hi = std::log(1e8);
  if (nc.empty() || power(std::exp(hi)) < kTargetPower) return std::numeric_limits<double>::quiet_NaN();
  for (int it = 0; it < 200 && hi - lo > 1e-10; ++it) {
    const double mid = 0.5 * (lo + hi);
    (power(std::exp(mid)) < kTargetPower ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

// The first crossing of 90% along the grid, interpolated linearly in log strength.
std::pair<double, Crossing> our_strength(const std::map<double, double>& power) {
  double prev_s = 0.0, prev_p = 0.0;
  bool first = true;
  for (const auto& [s, p] : power) {
    if (p >= kTargetPower) {
      if (first) return {s, Crossing::kAtMost};
      const double w = (kTargetPower - prev_p) / (p - prev_p);
      return {std::exp(std::log(prev_s) + w * (std::log(s) - std::log(prev_s))), Crossing::kInterpolated};
    }
    prev_s = s;
    prev_p = p;
    first = false;
  }
  return {power.empty() ? std::numeric_limits<double>::quiet_NaN() : power.rbegin()->first, Crossing::kBeyond};
}

}  // namespace

const char* to_string(Crossing c) {
  switch (c) {
    case Crossing::kInterpolated:
      return "interpolated";
    case Crossing::kAtMost:
      return "at most";
    case Crossing::kBeyond:
      return "beyond";
  }
  return "?";
}

std::string GapCheckOptions::Validate() const {
  std::ostringstream os;
  if (cases < 1)
    os << "cases must be at least 1, got " << cases;
  else if (strengths.empty())
    os << "at least one strength is needed";
  else if (n < 256)
    os << "n must be at least 256, got " << n;
  else if (!(freq > 0.0))
    os << "freq must be positive, got " << freq;
  else if (replicates < 20)
    os << "replicates must be at least 20, got " << replicates;
  for (double s : strengths)
    if (!(s > 0.0) && os.tellp() == 0) os << "strengths must be positive, got " << s;
  for (GapEffect f : families)
    if (f == GapEffect::kNone || f == GapEffect::kReparameterise || f == GapEffect::kTemperature ||
        f == GapEffect::kWN || f == GapEffect::kRW)
      if (os.tellp() == 0) os << "family " << to_string(f) << " cannot be withheld from a WN+RW base by this check";
  return os.str();
}

GapCheckResult run_gap_check(const GapCheckOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("gap-check: " + why);
  const ProcessContext ctx{options.freq, true};
  const Model base = parse_model(kBase, ctx);
  const Eigen::VectorXd base_theta = base.given_values();
  std::vector<Plan> plan;
  for (GapEffect f : options.families)
    for (int c = 0; c < options.cases; ++c)
      plan.push_back({f, options.strengths[static_cast<std::size_t>(c) % options.strengths.size()]});
  if (options.null_side) {
    for (int c = 0; c < 5 * options.cases; ++c) plan.push_back({GapEffect::kNone, 0.0});
    for (int c = 0; c < 2 * options.cases; ++c) plan.push_back({GapEffect::kReparameterise, 0.0});
  }
  // The oracle's null covariance: the base's exact Cov(nuhat) at the check's length.
  // The classical WV's default levels: J = floor(log2 N) (classical_wv.h).
  const int J = static_cast<int>(std::floor(std::log2(static_cast<double>(options.n))));
  const std::vector<double> tau = dyadic(J);
  const Eigen::LLT<Eigen::MatrixXd> v0(model_wv_covariance(base, base_theta, options.n, J));
  const Eigen::VectorXd nu_base = base.wv(base_theta, tau);
  GapCheckResult out;
  out.cases.resize(plan.size());
  std::atomic<int> done{0};
  const int total = static_cast<int>(plan.size());
  gmwm::parallel_for(std::size_t{0}, plan.size(), [&](std::size_t i) {
    const Plan& p = plan[i];
    GapCheckCase& c = out.cases[i];
    c.truth = p.truth;
    c.strength = p.strength;
    Rng rng = make_stream(options.seed, {0x6a70u, static_cast<std::uint64_t>(i)});
    Eigen::VectorXd theta = base_theta;
    Model model = base;
    Injection in;
    if (p.truth == GapEffect::kReparameterise) {
      boost::random::uniform_01<double> u;
      for (Eigen::Index k = 0; k < theta.size(); ++k) theta(k) *= u(rng) < 0.5 ? 1.0 - kOffFactor : 1.0 + kOffFactor;
      c.injected = base.to_string(theta);
    } else if (p.truth != GapEffect::kNone && p.truth != GapEffect::kOutliers) {
      in = make_injection(p.truth, p.strength, base, base_theta, options.n, rng, ctx);
      if (in.signal.empty()) {
        model = base + in.model;
        theta.resize(base_theta.size() + in.theta.size());
        theta << base_theta, in.theta;
        c.injected = in.model.to_string(in.theta);
      } else if (p.truth == GapEffect::kStep) {
        c.injected = "step of " + std::to_string(in.signal.back()) + " at sample " +
                     std::to_string(static_cast<std::int64_t>(in.truth_parameter));
      } else {
        c.injected = "transient " + std::to_string(in.signal.front()) + " exp(-t / " +
                     std::to_string(in.truth_parameter) + " samples)";
      }
    }
    std::vector<double> x = simulate(model, theta, options.n, options.seed, 2 * static_cast<std::uint64_t>(i) + 1);
    for (std::size_t t = 0; t < in.signal.size(); ++t) x[t] += in.signal[t];
    WaveletVariance wv = classical_wv(x.data(), options.n);
    if (p.truth == GapEffect::kOutliers) {
      // Spikes of +-a at kSpikeShare of the samples: each adds 2 (a/2)^2 to the level-1
      // sum of squares, so the level-1 WV grows by share a^2 / 2 = strength x nu_base(2).
      const double a = std::sqrt(2.0 * p.strength * base.wv(base_theta, dyadic(1))(0) / kSpikeShare);
      boost::random::uniform_01<double> u;
      for (double& v : x)
        if (u(rng) < kSpikeShare) v += u(rng) < 0.5 ? a : -a;
      wv = classical_wv(x.data(), options.n);
      in.dominant = {0, 1};
      c.injected = "spikes of +-" + std::to_string(a) + " at " + std::to_string(kSpikeShare) + " of the samples";
    }
    // The effect's expected WV at strength 1 (each is linear in the strength).
    c.oracle_nc = std::numeric_limits<double>::quiet_NaN();
    if (p.strength > 0.0) {
      Eigen::VectorXd dnu;
      if (p.truth == GapEffect::kOutliers) {
        // iid spikes of variance share a^2 = 2 strength nu_base(2): a WN of that variance.
        dnu = Eigen::VectorXd(J);
        for (int j = 0; j < J; ++j) dnu(j) = 2.0 * nu_base(0) / tau[static_cast<std::size_t>(j)];
      } else if (!in.signal.empty()) {
        dnu = classical_wv(in.signal.data(), options.n).values() / p.strength;
      } else {
        dnu = in.model.wv(in.theta, tau) / p.strength;
      }
      if (p.truth == GapEffect::kDR) {
        // omega at strength 1: the injected omega / sqrt(strength); the base's values in
        // kBase's order (WN sigma2, RW gamma2).
        const double omega1 = in.theta(0) / std::sqrt(p.strength);
        std::vector<double> m(static_cast<std::size_t>(options.n));
        for (std::size_t t = 0; t < m.size(); ++t) m[t] = omega1 * static_cast<double>(t);
        c.oracle_nc = series_noncentrality(m, base_theta(0), base_theta(1));
        c.oracle_time_domain = true;
      } else if (dnu.size() == J && dnu.allFinite()) {
        c.oracle_nc = noncentrality(v0, dnu);
      }
    }
    const WaveletVariance robust = robust::robust_wv(x.data(), options.n);
    GapOptions go;
    go.replicates = options.replicates;
    go.seed = options.seed + kCalibrationSeedOffset + i;
    go.context = ctx;
    const GapResult g = diagnose_gap(wv, base, base_theta, go, &robust, &x);
    c.reported = g.effect;
    c.detected = g.detected;
    c.located = overlaps(g, in.dominant);
    c.excess_removed = g.shrinkage.excess_removed;
    c.parameter_error = std::numeric_limits<double>::quiet_NaN();
    if (p.truth == GapEffect::kNone)
      c.correct = g.effect == GapEffect::kNone;
    else if (p.truth == GapEffect::kReparameterise)
      c.correct = g.effect == GapEffect::kNone || g.effect == GapEffect::kReparameterise;
    else
      c.correct = g.effect == p.truth;
    if (c.correct && g.final_fit.status != FitStatus::kFailed && g.final_fit.theta.size() == 2) {
      if (p.truth == GapEffect::kSin) c.parameter_error = std::abs(g.final_fit.theta(1) / in.truth_parameter - 1.0);
      if (p.truth == GapEffect::kAR1)
        c.parameter_error =
            std::abs(std::log(-1.0 / std::log(g.final_fit.theta(0)) / in.truth_parameter)) / std::log(2.0);
    }
    // STEP: the time error in windows of the sliding map (<= 1: within one window);
    // TRANSIENT: |log(T_hat / T)| / log 2 (<= 1: within a factor 2).
    if (c.correct && g.event && p.truth == GapEffect::kStep && g.window_length > 0)
      c.parameter_error =
          std::abs(static_cast<double>(g.event->sample) - in.truth_parameter) / static_cast<double>(g.window_length);
    if (c.correct && g.event && p.truth == GapEffect::kTransient)
      c.parameter_error = std::abs(std::log(g.event->time_constant / in.truth_parameter)) / std::log(2.0);
    const int d = ++done;
    if (options.progress) options.progress(d, total);
  });
  std::map<std::string, std::vector<double>> removed;
  std::map<std::string, std::map<double, std::pair<int, int>>> by_strength;
  for (const auto& c : out.cases) {
    const std::string t = to_string(c.truth);
    ++out.confusion[t][to_string(c.reported)];
    GapCheckFamily& f = out.families[t];
    ++f.cases;
    f.correct += c.correct;
    f.located += c.located;
    f.detected += c.detected;
    out.correct += c.correct;
    if ((c.truth == GapEffect::kNone || c.truth == GapEffect::kReparameterise) && !c.correct) ++out.false_alarms;
    if (c.correct && c.truth != GapEffect::kNone && c.truth != GapEffect::kReparameterise)
      removed[t].push_back(c.excess_removed);
    if (c.strength > 0.0) {
      auto& s = by_strength[t][c.strength];
      ++s.second;
      s.first += c.correct;
    }
  }
  std::map<std::string, std::vector<double>> nc;
  std::map<std::string, bool> series;
  for (const auto& c : out.cases)
    if (std::isfinite(c.oracle_nc)) {
      nc[to_string(c.truth)].push_back(c.oracle_nc);
      series[to_string(c.truth)] = c.oracle_time_domain;
    }
  for (auto& [t, f] : out.families) {
    f.median_excess_removed = median(removed[t]);
    for (const auto& [s, k] : by_strength[t]) f.power[s] = static_cast<double>(k.first) / k.second;
    f.strength_90 = f.oracle_strength_90 = f.oracle_ratio = std::numeric_limits<double>::quiet_NaN();
    if (f.power.empty()) continue;
    std::tie(f.strength_90, f.crossing) = our_strength(f.power);
    f.oracle_strength_90 = oracle_strength(nc[t], series[t]);
    f.oracle_ratio = f.strength_90 / f.oracle_strength_90;
  }
  return out;
}

std::vector<GapEffect> parse_gap_families(const std::string& list) {
  std::string known;
  for (const GapEffect e : GapCheckOptions{}.families) known += (known.empty() ? "" : ", ") + std::string(to_string(e));
  std::vector<GapEffect> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    const auto e = parse_gap_effect(item);
    if (!e) throw InputError("--families '" + list + "': unknown effect '" + item + "' (" + known + ")");
    out.push_back(*e);
  }
  if (out.empty()) throw InputError("--families: at least one family is needed");
  return out;
}

std::vector<double> parse_gap_strengths(const std::string& list) {
  std::vector<double> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    // Decimal only: from_chars takes no '+', and "inf", "nan" are refused (std::stod took "inf").
    std::string_view t(item);
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    double v = 0.0;
    const bool starts = !t.empty() && (std::isdigit(static_cast<unsigned char>(t.front())) || t.front() == '.');
    const auto [end, ec] = starts ? std::from_chars(t.data(), t.data() + t.size(), v, std::chars_format::general)
                                  : std::from_chars_result{t.data(), std::errc::invalid_argument};
    if (!starts || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v) || !(v > 0.0))
      throw InputError("--strengths '" + list + "': expected positive numbers separated by commas, found '" + item +
                       "'");
    out.push_back(v);
  }
  if (out.empty()) throw InputError("--strengths: at least one strength is needed");
  return out;
}

}  // namespace gmwm::gap
