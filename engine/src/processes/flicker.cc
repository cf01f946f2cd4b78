// FLICKER: 1/f ("bias instability") noise as a sum of AR1 processes, one per octave of
// correlation time T_k = 2^k samples for k = kmin..kmax, each with stationary variance
// B2 ln2 / pi (docs/statistics.md section 3). Summed over octaves the AR1 spectra give
// S(f) ~ (B2 ln2 / pi) / (2 ln2 f) = B2 / (2 pi f): a flat WV ("plateau") of B2 ln2 / pi at
// scales well inside the octave range, rolling off below 2^kmin and above 2^kmax samples.
// B2 is the squared bias-instability coefficient of the 0.664 convention: the Allan
// deviation floor is B sqrt(2 ln2 / pi) = 0.664 B, i.e. AVAR = 2 WV = 2 B2 ln2 / pi.
//
// The WV is linear in B2; each octave's AR1 WV goes through the stable closed form of
// ar1_math.h with phi_k = exp(-L_k), L_k = 2^-k, so octaves far beyond the record
// (phi within 1e-12 of 1) cost no accuracy.
//
// Structural arguments: FLICKER(kmin=0,kmax=40) by default (written only when they differ):
// the octaves start at one sample (below every Haar scale) and end at 2^40 samples
// (beyond any record: an octave with T >> tau adds ~ s tau / (6 T), so the terms beyond
// the record sum to a fraction ~ tau / T_max of the plateau).
#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <sstream>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include <boost/math/constants/constants.hpp>
#include <boost/random/normal_distribution.hpp>

#include "ar1_math.h"
#include "flicker_simulation.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/process_registry.h"
#include "process_util.h"

namespace gmwm {
namespace {

/// Default octave range (see the file comment).
constexpr long kFlickerDefaultKmin = 0;
constexpr long kFlickerDefaultKmax = 40;
/// Octaves beyond 2^62 samples would overflow the exponent arithmetic of the structure;
/// no record comes close.
constexpr long kFlickerMaxK = 62;

class Flicker final : public Process {
 public:
  explicit Flicker(const ProcessArgs& args) {
    if (auto it = args.structural.find("kmin"); it != args.structural.end()) kmin_ = it->second;
    if (auto it = args.structural.find("kmax"); it != args.structural.end()) kmax_ = it->second;
    if (kmin_ < 0 || kmax_ > kFlickerMaxK || kmin_ > kmax_) {
      std::ostringstream os;
      os << "FLICKER: the octave range must satisfy 0 <= kmin <= kmax <= " << kFlickerMaxK << " (got kmin=" << kmin_
         << ", kmax=" << kmax_ << ")";
      throw InputError(os.str());
    }
    // The unit WV at the dyadic scales, once: fits evaluate it at every iteration, and
    // each value sums kmax - kmin + 1 stable AR1 closed forms.
    for (int j = 1; j < kDyadicTable; ++j) dyadic_[static_cast<std::size_t>(j)] = compute_unit_wv(std::ldexp(1.0, j));
  }
  std::string name() const override { return "FLICKER"; }
  ProcessRole role() const override { return ProcessRole::kFlicker; }
  std::string structure() const override {
    if (kmin_ == kFlickerDefaultKmin && kmax_ == kFlickerDefaultKmax) return {};
    return "kmin=" + std::to_string(kmin_) + ",kmax=" + std::to_string(kmax_);
  }
  int canonical_rank() const override { return 100; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{
        {"B2", Transform::kLog, "squared bias-instability coefficient (WV plateau B2 ln2 / pi)"}};
    return specs;
  }
  bool linear() const override { return true; }

