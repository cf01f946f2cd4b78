#pragma once
// A latent process of a GMWM model (WN, QN, RW, DR, AR1, GM, MA1, ARMA11, ARMA(p,q),
// SIN, ...). Each process is a type deriving from Process, defined in one file under
// engine/src/processes/ together with its registration (GMWM_REGISTER_PROCESS), so
// adding a process touches that file plus its test.
//
// Parameters are the natural, discrete (per-sample) ones of docs/design.md section 2 ("natural space").
// Optimisers work in an unconstrained space obtained parameter by parameter through the
// Transform of each ParameterSpec.
//
// Scales are given as tau = 2^j in samples (doubles, so that the formulas read as in
// docs/statistics.md section 3); wv() takes any tau >= 2 (an averaging time of tau / 2
// samples, whole or not) unless needs_whole_scales().

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/kalman.h"
#include "gmwm/engine/physical.h"
#include "gmwm/engine/random.h"

namespace gmwm {

/// Bounds of the unconstrained parameters the optimiser keeps to. atanh: 1 - tanh(u) =
/// 2 / (e^{2u} + 1), so u = 17.6 allows |phi| up to 1 - 1e-15 (nine units in the last
/// place of 1). There an AR1's WV equals RW(gamma2 = sigma2)'s to 2e-10 relative at
/// tau = 2^19 (and MA1's with theta -> -1 QN's), so a model with an AR1 slot reaches a
/// random walk's fit to within 1e-9 of its objective, as representation requires
/// (model_relations.h); the AR1 formulas are evaluated through L = -ln(phi) and stay
/// exact there (ar1_math.h; 1 - 1e-9 left 2.6e-8 of the objective on the table on real
/// data). log: e^{+-100} covers any physical variance; logit(2f): f in
/// (0.5 e^-30, 0.5 (1 - e^-30)).
constexpr double kAtanhBound = 17.6;
constexpr double kLogBound = 100.0;
constexpr double kLogitBound = 30.0;
constexpr double kIdentityBound = 1e6;

/// Map from a parameter's natural domain to the real line.
enum class Transform {
  kLog,        ///< (0, inf):   u = log(x)
  kAtanh,      ///< (-1, 1):    u = atanh(x)
  kIdentity,   ///< (-inf, inf): u = x
  kLogitHalf,  ///< (0, 1/2):   u = logit(2x)   (frequencies in cycles/sample)
};

/// Natural value -> unconstrained value.
double to_unconstrained(Transform t, double x);
/// Unconstrained value -> natural value.
double from_unconstrained(Transform t, double u);
/// d natural / d unconstrained, evaluated at unconstrained value u.
double dnatural_du(Transform t, double u);
/// d^2 natural / d unconstrained^2 at u.
double d2natural_du2(Transform t, double u);

struct ParameterSpec {
  std::string name;     ///< as in the model syntax, e.g. "sigma2", "phi"
  Transform transform;  ///< domain of the natural parameter
  std::string meaning;  ///< one line for help texts and reports
  /// The model depends on the parameter through its magnitude only (DR's omega: the WV
  /// sees omega^2). Its value may be negative; the optimiser works on |x| (the transform
  /// applies to |x|) and the sign is carried from the starting value, or set from the
  /// time domain (orient_by_series in fit.h).
  bool signed_magnitude = false;
};

/// What a process may need to know about the signal it models.
struct ProcessContext {
  double freq = 1.0;        ///< sampling rate in Hz (1 when unknown)
  bool freq_known = false;  ///< whether freq came from the data or --freq
};

/// Information for a starting-value guess (see Process::initial_guess).
struct GuessContext {
  std::span<const double> tau;  ///< scales in samples
  std::span<const double> wv;   ///< the part of the empirical WV this component should explain
  double tau_hint = 0.0;        ///< scale where this component should dominate (AR1: its peak)
};

/// Mean and variance of the sum x_1 + ... + x_K of K consecutive samples (see
/// Process::sum_moments).
struct SumMoments {
  double mean = 0.0;
  double variance = 0.0;
};

/// A component as a continuous-time linear Gauss-Markov model, for navigation-error
/// analysis (nav/): states x with dx/dt = F x + w, w white with power spectral density Qc
/// (states' units^2 / Hz), x(0) ~ N(0, P0); the component's value y = H x + v, v white of
/// density `white` (U^2/Hz), independent of w. A WN is v alone; a RW one state (F = 0,
/// Qc = K^2); an AR1 or GM a first-order Gauss-Markov state (F = -1/T, Qc = 2 s2 / T,
/// P0 = s2); a DR a rate ramp of random sign (x = [value, slope], P0 = diag(0, R^2)).
/// Everything in the data's unit U and in seconds, from theta at the sampling rate.
struct ContinuousForm {
  Eigen::MatrixXd F, Qc, P0;  ///< n x n (n may be 0)
  Eigen::RowVectorXd H;       ///< 1 x n
  double white = 0.0;         ///< density of the white part of y, U^2/Hz
  /// Bounded errors the form leaves out, one sentence each (QN: the rounding of the
  /// integrated output, which never accumulates).
  std::vector<std::string> notes;
  int states() const { return static_cast<int>(F.rows()); }
};

/// A form without states: a white part of density `white` alone (WN; QN with 0 and a note).
ContinuousForm stateless_form(double white);

/// A first-order Gauss-Markov state of correlation time T (s) and stationary variance s2:
/// F = -1/T, Qc = 2 s2 / T, P0 = s2, H = 1 (AR1 and GM's continuous form), sampled every
/// dt seconds. What a navigation system integrates is the samples (dt sum x_k), whose
/// variance grows at s2 dt coth(L / 2) per second (L = dt / T) where the continuous
/// state's integral grows at 2 s2 T = s2 dt (2 / L): the form adds the difference as a white
/// part, s2 dt (coth(L / 2) - 2 / L) >= 0 (coth x >= 1 / x), so that the integral's growth
/// is the samples' (21% more for an AR1 with phi = 0.16; L^2 / 12 relative for a slow one).
ContinuousForm gauss_markov_form(double T, double s2, double dt);

/// What a process stands for in a sensor's error budget (the terms of IEEE Std 952-1997,
/// annex C, and of the simulators' configs), asked of the process by every module that
/// explains a model (gap's candidates, nav's filter, the simulator conversions) instead of
/// testing its name. Listed with its name once (to_string below).
enum class ProcessRole {
  kWhite,         ///< white noise: angle / velocity random walk (WN)
  kQuantization,  ///< quantization noise (QN)
  kWalk,          ///< random walk of the rate: rate random walk (RW)
  kDrift,         ///< a deterministic rate ramp (DR)
  kBias,          ///< a correlated bias with a correlation time: Gauss-Markov (AR1, GM)
  kFlicker,       ///< 1/f noise: bias instability's flicker floor (FLICKER)
  kPeriodic,      ///< a sinusoid (SIN)
  kOther,         ///< no standard sensor-error meaning (MA1, ARMA11, ARMA)
};
/// "white", "quantization", "walk", "drift", "bias", "flicker", "periodic", "other".
const char* to_string(ProcessRole r);
/// True for the roles of which a model needs one component at most, because two of them sum
/// to one of the same role and shape (WN, QN, RW: their sizes add; DR: the slopes add):
/// white, quantization, walk, drift.
bool single_per_model(ProcessRole r);

class Process;
using ProcessPtr = std::shared_ptr<const Process>;

/// A simpler process that may stand for one component (Process::simpler_forms).
struct SimplerForm {
  ProcessPtr process;         ///< e.g. WN for an AR1 with phi near 0
  std::vector<double> theta;  ///< its parameters reproducing the component where it can
  std::string label;          ///< how the component reads then: "WN-like", "RW-like"
};

class Process {
 public:
  virtual ~Process() = default;

