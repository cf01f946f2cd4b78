#include <algorithm>
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
  for (const char* n : {"WN", "QN", "RW", "DR", "AR1", "GM", "MA1", "ARMA11", "ARMA", "SIN"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  EXPECT_NE(ProcessRegistry::instance().find("ar1"), nullptr);
  EXPECT_EQ(ProcessRegistry::instance().find("ARMA")->structural_keys, (std::vector<std::string>{"p", "q"}));
}

TEST(ProcessRegistry, IsBuiltExplicitlyWithExactlyTheBuiltInProcesses) {
  // The registry is filled at first use from engine/src/processes/builtin_processes.h, not
  // by load-time side effects: the same eleven types in a static build.
  auto names = ProcessRegistry::instance().names();
  std::erase(names, "MYWN");  // added by the next test when run in the same process
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

}  // namespace
}  // namespace gmwm::test
