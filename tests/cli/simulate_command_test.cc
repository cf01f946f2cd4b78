// `gmwm simulate` at the ends of the doubles (issue 42 item 12): what it writes is finite,
// and what it cannot write is refused in one line naming the option and the bound,
// nothing written and nothing of the user's overwritten.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::expect_bad_input;
using gmwm::test::read_text;
using gmwm::test::run_gmwm;
using gmwm::test::write_text;

namespace {

class GmwmSimulate : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_simulate"); }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs simulate into s.csv and returns its values (every one finite).
  std::vector<double> simulated(std::vector<std::string> args) {
    args.insert(args.begin(), "simulate");
    for (const char* a : {"--output", "s.csv", "--quiet"}) args.emplace_back(a);
    const auto r = run_gmwm(args, dir_);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::vector<double> values;
    std::istringstream rows(read_text(dir_ / "s.csv"));
    std::string row;
    std::getline(rows, row);  // the header
    while (std::getline(rows, row)) {
      values.push_back(std::stod(row));
      EXPECT_TRUE(std::isfinite(values.back())) << row;
    }
    return values;
  }

  fs::path dir_;
};

TEST_F(GmwmSimulate, WritesFiniteValuesForVariancesNearTheLargestDouble) {
  // QN formed 12 Q2 and ARMA sigma2 times its unit covariance: both inf, every row
  // 'inf' or 'nan'. The engine's values scale exactly (Simulate.ScalesEveryProcesses...).
  EXPECT_EQ(simulated({"--model", "QN(Q2=1e308)", "--n", "100"}).size(), 100u);
  EXPECT_EQ(simulated({"--model", "ARMA(p=1,q=1,phi1=0.999,theta1=0.5,sigma2=1e308)", "--n", "100"}).size(), 100u);
  // A drift up to 9.9e306 is a double's.
  const std::vector<double> drift = simulated({"--model", "DR(omega=1e305)", "--n", "100"});
  ASSERT_EQ(drift.size(), 100u);
  EXPECT_EQ(drift.back(), 99e305);
}

TEST_F(GmwmSimulate, KeepsValuesAQuantumCannotResolveInsteadOfWritingInf) {
  // 1e300 / 1e-10 overflowed to inf. A quotient of 2^53 or more means the step is below the
  // value's own spacing: the nearest multiple rounds to the value itself.
  const std::vector<double> plain = simulated({"--model", "WN(sigma2=1e300)", "--n", "50"});
  EXPECT_EQ(simulated({"--model", "WN(sigma2=1e300)", "--n", "50", "--quantum", "1e-10"}), plain);
  // An ordinary step still rounds.
  for (double v : simulated({"--model", "WN(sigma2=1)", "--n", "50", "--quantum", "0.25"}))
    EXPECT_EQ(v, std::nearbyint(v * 4.0) / 4.0) << v;
}

TEST_F(GmwmSimulate, RefusesValuesBeyondADoubleInOneLineLeavingTheOutputAsItWas) {
  write_text(dir_ / "s.csv", "keep\n");
  const fs::path json = dir_ / "s.json";
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "simulate");
    for (const char* a : {"--output", "s.csv", "--json", "s.json"}) args.emplace_back(a);
    return run_gmwm(args, dir_);
  };
  // A subnormal step: 1 / 1e-320 is inf, every value divided by it too.
  expect_bad_input(run({"--model", "WN(sigma2=1)", "--n", "100", "--quantum", "1e-320"}),
                   {"--quantum", "at least 2.2e-308"}, json);
  // omega t passes 1.8e308 at t = 1798.
  expect_bad_input(run({"--model", "DR(omega=1e305)", "--n", "10000"}),
                   {"--model 'DR(omega=1e305)' with --n 10000", "component 1 (DR)", "beyond the largest double",
                    "sample 1798", "|omega| (n - 1) <= 1.8e308"},
                   json);
  // Rounding 1.7e308 up to the next multiple of 1e308.
  expect_bad_input(run({"--model", "DR(omega=1.8e306)", "--n", "100", "--quantum", "1e308"}),
                   {"--quantum", "beyond the largest double", "a smaller step"}, json);
  EXPECT_EQ(read_text(dir_ / "s.csv"), "keep\n");
}

}  // namespace
