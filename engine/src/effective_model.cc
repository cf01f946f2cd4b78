#include "gmwm/engine/effective_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/random.h"
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

// What a reduction removed that carried a share of the WV: the WVs of the shapes the
// removed part could have taken (one column each; Process::shape_family), and whether its
// size is one-signed (a variance: the fit collapses it rather than go negative).
struct Removal {
  Eigen::MatrixXd shapes;
  bool one_sided = true;
};

struct Candidate {
  std::vector<Part> parts;
  std::vector<Removal> removals;  ///< this step's (carried parts only)
  std::string text;
  double statistic = 0.0, p_value = 0.0;
  int removed = 0;
  bool carried = false;    ///< the reduced component(s) carried a share of the WV
  int df = 0;              ///< degrees of freedom of the test: parameters removed that carried a share
  Eigen::VectorXd metric;  ///< W^1/2 of the reduced model the test measured with
};

// A component's WV closer to zero than this (squared distance in units of the WV's own
// standard deviations, summed over levels) carries no share of it: 0.001 is a shift of
// 0.03 standard deviations at one level, far below anything a test at 5% resolves.
constexpr double kNoShare = 1e-3;

// The test's null distribution is simulated (Hansen 1996, "Inference when a nuisance
// parameter is not identified under the null hypothesis", Econometrica 64:413): draws of
// nuhat - nu ~ N(0, V) through the linearised fit. 2000 draws put the Monte-Carlo
// standard error of a p-value near 0.05 at sqrt(0.05 x 0.95 / 2000) = 0.5 points. The
// seed is fixed: the same fit always gets the same decision.
constexpr int kCalibrationDraws = 2000;
constexpr std::uint64_t kCalibrationSeed = 0x27'0001;
// Sequential stopping (Besag & Clifford 1991, "Sequential Monte Carlo p-values",
// Biometrika 78:301): 20 exceedances estimate p to about 1 / sqrt(20) = 22% relative, so
// a p-value at least twice alpha is resolved as above alpha (4.5 standard errors);
// batches of 100 draws.
constexpr Eigen::Index kSequentialHits = 20;
constexpr Eigen::Index kSequentialBatch = 100;
constexpr double kSequentialMargin = 2.0;
// And a p-value at most a quarter of alpha after 400 draws is resolved as below it (at
// p = alpha = 0.05 the estimate's standard error is 0.011, and 0.0125 is 3.4 of them away).
constexpr Eigen::Index kSequentialMinDraws = 400;
constexpr double kSequentialFloor = 0.25;
// Columns of W^1/2 D whose pivoted-QR diagonal falls below this fraction of the largest
// are dependent (a parameter at its bound, two AR1s at one phi) and left out of the basis.
constexpr double kRankTolerance = 1e-9;
// The reduced model's parameters are moved to the statistic's minimum by at most this many
// Gauss-Newton steps (each halved down to kSmallestStep while it leaves the parameter
// space or does not lower the distance): from the reduction's own values (a re-sized
// component) the distance is within a few percent of its minimum after one or two.
constexpr int kProjectionSteps = 4;
constexpr double kSmallestStep = 1.0 / 8.0;

// Jacobian of the parts' total WV with respect to all their parameters (J x p).
Eigen::MatrixXd jacobian_of(const std::vector<Part>& parts, std::span<const double> tau) {
  const auto J = static_cast<Eigen::Index>(tau.size());
  Eigen::MatrixXd d(J, parameters_of(parts));
  Eigen::Index col = 0;
  for (const auto& p : parts) {
    Eigen::MatrixXd block(J, p.process->size());
    p.process->wv_jacobian(p.theta, tau, block);
    d.middleCols(col, block.cols()) = block;
    col += block.cols();
  }
  return d;
}

// The reduction test's statistic and its null distribution. For a reduced model R of the
// fit F: S = min over R's parameters (one Gauss-Newton step from the reduction's values)
// of sum_j w_j (nu_R - nu_F)_j^2, w_j = 1 / V_jj, the fit's own metric. Under R, to first
// order, F's fit adds to R's the projection of nuhat - nu on the removed part's direction
// g (orthogonalised against R's tangent space in that metric) and picks the g among the
// part's shapes that fits best, so S = max_g (a_g' e)^2 with a_g = W g~ / |g~|_W and
// e ~ N(0, V); with several removed parts, the sum of their maxima. Its quantiles are
// simulated, so the test keeps its level with correlated levels (a_g' V a_g != 1) and a
// nuisance parameter (an AR1's phi) that a chi-square with one degree of freedom per
// parameter ignores (issue 27: 23-28% instead of 5%).
class ReductionTest {
 public:
  ReductionTest(std::span<const double> tau, const Eigen::MatrixXd& v, const Eigen::VectorXd& w)
      : tau_(tau), v_(v), sqrt_w_(w.array().sqrt()) {}

