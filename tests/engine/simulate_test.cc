// Simulation (simulate.h) at the ends of the doubles: every process's values scale exactly
// with its variances up to the largest a double holds, and a value beyond a double is
// refused naming the component, never returned (issue 42 item 12).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

namespace gmwm {
namespace {

TEST(Simulate, ScalesEveryProcessesValuesExactlyUpToTheLargestVariances) {
  // Data times 2^511 are the same model with its variances times 4^511 = 2^1022 (4.5e307;
  // Model::scaled): drawn from the same streams, every value is the unit model's times
  // 2^511 exactly (products and sums by a power of two do not round), so the values are
  // the right ones wherever a double holds them. QN formed 12 Q2 (inf) and ARMA sigma2
  // times its unit covariance (inf, then the eigen solver's NaN): every sample non-finite.
  const char* const kModels[] = {"WN(sigma2=1)",
                                 "QN(Q2=1)",
                                 "RW(gamma2=1)",
                                 "DR(omega=1)",
                                 "AR1(phi=0.999,sigma2=1)",
                                 "GM(beta=1,sigma2_gm=1)",
                                 "MA1(theta=0.9,sigma2=1)",
                                 "ARMA11(phi=0.999,theta=0.5,sigma2=1)",
                                 "ARMA(p=1,q=1,phi1=0.999,theta1=0.5,sigma2=1)",
                                 "SIN(A2=1,f=0.1)",
                                 "FLICKER(B2=1)"};
  constexpr std::int64_t kN = 4096;
  for (const char* spec : kModels) {
    const Model m = parse_model(spec, ProcessContext{100.0, true});
    const Eigen::VectorXd unit = m.given_values();
    const Eigen::VectorXd huge = m.scaled(unit, std::ldexp(1.0, 1022));
    const std::vector<double> a = simulate(m, unit, kN, 42), b = simulate(m, huge, kN, 42);
    for (std::int64_t k = 0; k < kN; ++k) {
      const auto i = static_cast<std::size_t>(k);
      ASSERT_EQ(b[i], std::ldexp(a[i], 511)) << spec << ", sample " << k;
    }
  }
}

TEST(Simulate, RefusesADriftBeyondTheLargestDoubleNamingTheComponentAndTheSample) {
  // omega t passes 1.8e308 at t = 1798 for omega = 1e305: was written as inf rows.
  const Model m = parse_model("WN(sigma2=1)+DR(omega=1e305)");
  try {
    simulate(m, m.given_values(), 10000, 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("component 2 (DR) takes the simulated series beyond the largest double "
                                         "(1.8e308) at sample 1798 of 10000"),
              std::string::npos)
        << e.what();
  }
  // Up to there, it holds: 1797 samples end at 1.797e308.
  const std::vector<double> x = simulate(m, m.given_values(), 1798, 1);
  EXPECT_TRUE(std::isfinite(x.back()));
  EXPECT_THROW(simulate_many(m, m.given_values(), 10000, 3, 1), InputError);
}

}  // namespace
}  // namespace gmwm
