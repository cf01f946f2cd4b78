// Physical quantities (engine/include/gmwm/engine/physical.h): unit rendering, the
// default conversion and the mapping of parameter intervals. The conversions of each
// process are tested in tests/engine/processes/<process>_test.cc.
#include "gmwm/engine/physical.h"

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/process.h"
#include "gmwm/engine/process_registry.h"

namespace gmwm {
namespace {

std::unique_ptr<Process> make(const std::string& name, const ProcessContext& ctx = {}) {
  return ProcessRegistry::instance().create(name, {ctx, {}});
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "no error";
}

TEST(RenderUnit, SubstitutesTheDataUnitAndCollectsSeconds) {
  EXPECT_EQ(render_unit("U/sqrt(Hz)", "deg/s"), "deg/s/sqrt(Hz)");
  EXPECT_EQ(render_unit("U/s/sqrt(Hz)", "deg/s"), "deg/s^2/sqrt(Hz)");
  EXPECT_EQ(render_unit("U/s/sqrt(Hz)", "m/s^2"), "m/s^3/sqrt(Hz)");
  EXPECT_EQ(render_unit("U*s", "deg/s"), "deg");
  EXPECT_EQ(render_unit("U*s", "m/s^2"), "m/s");
  EXPECT_EQ(render_unit("U*s", "g"), "g*s");
  EXPECT_EQ(render_unit("U/s", "rad/s"), "rad/s^2");
  EXPECT_EQ(render_unit("U", "rad/s"), "rad/s");
  EXPECT_EQ(render_unit("U/sqrt(Hz)", "g"), "g/sqrt(Hz)");
  EXPECT_EQ(render_unit("s", "deg/s"), "s");
  EXPECT_EQ(render_unit("Hz", "deg/s"), "Hz");
  EXPECT_EQ(render_unit("", "deg/s"), "");
}

TEST(RenderUnit, HandlesDimensionlessDataParenthesesAndUInADenominator) {
  EXPECT_EQ(render_unit("U", ""), "");
  EXPECT_EQ(render_unit("U/s", ""), "1/s");
  EXPECT_EQ(render_unit("U*s", ""), "s");
  EXPECT_EQ(render_unit("U*s", "1/s"), "");
  EXPECT_EQ(render_unit("U/sqrt(Hz)", "(deg/s)"), "(deg/s)/sqrt(Hz)");
  EXPECT_EQ(render_unit("1/U", "deg/s"), "s/deg");
  EXPECT_EQ(render_unit("U/s", "deg/h"), "deg/s/h");
}

TEST(PhysicalQuantities, DefaultReportsTheDiscreteParameters) {
  const auto p = make("MA1");
  const auto q = p->physical(std::vector<double>{0.4, 2.0}, 100.0);
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].name, "theta");
  EXPECT_EQ(q[0].value, 0.4);
  EXPECT_EQ(q[0].unit_pattern, "");
  EXPECT_NE(q[0].convention.find("MA1 coefficient"), std::string::npos);
}

