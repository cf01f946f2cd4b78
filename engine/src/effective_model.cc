#include "gmwm/engine/effective_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "starting_values.h"

namespace gmwm {

std::string EffectiveOptions::Validate() const {
  if (!(alpha > 0.0 && alpha < 1.0)) return "effective model: alpha must be in (0, 1), got " + std::to_string(alpha);
  return {};
}

namespace {

// One component as it stands during the reduction.
struct Part {
  ProcessPtr process;
  std::vector<double> theta;
  std::string label;  // "WN-like", ... ("" when as fitted)
};

struct State {
  std::vector<Part> parts;
  std::vector<std::string> reductions;
};

Eigen::VectorXd part_wv(const Part& p, std::span<const double> tau) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(tau.size()));
  p.process->wv(p.theta, tau, {out.data(), tau.size()});
  return out;
}

Eigen::VectorXd total_wv(const std::vector<Part>& parts, std::span<const double> tau) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tau.size()));
  for (const auto& p : parts) out += part_wv(p, tau);
  return out;
}

int parameters_of(const std::vector<Part>& parts) {
  int n = 0;
  for (const auto& p : parts) n += p.process->size();
  return n;
}

// "AR1(phi=0.0031,sigma2=0.1)": compact, for the reduction lines.
std::string text_of(const Part& p) {
  std::string s = p.process->name() + "(";
  const auto& specs = p.process->parameters();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", p.process->to_display(static_cast<int>(k), p.theta[k]));
    s += (k ? "," : "") + specs[k].name + "=" + buf;
  }
  return s + ")";
}

// Rescales q's linear size parameter so that its WV best matches `target` (weights w).
void fit_size(Part& q, const Eigen::VectorXd& target, const Eigen::VectorXd& w, std::span<const double> tau) {
  const int k = detail::linear_scale_parameter(*q.process, q.theta, tau);
  if (k < 0) return;
  const Eigen::VectorXd f = part_wv(q, tau);
  const double den = (w.array() * f.array() * f.array()).sum();
  const double num = (w.array() * f.array() * target.array()).sum();
  const double s = num / den;
  if (std::isfinite(s) && s > 0.0) q.theta[static_cast<std::size_t>(k)] *= s;
}

struct Candidate {
  std::vector<Part> parts;
  std::string text;
  double statistic = 0.0, p_value = 0.0;
  int removed = 0;
  bool carried = false;  ///< the reduced component(s) carried a share of the WV
  int df = 0;            ///< degrees of freedom of the test: parameters removed that carried a share
};

// A component's WV closer to zero than this (squared distance in units of the WV's own
// standard deviations, summed over levels) carries no share of it: 0.001 is a shift of
// 0.03 standard deviations at one level, far below anything a test at 5% resolves.
constexpr double kNoShare = 1e-3;

}  // namespace

