// The fleet's band of Allan deviations (fleet/fleet_band.h), computed by fleet/ and drawn by the
// page: median, min-max and 5-95% envelopes of the units' curves per tau.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gmwm/fleet/fleet_band.h"

namespace gmwm::fleet {
namespace {

AdevSeries series(std::vector<double> tau, std::vector<double> value) { return {std::move(tau), std::move(value)}; }

TEST(FleetAdevBand, OnOneGridTakesTheMedianAndTheExtremesOfTheUnitsAtEachTau) {
  const std::vector<AdevSeries> units = {series({0.1, 1.0}, {1.0, 4.0}), series({0.1, 1.0}, {2.0, 1.0}),
                                         series({0.1, 1.0}, {4.0, 2.0})};
  const FleetAdevBand b = adev_band(units);
  EXPECT_FALSE(b.interpolated);
  EXPECT_FALSE(b.percentiles) << "3 units: no 5-95% envelope below " << kBandPercentileUnits;
  ASSERT_EQ(b.tau, (std::vector<double>{0.1, 1.0}));
  EXPECT_DOUBLE_EQ(b.median[0], 2.0);
  EXPECT_DOUBLE_EQ(b.median[1], 2.0);
  EXPECT_EQ(b.min, (std::vector<double>{1.0, 1.0}));
  EXPECT_EQ(b.max, (std::vector<double>{4.0, 4.0}));
  EXPECT_TRUE(std::isnan(b.p05[0]) && std::isnan(b.p95[1]));
  EXPECT_EQ(b.count, (std::vector<int>{3, 3}));
}

TEST(FleetAdevBand, TheMedianOfAnEvenCountIsTheGeometricMeanOfTheMiddleTwo) {
  const FleetAdevBand b = adev_band({series({1.0}, {1.0}), series({1.0}, {4.0})});
  EXPECT_NEAR(b.median[0], 2.0, 1e-15);
}

TEST(FleetAdevBand, FromTwentyUnitsDrawsTheFiveToNinetyFivePercentEnvelopeOfTheLogs) {
  // Values e^0 .. e^19: the type-7 quantiles of the logs are 0.05 * 19 = 0.95 and 18.05.
  std::vector<AdevSeries> units;
  for (int k = 0; k < kBandPercentileUnits; ++k) units.push_back(series({1.0}, {std::exp(k)}));
  const FleetAdevBand b = adev_band(units);
  ASSERT_TRUE(b.percentiles);
  EXPECT_NEAR(std::log(b.p05[0]), 0.95, 1e-12);
  EXPECT_NEAR(std::log(b.p95[0]), 18.05, 1e-12);
  EXPECT_NEAR(std::log(b.median[0]), 9.5, 1e-12);
}

TEST(FleetAdevBand, UnitsOnDifferentGridsAreInterpolatedInLogLogOnACommonOne) {
  // A -1/2 slope on both: the interpolated values stay on the line tau^-1/2.
  const FleetAdevBand b =
      adev_band({series({1.0, 100.0}, {1.0, 0.1}), series({1.0, 10.0, 100.0}, {1.0, std::sqrt(0.1), 0.1})});
  EXPECT_TRUE(b.interpolated);
  ASSERT_GE(b.tau.size(), 3u);
  for (std::size_t i = 0; i < b.tau.size(); ++i) EXPECT_NEAR(b.median[i], 1.0 / std::sqrt(b.tau[i]), 1e-12);
}

TEST(FleetAdevBand, KeepsOnlyPositiveFiniteDeviationsOfAUnitInTheSummaryUnit) {
  AllanDeviation a;
  a.tau = {0.01, 0.02, 0.04};
  a.adev = {2.0, 0.0, NAN};
  const AdevSeries s = positive_series(a, 0.5);
  EXPECT_EQ(s.tau, (std::vector<double>{0.01}));
  EXPECT_EQ(s.value, (std::vector<double>{1.0}));
  EXPECT_EQ(adev_band({}).units, 0);
}

}  // namespace
}  // namespace gmwm::fleet
