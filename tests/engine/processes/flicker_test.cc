// FLICKER (engine/src/processes/flicker.cc): 1/f noise as one AR1 per octave.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "../../../engine/src/processes/flicker_simulation.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

constexpr double kLn2OverPi = 0.69314718055994530942 / 3.14159265358979323846;

// Reference: the sum over k = 0..39 of the AR1 closed form (docs/statistics.md section 3) with
// phi = exp(-2^-k) and stationary variance 1, at 50 significant digits (mpmath):
//   from mpmath import mp, mpf, exp; mp.dps = 50
//   ar1 = lambda p, s2, t: s2*((p**2-1)*t + 2*p*(p**t - 4*p**(t/2) + 3))/((p-1)**3*(p+1)*t**2)
//   sum(ar1(exp(-1/mpf(2)**k), 1 - exp(-2/mpf(2)**k), mpf(2)**j) for k in range(40))
TEST(FlickerProcess, MatchesAHighPrecisionSumOfOctaveAr1s) {
  const auto p = make_process("FLICKER", {{"kmin", 0}, {"kmax", 39}});
  const std::vector<double> tau = {2.0, 4.0, 32.0, 1024.0, std::ldexp(1.0, 20), std::ldexp(1.0, 30)};
  const std::vector<double> expected = {0.7433669398597585,  0.76703191695959206, 0.95218240788698986,
                                        0.99837600503627839, 0.99999808969834774, 0.99967455706890806};
  // B2 = pi / ln2 makes each octave's stationary variance 1.
  expect_all_relatively_near(wv_of(*p, std::vector<double>{1.0 / kLn2OverPi}, tau), expected, 1e-10,
                             "FLICKER(kmin=0,kmax=39)");
}

TEST(FlickerProcess, HasThePlateauB2Ln2OverPiInsideItsOctaveRange) {
  const auto p = make_process("FLICKER");
  const double b2 = 3e-7;
  const auto tau = dyadic_scales(30, 8);
  for (double v : wv_of(*p, std::vector<double>{b2}, tau)) EXPECT_NEAR(v / (b2 * kLn2OverPi), 1.0, 0.01);
  // Beyond 2^kmax the plateau falls off (like an AR1 beyond its correlation time).
  const auto short_range = make_process("FLICKER", {{"kmin", 0}, {"kmax", 8}});
  const std::vector<double> far = {std::ldexp(1.0, 16)};
  EXPECT_LT(wv_of(*short_range, std::vector<double>{b2}, far)[0], 0.05 * b2 * kLn2OverPi);
}

TEST(FlickerProcess, IsLinearWithAnalyticDerivatives) {
  const auto p = make_process("FLICKER");
  EXPECT_TRUE(p->linear());
  EXPECT_EQ(p->canonical_rank(), 100);
  expect_derivatives_match_finite_differences(*p, {2e-5}, dyadic_scales(12));
}

TEST(FlickerProcess, AutocovarianceReproducesTheWaveletVariance) {
  const auto p = make_process("FLICKER", {{"kmin", 0}, {"kmax", 12}});
  const std::vector<double> theta{0.8};
  const auto tau = dyadic_scales(6);
  expect_all_relatively_near(wv_from_autocovariance(*p, theta, tau), wv_of(*p, theta, tau), 1e-9, "FLICKER from g");
}

TEST(FlickerProcess, SimulatedMomentsMatchTheAutocovariance) {
  const auto p = make_process("FLICKER", {{"kmin", 0}, {"kmax", 10}});
  expect_simulated_moments_match(*p, std::vector<double>{1.3}, {.length = 128, .replicates = 2000, .seed = 901});
}

TEST(FlickerProcess, TheBlockBridgeAndTheOctaveRecursionDrawTheSameAutocovariance) {
  // Octaves 2^0..2^12 samples on records of 256 (the slow octaves far beyond the record):
  // the mean lag-h product over 4000 draws of each against s sum_k phi_k^h, within 4 of
  // its Monte-Carlo standard errors (from the draws' own spread).
  constexpr long kKmin = 0, kKmax = 12;
  constexpr std::size_t kN = 256;
  constexpr int kDraws = 4000;
  constexpr double kS = 0.7;
  // Blocks of 64 and of 7 (256 = 36 x 7 + 4: a tail after the last whole block).
  const internal::FlickerBridge wide = internal::make_flicker_bridge(kKmin, kKmax),
                                narrow = internal::make_flicker_bridge(kKmin, kKmax, 7);
  ASSERT_TRUE(wide.usable() && narrow.usable());
  const std::size_t lags[] = {0, 1, 16, 128, 255};
  for (const int way : {0, 1, 2}) {
    const char* name = way == 0 ? "bridge, blocks of 64" : way == 1 ? "bridge, blocks of 7" : "octaves";
    double sum[5] = {}, sum2[5] = {};
    for (int d = 0; d < kDraws; ++d) {
      Rng rng = make_stream(4401, {static_cast<std::uint64_t>(d), static_cast<std::uint64_t>(way)});
      std::vector<double> x(kN, 0.0);
      if (way == 2)
        internal::simulate_flicker_octaves(kKmin, kKmax, kS, rng, x);
      else
        internal::simulate_flicker_bridge(way == 0 ? wide : narrow, kS, rng, x);
      for (int i = 0; i < 5; ++i) {
        const std::size_t h = lags[i];
        double a = 0.0;
        for (std::size_t t = 0; t + h < kN; ++t) a += x[t] * x[t + h];
        a /= static_cast<double>(kN - h);
        sum[i] += a, sum2[i] += a * a;
      }
    }
    for (int i = 0; i < 5; ++i) {
      double truth = 0.0;
      for (long k = kKmin; k <= kKmax; ++k)
        truth += kS * std::pow(std::exp(-std::ldexp(1.0, static_cast<int>(-k))), static_cast<double>(lags[i]));
      const double mean = sum[i] / kDraws, se = std::sqrt((sum2[i] / kDraws - mean * mean) / kDraws);
      EXPECT_NEAR(mean, truth, 4.0 * se) << name << ", lag " << lags[i];
    }
  }
}