EffectiveModel effective_model(const WaveletVariance& wv, const Model& model, const Eigen::VectorXd& theta,
                               const EffectiveOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  check_size_match("effective_model", "theta", static_cast<std::size_t>(theta.size()), "parameters",
                   static_cast<std::size_t>(model.num_parameters()));
  const std::span<const double> tau = wv.tau;
  const auto J = static_cast<Eigen::Index>(tau.size());
  State st;
  for (int c = 0; c < model.num_components(); ++c) {
    const auto& comp = model.components()[static_cast<std::size_t>(c)];
    st.parts.push_back({comp.process,
                        std::vector<double>(theta.data() + model.offset(c), theta.data() + model.offset(c) + comp.process->size()),
                        ""});
  }
  const int original_parameters = parameters_of(st.parts);
  const Eigen::VectorXd nu_fit = total_wv(st.parts, tau);
  // The statistic's yardstick: S = sum_j d_j^2 / Var(nuhat_j), levels independent, as the
  // selection's objective weighs them (its model-based Omega is diag(V)^-1). Var from
  // options.covariance (the exact Cov(nuhat) the rest of the inference uses); without it,
  // a chi-square with eta_j equivalent degrees of freedom (docs/statistics.md section 1),
  // inflated by 1/efficiency for a robust WV (section 2), whose variance is 2-5x the exact
  // one for the processes selection meets (typically 2.8x, issue 27) and reduces components
  // the objective clearly sees. (The full d' V^-1 d is smaller still for a smooth bump over
  // correlated levels: 3.2 for the slow AR1 of AR1(0.9, 0.1) + AR1(0.999, 1e-5) + WN(1) at
  // 2^17, against 7.0 on the diagonal and the objective's own 8.4.)
  Eigen::VectorXd sd(J), w(J);
  const double inflation = 1.0 / wv.efficiency.value_or(1.0);
  for (Eigen::Index j = 0; j < J; ++j) {
    const double level = nu_fit(j) > 0.0 && std::isfinite(nu_fit(j)) ? nu_fit(j) : std::abs(wv.wv[static_cast<std::size_t>(j)]);
    sd(j) = level * std::sqrt(2.0 / wv.eta[static_cast<std::size_t>(j)] * inflation);
  }
  if (options.covariance) {
    const Eigen::MatrixXd& v = *options.covariance;
    if (v.rows() != J || v.cols() != J)
      throw InvalidArgument("effective_model: the covariance is " + std::to_string(v.rows()) + " x " +
                            std::to_string(v.cols()) + ", the WV has " + std::to_string(J) + " levels");
    for (Eigen::Index j = 0; j < J; ++j)
      if (v(j, j) > 0.0 && std::isfinite(v(j, j))) sd(j) = std::sqrt(v(j, j));
  }
  for (Eigen::Index j = 0; j < J; ++j) w(j) = sd(j) > 0.0 && std::isfinite(sd(j)) ? 1.0 / (sd(j) * sd(j)) : 0.0;
  auto distance = [&](const Eigen::VectorXd& d) { return (w.array() * d.array() * d.array()).sum(); };
  auto statistic = [&](const std::vector<Part>& parts) { return distance(total_wv(parts, tau) - nu_fit); };
  // Whether a component carries a share of the WV the test can see at all: its own WV's
  // distance from zero above kNoShare. A collapsed term (an AR1 at sigma2 1e-16) carries
  // none; its parameters are removed without counting as degrees of freedom, so that they
  // do not give the test budget for dropping a component that does carry one (issue 27,
  // mechanism b).
  auto carries = [&](const Part& p) { return distance(part_wv(p, tau)) > kNoShare; };
  // Degrees of freedom of the accepted reductions so far (parameters that carried a share).
  int tested = 0;
  auto score = [&](Candidate& cand) {
    cand.removed = original_parameters - parameters_of(cand.parts);
    cand.statistic = statistic(cand.parts);
    cand.df = tested + (cand.carried ? cand.removed - (original_parameters - parameters_of(st.parts)) : 0);
    if (cand.removed <= 0 || !std::isfinite(cand.statistic)) {
      cand.p_value = 0.0;
      return;
    }
    if (cand.df <= 0) {
      cand.p_value = cand.statistic <= kNoShare ? 1.0 : 0.0;
      return;
    }
    const boost::math::chi_squared chi(cand.df);
    cand.p_value = boost::math::cdf(boost::math::complement(chi, std::min(cand.statistic, 1e300)));
  };

  for (;;) {
    std::vector<Candidate> cands;
    const auto& parts = st.parts;
    for (std::size_t c = 0; c < parts.size() && parts.size() > 1; ++c) {
      Candidate cand;
      for (std::size_t k = 0; k < parts.size(); ++k)
        if (k != c) cand.parts.push_back(parts[k]);
      cand.text = text_of(parts[c]) + " dropped: no visible share of the WV";
      cand.carried = carries(parts[c]);
      cands.push_back(std::move(cand));
    }
    for (std::size_t c = 0; c < parts.size(); ++c) {
      for (const SimplerForm& f : parts[c].process->simpler_forms(parts[c].theta)) {
        Part q{f.process, f.theta, f.label};
        if (!q.process->validate(q.theta).empty()) continue;
        fit_size(q, part_wv(parts[c], tau), w, tau);
        if (!q.process->validate(q.theta).empty()) continue;
        Candidate cand;
        cand.parts = parts;
        cand.parts[c] = q;
        cand.text = text_of(parts[c]) + " is " + f.label + ": " + text_of(q);
        cand.carried = carries(parts[c]);
        cands.push_back(std::move(cand));
      }
    }
    for (std::size_t a = 0; a < parts.size(); ++a)
      for (std::size_t b = a + 1; b < parts.size(); ++b) {
        if (!same_process(*parts[a].process, *parts[b].process)) continue;
        auto merged = parts[a].process->merged(parts[a].theta, parts[b].theta);
        if (!merged || !parts[a].process->validate(*merged).empty()) continue;
        Part q{parts[a].process, *merged, parts[a].label == parts[b].label ? parts[a].label : ""};
        fit_size(q, part_wv(parts[a], tau) + part_wv(parts[b], tau), w, tau);
        Candidate cand;
        for (std::size_t k = 0; k < parts.size(); ++k)
          if (k != b) cand.parts.push_back(k == a ? q : parts[k]);
        cand.text = text_of(parts[a]) + " and " + text_of(parts[b]) + " merged: " + text_of(q);
        cand.carried = carries(parts[a]) || carries(parts[b]);
        cands.push_back(std::move(cand));
      }
    const Candidate* best = nullptr;
    for (auto& cand : cands) {
      score(cand);
      const bool accepted =
          cand.removed > 0 &&
          (cand.df <= 0 ? cand.statistic <= kNoShare
                        : cand.statistic <= boost::math::quantile(boost::math::chi_squared(cand.df), 1.0 - options.alpha));
      if (accepted && (!best || cand.p_value > best->p_value)) best = &cand;
    }
    if (!best) break;
    st.parts = best->parts;
    st.reductions.push_back(best->text);
    tested = best->df;
  }

  EffectiveModel out;
  std::vector<Component> comps;
  Eigen::VectorXd th(parameters_of(st.parts));
  int pos = 0;
  for (const auto& p : st.parts) {
    comps.push_back({p.process, {}});
    for (double x : p.theta) th(pos++) = x;
  }
  std::vector<int> order;
  out.model = Model(std::move(comps)).canonical(&th, &order);
  out.theta = th;
  for (int k : order) out.labels.push_back(st.parts[static_cast<std::size_t>(k)].label);
  out.reductions = st.reductions;
  out.removed_parameters = original_parameters - out.model.num_parameters();
  out.tested_parameters = tested;
  if (out.removed_parameters > 0) {
    out.statistic = statistic(st.parts);
    out.threshold = tested > 0 ? boost::math::quantile(boost::math::chi_squared(tested), 1.0 - options.alpha) : kNoShare;
  }
  return out;
}

}  // namespace gmwm
