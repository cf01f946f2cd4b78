// Adding a process touches its own file, its test and one registry line (docs/extending.md,
// "A process"). This file is that recipe carried out for a test-only type: SDWN, a white
// noise parameterised by its standard deviation sigma (WV sigma^2 / tau). Its WV is written
// once over the scalar type, and JetDifferentiated gives the Jacobian and the Hessian; its
// role (white) is what the modules that explain a model ask of it. Registered here with one
// line, it parses, simulates, fits and passes the battery every built-in process passes.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <boost/random/normal_distribution.hpp>
#include <gtest/gtest.h>

#include "../../../engine/src/processes/process_util.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/process_registry.h"
#include "gmwm/engine/simulate.h"
#include "process_test_support.h"

namespace gmwm::test {
namespace {

class SdWhiteNoise final : public internal::JetDifferentiated<SdWhiteNoise, 1> {
 public:
  std::string name() const override { return "SDWN"; }
  ProcessRole role() const override { return ProcessRole::kWhite; }
  int canonical_rank() const override { return 55; }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> specs{{"sigma", Transform::kLog, "white-noise standard deviation"}};
    return specs;
  }
  void wv(std::span<const double> theta, std::span<const double> tau, std::span<double> out) const override {
    for (std::size_t k = 0; k < tau.size(); ++k) out[k] = theta[0] * theta[0] / tau[k];
  }
  template <class J>
  void derivatives(std::span<const double> theta, std::span<const double> tau, Eigen::Ref<Eigen::MatrixXd>* jac,
                   Eigen::Ref<Eigen::MatrixXd>* hess, std::span<double>* value = nullptr) const {
    const J s = J::variable(theta[0], 0);
    for (std::size_t k = 0; k < tau.size(); ++k)
      internal::store_jet_row(s * s / tau[k], static_cast<Eigen::Index>(k), jac, hess, value);
  }
  void generalized_autocovariance(std::span<const double> theta, std::span<double> out) const override {
    std::fill(out.begin(), out.end(), 0.0);
    if (!out.empty()) out[0] = theta[0] * theta[0];
  }
  void simulate(std::span<const double> theta, Rng& rng, std::span<double> out) const override {
    boost::random::normal_distribution<double> z(0.0, theta[0]);
    for (double& v : out) v += z(rng);
  }
  std::vector<double> initial_guess(const GuessContext& ctx) const override {
    const double s2 = ctx.tau.empty() ? 1.0 : ctx.tau[0] * ctx.wv[0];
    return {s2 > 0.0 && std::isfinite(s2) ? std::sqrt(s2) : 1.0};
  }
  // sigma is a standard deviation: the data times sqrt(c) have sigma times sqrt(c) (the
  // default would take every log-transformed parameter for a variance).
  std::vector<double> scaled(std::span<const double> theta, double c) const override {
    return {theta[0] * std::sqrt(c)};
  }
};

// The one registry line (an application's own type; a built-in one is a line in
// engine/src/processes/builtin_processes.h instead).
void register_sdwn() {
  ProcessRegistry::instance().add(
      {"SDWN", {}, [](const ProcessArgs&) { return std::make_unique<SdWhiteNoise>(); }, "white noise: SDWN(sigma)"});
}

TEST(AddedProcess, ParsesInModelStringsOnceRegisteredWithOneLine) {
  register_sdwn();
  const Model m = parse_model("RW+SDWN(sigma=2)").canonical();
  ASSERT_EQ(m.num_components(), 2);
  EXPECT_EQ(m.components()[0].process->name(), "SDWN");  // canonical rank 55: after WN, before QN
  EXPECT_EQ(m.given_values()(0), 2.0);
}

TEST(AddedProcess, GetsItsJacobianAndHessianFromTheOneWrittenWaveletVariance) {
  register_sdwn();
  const SdWhiteNoise p;
  expect_derivatives_match_finite_differences(p, {0.7}, dyadic_scales(8));
  // The WV of SDWN(sigma) is WN(sigma^2)'s.
  const std::vector<double> theta{0.7}, wn_theta{0.49};
  expect_all_relatively_near(wv_of(p, theta, dyadic_scales(8)), wv_of(*make_process("WN"), wn_theta, dyadic_scales(8)),
                             1e-15, "SDWN(0.7) against WN(0.49)");
  expect_all_relatively_near(wv_from_autocovariance(p, theta, dyadic_scales(8)), wv_of(p, theta, dyadic_scales(8)),
                             1e-12, "SDWN from g");
}

TEST(AddedProcess, IsAskedItsRoleAsTheBuiltInWhiteNoiseIs) {
  register_sdwn();
  const Model m = parse_model("SDWN+RW");
  EXPECT_EQ(m.components()[0].process->role(), make_process("WN")->role());
  EXPECT_STREQ(to_string(m.components()[0].process->role()), "white");
  EXPECT_TRUE(single_per_model(m.components()[0].process->role()));
  EXPECT_FALSE(m.components()[0].process->correlation_samples(std::vector<double>{1.0}).has_value());
}

TEST(AddedProcess, FitsSimulatedDataRecoveringItsStandardDeviation) {
  // SDWN(sigma = 2) + RW(gamma2 = 1e-3), 2^16 samples: sigma's estimate within 4 of its
  // standard errors (a two-sided 6e-5 bar) of the truth.
  register_sdwn();
  const Model truth = parse_model("SDWN(sigma=2)+RW(gamma2=1e-3)");
  const std::int64_t n = 1 << 16;
  const auto x = simulate(truth, truth.given_values(), n, 23, 0);
  const FitResult r = fit_gmwm(classical_wv(x.data(), n), parse_model("SDWN+RW"));
  ASSERT_EQ(r.status, FitStatus::kConverged) << r.message;
  ASSERT_GT(r.se.size(), 0);
  EXPECT_NEAR(r.theta(0), 2.0, 4.0 * r.se(0));
}

TEST(AddedProcess, IsScaledAsAStandardDeviationWhereTheDefaultWouldScaleAVariance) {
  const SdWhiteNoise p;
  const std::vector<double> theta{0.5};
  std::vector<double> base(4), scaled(4);
  const auto tau = dyadic_scales(4);
  p.wv(theta, tau, base);
  p.wv(p.scaled(theta, 16.0), tau, scaled);
  for (std::size_t k = 0; k < tau.size(); ++k) EXPECT_DOUBLE_EQ(scaled[k], 16.0 * base[k]);
}

}  // namespace
}  // namespace gmwm::test
