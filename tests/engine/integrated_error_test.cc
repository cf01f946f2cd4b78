// Predicted integrated-error growth (engine/include/gmwm/engine/integrated_error.h).
#include "gmwm/engine/integrated_error.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index k = 0;
  for (double d : v) x(k++) = d;
  return x;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "no error";
}

/// Var(x_1 + ... + x_K) of a stationary component by the direct double sum of its
/// autocovariance, sum_t sum_s g(|t - s|).
double direct_sum_variance(const Model& m, const Eigen::VectorXd& theta, int K) {
  const Process& p = *m.components()[0].process;
  std::vector<double> g(static_cast<std::size_t>(K));
  p.generalized_autocovariance({theta.data(), static_cast<std::size_t>(p.size())}, g);
  double v = 0.0;
  for (int t = 0; t < K; ++t)
    for (int s = 0; s < K; ++s) v += g[static_cast<std::size_t>(std::abs(t - s))];
  return v;
}

/// Monte-Carlo variance of S = (1/f) (x_1 + ... + x_K) over `paths` simulated series
/// (mean known to be 0, so the mean of S^2).
double monte_carlo_variance(const Model& m, const Eigen::VectorXd& theta, double freq, int K, int paths,
                            std::uint64_t seed) {
  const auto series = simulate_many(m, theta, K, paths, seed);
  double sum2 = 0.0;
  for (const auto& x : series) {
    double s = 0.0;
    for (double v : x) s += v;
    s /= freq;
    sum2 += s * s;
  }
  return sum2 / paths;
}

TEST(IntegratedError, WhiteNoiseGrowsAsTheSquareRootOfTheSampleCount) {
  // WN sigma2 = 5.7583e-06 (rad/s)^2 (EuRoC ADIS16448 gyro) at 200 Hz, 60 s: K = 12000,
  // sd = sqrt(12000 * 5.7583e-06) / 200 = 1.31434e-3 rad, which is N sqrt(T) with
  // N = 1.6968058e-4 rad/s/sqrt(Hz): 1.6968058e-4 * sqrt(60) = 1.31434e-3.
  const Model m = parse_model("WN");
  const auto e = integrated_error(m, vec({5.7583e-06}), 200.0, 60.0);
  EXPECT_EQ(e.samples, 12000);
  EXPECT_EQ(e.horizon_seconds, 60.0);
  EXPECT_NEAR(e.sd_random, std::sqrt(12000 * 5.7583e-06) / 200.0, 1e-15);
  EXPECT_NEAR(e.sd_random, 1.6968058227151392e-04 * std::sqrt(60.0), 1e-15);
  EXPECT_EQ(e.deterministic, 0.0);
  EXPECT_EQ(e.total_rms, e.sd_random);
  ASSERT_EQ(e.per_component_sd.size(), 1u);
  EXPECT_EQ(e.per_component_sd[0], e.sd_random);
  EXPECT_EQ(integrated_error_sd(m, vec({5.7583e-06}), 200.0, 60.0), e.sd_random);
}

TEST(IntegratedError, RandomWalkFollowsItsClosedFormAndTheContinuousLimit) {
  // gamma2 = K_rw^2 / f with K_rw = 1.9393e-5 rad/s^2/sqrt(Hz) (EuRoC ADIS16448) at 200 Hz:
  // 1.880442e-12. Over 60 s (K = 12000): sqrt(gamma2 K (K+1) (2K+1) / 6) / 200
  // = 5.204013e-3 rad, against the continuous K_rw T^1.5 / sqrt(3) = 5.203688e-3 (they
  // differ by O(1 / K)).
  const double gamma2 = 1.9393e-5 * 1.9393e-5 / 200.0;
  const Model m = parse_model("RW");
  const double sd = integrated_error_sd(m, vec({gamma2}), 200.0, 60.0);
  const double K = 12000.0;
  EXPECT_NEAR(sd, std::sqrt(gamma2 * K * (K + 1) * (2 * K + 1) / 6.0) / 200.0, 1e-15);
  EXPECT_NEAR(sd, 0.005204013183886366, 1e-12);
  EXPECT_NEAR(sd / (1.9393e-5 * std::pow(60.0, 1.5) / std::sqrt(3.0)), 1.0, 1.5 / K);
}

