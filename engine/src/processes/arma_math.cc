// ARMA(p, q) autocovariance and WV; see arma_math.h for the method.
#include "arma_math.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "process_util.h"

namespace gmwm::internal {
namespace {

using AJet = ArmaJet;

// AJet arithmetic over n variables up to the requested order (0, 1 or 2).
class JetOps {
 public:
  JetOps(int n, int order) : n_(n), order_(order) {}
  int order() const { return order_; }

  AJet constant(double c) const {
    AJet r;
    r.v = c;
    if (order_ >= 1) r.g = Eigen::VectorXd::Zero(n_);
    if (order_ >= 2) r.h = Eigen::MatrixXd::Zero(n_, n_);
    return r;
  }
  AJet variable(double c, int i) const {
    AJet r = constant(c);
    if (order_ >= 1) r.g(i) = 1.0;
    return r;
  }
  void set_zero(AJet& y) const {
    y.v = 0.0;
    if (order_ >= 1) y.g.setZero();
    if (order_ >= 2) y.h.setZero();
  }
  // y += c * x.
  void axpy(AJet& y, double c, const AJet& x) const {
    y.v += c * x.v;
    if (order_ >= 1) y.g += c * x.g;
    if (order_ >= 2) y.h += c * x.h;
  }
  // y += z * x where z is variable i with value c (gradient e_i, zero Hessian).
  void add_variable_times(AJet& y, double c, int i, const AJet& x) const {
    y.v += c * x.v;
    if (order_ >= 1) {
      y.g += c * x.g;
      y.g(i) += x.v;
    }
    if (order_ >= 2) {
      y.h += c * x.h;
      y.h.row(i) += x.g.transpose();
      y.h.col(i) += x.g;
    }
  }
  AJet sub(const AJet& a, const AJet& b) const {
    AJet r = a;
    axpy(r, -1.0, b);
    return r;
  }
  AJet mul(const AJet& a, const AJet& b) const {
    AJet r = constant(a.v * b.v);
    if (order_ >= 1) r.g = a.v * b.g + b.v * a.g;
    if (order_ >= 2) r.h = a.v * b.h + b.v * a.h + a.g * b.g.transpose() + b.g * a.g.transpose();
    return r;
  }
  AJet div(const AJet& a, const AJet& b) const {
    AJet q = constant(a.v / b.v);
    if (order_ >= 1) q.g = (a.g - q.v * b.g) / b.v;
    if (order_ >= 2) q.h = (a.h - q.v * b.h - q.g * b.g.transpose() - b.g * q.g.transpose()) / b.v;
    return q;
  }

