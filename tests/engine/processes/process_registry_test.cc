#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/process_registry.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

TEST(ProcessRegistry, KnowsEveryProcessOfTheLibrary) {
  const auto names = ProcessRegistry::instance().names();
  for (const char* n : {"WN", "QN", "RW", "DR", "AR1", "GM", "MA1", "ARMA11", "ARMA", "SIN", "FLICKER"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  EXPECT_NE(ProcessRegistry::instance().find("ar1"), nullptr);
  EXPECT_EQ(ProcessRegistry::instance().find("ARMA")->structural_keys, (std::vector<std::string>{"p", "q"}));
}

TEST(ProcessRegistry, IsBuiltExplicitlyWithExactlyTheBuiltInProcesses) {
  // The registry is filled at first use from engine/src/processes/builtin_processes.h, not
  // by load-time side effects: the same eleven types in a static build.
  auto names = ProcessRegistry::instance().names();
  std::erase(names, "MYWN");  // added by the next test when run in the same process
  std::erase(names, "SDWN");  // added by added_process_test.cc
  EXPECT_EQ(names,
            (std::vector<std::string>{"AR1", "ARMA", "ARMA11", "DR", "FLICKER", "GM", "MA1", "QN", "RW", "SIN", "WN"}));
}

TEST(ProcessRegistry, TakesAnApplicationsOwnProcessTypeButNeverReplacesOne) {
  ProcessRegistry& r = ProcessRegistry::instance();
  const ProcessEntry* wn = r.find("WN");
  ASSERT_NE(wn, nullptr);
  ProcessEntry mine = *wn;
  EXPECT_FALSE(r.add(mine));  // "WN" is taken
  mine.name = "MYWN";
  mine.summary = "an application's white noise";
  EXPECT_TRUE(r.add(mine));
  EXPECT_NE(r.find("mywn"), nullptr);
}

TEST(ProcessRegistry, EveryBuiltInProcessSaysItsRoleInTheErrorBudget) {
  // What gap, nav and the simulator conversions ask instead of testing names.
  const std::vector<std::pair<std::string, ProcessRole>> roles{
      {"WN", ProcessRole::kWhite},        {"QN", ProcessRole::kQuantization}, {"RW", ProcessRole::kWalk},
      {"DR", ProcessRole::kDrift},        {"AR1", ProcessRole::kBias},        {"GM", ProcessRole::kBias},
      {"FLICKER", ProcessRole::kFlicker}, {"SIN", ProcessRole::kPeriodic},    {"MA1", ProcessRole::kOther},
      {"ARMA11", ProcessRole::kOther}};
  for (const auto& [name, role] : roles) EXPECT_EQ(make_process(name)->role(), role) << name;
  EXPECT_EQ(make_process("ARMA", {{"p", 1}, {"q", 1}})->role(), ProcessRole::kOther);
  for (ProcessRole r : {ProcessRole::kWhite, ProcessRole::kQuantization, ProcessRole::kWalk, ProcessRole::kDrift})
    EXPECT_TRUE(single_per_model(r)) << to_string(r);
  for (ProcessRole r : {ProcessRole::kBias, ProcessRole::kFlicker, ProcessRole::kPeriodic, ProcessRole::kOther})
    EXPECT_FALSE(single_per_model(r)) << to_string(r);
}

TEST(ProcessRegistry, CorrelatedBiasesGiveTheirCorrelationTimeInSamples) {
  // AR1: -1 / ln(phi); GM at 100 Hz with beta = 0.5 / s: T = 2 s = 200 samples, which is the
  // AR1 of phi = exp(-beta / f)'s. None outside the bias role or without one (phi <= 0).
  const std::vector<double> ar1{std::exp(-1.0 / 200.0), 1.0}, negative{-0.5, 1.0};
  EXPECT_NEAR(*make_process("AR1")->correlation_samples(ar1), 200.0, 1e-9);
  EXPECT_FALSE(make_process("AR1")->correlation_samples(negative).has_value());
  ProcessArgs args;
  args.context = ProcessContext{100.0, true};
  const auto gm = ProcessRegistry::instance().create("GM", args);
  EXPECT_NEAR(*gm->correlation_samples(std::vector<double>{0.5, 1.0}), 200.0, 1e-12);
  EXPECT_FALSE(make_process("WN")->correlation_samples(std::vector<double>{1.0}).has_value());
}

TEST(ProcessRegistry, RejectsAnUnknownNameListingTheKnownOnes) {
  try {
    make_process("AR3");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("unknown process 'AR3'"), std::string::npos) << why;
    EXPECT_NE(why.find("ARMA11"), std::string::npos) << why;
  }
}

TEST(ProcessRegistry, CanonicalRanksFollowTheCliOrder) {
  const std::vector<std::string> order{"AR1", "GM", "MA1", "ARMA11", "ARMA", "WN", "QN", "RW", "DR", "SIN"};
  int previous = -1;
  for (const auto& n : order) {
    const auto p = n == "ARMA" ? make_process(n, {{"p", 1}, {"q", 1}}) : make_process(n);
    EXPECT_GT(p->canonical_rank(), previous) << n;
    previous = p->canonical_rank();
    EXPECT_EQ(p->name(), n);
  }
}

TEST(ProcessRegistry, EveryProcessGuessesAValidStartFromAnEmptyContext) {
  for (const auto& n : ProcessRegistry::instance().names()) {
    if (n == "FLICKER") continue;  // not part of this library's files
    const auto p = n == "ARMA" ? make_process(n, {{"p", 2}, {"q", 1}}) : make_process(n);
    EXPECT_EQ(p->validate(p->initial_guess({})), "") << n;
  }
}

TEST(ProcessRegistry, EveryProcessScaledByCHasCTimesItsWaveletVariance) {
  // Process::scaled: the parameters for the data times sqrt(c), whose WV is c times theta's
  // at every scale (what a plan computed at the model's unit scale rests on, record_plan.h).
  // Multiplying by a power of 4 is exact, so the WV is too but for its own roundings: 1e-13
  // relative; 1e-100 and 1e100 check that no parameter is left out or scaled twice.
  std::vector<double> tau;
  for (int j = 1; j <= 12; ++j) tau.push_back(std::ldexp(1.0, j));
  for (const auto& n : ProcessRegistry::instance().names()) {
    const auto p = n == "ARMA" ? make_process(n, {{"p", 2}, {"q", 1}}) : make_process(n);
    GuessContext guess;
    const std::vector<double> wv(tau.size(), 1.0);
    guess.tau = tau;
    guess.wv = wv;
    const std::vector<double> theta = p->initial_guess(guess);
    ASSERT_EQ(p->validate(theta), "") << n;
    std::vector<double> base(tau.size()), scaled(tau.size());
    p->wv(theta, tau, base);
    for (double c : {0.25, 1024.0, 1e-100, 1e100}) {
      const std::vector<double> s = p->scaled(theta, c);
      ASSERT_EQ(s.size(), theta.size()) << n;
      EXPECT_EQ(p->validate(s), "") << n << " x " << c;
      p->wv(s, tau, scaled);
      for (std::size_t k = 0; k < tau.size(); ++k)
        EXPECT_NEAR(scaled[k], c * base[k], 1e-13 * c * base[k]) << n << " x " << c << ", tau = " << tau[k];
    }
  }
}

TEST(ProcessRegistry, EveryProcessGivesItsWvAndJacobianTogetherAsItGivesThemApart) {
  // Process::wv_and_jacobian (an optimiser's every step) must be wv and wv_jacobian to the
  // bit: a fit's path, and so every figure, would otherwise depend on which was called.
  // Starts guessed around every third level of 12 and of 20.
  for (const double top : {12.0, 20.0}) {
    std::vector<double> tau;
    for (int j = 1; j <= static_cast<int>(top); ++j) tau.push_back(std::ldexp(1.0, j));
    std::vector<double> wv(tau.size());
    for (std::size_t k = 0; k < tau.size(); ++k) wv[k] = 1.0 / tau[k] + 1e-3 * tau[k];
    for (const auto& n : ProcessRegistry::instance().names()) {
      // ARMA(p, q)'s WV sums its autocovariance over each scale, O(tau): 2^20 costs 0.1 s an
      // evaluation, and its wv_and_jacobian is the default (wv, then wv_jacobian) anyway.
      if (n == "ARMA" && top > 12.0) continue;
      const auto p = n == "ARMA" ? make_process(n, {{"p", 2}, {"q", 1}}) : make_process(n);
      for (std::size_t h = 0; h < tau.size(); h += 3) {
        GuessContext guess;
        guess.tau = tau;
        guess.wv = wv;
        guess.tau_hint = tau[h];
        const std::vector<double> theta = p->initial_guess(guess);
        ASSERT_EQ(p->validate(theta), "") << n;
        const auto J = static_cast<Eigen::Index>(tau.size());
        std::vector<double> apart(tau.size()), together(tau.size());
        Eigen::MatrixXd jac_apart(J, p->size()), jac_together(J, p->size());
        p->wv(theta, tau, apart);
        p->wv_jacobian(theta, tau, jac_apart);
        p->wv_and_jacobian(theta, tau, together, jac_together);
        for (std::size_t k = 0; k < tau.size(); ++k) {
          EXPECT_EQ(std::bit_cast<std::uint64_t>(together[k]), std::bit_cast<std::uint64_t>(apart[k]))
              << n << " at tau = " << tau[k] << ": " << together[k] << " vs " << apart[k];
          for (int l = 0; l < p->size(); ++l)
            EXPECT_EQ(std::bit_cast<std::uint64_t>(jac_together(static_cast<Eigen::Index>(k), l)),
                      std::bit_cast<std::uint64_t>(jac_apart(static_cast<Eigen::Index>(k), l)))
                << n << " parameter " << l << " at tau = " << tau[k];
        }
      }
    }
  }
}

TEST(ProcessRegistry, EveryProcessButArmaGivesItsWvBetweenWholeScalesContinuously) {
  // A curve's averaging times need not be whole numbers of samples (curve.h): every process
  // whose WV is a closed form continues it in m = tau / 2, smoothly (the value at 2m +- 1e-7
  // within 1e-6 relative of the value at 2m, whole or not) and with the derivatives of that
  // continuation; ARMA(p, q), whose WV sums over lags, says it needs whole scales.
  const std::vector<double> tau{2.2, 7.4, 16.0, 41.3};
  for (const auto& n : ProcessRegistry::instance().names()) {
    const auto p = n == "ARMA" ? make_process(n, {{"p", 2}, {"q", 1}}) : make_process(n);
    EXPECT_EQ(p->needs_whole_scales(), n == "ARMA") << n;
    if (p->needs_whole_scales()) continue;
    GuessContext guess;
    const std::vector<double> wv(tau.size(), 1.0);
    guess.tau = tau;
    guess.wv = wv;
    const std::vector<double> theta = p->initial_guess(guess);
    ASSERT_EQ(p->validate(theta), "") << n;
    for (double t : tau) {
      std::vector<double> at(1), below(1), above(1);
      p->wv(theta, std::vector<double>{t}, at);
      p->wv(theta, std::vector<double>{t - 1e-7}, below);
      p->wv(theta, std::vector<double>{t + 1e-7}, above);
      ASSERT_TRUE(std::isfinite(at[0]) && at[0] > 0.0) << n << " at tau = " << t;
      EXPECT_NEAR(below[0], at[0], 1e-6 * at[0]) << n << " at tau = " << t;
      EXPECT_NEAR(above[0], at[0], 1e-6 * at[0]) << n << " at tau = " << t;
    }
    expect_derivatives_match_finite_differences(*p, theta, tau);
  }
}

}  // namespace
}  // namespace gmwm::test