TEST(IntegratedError, RandomWalkMatchesSimulatedPaths) {
  // The walk starts at 0 (simulate's sample 0 already holds one increment, as x_1 here).
  // 2000 paths: the variance estimate's relative sd is sqrt(2 / 2000); tolerance 4 of them.
  const Model m = parse_model("RW");
  const Eigen::VectorXd theta = vec({0.3});
  const double freq = 10.0;
  const int K = 40, paths = 2000;
  const double sd = integrated_error_sd(m, theta, freq, K / freq);
  EXPECT_NEAR(monte_carlo_variance(m, theta, freq, K, paths, 17) / (sd * sd), 1.0, 4.0 * std::sqrt(2.0 / paths));
}

TEST(IntegratedError, Ar1MatchesTheDirectDoubleSum) {
  for (double phi : {0.95, 0.3, -0.7}) {
    const Model m = parse_model("AR1");
    const Eigen::VectorXd theta = vec({phi, 0.2});
    for (int K : {1, 2, 7, 30}) {
      const double sd = integrated_error_sd(m, theta, 4.0, K / 4.0);
      EXPECT_NEAR(sd * sd * 16.0 / direct_sum_variance(m, theta, K), 1.0, 1e-12) << "phi = " << phi << ", K = " << K;
    }
  }
}

TEST(IntegratedError, Ar1MatchesSimulatedPaths) {
  // 2000 paths of AR1(0.95, 1) at 10 Hz over 5 s (K = 50), started from the stationary
  // distribution as simulate does; tolerance 4 Monte-Carlo standard errors of the variance.
  const Model m = parse_model("AR1");
  const Eigen::VectorXd theta = vec({0.95, 1.0});
  const double freq = 10.0;
  const int K = 50, paths = 2000;
  const double sd = integrated_error_sd(m, theta, freq, 5.0);
  EXPECT_NEAR(monte_carlo_variance(m, theta, freq, K, paths, 2024) / (sd * sd), 1.0, 4.0 * std::sqrt(2.0 / paths));
}

TEST(IntegratedError, DriftIsReportedAsADeterministicError) {
  // DR omega = 0.01 per sample at 100 Hz over 1 s (K = 100): omega K (K + 1) / 2 / f
  // = 0.01 * 5050 / 100 = 0.505. With WN(4e-4): sd = sqrt(100 * 4e-4) / 100 = 2e-3,
  // total = sqrt(0.505^2 + 0.002^2) = 0.50500396.
  const Model m = parse_model("WN+DR");
  const auto e = integrated_error(m, vec({4e-4, 0.01}), 100.0, 1.0);
  EXPECT_NEAR(e.deterministic, 0.505, 1e-15);
  EXPECT_NEAR(e.sd_random, 2e-3, 1e-17);
  EXPECT_NEAR(e.total_rms, std::sqrt(0.505 * 0.505 + 4e-6), 1e-15);
  ASSERT_EQ(e.per_component_sd.size(), 2u);
  EXPECT_EQ(e.per_component_sd[1], 0.0);
  EXPECT_NEAR(e.per_component_deterministic[1], 0.505, 1e-15);
  EXPECT_EQ(e.per_component_deterministic[0], 0.0);
}

TEST(IntegratedError, SinusoidMatchesItsClosedForm) {
  // x_t = A sin(w t + U): sum_{t=1}^K x_t = A Im(e^{iU} sum e^{iwt}), so its variance is
  // (A2 / 2) sin^2(K w / 2) / sin^2(w / 2), w = 2 pi f. Over whole periods it vanishes.
  const Model m = parse_model("SIN");
  const double a2 = 2.0, f = 0.0137, freq = 50.0;  // K f = 13.7 periods
  const int K = 1000;
  const double w = 2.0 * std::numbers::pi * f;
  const double expected = 0.5 * a2 * std::pow(std::sin(K * w / 2.0) / std::sin(w / 2.0), 2) / (freq * freq);
  const double sd = integrated_error_sd(m, vec({a2, f}), freq, K / freq);
  EXPECT_NEAR(sd * sd / expected, 1.0, 1e-10);
  EXPECT_NEAR(integrated_error_sd(m, vec({a2, 0.05}), freq, 100 / freq), 0.0, 1e-12);
}