  /// The WV per unit B2 at scale tau (from the table at dyadic scales).
  double unit_wv(double tau) const {
    int e = 0;
    if (std::frexp(tau, &e) == 0.5 && e - 1 >= 1 && e - 1 < kDyadicTable)
      return dyadic_[static_cast<std::size_t>(e - 1)];
    return compute_unit_wv(tau);
  }
  double compute_unit_wv(double tau) const {
    const double m = 0.5 * tau;
    double sum = 0.0;
    for (long k = kmin_; k <= kmax_; ++k) {
      const double L = std::ldexp(1.0, static_cast<int>(-k));
      // AR1 with stationary variance 1: innovation variance 1 - phi^2 = -expm1(-2L).
      sum += -std::expm1(-2.0 * L) * internal::ar1_unit_wv_log(L, m);
    }
    return kStationaryPerB2 * sum;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[0] * unit_wv(tau[k]);
  }
  void wv_jacobian(std::span<const double>, std::span<const double> tau,
                   Eigen::Ref<Eigen::MatrixXd> jac) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) jac(static_cast<Eigen::Index>(k), 0) = unit_wv(tau[k]);
  }
  void wv_hessian(std::span<const double>, std::span<const double>, Eigen::Ref<Eigen::MatrixXd> hess) const override {
    hess.setZero();
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    // Sum of the octaves' autocovariances s phi_k^h, s = B2 ln2 / pi.
    const double s = theta[0] * kStationaryPerB2;
    for (double& v : out) v = 0.0;
    for (long k = kmin_; k <= kmax_; ++k) {
      const double phi = std::exp(-std::ldexp(1.0, static_cast<int>(-k)));
      double c = s;
      for (double& v : out) {
        v += c;
        c *= phi;
      }
    }
  }
  // Exact in law (flicker_simulation.h): the block bridge, its constants once per process.
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    if (out.empty()) return;
    const double s = theta[0] * kStationaryPerB2;
    std::call_once(bridge_once_, [this] { bridge_ = internal::make_flicker_bridge(kmin_, kmax_); });
    if (bridge_.usable()) return internal::simulate_flicker_bridge(bridge_, s, rng, out);
    internal::simulate_flicker_octaves(kmin_, kmax_, s, rng, out);
  }
  // Scale-free: B2 is the same per sample or per second. The WV plateau B2 ln2 / pi gives
  // the Allan variance floor 2 B2 ln2 / pi (AVAR = 2 WV), i.e. the Allan deviation floor
  // sqrt(2 ln2 / pi) B = 0.6643 B, the IEEE 952 value for a flicker PSD B^2 / (2 pi F).
  std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const override {
    KalmanTerm k = Process::kalman_impl(theta, freq, filter_rate).front();
    k.role = "flicker (1/f): no finite state";
    k.note =
        "approximate it with 2-3 Gauss-Markov states over the band the filter cares about "
        "(fit AR1 terms in its place, e.g. gmwm select with 3*AR1)";
    return {k};
  }
  // Navigation-error analysis: one Gauss-Markov state per kOctavesPerState octaves, at the
  // group's geometric-mean correlation time with the group's variance. Octaves spaced 2x
  // sum to 1/f; spaced 8x the sum's spectrum stays within 0.966-1.040 of it over the
  // range (4x: 0.997-1.004 with twice the states; 16x: 0.889-1.121), 14 states per axis
  // for the default 41 octaves.
  std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const override {
    constexpr long kOctavesPerState = 3;
    ContinuousForm out;
    const long groups = (kmax_ - kmin_) / kOctavesPerState + 1;
    out.F = Eigen::MatrixXd::Zero(groups, groups);
    out.Qc = Eigen::MatrixXd::Zero(groups, groups);
    out.P0 = Eigen::MatrixXd::Zero(groups, groups);
    out.H = Eigen::RowVectorXd::Ones(groups);
    for (long g = 0; g < groups; ++g) {
      const long first = kmin_ + g * kOctavesPerState, last = std::min(kmax_, first + kOctavesPerState - 1);
      const double T = std::exp2(0.5 * static_cast<double>(first + last)) / freq;
      const ContinuousForm one =
          gauss_markov_form(T, static_cast<double>(last - first + 1) * theta[0] * kStationaryPerB2, 1.0 / freq);
      out.F(g, g) = one.F(0, 0);
      out.Qc(g, g) = one.Qc(0, 0);
      out.P0(g, g) = one.P0(0, 0);
      out.white += one.white;
    }
    out.notes.push_back("FLICKER as " + std::to_string(groups) + " Gauss-Markov states, one per " +
                        std::to_string(kOctavesPerState) + " octaves of correlation time (its 1/f spectrum within 4%)");
    return out;
  }
  std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double) const override {
    const double b = std::sqrt(theta[0]);
    return {
        {"flicker coefficient", b, "U", "B = sqrt(B2) (flicker PSD B^2 / (2 pi F))", PhysicalKind::kFlickerCoefficient},
        {"bias instability", kAdevFloorPerB * b, "U",
         "bias instability = 0.664 * B (IEEE 952 convention: the Allan deviation floor of "
         "flicker noise, sqrt(2 ln2 / pi) B)",
         PhysicalKind::kBiasInstability}};
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    // The plateau: the median of the WV this component should explain, per unit B2.
    if (ctx.wv.empty()) return {1.0};
    std::vector<double> w(ctx.wv.begin(), ctx.wv.end());
    std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2), w.end());
    return {internal::positive_or(w[w.size() / 2] / kStationaryPerB2, 1.0)};
  }

 private:
  /// Stationary variance of each octave per unit B2: ln2 / pi.
  static constexpr double kStationaryPerB2 = 0.69314718055994530942 / boost::math::constants::pi<double>();
  /// Allan deviation floor per unit B: sqrt(2 ln2 / pi) (IEEE 952's 0.664).
  static constexpr double kAdevFloorPerB = 0.6642824702679601;
  static constexpr int kDyadicTable = 63;  ///< tau = 2^1 .. 2^62
  long kmin_ = kFlickerDefaultKmin;
  long kmax_ = kFlickerDefaultKmax;
  std::array<double, kDyadicTable> dyadic_{};
  mutable std::once_flag bridge_once_;
  mutable internal::FlickerBridge bridge_;
};

}  // namespace