  /// Name as written in model strings, without structural arguments ("AR1", "ARMA").
  virtual std::string name() const = 0;
  /// Structural arguments as written in model strings, e.g. "p=2,q=1" for ARMA; empty
  /// for most processes.
  virtual std::string structure() const { return {}; }
  /// Position in canonical model strings (docs/cli.md: AR1, GM, MA1, ARMA11, ARMA, WN, QN, RW,
  /// DR, SIN, FLICKER): smaller comes first.
  virtual int canonical_rank() const = 0;
  /// Parameters in the order used in theta vectors.
  virtual const std::vector<ParameterSpec>& parameters() const = 0;
  int size() const { return static_cast<int>(parameters().size()); }

  /// The process's part in a sensor's error budget (ProcessRole). Default: kOther.
  virtual ProcessRole role() const { return ProcessRole::kOther; }
  /// The correlation time in samples of a correlated bias (role kBias) at theta: AR1
  /// -1 / ln(phi) for 0 < phi < 1, GM f / beta; nullopt for other roles and for values
  /// without one (an AR1 with phi <= 0 or phi >= 1). Default: nullopt.
  virtual std::optional<double> correlation_samples(std::span<const double> theta) const {
    (void)theta;
    return std::nullopt;
  }

  /// True when the process contributes no randomness (DR). Its Haar coefficients are then
  /// the constant deterministic_coefficient(theta, tau), which enters the covariance of
  /// the empirical WV through its products with the stochastic coefficients.
  virtual bool deterministic() const { return false; }
  /// The Haar MODWT coefficient of a deterministic process at scale tau, the same at
  /// every time (DR: omega tau / 4, the sign fixed by the filter's orientation: recent
  /// half minus older half). Zero for stochastic processes.
  virtual double deterministic_coefficient(std::span<const double> theta, double tau) const {
    (void)theta;
    (void)tau;
    return 0.0;
  }
  /// True when the WV is linear in every parameter (WN, QN, RW): used by optimism checks.
  virtual bool linear() const { return false; }
  /// True when wv() takes even whole scales only (a sum over lags: ARMA). The closed forms
  /// of the others are continued in m = tau / 2 between whole numbers (docs/statistics.md
  /// section 3), so that a curve given at any averaging time can be fitted (curve.h).
  virtual bool needs_whole_scales() const { return false; }
  /// Index of the parameter whose order sorts repeated components (AR1: phi), or -1.
  virtual int sort_key() const { return -1; }

