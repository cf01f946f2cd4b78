#include <algorithm>
#include <string>

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

}  // namespace
}  // namespace gmwm::test