TEST(PhysicalQuantities, CarryAKindThatCodePicksThemByNotTheirDisplayName) {
  struct Case {
    const char* process;
    std::vector<double> theta;
    std::vector<std::pair<PhysicalKind, const char*>> kinds;  // each quantity's kind and unit pattern
  };
  const std::vector<Case> cases = {
      {"WN", {1e-4}, {{PhysicalKind::kNoiseDensity, "U/sqrt(Hz)"}}},
      {"RW", {1e-8}, {{PhysicalKind::kRandomWalk, "U/s/sqrt(Hz)"}}},
      {"AR1", {0.9, 1e-4}, {{PhysicalKind::kCorrelationTime, "s"}, {PhysicalKind::kStationarySigma, "U"}}},
      {"GM", {0.1, 1e-4}, {{PhysicalKind::kCorrelationTime, "s"}, {PhysicalKind::kStationarySigma, "U"}}},
      {"DR", {1e-5}, {{PhysicalKind::kDriftRate, "U/s"}}},
      {"QN", {1e-6}, {{PhysicalKind::kQuantization, "U*s"}}},
      {"FLICKER", {1e-6}, {{PhysicalKind::kFlickerCoefficient, "U"}, {PhysicalKind::kBiasInstability, "U"}}},
      {"SIN", {1e-2, 0.01}, {{PhysicalKind::kAmplitude, "U"}, {PhysicalKind::kFrequency, "Hz"}}},
      {"MA1", {0.4, 2.0}, {{PhysicalKind::kParameter, ""}, {PhysicalKind::kParameter, ""}}},
  };
  for (const Case& c : cases) {
    const auto q = make(c.process)->physical(c.theta, 100.0);
    ASSERT_EQ(q.size(), c.kinds.size()) << c.process;
    for (std::size_t i = 0; i < q.size(); ++i) {
      EXPECT_EQ(q[i].kind, c.kinds[i].first) << c.process << " " << q[i].name;
      EXPECT_EQ(q[i].unit_pattern, c.kinds[i].second) << c.process << " " << q[i].name;
      if (q[i].kind != PhysicalKind::kParameter) EXPECT_EQ(quantity_of_kind(q, q[i].kind), q[i].value) << c.process;
    }
  }
  EXPECT_TRUE(
      std::isnan(quantity_of_kind(make("WN")->physical(std::vector<double>{1e-4}, 100.0), PhysicalKind::kRandomWalk)));
}

TEST(PhysicalQuantities, RejectAWrongSizeOrRateWithCheckMessages) {
  const auto p = make("WN");
  EXPECT_EQ(message_of([&] { p->physical(std::vector<double>{1.0}, 0.0); }),
            "Process::physical: freq is 0, but must be positive and finite");
  EXPECT_EQ(message_of([&] { p->physical(std::vector<double>{1.0}, INFINITY); }),
            "Process::physical: freq is inf, but must be positive and finite");
  EXPECT_EQ(message_of([&] {
              p->physical(std::vector<double>{1.0, 2.0}, 1.0);
            }),
            "Process::physical: size of theta (2) and size of parameters of WN (1) must match");
}

