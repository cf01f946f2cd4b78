// Each process's continuous-time Gauss-Markov form (process.h, ContinuousForm), which the
// navigation-error analysis (nav/) propagates: its shapes over every registered process,
// and the figures it must keep against the discrete process it stands for.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/process.h"
#include "gmwm/engine/process_registry.h"
#include "processes/process_test_support.h"

namespace gmwm {
namespace {

constexpr double kFreq = 100.0;  // Hz

ContinuousForm form_of(const std::string& spec) {
  const Model m = parse_model(spec, ProcessContext{kFreq, true});
  const Eigen::VectorXd theta = m.given_values();
  const Process& p = *m.components().front().process;
  const auto f = p.continuous_form({theta.data(), static_cast<std::size_t>(theta.size())}, kFreq);
  EXPECT_TRUE(f.has_value()) << spec;
  return f.value_or(ContinuousForm{});
}

TEST(ContinuousForm, EveryRegisteredProcessGivesAWellShapedFormOrNone) {
  for (const auto& n : ProcessRegistry::instance().names()) {
    if (n == "MYWN") continue;  // a test's own (process_registry_test.cc)
    const ProcessContext at{kFreq, true};
    const std::map<std::string, long> structure =
        n == "ARMA" ? std::map<std::string, long>{{"p", 2}, {"q", 1}} : std::map<std::string, long>{};
    const auto p = test::make_process(n, structure, at);
    const std::vector<double> theta = p->initial_guess({});
    const auto f = p->continuous_form(theta, kFreq);
    if (!f) continue;
    const int k = f->states();
    EXPECT_EQ(f->Qc.rows(), k) << n;
    EXPECT_EQ(f->P0.rows(), k) << n;
    EXPECT_EQ(f->H.cols(), k) << n;
    EXPECT_GE(f->white, 0.0) << n;
    if (k > 0) {
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(f->P0).eigenvalues().minCoeff(), 0.0) << n;
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(f->Qc).eigenvalues().minCoeff(), 0.0) << n;
    }
  }
}

TEST(ContinuousForm, AWhiteNoiseIsItsDensityAndARandomWalkItsRate) {
  const ContinuousForm wn = form_of("WN(sigma2=4e-6)");
  EXPECT_EQ(wn.states(), 0);
  EXPECT_DOUBLE_EQ(wn.white, 4e-6 / kFreq);  // N^2 = sigma2 / f
  const ContinuousForm rw = form_of("RW(gamma2=1e-10)");
  ASSERT_EQ(rw.states(), 1);
  EXPECT_DOUBLE_EQ(rw.F(0, 0), 0.0);
  EXPECT_DOUBLE_EQ(rw.Qc(0, 0), 1e-10 * kFreq);  // K^2 = gamma2 f
}

// The growth rate of the variance of dt times the sum of an AR1's samples, from its
// autocovariances: dt sigma2 / (1 - phi)^2 per second (the long-run variance of the
// samples, sigma2 / (1 - phi)^2, times dt^2 per sample, over dt seconds per sample).
double samples_growth(double phi, double sigma2) { return sigma2 / ((1.0 - phi) * (1.0 - phi)) / kFreq; }

TEST(ContinuousForm, AnAr1sIntegralGrowsAsItsSamplesSumDoesFastOrSlow) {
  // The state's integral grows at 2 s2 T; the form's white part adds what the samples'
  // rectangle sum has beyond it (21% for phi = 0.16, 1e-7 relative for phi = 0.999).
  for (const double phi : {0.16, 0.5, 0.9, 0.999, 0.99999}) {
    const double sigma2 = 1e-6;
    const ContinuousForm f = form_of("AR1(phi=" + std::to_string(phi) + ",sigma2=1e-6)");
    ASSERT_EQ(f.states(), 1);
    const double T = -1.0 / f.F(0, 0), s2 = f.P0(0, 0);
    EXPECT_NEAR(T, -1.0 / (kFreq * std::log(phi)), 1e-12 * T);
    EXPECT_NEAR(s2, sigma2 / (1.0 - phi * phi), 1e-12 * s2);
    const double growth = 2.0 * s2 * T + f.white, want = samples_growth(phi, sigma2);
    EXPECT_NEAR(growth, want, 1e-9 * want) << "phi = " << phi;
  }
  EXPECT_GT(form_of("AR1(phi=0.16,sigma2=1e-6)").white, 0.2 * samples_growth(0.16, 1e-6) / 1.21);
}