  // The test's metric W^1/2 (w_j = 1 / V_jj). Every method takes the metric of the reduced
  // model under test: V rescaled to that model's levels, D V D, keeps the correlation
  // C = W^1/2 V W^1/2 and the whitened draws W^1/2 e, so one set of draws serves all.
  const Eigen::VectorXd& base_metric() const { return sqrt_w_; }

  // The reduced parts with their parameters moved (Gauss-Newton, each step kept only
  // when every part stays valid and the distance falls) towards the minimum of
  // sum_j w_j (nu_R - nu_fit)_j^2; the distance there is the statistic S.
  double project(std::vector<Part>& parts, const Eigen::VectorXd& nu_fit, const Eigen::VectorXd& sqrt_w) const {
    // The residual of the current parts is kept from the distance that accepted them (their
    // total WV was computed twice per step: 4% of a selection).
    Eigen::VectorXd r = sqrt_w.cwiseProduct(total_wv(parts, tau_) - nu_fit);
    double s = r.squaredNorm();
    for (int step = 0; step < kProjectionSteps && std::isfinite(s); ++step) {
      const Eigen::MatrixXd d = sqrt_w.asDiagonal() * jacobian_of(parts, tau_);
      if (d.cols() == 0 || !d.allFinite()) break;
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(d);
      qr.setThreshold(kRankTolerance);
      const Eigen::VectorXd delta = qr.solve(-r);
      if (!delta.allFinite()) break;
      bool improved = false;
      for (double scale = 1.0; scale >= kSmallestStep && !improved; scale *= 0.5) {
        std::vector<Part> moved = parts;
        Eigen::Index k = 0;
        bool valid = true;
        for (auto& p : moved) {
          for (double& x : p.theta) x += scale * delta(k++);
          valid = valid && p.process->validate(p.theta).empty();
        }
        if (!valid) continue;
        Eigen::VectorXd rt = sqrt_w.cwiseProduct(total_wv(moved, tau_) - nu_fit);
        const double t = rt.squaredNorm();
        if (t < s) {
          parts = std::move(moved);
          r = std::move(rt);
          s = t;
          improved = true;
        }
      }
      if (!improved) break;
    }
    return s;
  }

  // P(S* >= s) under the reduced model, with the removals' shapes. 0 without drawing when
  // a Bonferroni bound already puts it below alpha (the statistic far beyond what the
  // shapes can produce under the null: most reductions of a selection's larger
  // candidates), so that only the reductions near acceptance are simulated.
  double p_value(const std::vector<Part>& parts, const std::vector<Removal>& removals, double s, double alpha,
                 const Eigen::VectorXd& sqrt_w) {
    const std::vector<Directions> dirs = directions(parts, removals, sqrt_w);
    if (dirs.empty()) return s <= kNoShare ? 1.0 : 0.0;
    if (s > bonferroni_bound(dirs, alpha)) return 0.0;
    // Sequential Monte-Carlo p-value (Besag & Clifford 1991): draw in batches until
    // kSequentialHits draws reach s with p = hits / drawn at least kSequentialMargin x alpha
    // (clearly accepted), or all are drawn (p = (hits + 1) / (draws + 1)). A reduction far
    // inside its null stops after a batch or two; one near the threshold uses every draw,
    // so the decision there has the full precision; one clearly beyond it stops at
    // kSequentialMinDraws.
    Eigen::Index hits = 0, drawn = 0;
    while (drawn < kCalibrationDraws) {
      const Eigen::Index count = std::min<Eigen::Index>(kSequentialBatch, kCalibrationDraws - drawn);
      hits += (null_draws(dirs, drawn, count).array() >= s).count();
      drawn += count;
      if (hits >= kSequentialHits &&
          static_cast<double>(hits) >= kSequentialMargin * alpha * static_cast<double>(drawn))
        return static_cast<double>(hits) / static_cast<double>(drawn);
      if (drawn >= kSequentialMinDraws &&
          static_cast<double>(hits) <= kSequentialFloor * alpha * static_cast<double>(drawn))
        break;  // clearly below alpha
    }
    return static_cast<double>(hits + 1) / static_cast<double>(drawn + 1);
  }