TEST(PhysicalInterval, MapsAOneParameterIntervalExactly) {
  // WN sigma2 in [4e-6, 9e-6] at 100 Hz: N in [sqrt(4e-8), sqrt(9e-8)] = [2e-4, 3e-4].
  const auto wn = make("WN");
  const auto wi =
      physical_interval(*wn, std::vector<double>{6e-6}, std::vector<double>{4e-6}, std::vector<double>{9e-6}, 100.0);
  ASSERT_EQ(wi.size(), 1u);
  EXPECT_NEAR(wi[0].low, 2e-4, 1e-16);
  EXPECT_NEAR(wi[0].high, 3e-4, 1e-16);
  // GM's T = 1 / beta is decreasing: beta in [1, 4] /s gives T in [0.25, 1] s.
  const auto gm = make("GM", {100.0, true});
  const auto gi = physical_interval(*gm, std::vector<double>{2.0, 3.0}, std::vector<double>{1.0, 2.0},
                                    std::vector<double>{4.0, 5.0}, 100.0);
  ASSERT_EQ(gi.size(), 2u);
  EXPECT_DOUBLE_EQ(gi[0].low, 0.25);
  EXPECT_DOUBLE_EQ(gi[0].high, 1.0);
  EXPECT_DOUBLE_EQ(gi[1].low, std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(gi[1].high, std::sqrt(5.0));
}

TEST(PhysicalInterval, TakesTheCornersForTwoParameterQuantities) {
  // AR1 at 10 Hz, phi in [0.8, 0.95], sigma2 in [0.5e-4, 2e-4]:
  //   T in [-1/(10 ln 0.8), -1/(10 ln 0.95)] = [0.44814201, 1.94957257] s (phi only);
  //   sigma in [sqrt(0.5e-4 / (1 - 0.64)), sqrt(2e-4 / (1 - 0.9025))] = [0.01178511, 0.04529108].
  const auto p = make("AR1");
  const auto r = physical_interval(*p, std::vector<double>{0.9, 1e-4}, std::vector<double>{0.8, 0.5e-4},
                                   std::vector<double>{0.95, 2e-4}, 10.0);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NEAR(r[0].low, 0.44814201177245505, 1e-14);
  EXPECT_NEAR(r[0].high, 1.949572574622367, 1e-13);
  EXPECT_NEAR(r[1].low, 0.011785113019775792, 1e-16);
  EXPECT_NEAR(r[1].high, 0.045291081365783824, 1e-16);
}

TEST(PhysicalInterval, FindsTheExtremumAtZeroOfAPhiIntervalAcrossZero) {
  // phi in [-0.5, 0.6], sigma2 in [0.5e-4, 2e-4] at 10 Hz: both quantities depend on |phi|
  // and are smallest at phi = 0: T in [0, -1/(10 ln 0.6)] = [0, 0.19576152];
  // sigma in [sqrt(0.5e-4), sqrt(2e-4 / (1 - 0.36))] = [0.00707107, 0.01767767].
  const auto p = make("AR1");
  const auto r = physical_interval(*p, std::vector<double>{0.3, 1e-4}, std::vector<double>{-0.5, 0.5e-4},
                                   std::vector<double>{0.6, 2e-4}, 10.0);
  EXPECT_EQ(r[0].low, 0.0);
  EXPECT_NEAR(r[0].high, 0.19576151889712176, 1e-15);
  EXPECT_NEAR(r[1].low, std::sqrt(0.5e-4), 1e-16);
  EXPECT_NEAR(r[1].high, 0.017677669529663688, 1e-16);
}

TEST(PhysicalInterval, GivesLimitsAtDomainEdgesAndNanForUnknownBounds) {
  const auto p = make("AR1");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // phi's upper bound at 1: T and sigma unbounded above.
  const auto edge = physical_interval(*p, std::vector<double>{0.9, 1.0}, std::vector<double>{0.5, 0.5},
                                      std::vector<double>{1.0, 2.0}, 1.0);
  EXPECT_TRUE(std::isinf(edge[0].high));
  EXPECT_TRUE(std::isinf(edge[1].high));
  EXPECT_NEAR(edge[0].low, 1.0 / std::log(2.0), 1e-15);
  // sigma2 without inference: the correlation time keeps its interval, sigma is NaN.
  const auto part = physical_interval(*p, std::vector<double>{0.9, 1.0}, std::vector<double>{0.5, nan},
                                      std::vector<double>{0.95, nan}, 1.0);
  EXPECT_NEAR(part[0].low, 1.0 / std::log(2.0), 1e-15);
  EXPECT_TRUE(std::isnan(part[1].low));
  EXPECT_TRUE(std::isnan(part[1].high));
}

TEST(PhysicalInterval, ContainsThePointEstimateAndRejectsBadArguments) {
  const auto p = make("SIN");
  const std::vector<double> theta{4.0, 0.1};
  const auto r = physical_interval(*p, theta, theta, theta, 50.0);
  EXPECT_DOUBLE_EQ(r[0].low, 2.0);
  EXPECT_DOUBLE_EQ(r[0].high, 2.0);
  EXPECT_DOUBLE_EQ(r[1].low, 5.0);
  EXPECT_DOUBLE_EQ(r[1].high, 5.0);
  EXPECT_EQ(message_of([&] {
              physical_interval(*p, theta, std::vector<double>{5.0, 0.05}, std::vector<double>{4.5, 0.2}, 50.0);
            }),
            "physical_interval: ci_low[0] is 5, but must be at most ci_high[0] = 4.5");
  EXPECT_EQ(message_of([&] { physical_interval(*p, theta, std::vector<double>{1.0}, theta, 50.0); }),
            "physical_interval: size of ci_low (1) and size of theta (2) must match");
  EXPECT_EQ(message_of([&] { physical_interval(*p, theta, theta, theta, -1.0); }),
            "Process::physical: freq is -1, but must be positive and finite");
}

}  // namespace
}  // namespace gmwm
