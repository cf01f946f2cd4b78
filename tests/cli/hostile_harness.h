#pragma once
// The bad-input contract checked over corpora of hostile inputs and options (issue 17,
// issue 25): each case exits 2 with exactly one line "gmwm: error: ..." naming the file or
// option and what was expected, writes nothing to stdout, creates or changes no file in its
// folder, and runs in under kMaxSeconds with the program's peak memory under kMaxRssBytes.
// The corpora live by category in tests/cli/hostile_*_test.cc; each instantiates
// HOSTILE_CORPUS over its own cases.

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_runner.h"
#include "test_support.h"

namespace gmwm::test::hostile {

// The bars of the contract (issue 17): a refusal is quick and cheap.
inline constexpr double kMaxSeconds = 10.0;
inline constexpr long kMaxRssBytes = 1L << 30;

using Setup = std::function<void(const std::filesystem::path&)>;

struct Case {
  std::string name;
  std::vector<std::string> args;
  std::vector<std::string> mentions;  ///< each must appear in the one error line
  Setup setup = nullptr;
  RunOptions how = {};
};

/// 4096 rows of a time column and two signals (gyro_x, accel_x) at 100 Hz.
std::string base_csv();

/// A string of the given byte values.
std::string bytes(std::initializer_list<int> b);

/// One gzip member holding `text` (test_support.h).
using ::gmwm::test::gzip_member;

/// A decompression bomb: `head` in a first member, then `copies` members of 1 MiB of `unit`
/// repeated (concatenated members are one gzip stream; each costs about 1 kB).
std::string gzip_bomb(const std::string& head, const std::string& unit, int copies);

/// A setup writing one file.
Setup file(const std::string& name, const std::string& text);

/// A setup running two setups.
Setup both(Setup a, Setup b);

/// Every file of a folder with its content (the folder's state).
std::map<std::string, std::string> snapshot(const std::filesystem::path& dir);

/// Runs the case in a fresh folder and checks every bar of the contract.
void expect_contract(const Case& c);

/// The test name of a case: its words in CamelCase.
std::string test_name(const std::string& name);

}  // namespace gmwm::test::hostile

/// A parameterised suite `Suite` over `cases` (a std::vector<Case>), one test per case.
#define HOSTILE_CORPUS(Suite, cases)                                                               \
  class Suite : public ::testing::TestWithParam<::gmwm::test::hostile::Case> {};                   \
  TEST_P(Suite, ExitsTwoWithOneLineNamingThePlaceAndLeavesEverythingAsItWas) {                     \
    ::gmwm::test::hostile::expect_contract(GetParam());                                            \
  }                                                                                                \
  INSTANTIATE_TEST_SUITE_P(Corpus, Suite, ::testing::ValuesIn(cases), [](const auto& param_info) { \
    return ::gmwm::test::hostile::test_name(param_info.param.name);                                \
  })
