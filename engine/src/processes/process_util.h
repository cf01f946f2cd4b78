#pragma once
// Helpers shared by the process implementations (internal to engine/src/processes).

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "gmwm/engine/check.h"
#include "gmwm/engine/process.h"
#include "gmwm/engine/random.h"
#include "jet.h"

namespace gmwm::internal {

/// m = tau / 2 for a Haar scale tau >= 2 samples (finite). At even whole tau the closed
/// forms are the WV exactly; between them (an averaging time that is no whole number of
/// samples: a curve digitised from a datasheet, curve.h) they are continued in m, smooth and
/// equal to the exact WV at every whole m (docs/statistics.md section 3). A form that sums
/// over lags takes haar_whole_half_scale.
inline double haar_half_scale(double tau, std::string_view who) {
  check_at_least(who, "tau", tau, 2.0);
  check_finite(who, "tau", tau);
  return 0.5 * tau;
}

/// m = tau / 2 for an even whole tau >= 2: the autocovariance sums (ARMA) need one.
inline double haar_whole_half_scale(double tau, std::string_view who) {
  check_at_least(who, "tau", tau, 2.0);
  // Evenness through an integer below 2^62 (every Haar scale of a record): fmod here was 1%
  // of a selection's CPU (issue 44); above, fmod.
  constexpr double kIntegerReach = 4611686018427387904.0;  // 2^62
  const bool even = tau < kIntegerReach ? (static_cast<double>(static_cast<std::int64_t>(tau)) == tau &&
                                           (static_cast<std::int64_t>(tau) & 1) == 0)
                                        : std::fmod(tau, 2.0) == 0.0;
  if (!even) detail::throw_check(who, "tau", tau, "an even integer");
  return 0.5 * tau;
}

/// The merged parameters of a process whose one parameter is a size that adds up (WN,
/// QN, RW): two components are exactly one with the sizes summed.
inline std::optional<std::vector<double>> summed_size(std::span<const double> a, std::span<const double> b) {
  return std::vector<double>{a[0] + b[0]};
}

/// phi at the optimiser's bound, tanh(kAtanhBound) = 1 - 1e-15: where an AR1 stands for a
/// random walk (its WV differs from RW(sigma2)'s by ~ tau (1 - phi) / 2 relative).
inline double phi_at_bound() { return std::tanh(kAtanhBound); }

/// x when it is finite and positive, else fallback (initial guesses must be valid).
inline double positive_or(double x, double fallback) { return (std::isfinite(x) && x > 0.0) ? x : fallback; }

/// The level a guess should match: the one nearest to ctx.tau_hint on a log scale, or,
/// without a hint, the one where ctx.wv peaks. 0 when ctx is empty.
inline std::size_t guess_level(const GuessContext& ctx) {
  const std::size_t n = std::min(ctx.tau.size(), ctx.wv.size());
  if (n == 0) return 0;
  std::size_t best = 0;
  if (ctx.tau_hint > 0.0) {
    double dist = INFINITY;
    for (std::size_t k = 0; k < n; ++k) {
      const double d = std::fabs(std::log(ctx.tau[k] / ctx.tau_hint));
      if (d < dist) {
        dist = d;
        best = k;
      }
    }
  } else {
    for (std::size_t k = 1; k < n; ++k)
      if (ctx.wv[k] > ctx.wv[best]) best = k;
  }
  return best;
}

/// ctx.tau_hint when given, else the tau of guess_level (else fallback).
inline double guess_tau(const GuessContext& ctx, double fallback) {
  if (ctx.tau_hint > 0.0 && std::isfinite(ctx.tau_hint)) return ctx.tau_hint;
  const std::size_t n = std::min(ctx.tau.size(), ctx.wv.size());
  return n ? ctx.tau[guess_level(ctx)] : fallback;
}

/// The derivatives of a process whose WV is written once over its scalar type (double or
/// Jet), forwarded to Derived::derivatives<J>(theta, tau, jac, hess, value): an optimiser's
/// gradient and the value with it through a first-order Jet, the Hessian through a
/// second-order one. N: the number of parameters. Derive from it instead of Process.
template <class Derived, int N>
class JetDifferentiated : public Process {
 public:
  void wv_jacobian(std::span<const double> theta, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const final {
    self().template derivatives<Jet<N, 1>>(theta, tau, &jac, nullptr);
  }
  void wv_and_jacobian(std::span<const double> theta, std::span<const double> tau, std::span<double> out,
                       Eigen::Ref<Eigen::MatrixXd> jac) const final {
    self().template derivatives<Jet<N, 1>>(theta, tau, &jac, nullptr, &out);
  }
  void wv_hessian(std::span<const double> theta, std::span<const double> tau,
                  Eigen::Ref<Eigen::MatrixXd> hess) const final {
    self().template derivatives<Jet<N>>(theta, tau, nullptr, &hess);
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

/// Writes a Jet's gradient into jac row k and its Hessian into hess row k
/// (hess(k, l * p + m) = d^2 / d theta_l d theta_m), p = N.
/// A Jet without a Hessian (order 1) is only for a call without `hess`.
/// With `value`, its element k receives the Jet's value.
template <int N, int O>
void store_jet_row(const Jet<N, O>& r, Eigen::Index k, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) {
  if (value) (*value)[static_cast<std::size_t>(k)] = r.v;
  for (int l = 0; l < N; ++l) {
    if (jac) (*jac)(k, l) = r.g(l);
    if constexpr (O == 2) {
      if (hess)
        for (int m = 0; m < N; ++m) (*hess)(k, l * N + m) = r.h(l, m);
    } else {
      assert(hess == nullptr);
    }
  }
}

/// An AR1 path: x_0 = start_sd z_0, x_t = phi x_{t-1} + sd z_t, z the
/// normal_distribution<double>(0, 1) draws of the component's stream in order.
struct Ar1Path {
  double phi = 0.0, sd = 0.0, start_sd = 0.0;
};

/// A process whose simulation is one AR1 path from its stream (AR1, GM): simulate() adds
/// consecutive such components' paths in one interleaved pass (simulate_ar1_paths).
class Ar1PathSource {
 public:
  virtual Ar1Path ar1_path(std::span<const double> theta) const = 0;

 protected:
  ~Ar1PathSource() = default;
};

namespace detail {
constexpr std::size_t kAr1Run = 512;  // draws per stream per run: G x 4 KiB, in L1

// G paths over the samples [t, t + m) of a run: each sample's value gets the paths added in
// their order, as G separate passes would add them; the G recursions are independent, so
// they overlap instead of each waiting on its own multiply-add chain.
template <std::size_t G>
void ar1_paths_run(const Ar1Path* p, const double (*z)[kAr1Run], double* state, double* o, std::size_t m, bool first) {
  double s[G];
  for (std::size_t i = 0; i < G; ++i) s[i] = state[i];
  std::size_t k = 0;
  if (first) {
    double v = o[0];
    for (std::size_t i = 0; i < G; ++i) {
      s[i] = p[i].start_sd * scaled_normal(z[i][0], 1.0);
      v += s[i];
    }
    o[0] = v;
    k = 1;
  }
  for (; k < m; ++k) {
    double v = o[k];
    for (std::size_t i = 0; i < G; ++i) {
      s[i] = p[i].phi * s[i] + p[i].sd * scaled_normal(z[i][k], 1.0);
      v += s[i];
    }
    o[k] = v;
  }
  for (std::size_t i = 0; i < G; ++i) state[i] = s[i];
}
}  // namespace detail

/// The AR1 paths of consecutive components added into out, path i drawing from rngs[i]:
/// the values (and each stream's draws) of adding them one at a time in their order,
/// four recursions interleaved at a time. A lone AR1's chain of a multiply and an add per
/// sample was 13% of a bootstrap's CPU (issue 44).
inline void simulate_ar1_paths(std::span<const Ar1Path> paths, std::span<Rng> rngs, std::span<double> out) {
  constexpr std::size_t kInterleaved = 4;
  const std::size_t n = out.size();
  double* o = out.data();
  for (std::size_t g0 = 0; g0 < paths.size(); g0 += kInterleaved) {
    const std::size_t g = std::min(kInterleaved, paths.size() - g0);
    double z[kInterleaved][detail::kAr1Run];
    double state[kInterleaved] = {0.0, 0.0, 0.0, 0.0};
    const Ar1Path* p = paths.data() + g0;
    for (std::size_t t = 0; t < n; t += detail::kAr1Run) {
      const std::size_t m = std::min(detail::kAr1Run, n - t);
      for (std::size_t i = 0; i < g; ++i) rngs[g0 + i].unit_normals(z[i], m);
      switch (g) {
        case 1:
          detail::ar1_paths_run<1>(p, z, state, o + t, m, t == 0);
          break;
        case 2:
          detail::ar1_paths_run<2>(p, z, state, o + t, m, t == 0);
          break;
        case 3:
          detail::ar1_paths_run<3>(p, z, state, o + t, m, t == 0);
          break;
        default:
          detail::ar1_paths_run<4>(p, z, state, o + t, m, t == 0);
          break;
      }
    }
  }
}

/// One AR1 path added into out (AR1, GM, each FLICKER octave).
inline void simulate_ar1_path(double phi, double sd, double start_sd, Rng& rng, std::span<double> out) {
  const Ar1Path path{phi, sd, start_sd};
  simulate_ar1_paths({&path, 1}, {&rng, 1}, out);
}

}  // namespace gmwm::internal