  /// Empty when theta is a valid natural parameter vector, else the reason (one line,
  /// naming the parameter), e.g. "sigma2 must be positive (got -1)".
  virtual std::string validate(std::span<const double> theta) const;

  /// Theoretical WV nu^2(tau_k) into out[k].
  virtual void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const = 0;
  /// jac(k, l) = d nu^2(tau_k) / d theta_l (natural parameters). jac is tau.size() x size().
  virtual void wv_jacobian(std::span<const double> theta, std::span<const double> tau,
                           Eigen::Ref<Eigen::MatrixXd> jac) const = 0;
  /// wv and wv_jacobian at one point, with the same values to the bit (test
  /// ProcessRegistry.EveryProcessGivesItsWvAndJacobianTogetherAsItGivesThemApart): what an
  /// optimiser asks at every step. The processes whose derivatives carry the value (Jet)
  /// form both in one pass.
  virtual void wv_and_jacobian(std::span<const double> theta, std::span<const double> tau, std::span<double> out,
                               Eigen::Ref<Eigen::MatrixXd> jac) const {
    wv(theta, tau, out);
    wv_jacobian(theta, tau, jac);
  }
  /// hess(k, l * p + m) = d^2 nu^2(tau_k) / d theta_l d theta_m. hess is tau.size() x p^2.
  virtual void wv_hessian(std::span<const double> theta, std::span<const double> tau,
                          Eigen::Ref<Eigen::MatrixXd> hess) const = 0;

  /// Generalised autocovariance g(h), h = 0..out.size()-1: for any two filters a, b with
  /// zero sum, Cov(sum_k a_k x_{t-k}, sum_l b_l x_{s-l}) = sum_k sum_l a_k b_l g(|t-k-s+l|).
  /// Stationary processes: the autocovariance. RW: -gamma2 |h| / 2 (minus the
  /// semivariogram). Deterministic processes: zeros.
  virtual void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const = 0;

  /// Adds one simulated path of length out.size() to out, drawing only from rng.
  virtual void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const = 0;

  /// A starting value explaining ctx.wv (around ctx.tau_hint when the process has a
  /// characteristic scale). Must return a valid theta.
  virtual std::vector<double> initial_guess(const GuessContext& ctx) const = 0;

  /// Value shown to users for parameter k (SIN's f in Hz when the rate is known); the
  /// inverse is from_display. Default: identity.
  virtual double to_display(int k, double natural) const {
    (void)k;
    return natural;
  }
  virtual double from_display(int k, double shown) const {
    (void)k;
    return shown;
  }

  /// Physical (continuous-time) quantities of theta at the sampling rate freq in Hz, with
  /// unit patterns in the data unit "U" (physical.h), e.g. WN: noise density
  /// N = sqrt(sigma2 / f) in U/sqrt(Hz). The number and order of the quantities depend on
  /// the process only, never on theta's values. theta is not validated beyond its size:
  /// the formulas are evaluated as they stand, so values on the edge of a domain give the
  /// limits (sigma2 = 0 -> N = 0; phi = 1 -> correlation time inf), which
  /// physical_interval relies on. Processes without a standard physical meaning (MA1,
  /// ARMA11, ARMA) keep the default: the discrete parameters unchanged, unit "", the
  /// convention naming them discrete. Throws InvalidArgument (check.h) for a theta of the
  /// wrong size or a non-positive or non-finite freq.
  std::vector<PhysicalQuantity> physical(std::span<const double> theta, double freq) const;

  /// The component's terms for a Kalman filter running at filter_rate Hz (kalman.h), from
  /// theta at the data's sampling rate freq. Throws InvalidArgument (check.h) for a theta
  /// of the wrong size or a non-positive or non-finite rate.
  std::vector<KalmanTerm> kalman(std::span<const double> theta, double freq, double filter_rate) const;

  /// The component as a continuous-time Gauss-Markov model at sampling rate freq Hz
  /// (ContinuousForm), or nullopt for a process without a finite one (SIN, FLICKER, MA1,
  /// ARMA). Throws InvalidArgument (check.h) for a theta of the wrong size or a
  /// non-positive or non-finite freq.
  std::optional<ContinuousForm> continuous_form(std::span<const double> theta, double freq) const;