  // The 1 - alpha quantile of S*.
  double critical_value(const std::vector<Part>& parts, const std::vector<Removal>& removals, double alpha,
                        const Eigen::VectorXd& sqrt_w) {
    const std::vector<Directions> dirs = directions(parts, removals, sqrt_w);
    if (dirs.empty()) return kNoShare;
    const Eigen::VectorXd draws = null_draws(dirs, 0, kCalibrationDraws);
    std::vector<double> v(draws.data(), draws.data() + draws.size());
    const auto k =
        std::min(static_cast<std::size_t>(std::floor((1.0 - alpha) * static_cast<double>(v.size()))), v.size() - 1);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  }

 private:
  // Orthonormal basis of W^1/2 D_R.
  Eigen::MatrixXd basis(const std::vector<Part>& parts, const Eigen::VectorXd& sqrt_w) const {
    const Eigen::MatrixXd d = sqrt_w.asDiagonal() * jacobian_of(parts, tau_);
    if (d.cols() == 0) return Eigen::MatrixXd(d.rows(), 0);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(d);
    qr.setThreshold(kRankTolerance);
    const Eigen::Index rank = qr.rank();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(d.rows(), rank);
    return q;
  }

  // W^1/2 e for each draw (J x draws), made once per call of effective_model.
  const Eigen::MatrixXd& scaled_errors() {
    if (u_.size() > 0) return u_;
    const auto J = v_.rows();
    Eigen::MatrixXd l;
    Eigen::LLT<Eigen::MatrixXd> llt(v_);
    if (llt.info() == Eigen::Success) {
      l = llt.matrixL();
    } else {  // not positive definite in floating point: the levels' own variances
      l = v_.diagonal().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    }
    Rng rng = make_stream(kCalibrationSeed, {static_cast<std::uint64_t>(J)});
    Eigen::MatrixXd e(J, kCalibrationDraws);  // column by column, as normal_distribution(0, 1) draws them
    rng.unit_normals(e.data(), static_cast<std::size_t>(e.size()));
    for (Eigen::Index i = 0; i < e.size(); ++i) e.data()[i] = scaled_normal(e.data()[i], 1.0);
    u_ = sqrt_w_.asDiagonal() * (l * e);
    return u_;
  }

  // One removal's directions in the whitened space: unit columns h~ (the shapes, W^1/2
  // scaled and orthogonalised against R's tangent space), each statistic (h~' W^1/2 e)^2
  // of variance c = h~' C h~ (C = W^1/2 V W^1/2, the levels' correlation).
  struct Directions {
    Eigen::MatrixXd unit;
    double largest_variance = 0.0;
    bool one_sided = true;
  };

  std::vector<Directions> directions(const std::vector<Part>& parts, const std::vector<Removal>& removals,
                                     const Eigen::VectorXd& sqrt_w) const {
    const Eigen::MatrixXd q = basis(parts, sqrt_w);
    std::vector<Directions> out;
    for (const Removal& rm : removals) {
      Eigen::MatrixXd h = sqrt_w.asDiagonal() * rm.shapes;
      const Eigen::VectorXd raw = h.colwise().norm();
      h -= q * (q.transpose() * h);
      Directions d;
      d.one_sided = rm.one_sided;
      d.unit.resize(h.rows(), h.cols());
      Eigen::Index kept = 0;
      for (Eigen::Index c = 0; c < h.cols(); ++c) {
        const double norm = h.col(c).norm();
        if (!(norm > kRankTolerance * raw(c) && norm > 0.0)) continue;
        d.unit.col(kept++) = h.col(c) / norm;
      }
      if (kept == 0) continue;  // the part adds nothing R cannot do: no excess to test
      d.unit.conservativeResize(Eigen::NoChange, kept);
      d.largest_variance = (d.unit.transpose() * correlation() * d.unit).diagonal().maxCoeff();
      out.push_back(std::move(d));
    }
    return out;
  }

  // P(sum_k max_g X_kg > sum_k t_k) <= sum_k P(max_g X_kg > t_k) <= sum_k G_k P(c_k chi > t_k):
  // with t_k at alpha / (K G_k) each, a statistic above their sum has p below alpha.
  double bonferroni_bound(const std::vector<Directions>& dirs, double alpha) const {
    double bound = 0.0;
    const boost::math::normal z;
    for (const auto& d : dirs) {
      const double tail = alpha / static_cast<double>(dirs.size() * static_cast<std::size_t>(d.unit.cols()));
      const double q = boost::math::quantile(boost::math::complement(z, d.one_sided ? tail : tail / 2.0));
      bound += d.largest_variance * q * q;
    }
    return bound;
  }

  const Eigen::MatrixXd& correlation() const {
    if (c_.size() == 0) c_ = sqrt_w_.asDiagonal() * v_ * sqrt_w_.asDiagonal();
    return c_;
  }

