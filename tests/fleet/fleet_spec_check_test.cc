// A fleet's rows against its spec (fleet_study.h, check_spec) and its summary in mixed units:
// each figure converted to the limit's unit (B as the Allan minimum 0.664 B for an in-run
// stability), a bound decides only when within, the interval said, rows recorded in other
// units summarised in SI.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/fleet_spec.h"

using namespace gmwm;
using namespace gmwm::fleet;

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A gyro row in `unit` whose N is `n` (that unit per sqrt(Hz)) with a 10% interval, and B = `b`.
FleetRow gyro_row(const std::string& unit_id, const std::string& data_unit, double n, double b,
                  ReadoffStatus status = ReadoffStatus::kRead) {
  FleetRow r;
  r.unit = unit_id;
  r.model = "ADIS16405";
  r.group = "ADIS16405";
  r.axis = "gyro_x";
  r.data_unit = data_unit;
  r.figures_known = true;
  r.figures.white.figure.value = n;
  r.figures.white.figure.low = 0.9 * n;
  r.figures.white.figure.high = 1.1 * n;
  r.figures.white.figure.status = status;
  r.figures.instability.figure.value = b;
  r.figures.instability.figure.low = 0.9 * b;
  r.figures.instability.figure.high = 1.1 * b;
  r.figures.instability.figure.status = ReadoffStatus::kRead;
  r.figures.walk.figure.status = ReadoffStatus::kBound;
  return r;
}

io::FleetSpec adis_spec() {
  return io::parse_fleet_spec(
      "ADIS16405:\n  gyroscope:\n    angle_random_walk: 2 deg/sqrt(h)\n    in_run_bias_stability: 0.007 deg/s\n",
      "spec.yaml");
}

// N in deg/s/sqrt(Hz) of an angle random walk in deg/sqrt(h): ARW / 60.
constexpr double arw(double deg_per_sqrt_h) { return deg_per_sqrt_h / 60.0; }

TEST(FleetSpecCheck, ComparesEachFigureInTheLimitsOwnUnitWhateverTheDataUnit) {
  // 2.5 deg/sqrt(h) recorded in deg/s, the same in rad/s: both above 2 deg/sqrt(h).
  std::vector<FleetRow> rows = {gyro_row("A", "deg/s", arw(2.5), 0.005 / 0.6642824702679600),
                                gyro_row("B", "rad/s", arw(2.5) / kDegPerRad, 0.005 / 0.6642824702679600 / kDegPerRad),
                                gyro_row("C", "deg/s", arw(1.5), 0.009 / 0.6642824702679600)};
  check_spec(rows, adis_spec());
  for (const FleetRow& r : rows) ASSERT_EQ(r.spec.size(), 2u) << r.unit;
  EXPECT_NEAR(rows[0].spec[0].value, 2.5, 1e-12);
  EXPECT_NEAR(rows[1].spec[0].value, 2.5, 1e-12);
  EXPECT_EQ(rows[0].spec[0].verdict, SpecVerdict::kFail);
  EXPECT_EQ(rows[1].spec[0].verdict, SpecVerdict::kFail);
  EXPECT_EQ(rows[2].spec[0].verdict, SpecVerdict::kPass);
  // The interval 2.25-2.75 lies wholly above 2.
  EXPECT_NE(rows[0].spec[0].note.find("wholly above it"), std::string::npos) << rows[0].spec[0].note;
  // B against an in-run stability: 0.664 B is the Allan minimum (0.005 and 0.009 deg/s).
  EXPECT_EQ(rows[0].spec[1].figure, 'B');
  EXPECT_NEAR(rows[0].spec[1].value, 0.005, 1e-12);
  EXPECT_EQ(rows[0].spec[1].verdict, SpecVerdict::kPass);
  EXPECT_NEAR(rows[1].spec[1].value, 0.005, 1e-12);
  EXPECT_EQ(rows[2].spec[1].verdict, SpecVerdict::kFail);
  EXPECT_NE(rows[2].spec[1].note.find("0.664 B"), std::string::npos) << rows[2].spec[1].note;
}

TEST(FleetSpecCheck, ABoundDecidesOnlyWhenItIsWithinTheLimit) {
  std::vector<FleetRow> rows = {gyro_row("low", "deg/s", arw(1.0), 0.001, ReadoffStatus::kBound),
                                gyro_row("high", "deg/s", arw(3.0), 0.001, ReadoffStatus::kBound)};
  check_spec(rows, adis_spec());
  EXPECT_EQ(rows[0].spec[0].verdict, SpecVerdict::kPass);
  EXPECT_EQ(rows[1].spec[0].verdict, SpecVerdict::kUnknown);
  EXPECT_NE(rows[1].spec[0].note.find("cannot tell"), std::string::npos) << rows[1].spec[0].note;
}

TEST(FleetSpecCheck, SaysWhyARowIsNotChecked) {
  std::vector<FleetRow> rows = {gyro_row("A", "deg/s", arw(1.0), 0.001), gyro_row("B", "", arw(1.0), 0.001),
                                gyro_row("C", "deg/s", arw(1.0), 0.001)};
  rows[0].model = "BMI088";
  rows[1].data_unit = "";  // taken as SI from the column's name
  rows[2].axis = "temperature";
  rows[2].data_unit = "";
  check_spec(rows, adis_spec());
  EXPECT_TRUE(rows[0].spec.empty());
  EXPECT_EQ(rows[0].spec_note, "no limits in the spec for model BMI088's gyroscope");
  EXPECT_EQ(rows[1].spec.size(), 2u);
  EXPECT_NE(rows[1].spec_note.find("taken as SI (rad/s)"), std::string::npos) << rows[1].spec_note;
  EXPECT_TRUE(rows[2].spec.empty());
  EXPECT_NE(rows[2].spec_note.find("neither the unit nor the column's name"), std::string::npos);
}

TEST(FleetSummary, RowsRecordedInDifferentUnitsAreSummarisedInSi) {
  // Six units of one N, three recorded in deg/s and three in rad/s; a seventh at 3x in deg/s.
  std::vector<FleetRow> rows;
  for (int k = 0; k < 6; ++k)
    rows.push_back(
        k % 2 ? gyro_row("u" + std::to_string(k), "deg/s", 1e-3 * (1.0 + 0.01 * k), 1e-3)
              : gyro_row("u" + std::to_string(k), "rad/s", 1e-3 * (1.0 + 0.01 * k) / kDegPerRad, 1e-3 / kDegPerRad));
  rows.push_back(gyro_row("odd", "deg/s", 3e-3, 1e-3));
  const std::vector<FleetFigureSummary> s = fleet_summary(rows);
  ASSERT_EQ(s.size(), static_cast<std::size_t>(kFigureCount));  // N, K, B, Q, R
  EXPECT_EQ(s[0].unit, "rad/s");
  EXPECT_NEAR(s[0].median, 1.03e-3 / kDegPerRad, 1e-3 * 0.011 / kDegPerRad);
  EXPECT_EQ(s[0].flagged, std::vector<std::string>{"odd"});
  // One unit recorded in deg/s alone: its own unit.
  std::vector<FleetRow> one = {gyro_row("a", "deg/s", 1e-3, 1e-3)};
  EXPECT_EQ(fleet_summary(one)[0].unit, "deg/s");
}

}  // namespace
