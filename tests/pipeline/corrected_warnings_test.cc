// A corrected configuration is never silently worse than its input, nor more optimistic
// than the data's model (issue 43, item 6): the rule behind CorrectedColumn::warnings,
// which the header, the terminal, the JSON and the report all print.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/pipeline/corrected_config.h"

namespace gmwm::pipeline {
namespace {

gap::GapAssessment assessed(double objective, int outside, double navigation) {
  gap::GapAssessment a;
  a.objective = objective;
  a.levels_outside = outside;
  a.navigation_rms = navigation;
  return a;
}

CorrectedColumn column(gap::GapAssessment input, gap::GapAssessment file, gap::GapAssessment full) {
  CorrectedColumn c;
  c.name = "gyro_x";
  c.expressible = parse_model("WN(sigma2=1e-4)+RW(gamma2=1e-12)");
  c.expressible_theta = c.expressible.given_values();
  c.before = input;
  c.with_config = file;
  c.with_full = full;
  return c;
}

bool says(const std::vector<std::string>& lines, const std::string& what) {
  for (const auto& l : lines)
    if (l.find(what) != std::string::npos) return true;
  return false;
}

TEST(CorrectedColumnWarnings, AFileBetterThanItsInputAndAsCautiousAsTheModelGetsNone) {
  EXPECT_TRUE(
      corrected_column_warnings(column(assessed(2.76e5, 16, 1.0), assessed(40.0, 2, 1.1), assessed(12.0, 0, 1.2)))
          .empty());
}

TEST(CorrectedColumnWarnings, AFileWorseThanItsInputIsSaidWithBothObjectivesAndLevels) {
  // The accel_z: objective 2.76e5 -> 4.28e5, levels outside 16 -> 18.
  const auto w =
      corrected_column_warnings(column(assessed(2.76e5, 16, 1.0), assessed(4.28e5, 18, 1.0), assessed(30.0, 1, 1.0)));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(
      says(w, "worse than its input here: objective 2.76e+05 -> 4.28e+05 (full model 30), levels outside 16 -> 18"))
      << w[0];
  // More levels outside alone is said too, with the objective that fell; an objective within
  // the tolerance is not.
  const auto more =
      corrected_column_warnings(column(assessed(100.0, 3, 1.0), assessed(90.0, 4, 1.0), assessed(10.0, 0, 1.0)));
  ASSERT_EQ(more.size(), 1u);
  EXPECT_TRUE(says(more,
                   "more levels outside the model's band than its input here: levels outside 3 -> 4, though its "
                   "objective 100 -> 90"))
      << more[0];
  EXPECT_TRUE(corrected_column_warnings(column(assessed(100.0, 3, 1.0),
                                               assessed(100.0 * (1.0 + kWorseThanInputTolerance / 2.0), 3, 1.0),
                                               assessed(10.0, 0, 1.0)))
                  .empty());
}

TEST(CorrectedColumnWarnings, AFileMoreOptimisticThanTheDataModelIsSaidWithItsIntegratedError) {
  // The Kalibr gyro: 0.37 deg after 60 s against 1.18 deg for the data's own model.
  const auto w =
      corrected_column_warnings(column(assessed(50.0, 4, 2.0), assessed(20.0, 2, 0.37), assessed(10.0, 0, 1.18)));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(says(w, "more optimistic than the data's model")) << w[0];
  EXPECT_TRUE(says(w, "0.37 against the full model's 1.18")) << w[0];
  // Within kOptimisticShare of the model's: no warning.
  EXPECT_TRUE(corrected_column_warnings(column(assessed(50.0, 4, 2.0), assessed(20.0, 2, 0.9), assessed(10.0, 0, 1.0)))
                  .empty());
}

TEST(CorrectedColumnWarnings, AColumnWhoseFiguresAreKeptAsTheInputsGetsNone) {
  CorrectedColumn c = column(assessed(10.0, 1, 1.0), assessed(40.0, 5, 0.1), assessed(5.0, 0, 1.0));
  c.verdict = CorrectedVerdict::kKeptSubset;
  EXPECT_TRUE(corrected_column_warnings(c).empty());
}

}  // namespace
}  // namespace gmwm::pipeline