  // S* of draws [from, from + count).
  Eigen::VectorXd null_draws(const std::vector<Directions>& dirs, Eigen::Index from, Eigen::Index count) {
    Eigen::VectorXd total = Eigen::VectorXd::Zero(count);
    for (const Directions& d : dirs) {
      const Eigen::MatrixXd z = d.unit.transpose() * scaled_errors().middleCols(from, count);  // shapes x draws
      for (Eigen::Index b = 0; b < z.cols(); ++b) {
        double best = 0.0;
        for (Eigen::Index g = 0; g < z.rows(); ++g) {
          const double x = d.one_sided ? std::max(z(g, b), 0.0) : z(g, b);
          best = std::max(best, x * x);
        }
        total(b) += best;
      }
    }
    return total;
  }

  std::span<const double> tau_;
  const Eigen::MatrixXd& v_;
  Eigen::VectorXd sqrt_w_;
  Eigen::MatrixXd u_;
  mutable Eigen::MatrixXd c_;
};

// The shapes of a part's process over tau (Process::shape_family), one WV per column.
Eigen::MatrixXd shapes_of(const Part& p, std::span<const double> tau) {
  const auto family = p.process->shape_family(p.theta, tau);
  Eigen::MatrixXd out(static_cast<Eigen::Index>(tau.size()), static_cast<Eigen::Index>(family.size()));
  for (std::size_t k = 0; k < family.size(); ++k)
    out.col(static_cast<Eigen::Index>(k)) = part_wv({p.process, family[k], ""}, tau);
  return out;
}

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
    st.parts.push_back(
        {comp.process,
         std::vector<double>(theta.data() + model.offset(c), theta.data() + model.offset(c) + comp.process->size()),
         ""});
  }
  const int original_parameters = parameters_of(st.parts);
  const Eigen::VectorXd nu_fit = total_wv(st.parts, tau);
  // The metric: w_j = 1 / Var(nuhat_j), levels weighed as the selection's objective weighs
  // them (its model-based Omega is diag(V)^-1). V is options.covariance (the exact
  // Cov(nuhat) the rest of the inference uses); without it, the chi-square approximation's
  // diagonal with eta_j equivalent degrees of freedom (docs/statistics.md section 1),
  // inflated by 1/efficiency for a robust WV (section 2), whose variance is 2-5x the exact
  // one for the processes selection meets (typically 2.8x, issue 27) and reduces
  // components the objective clearly sees.
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(J, J);
  const double inflation = 1.0 / wv.efficiency.value_or(1.0);
  for (Eigen::Index j = 0; j < J; ++j) {
    const double level =
        nu_fit(j) > 0.0 && std::isfinite(nu_fit(j)) ? nu_fit(j) : std::abs(wv.wv[static_cast<std::size_t>(j)]);
    v(j, j) = level * level * 2.0 / wv.eta[static_cast<std::size_t>(j)] * inflation;
  }
  if (options.covariance) {
    const Eigen::MatrixXd& given = *options.covariance;
    if (given.rows() != J || given.cols() != J)
      throw InvalidArgument("effective_model: the covariance is " + std::to_string(given.rows()) + " x " +
                            std::to_string(given.cols()) + ", the WV has " + std::to_string(J) + " levels");
    if (given.allFinite() && (given.diagonal().array() > 0.0).all())
      v = given;
    else
      for (Eigen::Index j = 0; j < J; ++j)
        if (given(j, j) > 0.0 && std::isfinite(given(j, j))) v(j, j) = given(j, j);
  }
  Eigen::VectorXd w(J);
  for (Eigen::Index j = 0; j < J; ++j) w(j) = v(j, j) > 0.0 && std::isfinite(v(j, j)) ? 1.0 / v(j, j) : 0.0;
  auto distance = [&](const Eigen::VectorXd& d) { return (w.array() * d.array() * d.array()).sum(); };
  ReductionTest test(tau, v, w);
  // The metric of a reduced model: V is the model's covariance at the WV options.covariance_wv
  // (the selection's pilot fit); the reduction is tested under its null, the reduced model,
  // so V's variances are taken at the reduced model's levels, V_R = D V D with
  // D_j = nu_R,j / nu_at,j (Var(nuhat_j) scales as nu_j^2 at a given spectral shape). The
  // pilot fits the coarse levels' chance lows (their few degrees of freedom put the median
  // of nuhat_j below its mean), so its V there was 3-100x below the truth's, and a slow AR1
  // that only follows those lows was tested as if it stood out from a random walk (issue 27:
  // a WN+QN+RW truth read as AR1+WN+QN in 27 of 100 series).
  const Eigen::VectorXd* nu_at = options.covariance && options.covariance_wv && options.covariance_wv->size() == J
                                     ? &*options.covariance_wv
                                     : nullptr;
  auto metric_of = [&](const std::vector<Part>& parts) -> Eigen::VectorXd {
    Eigen::VectorXd m = test.base_metric();
    if (!nu_at) return m;
    const Eigen::VectorXd nu_r = total_wv(parts, tau);
    for (Eigen::Index j = 0; j < J; ++j) {
      const double d = nu_r(j) / (*nu_at)(j);
      if (std::isfinite(d) && d > 0.0) m(j) /= d;
    }
    return m;
  };
  // S under the reduced model's metric: projected under the base metric first (the
  // reduction's values may be far from the minimum), then again under the metric of the
  // model reached, whose values the test then uses.
  auto statistic_of = [&](std::vector<Part>& parts, Eigen::VectorXd& metric) {
    double s = test.project(parts, nu_fit, test.base_metric());
    if (!nu_at || !std::isfinite(s)) {
      metric = test.base_metric();
      return s;
    }
    metric = metric_of(parts);
    s = test.project(parts, nu_fit, metric);
    metric = metric_of(parts);
    return test.project(parts, nu_fit, metric);
  };
  // Each part's shapes, computed once per call (a part stays as it is, and is tried in
  // several reductions, until a reduction is accepted).
  std::map<std::pair<const Process*, std::vector<double>>, Eigen::MatrixXd> shape_cache;
  auto shapes = [&](const Part& p) -> const Eigen::MatrixXd& {
    const auto key = std::make_pair(p.process.get(), p.theta);
    auto it = shape_cache.find(key);
    if (it == shape_cache.end()) it = shape_cache.emplace(key, shapes_of(p, tau)).first;
    return it->second;
  };
  // Whether a component carries a share of the WV the test can see at all: its own WV's
  // distance from zero above kNoShare. A collapsed term (an AR1 at sigma2 1e-16) carries
  // none; it is removed without a test, and adds nothing to the null distribution, so that
  // it gives no budget for dropping a component that does carry one (issue 27, mechanism b).
  auto carries = [&](const Part& p) { return distance(part_wv(p, tau)) > kNoShare; };
  // The carried parts removed by the accepted reductions so far (the statistic is always
  // against the original fit, so its null sums over all of them).
  std::vector<Removal> accepted;
  int tested = 0;
  auto score = [&](Candidate& cand) {
    cand.removed = original_parameters - parameters_of(cand.parts);
    cand.statistic = statistic_of(cand.parts, cand.metric);
    const int step_removed = cand.removed - (original_parameters - parameters_of(st.parts));
    cand.df = tested + (cand.carried ? step_removed : 0);
    if (cand.removed <= 0 || !std::isfinite(cand.statistic)) {
      cand.p_value = 0.0;
      return;
    }
    if (cand.df <= 0) {
      cand.p_value = cand.statistic <= kNoShare ? 1.0 : 0.0;
      return;
    }
    std::vector<Removal> all = accepted;
    all.insert(all.end(), cand.removals.begin(), cand.removals.end());
    cand.p_value = test.p_value(cand.parts, all, cand.statistic, options.alpha, cand.metric);
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
      if (cand.carried) cand.removals.push_back({shapes(parts[c]), true});
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
        // What the component has beyond the simpler form: one direction, either sign. (Its
        // whole shape family here, as for a drop, over-reduces: level 1.0%, power 17% against
        // the oracle's 41%, tools/bench/RESULTS.md.)
        if (cand.carried) cand.removals.push_back({part_wv(parts[c], tau) - part_wv(q, tau), false});
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
        // Two of one process where the merged one stands: a second one of any shape beside it.
        if (cand.carried) cand.removals.push_back({shapes(parts[b]), true});
        cands.push_back(std::move(cand));
      }
    Candidate* best = nullptr;
    for (auto& cand : cands) {
      score(cand);
      const bool accepted_here = cand.removed > 0 && cand.p_value > options.alpha;
      if (accepted_here && (!best || cand.p_value > best->p_value ||
                            (cand.p_value == best->p_value && cand.statistic < best->statistic)))
        best = &cand;
    }
    if (!best) break;
    st.parts = best->parts;
    st.reductions.push_back(best->text);
    accepted.insert(accepted.end(), best->removals.begin(), best->removals.end());
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
    Eigen::VectorXd metric;
    out.statistic = statistic_of(st.parts, metric);
    out.threshold = tested > 0 ? test.critical_value(st.parts, accepted, options.alpha, metric) : kNoShare;
  }
  return out;
}

}  // namespace gmwm
