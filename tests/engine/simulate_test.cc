// Simulation (simulate.h) at the ends of the doubles: every process's values scale exactly
// with its variances up to the largest a double holds, and a value beyond a double is
// refused naming the component, never returned (issue 42 item 12).
#include <gtest/gtest.h>

#include <boost/random/normal_distribution.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
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

TEST(Simulate, AddsInterleavedAr1PathsAsEachComponentAddingItsOwnPathInOrder) {
  // Runs of consecutive AR1 / GM components are simulated in one interleaved pass (four
  // recursions at a time): the series must be, bit for bit, the components' own simulate
  // from their streams added one after another in model order. Five AR1-like components in
  // a row (a run of four and one more), a WN between, one alone, a length not a multiple
  // of the runs of draws (512).
  const Model m = parse_model(
      "AR1(phi=0.9,sigma2=1)+AR1(phi=-0.5,sigma2=2)+GM(beta=3,sigma2_gm=0.5)+AR1(phi=0.999,sigma2=1e-3)+"
      "AR1(phi=0.1,sigma2=4)+WN(sigma2=1)+AR1(phi=0.5,sigma2=1)+RW(gamma2=1e-4)",
      ProcessContext{100.0, true});
  const Eigen::VectorXd theta = m.given_values();
  for (const std::int64_t n : {std::int64_t{1}, std::int64_t{513}, std::int64_t{5000}}) {
    const std::vector<double> x = simulate(m, theta, n, 7, 3);
    std::vector<double> y(static_cast<std::size_t>(n), 0.0);
    for (int c = 0; c < m.num_components(); ++c) {
      const auto& p = *m.components()[static_cast<std::size_t>(c)].process;
      Rng rng = make_stream(7, {3, static_cast<std::uint64_t>(c)});
      const double* th = theta.data() + m.offset(c);
      if (p.name() != "AR1") {
        p.simulate({th, static_cast<std::size_t>(p.size())}, rng, y);
        continue;
      }
      // The AR1 by its definition, one Boost normal call per sample.
      boost::random::normal_distribution<double> z(0.0, 1.0);
      const double phi = th[0], sd = std::sqrt(th[1]);
      double v = sd / std::sqrt((1.0 - phi) * (1.0 + phi)) * z(rng);
      y[0] += v;
      for (std::size_t t = 1; t < y.size(); ++t) {
        v = phi * v + sd * z(rng);
        y[t] += v;
      }
    }
    for (std::size_t k = 0; k < y.size(); ++k) ASSERT_EQ(x[k], y[k]) << "n " << n << ", sample " << k;
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