GMWM_REGISTER_PROCESS(Flicker, "FLICKER",
                      "1/f noise as one AR1 per octave: FLICKER(B2), plateau B2 ln2/pi; FLICKER(kmin=..,kmax=..) "
                      "sets the octaves 2^kmin..2^kmax samples",
                      "kmin", "kmax");

namespace internal {

void simulate_flicker_octaves(long kmin, long kmax, double s, Rng& rng, std::span<double> out) {
  for (long k = kmin; k <= kmax; ++k) {
    const double L = std::ldexp(1.0, static_cast<int>(-k));
    const double phi = std::exp(-L);
    const double sd = std::sqrt(-s * std::expm1(-2.0 * L));  // innovation sd
    simulate_ar1_path(phi, sd, std::sqrt(s), rng, out);      // stationary start
  }
}

FlickerBridge make_flicker_bridge(long kmin, long kmax, int block) {
  const auto K = static_cast<Eigen::Index>(kmax - kmin + 1);
  const int D = block;
  FlickerBridge b;
  b.decay.resize(K), b.step_sd.resize(K), b.phi.resize(K), b.sd.resize(K);
  b.ends.resize(D - 1, 2 * K);
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(D - 1, D - 1);
  for (Eigen::Index k = 0; k < K; ++k) {
    const double L = std::ldexp(1.0, -static_cast<int>(kmin + k));
    const auto pw = [L](double m) { return std::exp(-m * L); };            // phi^m
    const auto one_minus = [L](double m) { return -std::expm1(-m * L); };  // 1 - phi^m
    b.phi(k) = pw(1.0), b.sd(k) = std::sqrt(one_minus(2.0));
    b.decay(k) = pw(D), b.step_sd(k) = std::sqrt(one_minus(2.0 * D));
    const double whole = one_minus(2.0 * D);
    for (int t = 1; t < D; ++t) {
      b.ends(t - 1, k) = pw(t) * one_minus(2.0 * (D - t)) / whole;
      b.ends(t - 1, K + k) = pw(D - t) * one_minus(2.0 * t) / whole;
      for (int j = t; j < D; ++j)
        cov(j - 1, t - 1) += pw(j - t) * one_minus(2.0 * t) * one_minus(2.0 * (D - j)) / whole;
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(cov.selfadjointView<Eigen::Lower>());
  if (llt.info() != Eigen::Success) return {};
  b.chol = llt.matrixL();
  // The mean map in factored form: ends = U S V', kept to the singular values above
  // kBridgeRankTolerance of the largest (the octaves slower than a block have nearly
  // linear a_k, b_k: 18 of 82 at the default octaves and blocks; the next is 1.5e-17 of the
  // largest, the matrix's own rounding), so the mean costs r (2K + D - 1) multiply-adds a
  // block instead of 2K (D - 1).
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(b.ends, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  Eigen::Index r = 0;
  while (r < sv.size() && sv(r) > kBridgeRankTolerance * sv(0)) ++r;
  b.mean_from = svd.matrixU().leftCols(r) * sv.head(r).asDiagonal();
  b.mean_of = svd.matrixV().leftCols(r).transpose();
  b.block = D;
  return b;
}

void simulate_flicker_bridge(const FlickerBridge& b, double s, Rng& rng, std::span<double> out) {
  const Eigen::Index K = b.decay.size();
  const int D = b.block;
  const double scale = std::sqrt(s);
  // Blocks go in batches of kFlickerBatch: their draws are taken in the order of the
  // block-by-block recursion (each block's K start and K end states, then its D - 1
  // interior normals), then matrix-matrix products give every interior of the batch: the
  // mean through the factored map (its r coordinates of the states, then the D - 1 values)
  // and the triangular Cholesky factor times the normals. Block by block these were a
  // 63 x 82 and a 63 x 63 triangular matrix-vector product, 35% of a datasheet gap run's
  // CPU (issue 44).
  const Eigen::Index rows = 2 * K + (D - 1);
  thread_local Eigen::MatrixXd draws, interior, coords;
  draws.resize(rows, kFlickerBatch);
  // Every normal_distribution<double>(0, 1) draw below is scaled_normal(unit, 1.0) of
  // Rng::unit_normals' draws, taken in the same order.
  Eigen::VectorXd start(K);
  rng.unit_normals(start.data(), static_cast<std::size_t>(K));
  for (Eigen::Index k = 0; k < K; ++k) start(k) = scaled_normal(start(k), 1.0);  // stationary start
  thread_local std::vector<double> unit;
  unit.resize(static_cast<std::size_t>(K + D - 1));
  out[0] += scale * start.sum();
  const std::size_t n = out.size();
  std::size_t t = 0;
  while (t + static_cast<std::size_t>(D) < n) {
    // The blocks of this batch: whole blocks [t, t + D] while t + D < n.
    const std::size_t left = (n - 1 - t) / static_cast<std::size_t>(D);
    const auto nb = static_cast<Eigen::Index>(std::min<std::size_t>(left, static_cast<std::size_t>(kFlickerBatch)));
    for (Eigen::Index c = 0; c < nb; ++c) {
      double* col = draws.col(c).data();
      const double* from = c == 0 ? start.data() : draws.col(c - 1).data() + K;
      rng.unit_normals(unit.data(), unit.size());  // the block's K end draws, then its D - 1 interior ones
      for (Eigen::Index k = 0; k < K; ++k) {
        col[k] = from[k];
        col[K + k] = b.decay(k) * from[k] + b.step_sd(k) * scaled_normal(unit[static_cast<std::size_t>(k)], 1.0);
      }
      for (int i = 0; i < D - 1; ++i) col[2 * K + i] = scaled_normal(unit[static_cast<std::size_t>(K + i)], 1.0);
    }
    coords.noalias() = b.mean_of * draws.topLeftCorner(2 * K, nb);
    interior.noalias() = b.mean_from * coords;
    interior.noalias() += b.chol.triangularView<Eigen::Lower>() * draws.bottomLeftCorner(D - 1, nb);
    for (Eigen::Index c = 0; c < nb; ++c) {
      const std::size_t base = t + static_cast<std::size_t>(c) * static_cast<std::size_t>(D);
      const double* in = interior.col(c).data();
      for (int i = 0; i < D - 1; ++i) out[base + 1 + static_cast<std::size_t>(i)] += scale * in[i];
      out[base + static_cast<std::size_t>(D)] += scale * draws.col(c).segment(K, K).sum();
    }
    start = draws.col(nb - 1).segment(K, K);
    t += static_cast<std::size_t>(nb) * static_cast<std::size_t>(D);
  }
  // The samples after the last whole block: the recursion from the states there.
  for (Eigen::Index k = 0; k < K; ++k) {
    double x = start(k);
    const double phi = b.phi(k), sd = b.sd(k);
    if (t + 1 < n)
      for_unit_normals(rng, n - t - 1, [&](const double* z, std::size_t u0, std::size_t m) {
        double y = x;  // a local: a captured one might alias out[]
        double* o = out.data() + t + 1 + u0;
        for (std::size_t i = 0; i < m; ++i) {
          y = phi * y + sd * scaled_normal(z[i], 1.0);
          o[i] += scale * y;
        }
        x = y;
      });
  }
}

}  // namespace internal

}  // namespace gmwm