TEST(IntegratedError, QuantizationNoiseStaysBounded) {
  // x_t = sqrt(12 Q2) (U_t - U_{t-1}) telescopes: Var(sum) = 12 Q2 * 2 / 12 = 2 Q2 for any K.
  const Model m = parse_model("QN");
  for (double horizon : {0.01, 1.0, 1000.0})
    EXPECT_NEAR(integrated_error_sd(m, vec({3e-6}), 100.0, horizon), std::sqrt(6e-6) / 100.0, 1e-15);
}

TEST(IntegratedError, FlickerMatchesTheDirectDoubleSum) {
  const Model m = parse_model("FLICKER(kmin=0,kmax=5)");
  const Eigen::VectorXd theta = vec({2e-5});
  for (int K : {1, 9, 64}) {
    const double sd = integrated_error_sd(m, theta, 1.0, K);
    EXPECT_NEAR(sd * sd / direct_sum_variance(m, theta, K), 1.0, 1e-12) << "K = " << K;
  }
}

TEST(IntegratedError, ComponentsAddInVarianceAndHorizonsShareOneCall) {
  // AR1 + WN + RW + FLICKER at 200 Hz: each horizon equals its own call, and the total
  // variance is the sum of the components'. 5000 s is K = 1e6 samples.
  const Model m = parse_model("AR1+WN+RW+FLICKER", {200.0, true});
  const Eigen::VectorXd theta = vec({0.999, 1e-6, 3e-6, 1e-12, 4e-8});
  const std::vector<double> horizons{60.0, 1.0, 5000.0, 0.005};
  const auto all = integrated_error(m, theta, 200.0, horizons);
  ASSERT_EQ(all.size(), horizons.size());
  for (std::size_t h = 0; h < horizons.size(); ++h) {
    const auto one = integrated_error(m, theta, 200.0, horizons[h]);
    EXPECT_EQ(all[h].samples, std::llround(horizons[h] * 200.0));
    EXPECT_DOUBLE_EQ(all[h].sd_random, one.sd_random);
    double v = 0.0;
    for (double s : all[h].per_component_sd) v += s * s;
    EXPECT_NEAR(std::sqrt(v) / all[h].sd_random, 1.0, 1e-14);
    // WN's share is exact: sqrt(K sigma2) / f.
    EXPECT_NEAR(all[h].per_component_sd[1] / (std::sqrt(all[h].samples * 3e-6) / 200.0), 1.0, 1e-13);
  }
  EXPECT_LT(all[1].sd_random, all[0].sd_random);
  EXPECT_LT(all[0].sd_random, all[2].sd_random);
}

TEST(IntegratedError, RejectsBadArgumentsWithCheckMessages) {
  const Model m = parse_model("WN+AR1");
  const Eigen::VectorXd theta = vec({1.0, 0.5, 1.0});
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, 100.0, 0.0); }),
            "integrated_error: horizon_seconds is 0, but must be positive and finite");
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, 100.0, -60.0); }),
            "integrated_error: horizon_seconds is -60, but must be positive and finite");
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, 0.0, 60.0); }),
            "integrated_error: freq is 0, but must be positive and finite");
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, NAN, 60.0); }),
            "integrated_error: freq is nan, but must be positive and finite");
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, 100.0, 0.001); }),
            "integrated_error: horizon_seconds * freq (samples) is 0.10000000000000001, but must be at "
            "least 0.500000");
  EXPECT_EQ(message_of([&] { integrated_error(m, theta, 1000.0, 1e6); }),
            "integrated_error: horizon_seconds * freq (samples) is 1000000000, but must be at most 67108864");
  EXPECT_EQ(message_of([&] {
              integrated_error(m, vec({1.0, 1.5, 1.0}), 100.0, 60.0);
            }),
            "integrated_error: component 2 (AR1): phi must be in (-1, 1) (got 1.5)");
  EXPECT_EQ(message_of([&] {
              integrated_error(m, vec({1.0, 0.5}), 100.0, 60.0);
            }),
            "integrated_error: model takes 3 parameters, got 2");
  const Model gm = parse_model("GM", {100.0, true});
  EXPECT_EQ(message_of([&] {
              integrated_error(gm, vec({1.0, 1.0}), 200.0, 60.0);
            }),
            "integrated_error: freq is 200, but must be the rate component 1 (GM) was built with, 100 Hz");
}

}  // namespace
}  // namespace gmwm
