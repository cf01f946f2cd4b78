// Success paths of `gmwm wv`, `gmwm fit` and `gmwm simulate`, end to end: the JSON
// contract (docs/cli.md), values equal to the library's, reproducibility across thread counts.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/random.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"
#include "gmwm/robust/robust_wv.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::test::read_json;
using gmwm::test::run_gmwm;
using nlohmann::json;

namespace {

constexpr const char* kTruth = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-10)";

class GmwmCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli"); }
  void TearDown() override { fs::remove_all(dir_); }

  /// Simulates `signals` series of kTruth at 100 Hz into sim.csv.gz.
  void simulate(int n, int signals) {
    auto r = run_gmwm({"simulate", "--model", kTruth, "--n", std::to_string(n), "--freq", "100", "--signals",
                       std::to_string(signals), "--output", "sim.csv.gz", "--json", "sim.json", "--quiet"},
                      dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }

  fs::path dir_;
};

void expect_common_top_level(const json& doc, const std::string& command) {
  EXPECT_EQ(doc.at("tool"), "gmwm");
  EXPECT_TRUE(doc.at("version").is_string());
  EXPECT_EQ(doc.at("command"), command);
  ASSERT_TRUE(doc.at("columns").is_array());
  ASSERT_TRUE(doc.at("run").is_object());
  EXPECT_TRUE(doc.at("run").contains("threads"));
}

void expect_levels_equal_library(const json& levels, const gmwm::WaveletVariance& wv, double freq) {
  ASSERT_EQ(levels.size(), static_cast<std::size_t>(wv.levels()));
  for (int j = 0; j < wv.levels(); ++j) {
    const auto k = static_cast<std::size_t>(j);
    const json& l = levels[k];
    EXPECT_EQ(l.at("level"), j + 1);
    EXPECT_EQ(l.at("tau").get<double>(), wv.tau[k]);
    EXPECT_DOUBLE_EQ(l.at("tau_seconds").get<double>(), wv.tau[k] / freq);
    EXPECT_DOUBLE_EQ(l.at("wv").get<double>(), wv.wv[k]);
    EXPECT_DOUBLE_EQ(l.at("ci_low").get<double>(), wv.ci_low[k]);
    EXPECT_DOUBLE_EQ(l.at("ci_high").get<double>(), wv.ci_high[k]);
    EXPECT_EQ(l.at("coefficients").get<std::int64_t>(), wv.coefficients[k]);
  }
}

}  // namespace

