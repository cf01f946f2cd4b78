// Kalman-filter terms of each process (engine/kalman.h): hand-computed values of q, F and
// the discrete R / Q_d at the filter's rate, and the argument checks.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gmwm/engine/check.h"
#include "gmwm/engine/kalman.h"
#include "gmwm/engine/process.h"
#include "gmwm/engine/process_registry.h"

namespace gmwm {
namespace {

std::unique_ptr<Process> make(const std::string& name) {
  return ProcessRegistry::instance().create(name, {ProcessContext{100.0, true}, {}});
}

KalmanTerm only(const std::string& name, std::vector<double> theta, double freq, double filter_rate) {
  const auto terms = make(name)->kalman(theta, freq, filter_rate);
  EXPECT_EQ(terms.size(), 1u) << name;
  return terms.front();
}

TEST(KalmanTerms, WhiteNoiseIsAMeasurementNoiseWhoseVarianceScalesWithTheFilterRate) {
  // EuRoC ADIS16448: sigma2 = 5.7583e-06 (rad/s)^2 per sample at 200 Hz, i.e.
  // q = N^2 = 5.7583e-06 / 200 = 2.87915e-08 (rad/s)^2/Hz (N = 1.6968e-04 rad/s/sqrt(Hz)).
  const KalmanTerm at_data_rate = only("WN", {5.7583e-06}, 200.0, 200.0);
  EXPECT_NEAR(at_data_rate.q, 2.87915e-08, 1e-13);
  EXPECT_NEAR(at_data_rate.discrete, 5.7583e-06, 1e-15);                             // R = sigma2 at the data rate
  EXPECT_NEAR(only("WN", {5.7583e-06}, 200.0, 100.0).discrete, 2.87915e-06, 1e-15);  // q x 100 Hz
  EXPECT_EQ(at_data_rate.q_unit, "U^2/Hz");
}

TEST(KalmanTerms, RandomWalkIsABiasStateWithQdEqualToQTimesDt) {
  // gamma2 = 1e-10 per sample at 100 Hz: q = K^2 = 1e-10 x 100 = 1e-8 U^2/s; at 200 Hz
  // Q_d = q / 200 = 5e-11.
  const KalmanTerm k = only("RW", {1e-10}, 100.0, 200.0);
  EXPECT_NEAR(k.q, 1e-8, 1e-20);
  EXPECT_EQ(k.transition, 1.0);
  EXPECT_NEAR(k.discrete, 5e-11, 1e-22);
}

TEST(KalmanTerms, Ar1AndGaussMarkovGiveTheExactDiscretisationOfTheSameState) {
  // T = 10 s at 100 Hz: phi = exp(-1/1000); stationary variance s2 = 4e-6, so the AR1's
  // innovation variance is s2 (1 - phi^2). q = 2 s2 / T = 8e-7 U^2/s. At the data rate
  // F = phi and Q_d = s2 (1 - phi^2) (the AR1's own innovation variance).
  const double phi = std::exp(-1.0 / 1000.0), s2 = 4e-6, inno = s2 * (1.0 - phi * phi);
  const KalmanTerm a = only("AR1", {phi, inno}, 100.0, 100.0);
  EXPECT_NEAR(a.q, 8e-7, 1e-17);
  EXPECT_NEAR(a.transition, phi, 1e-15);
  EXPECT_NEAR(a.discrete, inno, 1e-18);
  // GM(beta = 1/T, sigma2_gm = s2) is the same state.
  const KalmanTerm g = only("GM", {0.1, s2}, 100.0, 100.0);
  EXPECT_NEAR(g.q, a.q, 1e-17);
  EXPECT_NEAR(g.transition, a.transition, 1e-15);
  EXPECT_NEAR(g.discrete, a.discrete, 1e-18);
  // At 50 Hz: F = exp(-0.02 / 10), Q_d = s2 (1 - F^2).
  const KalmanTerm slow = only("AR1", {phi, inno}, 100.0, 50.0);
  EXPECT_NEAR(slow.transition, std::exp(-0.002), 1e-15);
  EXPECT_NEAR(slow.discrete, s2 * (1.0 - std::exp(-0.004)), 1e-18);
}

TEST(KalmanTerms, DriftIsANoiseFreeRateStateAndQuantizationAMeasurementNoise) {
  const KalmanTerm d = only("DR", {1e-6}, 100.0, 100.0);
  EXPECT_EQ(d.q, 0.0);
  EXPECT_NEAR(d.discrete, 1e-4, 1e-18);  // omega f
  // Q2 = 1e-8 at 100 Hz: Q = 1e-4 / 100 = 1e-6 U s; R = 2 Q^2 f_k^2 = 2e-8 at 100 Hz
  // (= 2 Q2, the variance of the difference of two rounding errors).
  EXPECT_NEAR(only("QN", {1e-8}, 100.0, 100.0).discrete, 2e-8, 1e-20);
}

TEST(KalmanTerms, ProcessesWithoutAFiniteStateSaySoInsteadOfANumber) {
  const KalmanTerm f = only("FLICKER", {1e-6}, 100.0, 100.0);
  EXPECT_TRUE(std::isnan(f.discrete));
  EXPECT_NE(f.note.find("Gauss-Markov"), std::string::npos);
  const KalmanTerm m = only("MA1", {0.5, 1.0}, 100.0, 100.0);
  EXPECT_NE(m.role.find("no finite"), std::string::npos);
}

TEST(KalmanTerms, RejectANonPositiveFilterRateAndAThetaOfTheWrongSize) {
  try {
    make("WN")->kalman(std::vector<double>{1.0}, 100.0, 0.0);
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("filter_rate"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make("AR1")->kalman(std::vector<double>{0.5}, 100.0, 100.0), InvalidArgument);
}

}  // namespace
}  // namespace gmwm