TEST(FlickerProcess, SimulatedRecordsHaveThePlateauAtEveryScaleOfTheRecord) {
  // The default 41 octaves (to 2^40 samples) on records of 2^15: the mean classical WV of 200
  // draws against the model's at levels 1..12, within 4 Monte-Carlo standard errors.
  const Model m = parse_model("FLICKER(B2=2e-6)");
  const Eigen::VectorXd theta = m.given_values();
  constexpr std::int64_t kN = std::int64_t{1} << 15;
  constexpr int kDraws = 200, kLevels = 12;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(kLevels), sum2 = Eigen::VectorXd::Zero(kLevels);
  for (int d = 0; d < kDraws; ++d) {
    const std::vector<double> x = simulate(m, theta, kN, 4402, static_cast<std::uint64_t>(d));
    const Eigen::VectorXd nu = classical_wv(x.data(), kN, WvOptions{.levels = kLevels}).values();
    sum += nu, sum2 += nu.cwiseProduct(nu);
  }
  std::vector<double> tau;
  for (int j = 1; j <= kLevels; ++j) tau.push_back(std::ldexp(1.0, j));
  const Eigen::VectorXd model_wv = m.wv(theta, tau);
  for (int j = 0; j < kLevels; ++j) {
    const double mean = sum(j) / kDraws, se = std::sqrt((sum2(j) / kDraws - mean * mean) / kDraws);
    EXPECT_NEAR(mean, model_wv(j), 4.0 * se) << "level " << j + 1;
  }
}

TEST(FlickerProcess, WritesItsOctaveRangeOnlyWhenNotTheDefault) {
  EXPECT_EQ(parse_model("FLICKER").to_string(), "FLICKER");
  EXPECT_EQ(parse_model("FLICKER(kmin=2,kmax=20)").to_string(), "FLICKER(kmin=2,kmax=20)");
  EXPECT_EQ(parse_model("WN+FLICKER+AR1").canonical().to_string(), "AR1+WN+FLICKER");
}

TEST(FlickerProcess, RejectsABadOctaveRangeOrAnUnknownKeyWithOneClearLine) {
  auto message = [](const std::string& spec) {
    try {
      parse_model(spec);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("FLICKER(kmin=9,kmax=3)").find("0 <= kmin <= kmax <= 62 (got kmin=9, kmax=3)"), std::string::npos)
      << message("FLICKER(kmin=9,kmax=3)");
  EXPECT_NE(message("FLICKER(kmax=70)").find("kmax=70"), std::string::npos);
  EXPECT_NE(message("FLICKER(octaves=3)").find("FLICKER has no parameter 'octaves' (parameters: B2)"),
            std::string::npos)
      << message("FLICKER(octaves=3)");
}

TEST(FlickerProcess, PhysicalCoefficientAndBiasInstability) {
  // B2 = 4e-6 (deg/s)^2: B = 2e-3 deg/s; bias instability = sqrt(2 ln2 / pi) B
  // = 0.66428247 * 2e-3 = 1.3285649e-3 deg/s (IEEE 952's 0.664 B), at any rate.
  const auto p = make_process("FLICKER");
  const std::vector<double> theta{4e-6};
  const auto q = p->physical(theta, 200.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "flicker coefficient");
  EXPECT_NEAR(q[0].value, 2e-3, 1e-15);
  EXPECT_EQ(q[1].name, "bias instability");
  EXPECT_NEAR(q[1].value, 1.32856494053592e-3, 1e-15);
  EXPECT_EQ(render_unit(q[1].unit_pattern, "deg/s"), "deg/s");
  EXPECT_NE(q[1].convention.find("0.664"), std::string::npos);
  EXPECT_EQ(p->physical(theta, 1.0)[1].value, q[1].value);
  // It is the Allan deviation floor: sqrt(AVAR) = sqrt(2 WV) on the plateau (within its
  // 1% ripple, see HasThePlateauB2Ln2OverPiInsideItsOctaveRange).
  const std::vector<double> tau{std::ldexp(1.0, 16)};
  EXPECT_NEAR(std::sqrt(2.0 * wv_of(*p, theta, tau)[0]) / q[1].value, 1.0, 0.01);
}

}  // namespace
}  // namespace gmwm::test
