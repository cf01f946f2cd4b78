#pragma once
// What any WV-based test can see of a component of a true model (issue 27's oracles),
// shared by the selection benchmarks.
//
// noncentrality: per component, nc = d' V0^-1 d of its WV d at the true values under the
// exact covariance V0 of nuhat at the truth (J = log2 N levels). Dropping the component
// and refitting the others shifts the expected WV by at most d, so no test has more power
// than the oracle test of its absence with every other parameter known: oracle_power(nc).
// refit_noncentrality: the same with the other components re-estimated, the minimum over
// the model without the component of (nu0 - nu(theta))' V0^-1 (nu0 - nu(theta)): what a
// test that knows the forms but not the values can see (a component another one can
// mimic, like a WN beside an AR1 and a QN, is much less visible than nc says).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/model.h"
#include "gmwm/engine/wv_covariance.h"

namespace gmwm::bench {

inline std::vector<double> octave_scales(std::int64_t n) {
  std::vector<double> tau;
  const int J = static_cast<int>(std::log2(static_cast<double>(n)));
  for (int j = 1; j <= J; ++j) tau.push_back(std::ldexp(1.0, j));
  return tau;
}

inline std::vector<double> noncentrality(const Model& truth, std::int64_t n) {
  const std::vector<double> tau = octave_scales(n);
  const int J = static_cast<int>(tau.size());
  const Eigen::VectorXd theta = truth.given_values();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(model_wv_covariance(truth, theta, n, J));
  std::vector<double> out;
  for (int c = 0; c < truth.num_components(); ++c) {
    const Process& p = *truth.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> f(tau.size());
    p.wv({theta.data() + truth.offset(c), static_cast<std::size_t>(p.size())}, tau, f);
    const Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(f.data(), J);
    out.push_back(d.dot(ldlt.solve(d)));
  }
  return out;
}

inline std::vector<double> refit_noncentrality(const Model& truth, std::int64_t n) {
  WaveletVariance w;
  w.tau = octave_scales(n);
  const int J = static_cast<int>(w.tau.size());
  for (double tau : w.tau) {
    w.coefficients.push_back(n - static_cast<std::int64_t>(tau) + 1);
    w.eta.push_back(std::max(static_cast<double>(w.coefficients.back()) / tau, 1.0));
    w.notes.emplace_back();
  }
  w.n = n;
  const Eigen::VectorXd theta = truth.given_values();
  const Eigen::VectorXd nu0 = truth.wv(theta, w.tau);
  w.wv.assign(nu0.data(), nu0.data() + J);
  w.ci_low = w.ci_high = w.variance = w.wv;
  const Eigen::MatrixXd v0 = model_wv_covariance(truth, theta, n, J);
  const Eigen::MatrixXd omega = v0.ldlt().solve(Eigen::MatrixXd::Identity(J, J));
  std::vector<double> out;
  for (int c = 0; c < truth.num_components(); ++c) {
    std::vector<Component> kept;
    Eigen::VectorXd start(truth.num_parameters() - truth.components()[static_cast<std::size_t>(c)].process->size());
    int pos = 0;
    for (int k = 0; k < truth.num_components(); ++k) {
      if (k == c) continue;
      kept.push_back(truth.components()[static_cast<std::size_t>(k)]);
      const int size = truth.components()[static_cast<std::size_t>(k)].process->size();
      start.segment(pos, size) = theta.segment(truth.offset(k), size);
      pos += size;
    }
    FitOptions fo;
    fo.omega_matrix = omega;
    fo.inference = false;
    fo.starts = {start};
    out.push_back(fit_gmwm(w, Model(kept), fo).objective);
  }
  return out;
}

/// The oracle's power for one component: the chi-square test (1 df, level alpha) of its
/// absence, non-centrality nc.
inline double oracle_power(double nc, double alpha = 0.05) {
  const double q = boost::math::quantile(boost::math::chi_squared(1.0), 1.0 - alpha);
  return boost::math::cdf(boost::math::complement(boost::math::non_central_chi_squared(1.0, nc), q));
}

}  // namespace gmwm::bench