  /// For each K in counts (each >= 1), the mean and variance of x_1 + ... + x_K, the K
  /// samples after time 0 of a path whose non-stationary part starts at 0 at time 0 (RW:
  /// x_t = e_1 + ... + e_t, as simulate's samples 0..K-1; DR: x_t = omega t, t = 1..K).
  /// The default is for stationary processes: mean 0 and variance
  /// K g(0) + 2 sum_{h=1}^{K-1} (K - h) g(h) from generalized_autocovariance, O(max K)
  /// time and memory for all counts together. Non-stationary processes (RW, DR) override
  /// it with their closed forms. Used for the integrated error (integrated_error.h).
  virtual std::vector<SumMoments> sum_moments(std::span<const double> theta,
                                              std::span<const std::int64_t> counts) const;

  /// Parameters with which this process reproduces the WV of `other` at `other_theta`,
  /// exactly or in a limit of this process's space taken to the optimiser's bound, or
  /// nullopt when it cannot. The default covers the same process (and structure); a
  /// process that contains others overrides it (AR1: WN at phi = 0, RW as phi -> 1;
  /// MA1: WN, QN; ARMA11: AR1, MA1, WN, QN; GM: WN, RW, AR1). A model represents another
  /// when its components can take the other's components one each, the rest vanishing:
  /// its fit must then never end above the other's (model_relations.h).
  virtual std::optional<std::vector<double>> represent(const Process& other, std::span<const double> other_theta) const;

  /// Simpler processes this component may be indistinguishable from, each with the
  /// parameters that match it where the simpler one can (AR1: WN with its long-run
  /// variance sigma2 / (1 - phi)^2, RW with gamma2 = sigma2). Whether the difference is
  /// visible in the data is decided by the caller (effective_model.h). Default: none.
  virtual std::vector<SimplerForm> simpler_forms(std::span<const double> theta) const;

  /// Parameter vectors (each the size of theta, at theta's size) spanning the shapes this
  /// component's WV can take over the scales tau: the values of the parameters that are
  /// not identified once its size is 0 (an AR1's phi). A test that the component is absent
  /// takes the largest excess over them (effective_model.h; Davies 1987, Hansen 1996).
  /// Default: {theta} (the shape is fixed: WN, QN, RW, DR ...).
  virtual std::vector<std::vector<double>> shape_family(std::span<const double> theta,
                                                        std::span<const double> tau) const;

  /// The parameters of one component of this process equal (or closest) to the sum of
  /// two of them with theta_a and theta_b, or nullopt when sums never merge. Default:
  /// nullopt. WN, QN, RW add their sizes; AR1 merges at a common phi.
  virtual std::optional<std::vector<double>> merged(std::span<const double> a, std::span<const double> b) const;

  /// The parameters of this component for its data multiplied by sqrt(c) (c > 0): its WV
  /// is then c times theta's at every scale. Default: every parameter with a log transform
  /// (a variance: sigma2, gamma2, Q2, A2, B2, sigma2_gm) times c, the others (phi, theta,
  /// f) as they are; a process with a log-transformed parameter that is no variance
  /// overrides it (DR: omega times sqrt(c); GM: beta as it is). What lets a computation
  /// whose answer depends on ratios of the parameters run at the model's unit scale
  /// (record_plan.h); a test holds every registered process to the WV's factor c.
  virtual std::vector<double> scaled(std::span<const double> theta, double c) const;

  const ProcessContext& context() const { return context_; }
  void set_context(const ProcessContext& c) { context_ = c; }

 protected:
  /// The conversion behind physical(), called with a theta of the right size and a
  /// positive freq. Default: the discrete parameters unchanged (see physical()).
  virtual std::vector<PhysicalQuantity> physical_impl(std::span<const double> theta, double freq) const;
  /// The terms behind kalman(), with a checked theta size and positive rates. Default: one
  /// term saying the process has no finite Gauss-Markov form.
  virtual std::vector<KalmanTerm> kalman_impl(std::span<const double> theta, double freq, double filter_rate) const;
  /// The form behind continuous_form(), with a checked theta size and a positive rate.
  /// Default: nullopt (no finite Gauss-Markov form).
  virtual std::optional<ContinuousForm> continuous_form_impl(std::span<const double> theta, double freq) const;

 private:
  ProcessContext context_;
};

/// A registered process by name (as in model strings), with the given context. Throws
/// InputError for an unknown name; for processes with structural arguments use the
/// registry.
ProcessPtr make_process(const std::string& name, const ProcessContext& context);

/// True when a and b are the same process with the same structure.
bool same_process(const Process& a, const Process& b);

}  // namespace gmwm