TEST(ContinuousForm, AGaussMarkovIsTheAr1AtItsRate) {
  // GM(beta, sigma2_gm) at f is AR1(phi = exp(-beta / f)): T = 1 / beta, s2 = sigma2_gm,
  // and the same excess of its samples' sum, s2 dt (1 + phi) / (1 - phi) - 2 s2 T.
  const ContinuousForm gm = form_of("GM(beta=0.5,sigma2_gm=2e-6)");
  const double dt = 1.0 / kFreq, phi = std::exp(-0.5 * dt), T = 2.0, s2 = 2e-6;
  EXPECT_NEAR(gm.F(0, 0), -1.0 / T, 1e-15);
  EXPECT_NEAR(gm.P0(0, 0), s2, 1e-20);
  const double w = s2 * dt * (1.0 + phi) / (1.0 - phi) - 2.0 * s2 * T;  // L = 0.005: 3e-6 relative of the growth
  EXPECT_NEAR(gm.white, w, 1e-6 * w);  // the difference above loses ~6 of its 16 digits
}

TEST(ContinuousForm, ADriftIsARampOfItsRateAndQuantizationHasNoStateButANote) {
  const ContinuousForm dr = form_of("DR(omega=1e-7)");
  ASSERT_EQ(dr.states(), 2);
  EXPECT_DOUBLE_EQ(dr.P0(1, 1), (1e-7 * kFreq) * (1e-7 * kFreq));  // R = omega f per second
  EXPECT_DOUBLE_EQ(dr.F(0, 1), 1.0);
  const ContinuousForm qn = form_of("QN(Q2=1e-6)");
  EXPECT_EQ(qn.states(), 0);
  EXPECT_EQ(qn.white, 0.0);
  EXPECT_FALSE(qn.notes.empty());
}

TEST(ContinuousForm, AFlickerIsOneGaussMarkovStatePerThreeOctavesWithTheOctavesVariance) {
  // FLICKER(B2) is one AR1 per octave 2^0..2^40 samples, each of variance B2 ln2 / pi: the
  // form groups them by three (14 states), keeping the total variance.
  const ContinuousForm f = form_of("FLICKER(B2=1e-6)");
  ASSERT_EQ(f.states(), 14);
  const double per_octave = 1e-6 * std::log(2.0) / 3.14159265358979323846;
  EXPECT_NEAR(f.P0.trace(), 41.0 * per_octave, 1e-12 * 41.0 * per_octave);
  EXPECT_NEAR(-1.0 / f.F(0, 0), 2.0 / kFreq, 1e-15);  // octaves 0..2: 2^1 samples
  EXPECT_FALSE(f.notes.empty());
}

TEST(ContinuousForm, IsNoneForAnOscillatingAr1AndASinusoid) {
  const Model m = parse_model("AR1(phi=-0.5,sigma2=1)");
  const Eigen::VectorXd t = m.given_values();
  EXPECT_FALSE(m.components().front().process->continuous_form({t.data(), 2}, kFreq).has_value());
  const Model s = parse_model("SIN(A2=1,f=0.1)");
  const Eigen::VectorXd ts = s.given_values();
  EXPECT_FALSE(s.components().front().process->continuous_form({ts.data(), 2}, kFreq).has_value());
}

}  // namespace
}  // namespace gmwm
