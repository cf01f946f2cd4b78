// Fit quality said plainly (issue 13, item 4): every candidate rejected, where the chosen
// model misses, one-sided intervals at a parameter's bound, non-converged candidates
// counted, degenerate fits named.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using json = nlohmann::json;

namespace {

class GmwmFitQuality : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_quality"); }
  void TearDown() override { fs::remove_all(dir_); }
  void simulate(const std::string& model, int n = 65536) {
    const auto r = run_gmwm({"simulate", "--model", model, "--n", std::to_string(n), "--freq", "100", "--names",
                             "gyro_x", "--output", "sim.csv.gz", "--quiet"},
                            dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  fs::path dir_;
};

}  // namespace

TEST_F(GmwmFitQuality, SaysWhenEveryCandidateIsRejectedAndWhereTheChosenOneMisses) {
  // A tone at 12.5 Hz (period 8 samples) that no sub-model of AR1+WN+RW can follow.
  simulate("WN(sigma2=1)+SIN(A2=2,f=12.5)+RW(gamma2=1e-6)");
  const auto r = run_gmwm({"select", "sim.csv.gz", "--model", "AR1+WN+RW", "--verbose", "--json", "s.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.out.find("fit quality: every candidate is rejected at 5%: no sub-model of AR1+WN+RW describes these data"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("the data depart most at 0.08 s"), std::string::npos) << r.out;
  const json col = read_json(dir_ / "s.json").at("columns").at(0);
  EXPECT_TRUE(col.at("all_rejected").get<bool>());
  const json& q = col.at("best_fit").at("quality");
  EXPECT_TRUE(q.at("rejected").get<bool>());
  ASSERT_EQ(q.at("worst_levels").size(), 3u);
  EXPECT_EQ(q.at("worst_levels").at(0).at("level"), 3) << "tau = 8 samples, one period of the tone, holds it";
  EXPECT_GT(std::abs(q.at("worst_levels").at(0).at("z").get<double>()), 10.0);
}

TEST_F(GmwmFitQuality, AnAr1AtItsBoundGetsAOneSidedIntervalNotTheWholeDomain) {
  // A random walk fitted as an AR1: phi goes to its bound near 1.
  simulate("WN(sigma2=1)+RW(gamma2=1e-4)", 131072);
  const auto r = run_gmwm({"fit", "sim.csv.gz", "--model", "AR1+WN", "--verbose", "--json", "f.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "f.json");
  const json& params = doc.at("columns").at(0).at("parameters");
  const json& phi = params.at(0);
  ASSERT_EQ(phi.at("name"), "phi");
  EXPECT_GT(phi.at("value").get<double>(), 0.999);
  EXPECT_EQ(phi.at("interval"), "one-sided") << phi.dump();
  EXPECT_DOUBLE_EQ(phi.at("ci_high").get<double>(), 1.0);
  EXPECT_GT(phi.at("ci_low").get<double>(), 0.99) << "never [-1, 1] around a tiny se";
  EXPECT_NE(r.out.find("one-sided"), std::string::npos) << r.out;
}

TEST_F(GmwmFitQuality, CountsCandidatesThatStoppedBeforeConvergingOnTheTerminal) {
  simulate("AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=1)");
  const auto r = run_gmwm(
      {"select", "sim.csv.gz", "--model", "3*AR1+WN+RW", "--max-evaluations", "10", "--verbose", "--json", "s.json"},
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json col = read_json(dir_ / "s.json").at("columns").at(0);
  const int not_converged = col.at("not_converged").get<int>();
  ASSERT_GT(not_converged, 0) << "ten evaluations cannot converge every candidate";
  EXPECT_NE(r.out.find(" stopped before converging"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(std::to_string(not_converged) + " stopped before converging"), std::string::npos) << r.out;
}

TEST_F(GmwmFitQuality, NamesACollapsedComponentAsADegenerateFit) {
  simulate("AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=1)", 131072);
  const auto r = run_gmwm({"fit", "sim.csv.gz", "--model", "AR1+WN+QN", "--verbose", "--json", "f.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "f.json");
  const json& q = doc.at("columns").at(0).at("quality");
  EXPECT_TRUE(q.at("degenerate").get<bool>()) << q.dump();
  EXPECT_NE(q.at("degeneracy").get<std::string>().find("QN[3] collapsed"), std::string::npos) << q.dump();
  EXPECT_NE(r.out.find("fit quality: degenerate fit: QN[3] collapsed"), std::string::npos) << r.out;
}