TEST_F(GmwmCli, WvJsonHasTheContractFieldsAndTheLibrarysValues) {
  std::vector<gmwm::io::Signal> signals(2);
  signals[0].name = "gyro_x";
  signals[1].name = "gyro_y";
  std::mt19937_64 rng(3);
  std::normal_distribution<double> z;
  double rw = 0.0;
  std::vector<double> a, b;
  for (int i = 0; i < 5000; ++i) {
    rw += 0.01 * z(rng);
    a.push_back(z(rng) + rw);
    b.push_back(0.1 * z(rng));
  }
  signals[0].values = std::move(a);
  signals[1].values = std::move(b);
  gmwm::io::write_signals((dir_ / "in.csv").string(), signals, std::nullopt);

  auto r = run_gmwm({"wv", "in.csv", "--freq", "50", "--alpha", "0.1", "--json", "wv.json", "--csv", "wv.csv"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  // The terminal table.
  for (const char* head : {"level", "tau", "tau [s]", "WV", "CI low", "CI high", "M_j"})
    EXPECT_NE(r.out.find(head), std::string::npos) << head;

  const json doc = read_json(dir_ / "wv.json");
  expect_common_top_level(doc, "wv");
  ASSERT_EQ(doc["columns"].size(), 2u);
  gmwm::WvOptions options;
  options.alpha = 0.1;
  for (std::size_t k = 0; k < 2; ++k) {
    const json& c = doc["columns"][k];
    EXPECT_EQ(c.at("name"), signals[k].name);
    EXPECT_EQ(c.at("n"), 5000);
    EXPECT_EQ(c.at("freq"), 50.0);
    EXPECT_EQ(c.at("estimator"), "classical");
    EXPECT_TRUE(c.at("efficiency").is_null());
    const auto wv = gmwm::classical_wv(signals[k].values.data(), 5000, options);
    expect_levels_equal_library(c.at("levels"), wv, 50.0);
  }
  // The CSV table: a header and one row per column and level.
  const auto csv = gmwm::test::lines_of(gmwm::test::read_text(dir_ / "wv.csv"));
  ASSERT_EQ(csv.size(), 1u + 2u * doc["columns"][0]["levels"].size());
  EXPECT_EQ(csv[0], "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients");
}

TEST_F(GmwmCli, WvJsonOnStandardOutputIsTheOnlyThingThere) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 1000);
  auto r = run_gmwm({"wv", "noise.csv", "--freq", "10", "--levels", "4", "--json", "-"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  expect_common_top_level(doc, "wv");
  EXPECT_EQ(doc["columns"][0]["levels"].size(), 4u);
  EXPECT_EQ(doc["columns"][0]["levels"][3]["tau_seconds"], 1.6);
}

TEST_F(GmwmCli, QuietPrintsNothingOnSuccess) {
  gmwm::test::write_noise_csv(dir_ / "noise.csv", 1000);
  auto r = run_gmwm({"wv", "noise.csv", "--freq", "10", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST_F(GmwmCli, SimulateWritesWhatItSaysAndIsReproducibleFromTheSeed) {
  simulate(4096, 3);
  const json doc = read_json(dir_ / "sim.json");
  expect_common_top_level(doc, "simulate");
  ASSERT_EQ(doc["columns"].size(), 3u);
  EXPECT_EQ(doc["columns"][0]["n"], 4096);
  EXPECT_EQ(doc["seed"], gmwm::kDefaultSeed);
  const auto set = gmwm::io::read_signals((dir_ / "sim.csv.gz").string(), {});
  ASSERT_EQ(set.signals.size(), 3u);
  EXPECT_EQ(set.signals[0].values.size(), 4096u);
  EXPECT_TRUE(set.freq_known);
  EXPECT_NEAR(set.freq, 100.0, 1e-9);
  EXPECT_NE(set.signals[0].values, set.signals[1].values);

  // The same seed gives the same data; another seed different data.
  auto again = run_gmwm({"simulate", "--model", kTruth, "--n", "4096", "--freq", "100", "--signals", "3", "--output",
                         "again.csv.gz", "--quiet"},
                        dir_);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(gmwm::io::read_signals((dir_ / "again.csv.gz").string(), {}).signals[2].values, set.signals[2].values);
  auto other = run_gmwm({"simulate", "--model", kTruth, "--n", "4096", "--freq", "100", "--signals", "3", "--output",
                         "other.csv.gz", "--seed", "7", "--quiet"},
                        dir_);
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_NE(gmwm::io::read_signals((dir_ / "other.csv.gz").string(), {}).signals[2].values, set.signals[2].values);
}

TEST_F(GmwmCli, SimulateThenFitRecoversTheModel) {
  simulate(1 << 16, 1);
  auto r = run_gmwm({"fit", "sim.csv.gz", "--model", "AR1+WN+RW", "--verbose", "--json", "fit.json"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* word : {"model:", "process", "component", "se", "objective", "status"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word;

  const json doc = read_json(dir_ / "fit.json");
  expect_common_top_level(doc, "fit");
  ASSERT_EQ(doc["columns"].size(), 1u);
  const json& c = doc["columns"][0];
  EXPECT_EQ(c.at("name"), "x");
  EXPECT_EQ(c.at("n"), 1 << 16);
  EXPECT_NEAR(c.at("freq").get<double>(), 100.0, 1e-9);
  const std::string status = c.at("status");
  EXPECT_TRUE(status == "converged" || status == "not_converged") << status;
  EXPECT_TRUE(c.at("message").is_string());
  EXPECT_TRUE(c.at("objective").is_number());
  for (const char* k : {"statistic", "df", "p_value"}) EXPECT_TRUE(c.at("gof").contains(k)) << k;
  EXPECT_EQ(c.at("levels").size(), 16u);
  EXPECT_EQ(c.at("implied_wv").size(), 16u);
  EXPECT_EQ(c.at("model").get<std::string>().rfind("AR1(phi=", 0), 0u) << c.at("model");

  const json& p = c.at("parameters");
  ASSERT_EQ(p.size(), 4u);
  const char* names[] = {"phi", "sigma2", "sigma2", "gamma2"};
  const char* procs[] = {"AR1", "AR1", "WN", "RW"};
  const int comps[] = {1, 1, 2, 3};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(p[k].at("process"), procs[k]);
    EXPECT_EQ(p[k].at("component"), comps[k]);
    EXPECT_EQ(p[k].at("name"), names[k]);
    for (const char* f : {"value", "se", "ci_low", "ci_high"}) EXPECT_TRUE(p[k].contains(f)) << f;
  }
  // The simulated truth, within generous bounds for 2^16 samples.
  EXPECT_NEAR(p[0]["value"].get<double>(), 0.999, 0.003);
  EXPECT_NEAR(p[1]["value"].get<double>() / 1e-8, 1.0, 0.5);
  EXPECT_NEAR(p[2]["value"].get<double>() / 1e-5, 1.0, 0.05);
  EXPECT_GT(p[3]["value"].get<double>(), 0.0);

  // The fitted model string is usable as SPEC_WITH_VALUES.
  auto again = run_gmwm(
      {"simulate", "--model", c.at("model").get<std::string>(), "--n", "64", "--output", "refit.csv", "--quiet"}, dir_);
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

TEST_F(GmwmCli, ANegativeDriftSurvivesSimulateFitAndItsInterval) {
  // The WV sees omega^2; the sign must come back from the series through fit.
  auto r = run_gmwm({"simulate", "--model", "WN(sigma2=1)+DR(omega=-1e-3)", "--n", "65536", "--freq", "100", "--names",
                     "x", "--output", "dr.csv", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_gmwm({"fit", "dr.csv", "--model", "WN+DR", "--json", "f.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = read_json(dir_ / "f.json")["columns"][0];
  const std::string model = c.at("model");
  EXPECT_NE(model.find("DR(omega=-"), std::string::npos) << model;
  const json& p = c.at("parameters");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].at("process"), "DR");
  EXPECT_NEAR(p[1]["value"].get<double>() / -1e-3, 1.0, 0.05);
  EXPECT_LT(p[1]["ci_high"].get<double>(), 0.0);
  EXPECT_LT(p[1]["ci_low"].get<double>(), p[1]["value"].get<double>());
}

TEST_F(GmwmCli, ThreadCountDoesNotChangeTheWvOrFitJson) {
  simulate(1 << 14, 3);
  for (const std::string cmd : {"wv", "fit"}) {
    std::vector<json> docs;
    for (const std::string threads : {"1", "2"}) {
      std::vector<std::string> args = {cmd,      "sim.csv.gz", "--threads", threads, "--json", cmd + threads + ".json",
                                       "--quiet"};
      if (cmd == "fit") {
        args.push_back("--model");
        args.push_back("AR1+WN+RW");
      }
      auto r = run_gmwm(args, dir_);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      docs.push_back(read_json(dir_ / (cmd + threads + ".json")));
    }
    EXPECT_EQ(docs[0]["run"]["threads"], 1);
    EXPECT_EQ(docs[1]["run"]["threads"], 2);
    EXPECT_EQ(gmwm::test::without_run(docs[0]), gmwm::test::without_run(docs[1])) << cmd;
  }
}

TEST_F(GmwmCli, FitSelectAndWvReportTheAllanDeviationAsAStageOfItsOwn) {
  // Issue 27: the data's Allan deviation behind the noise figures comes from the WV's own
  // transforms, and run.seconds names its time; without a rate, or with the robust WV
  // (whose figures read the robust WV itself), there is none.
  simulate(20000, 1);
  const std::vector<std::vector<std::string>> runs = {{"fit", "sim.csv.gz", "--model", "WN+RW"},
                                                      {"select", "sim.csv.gz", "--model", "WN+RW"},
                                                      {"wv", "sim.csv.gz", "--adev"},
                                                      {"fit", "sim.csv.gz", "--model", "WN+RW", "--robust"}};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    std::vector<std::string> args = runs[i];
    args.insert(args.end(), {"--quiet", "--json", "r.json"});
    const auto r = run_gmwm(args, dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json seconds = read_json(dir_ / "r.json").at("run").at("seconds");
    for (const char* stage : {"read", "wv", "allan", "total"}) EXPECT_TRUE(seconds.contains(stage)) << stage;
    if (i < 3)
      EXPECT_GT(seconds.at("allan").get<double>(), 0.0) << args[0];
    else
      EXPECT_EQ(seconds.at("allan").get<double>(), 0.0);
    EXPECT_LE(seconds.at("wv").get<double>() + seconds.at("allan").get<double>(), seconds.at("total").get<double>());
  }
}

TEST_F(GmwmCli, FitWithTheModelBasedOmegaReportsAStatusAndExits0) {
  simulate(1 << 13, 1);
  auto r =
      run_gmwm({"fit", "sim.csv.gz", "--model", "AR1+WN", "--omega", "full", "--json", "fit.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fit.json");
  const std::string status = doc["columns"][0].at("status");
  EXPECT_TRUE(status == "converged" || status == "not_converged") << status;
  if (status == "not_converged") {
    EXPECT_NE(r.err.find("warning"), std::string::npos);
  }
  EXPECT_EQ(doc["columns"][0]["omega"], "full");
}

TEST_F(GmwmCli, RobustWvJsonHasTheDiagnosticFieldsAndTheLibrarysValues) {
  simulate(1 << 12, 1);
  auto r = run_gmwm({"wv", "sim.csv.gz", "--robust", "--eff", "0.8", "--estimator", "bisquare", "--json", "wv.json",
                     "--csv", "wv.csv", "--quiet"},
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json col = read_json(dir_ / "wv.json")["columns"][0];
  EXPECT_EQ(col.at("estimator"), "bisquare");
  EXPECT_DOUBLE_EQ(col.at("efficiency").get<double>(), 0.8);
  EXPECT_TRUE(col.at("quantization").contains("detected"));
  const auto set = gmwm::io::read_signals((dir_ / "sim.csv.gz").string(), {});
  const auto& x = set.signals[0].values;
  gmwm::robust::RobustWvOptions o;
  o.estimator = gmwm::robust::RobustKind::kBisquare;
  o.efficiency = 0.8;
  const auto robust = gmwm::robust::robust_wv(x.data(), static_cast<std::int64_t>(x.size()), o);
  const auto classical = gmwm::classical_wv(x.data(), static_cast<std::int64_t>(x.size()));
  expect_levels_equal_library(col.at("levels"), robust, set.freq);
  for (int j = 0; j < robust.levels(); ++j) {
    const json& l = col["levels"][static_cast<std::size_t>(j)];
    EXPECT_DOUBLE_EQ(l.at("classical_wv").get<double>(), classical.wv[static_cast<std::size_t>(j)]);
    EXPECT_DOUBLE_EQ(l.at("robust_to_classical").get<double>(),
                     robust.wv[static_cast<std::size_t>(j)] / classical.wv[static_cast<std::size_t>(j)]);
    EXPECT_TRUE(l.at("ci_disjoint").is_boolean());
    EXPECT_FALSE(l.at("contaminated").get<bool>()) << "clean simulated data flagged at level " << j + 1;
  }
  // How the estimator treated small samples and spikes is stated (clean data: no spikes).
  EXPECT_NE(col.at("small_sample").get<std::string>().find("bias correction"), std::string::npos);
  EXPECT_EQ(col.at("screening").at("replaced_samples").get<std::int64_t>(), 0);
  EXPECT_TRUE(col.at("screening").at("replaced_ranges").empty());
  EXPECT_EQ(col.at("screening").at("note").get<std::string>().rfind("spike screen: 0 samples", 0), 0u)
      << col.at("screening").at("note");
  EXPECT_TRUE(fs::exists(dir_ / "wv.csv"));
}

TEST_F(GmwmCli, RobustWvReportsTheReplacedSpikesAndCanKeepThem) {
  // Two spikes of 50 sd in simulated data: replaced by default and listed (0-based
  // sample ranges); --no-spike-screen keeps them and says so.
  simulate(1 << 12, 1);
  auto set = gmwm::io::read_signals((dir_ / "sim.csv.gz").string(), {});
  std::vector<double> x = set.signals[0].values.to_vector();
  double ms = 0.0;
  for (std::size_t t = 1; t < x.size(); ++t) ms += (x[t] - x[t - 1]) * (x[t] - x[t - 1]);
  const double sd = std::sqrt(ms / static_cast<double>(x.size()));  // of the increments
  x[1000] += 50.0 * sd;
  x[3000] -= 50.0 * sd;
  set.signals[0].values = std::move(x);
  gmwm::io::write_signals((dir_ / "spiky.csv").string(), set.signals, 100.0);
  auto r = run_gmwm({"wv", "spiky.csv", "--robust", "--json", "s.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json screening = read_json(dir_ / "s.json")["columns"][0].at("screening");
  EXPECT_EQ(screening.at("replaced_samples").get<int>(), 2);
  EXPECT_EQ(screening.at("replaced_ranges"), json::parse("[[1000, 1000], [3000, 3000]]"));
  auto off = run_gmwm({"wv", "spiky.csv", "--robust", "--no-spike-screen", "--json", "o.json", "--quiet"}, dir_);
  ASSERT_EQ(off.exit_code, 0) << off.err;
  const json kept = read_json(dir_ / "o.json")["columns"][0].at("screening");
  EXPECT_EQ(kept.at("note"), "spike screen off");
  EXPECT_EQ(kept.at("replaced_samples").get<int>(), 0);
}

TEST_F(GmwmCli, RobustFitUsesTheRobustWvAndInflatesTheModelBasedOmega) {
  simulate(1 << 13, 1);
  auto classical =
      run_gmwm({"fit", "sim.csv.gz", "--model", "AR1+WN", "--omega", "full", "--json", "c.json", "--quiet"}, dir_);
  auto robust = run_gmwm(
      {"fit", "sim.csv.gz", "--model", "AR1+WN", "--omega", "full", "--robust", "--json", "r.json", "--quiet"}, dir_);
  ASSERT_EQ(classical.exit_code, 0) << classical.err;
  ASSERT_EQ(robust.exit_code, 0) << robust.err;
  const json c = read_json(dir_ / "c.json")["columns"][0];
  const json r = read_json(dir_ / "r.json")["columns"][0];
  EXPECT_EQ(r["levels"][0]["wv"].get<double>() == c["levels"][0]["wv"].get<double>(), false)
      << "the robust fit must use the robust WV";
  // Efficiency 0.6: standard errors of the same parameters are larger (variance / 0.6).
  const double se_c = c["parameters"][0]["se"].get<double>(), se_r = r["parameters"][0]["se"].get<double>();
  EXPECT_GT(se_r, se_c);
}

TEST_F(GmwmCli, HelpAndVersionExit0) {
  EXPECT_EQ(run_gmwm({"--help"}, dir_).exit_code, 0);
  EXPECT_EQ(run_gmwm({"--version"}, dir_).exit_code, 0);
  for (const char* cmd : {"wv", "fit", "simulate"}) {
    auto r = run_gmwm({cmd, "--help"}, dir_);
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("--json"), std::string::npos) << cmd;
  }
}

TEST_F(GmwmCli, WvOfARealImuRecordingHasEveryLevel) {
  GMWM_REQUIRE_SHARED_DATA();
  const std::string file = gmwm::test::shared_data_file("adis_16405_imu1.csv.gz");
  auto r =
      run_gmwm({"wv", file, "--freq", "100", "--columns", "gyro_x,accel_z", "--json", "adis.json", "--quiet"}, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "adis.json");
  ASSERT_EQ(doc["columns"].size(), 2u);
  for (const auto& c : doc["columns"]) {
    EXPECT_EQ(c["n"], 1000000);
    ASSERT_EQ(c["levels"].size(), 19u);  // floor(log2 1e6)
    EXPECT_EQ(c["levels"][18]["coefficients"], 1000000 - (1 << 19) + 1);
    for (const auto& l : c["levels"]) EXPECT_GT(l["wv"].get<double>(), 0.0);
  }
}

TEST_F(GmwmCli, ShippedExampleIsReproducedByItsDocumentedCommand) {
  // The command of data/README.md, with the output in a temporary folder.
  auto r =
      run_gmwm({"simulate", "--model", "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-10)", "--n", "65536",
                "--freq", "100", "--signals", "6", "--names", "gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z",
                "--quantum", "1e-6", "--seed", "20261121", "--output", "example.csv.gz", "--quiet"},
               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto shipped =
      gmwm::io::read_signals((fs::path(GMWM_SOURCE_DIR) / "data" / "example_imu6.csv.gz").string(), {});
  const auto again = gmwm::io::read_signals((dir_ / "example.csv.gz").string(), {});
  ASSERT_EQ(shipped.signals.size(), 6u);
  ASSERT_EQ(again.signals.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(shipped.signals[k].name, again.signals[k].name);
    EXPECT_TRUE(shipped.signals[k].values == again.signals[k].values)
        << "data/example_imu6.csv.gz no longer matches its documented command (column " << shipped.signals[k].name
        << "): if the simulation changed on purpose, regenerate it as data/README.md says";
  }
}

TEST_F(GmwmCli, FitThatStopsBeforeConvergingExits0WithAWarningAndItsStatus) {
  auto r = run_gmwm({"fit", (fs::path(GMWM_SOURCE_DIR) / "data" / "example_imu6.csv.gz").string(), "--columns",
                     "gyro_x", "--model", "AR1+WN+RW", "--max-evaluations", "10", "--json", "fit.json", "--quiet"},
                    dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const json doc = read_json(dir_ / "fit.json");
  const json& c = doc["columns"][0];
  EXPECT_EQ(c.at("status"), "not_converged");
  EXPECT_FALSE(c.at("message").get<std::string>().empty());
  const auto err = gmwm::test::lines_of(r.err);
  ASSERT_EQ(err.size(), 1u) << r.err;
  EXPECT_EQ(err[0].rfind("gmwm: warning: ", 0), 0u) << err[0];
  EXPECT_NE(err[0].find("gyro_x"), std::string::npos) << err[0];
}

TEST_F(GmwmCli, ARecordBeyondTheMemoryOptionGivesTheSameWvFitAndSelectionFromTemporaryFiles) {
  // 2^19 samples of two columns need 16 MB at 16 bytes a value; --memory 4 (MB) sends
  // them to temporary files from the first check past 4 MB. Every result is the same.
  simulate(1 << 19, 2);
  const std::vector<std::vector<std::string>> runs = {{"wv", "sim.csv.gz", "--adev"},
                                                      {"fit", "sim.csv.gz", "--model", "AR1+WN+RW"},
                                                      {"select", "sim.csv.gz", "--model", "2*AR1+WN+RW"}};
  for (const auto& args : runs) {
    auto in_memory = args, spilled = args;
    in_memory.insert(in_memory.end(), {"--json", "a.json", "--quiet"});
    spilled.insert(spilled.end(), {"--memory", "4", "--json", "b.json", "--quiet"});
    ASSERT_EQ(run_gmwm(in_memory, dir_).exit_code, 0) << args[0];
    const auto r = run_gmwm(spilled, dir_);
    ASSERT_EQ(r.exit_code, 0) << args[0] << ": " << r.err;
    json a = gmwm::test::read_json(dir_ / "a.json"), b = gmwm::test::read_json(dir_ / "b.json");
    a.erase("run");
    b.erase("run");
    EXPECT_EQ(a, b) << args[0];
  }
}