 private:
  int n_;
  int order_;
};

struct ArmaSetup {
  std::vector<AJet> phi;  // phi_1..phi_p at [0..p-1]
  std::vector<AJet> r;    // r_0..r_q
  AJet u;                 // gamma(0) (1 - sum phi)
  AJet gamma0;
  std::vector<AJet> v;      // v(0..p), v(0) = 0
  std::vector<AJet> gamma;  // gamma(0..p)
};

ArmaSetup solve_setup(const JetOps& ops, std::span<const double> phi, std::span<const double> theta) {
  const int p = static_cast<int>(phi.size()), q = static_cast<int>(theta.size());
  ArmaSetup s;
  std::vector<AJet> th{ops.constant(1.0)};  // theta_0 = 1
  for (int i = 0; i < p; ++i) s.phi.push_back(ops.variable(phi[static_cast<std::size_t>(i)], i));
  for (int j = 0; j < q; ++j) th.push_back(ops.variable(theta[static_cast<std::size_t>(j)], p + j));

  std::vector<AJet> psi{ops.constant(1.0)};
  for (int j = 1; j <= q; ++j) {
    AJet x = th[static_cast<std::size_t>(j)];
    for (int i = 1; i <= std::min(j, p); ++i)
      ops.add_variable_times(x, phi[static_cast<std::size_t>(i - 1)], i - 1, psi[static_cast<std::size_t>(j - i)]);
    psi.push_back(x);
  }
  for (int k = 0; k <= q; ++k) {
    AJet x = ops.constant(0.0);
    for (int j = k; j <= q; ++j) {
      const AJet t = ops.mul(th[static_cast<std::size_t>(j)], psi[static_cast<std::size_t>(j - k)]);
      ops.axpy(x, 1.0, t);
    }
    s.r.push_back(x);
  }

  // Unknowns z = (u, v_1..v_p); row 0: u + sum_i phi_i v_i = r_0;
  // row k >= 1: u - v_k + sum_{i != k} phi_i v_|k-i| = r_k.
  const int n = p + 1;
  std::vector<std::vector<AJet>> a(static_cast<std::size_t>(n),
                                   std::vector<AJet>(static_cast<std::size_t>(n), ops.constant(0.0)));
  std::vector<AJet> b;
  auto at = [&](int row, int col) -> AJet& { return a[static_cast<std::size_t>(row)][static_cast<std::size_t>(col)]; };
  for (int k = 0; k < n; ++k) {
    at(k, 0) = ops.constant(1.0);
    if (k >= 1) at(k, k).v -= 1.0;
    for (int i = 1; i <= p; ++i) {
      const int c = k == 0 ? i : std::abs(k - i);
      if (c == 0) continue;
      ops.axpy(at(k, c), 1.0, s.phi[static_cast<std::size_t>(i - 1)]);
    }
    b.push_back(k <= q ? s.r[static_cast<std::size_t>(k)] : ops.constant(0.0));
  }
  // Gaussian elimination with partial pivoting (on values), in jet arithmetic.
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(at(r, c).v) > std::fabs(at(piv, c).v)) piv = r;
    std::swap(a[static_cast<std::size_t>(c)], a[static_cast<std::size_t>(piv)]);
    std::swap(b[static_cast<std::size_t>(c)], b[static_cast<std::size_t>(piv)]);
    for (int r = c + 1; r < n; ++r) {
      const AJet f = ops.div(at(r, c), at(c, c));
      for (int j = c + 1; j < n; ++j) at(r, j) = ops.sub(at(r, j), ops.mul(f, at(c, j)));
      b[static_cast<std::size_t>(r)] =
          ops.sub(b[static_cast<std::size_t>(r)], ops.mul(f, b[static_cast<std::size_t>(c)]));
    }
  }
  std::vector<AJet> z(static_cast<std::size_t>(n));
  for (int c = n - 1; c >= 0; --c) {
    AJet x = b[static_cast<std::size_t>(c)];
    for (int j = c + 1; j < n; ++j) x = ops.sub(x, ops.mul(at(c, j), z[static_cast<std::size_t>(j)]));
    z[static_cast<std::size_t>(c)] = ops.div(x, at(c, c));
  }
  s.u = z[0];
  AJet phi_at_one = ops.constant(1.0);  // 1 - sum phi_i
  for (const AJet& f : s.phi) ops.axpy(phi_at_one, -1.0, f);
  s.gamma0 = ops.div(s.u, phi_at_one);
  s.v.push_back(ops.constant(0.0));
  s.gamma.push_back(s.gamma0);
  for (int c = 1; c <= p; ++c) {
    s.v.push_back(z[static_cast<std::size_t>(c)]);
    s.gamma.push_back(ops.sub(s.gamma0, z[static_cast<std::size_t>(c)]));
  }
  return s;
}

}  // namespace

int first_unstable_reflection(std::span<const double> a) {
  std::vector<double> c(a.begin(), a.end());
  for (std::size_t k = c.size(); k >= 1; --k) {
    const double r = c[k - 1];
    if (!(std::fabs(r) < 1.0)) return static_cast<int>(k);
    std::vector<double> next(k - 1);
    for (std::size_t i = 1; i < k; ++i) next[i - 1] = (c[i - 1] + r * c[k - i - 1]) / (1.0 - r * r);
    c = std::move(next);
  }
  return 0;
}

std::vector<ArmaJet> arma_unit_wv(std::span<const double> phi, std::span<const double> theta,
                                  std::span<const double> tau, int order) {
  const int p = static_cast<int>(phi.size()), q = static_cast<int>(theta.size());
  const JetOps ops(p + q, order);
  const ArmaSetup s = solve_setup(ops, phi, theta);

  // Levels by decreasing m: those with 2m - 1 >= k are a prefix.
  std::vector<double> m(tau.size());
  for (std::size_t l = 0; l < tau.size(); ++l) m[l] = haar_whole_half_scale(tau[l], "ARMA::wv");
  std::vector<std::size_t> idx(tau.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::sort(idx.begin(), idx.end(), [&](std::size_t x, std::size_t y) { return m[x] > m[y]; });
  std::vector<AJet> acc_v(tau.size(), ops.constant(0.0)), acc_g(tau.size(), ops.constant(0.0));
  std::vector<double> abs_v(tau.size(), 0.0), abs_g(tau.size(), 0.0);

  const long kmax = tau.empty() ? 0 : static_cast<long>(2.0 * m[idx[0]]) - 1;
  const std::size_t ring = static_cast<std::size_t>(std::max(p, 1));
  std::vector<AJet> ring_v(ring, ops.constant(0.0)), ring_g(ring, ops.constant(0.0));
  AJet cur_v = ops.constant(0.0), cur_g = ops.constant(0.0);
  std::size_t active = tau.size();
  for (long k = 1; k <= kmax; ++k) {
    if (k <= p) {
      cur_v = s.v[static_cast<std::size_t>(k)];
      cur_g = s.gamma[static_cast<std::size_t>(k)];
    } else {
      cur_v = s.u;
      ops.set_zero(cur_g);
      if (k <= q) {
        ops.axpy(cur_v, -1.0, s.r[static_cast<std::size_t>(k)]);
        ops.axpy(cur_g, 1.0, s.r[static_cast<std::size_t>(k)]);
      }
      for (int i = 1; i <= p; ++i) {
        const std::size_t slot = static_cast<std::size_t>(k - i) % ring;
        ops.add_variable_times(cur_v, phi[static_cast<std::size_t>(i - 1)], i - 1, ring_v[slot]);
        ops.add_variable_times(cur_g, phi[static_cast<std::size_t>(i - 1)], i - 1, ring_g[slot]);
      }
    }
    if (p > 0) {
      ring_v[static_cast<std::size_t>(k) % ring] = cur_v;
      ring_g[static_cast<std::size_t>(k) % ring] = cur_g;
    }
    while (active > 0 && 2.0 * m[idx[active - 1]] - 1.0 < static_cast<double>(k)) --active;
    for (std::size_t a = 0; a < active; ++a) {
      const std::size_t l = idx[a];
      const double kk = static_cast<double>(k);
      const double w = kk < m[l] ? 3.0 * kk - 2.0 * m[l] : 2.0 * m[l] - kk;
      ops.axpy(acc_v[l], w, cur_v);
      ops.axpy(acc_g[l], w, cur_g);
      abs_v[l] += std::fabs(w * cur_v.v);
      abs_g[l] += std::fabs(w * cur_g.v);
    }
  }

  std::vector<ArmaJet> out(tau.size());
  for (std::size_t l = 0; l < tau.size(); ++l) {
    const double scale = 2.0 / (tau[l] * tau[l]);
    AJet r = ops.constant(0.0);
    if (abs_v[l] <= abs_g[l] + m[l] * std::fabs(s.gamma0.v)) {
      ops.axpy(r, scale, acc_v[l]);
    } else {
      ops.axpy(r, scale * m[l], s.gamma0);
      ops.axpy(r, -scale, acc_g[l]);
    }
    out[l] = std::move(r);
  }
  return out;
}

void arma_unit_autocovariance(std::span<const double> phi, std::span<const double> theta, std::span<double> out) {
  if (out.empty()) return;
  const std::size_t p = phi.size(), q = theta.size();
  const ArmaSetup s = solve_setup(JetOps(static_cast<int>(p + q), 0), phi, theta);
  for (std::size_t h = 0; h < out.size(); ++h) {
    if (h <= p) {
      out[h] = s.gamma[h].v;
      continue;
    }
    double x = h <= q ? s.r[h].v : 0.0;
    for (std::size_t i = 1; i <= p; ++i) x += phi[i - 1] * out[h - i];
    out[h] = x;
  }
}

std::vector<double> arma_psi_weights(std::span<const double> phi, std::span<const double> theta, std::size_t count) {
  std::vector<double> psi;
  for (std::size_t j = 0; j < count; ++j) {
    double x = j == 0 ? 1.0 : (j <= theta.size() ? theta[j - 1] : 0.0);
    for (std::size_t i = 1; i <= std::min(j, phi.size()); ++i) x += phi[i - 1] * psi[j - i];
    psi.push_back(x);
  }
  return psi;
}

}  // namespace gmwm::internal
