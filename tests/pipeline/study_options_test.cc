// The studies' Options refuse what they own or cannot do, with one line naming the setting:
// the gap study sets GapOptions' per-column fields itself; the export derives its inflation
// with consistent_for, and only for the WN + RW formats.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/gap/gap.h"
#include "gmwm/pipeline/export_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/nav_study.h"
#include "gmwm/pipeline/select_study.h"

namespace gmwm::pipeline {
namespace {

TEST(GapStudyOptions, HandsDownTheDiagnosisSettingsAndRefusesTheStudysOwnFields) {
  GapStudyOptions o;
  o.baseline = ModelBaseline{"WN(sigma2=1)"};
  o.gap.max_steps = 1;
  o.gap.min_effect = 0.2;
  o.gap.candidates = {gap::GapEffect::kDR};
  EXPECT_EQ(o.Validate(), "");
  o.gap.unit = "deg/s";
  EXPECT_NE(o.Validate().find("leave gap.estimator, refit_baseline, context, unit, progress and missing unset"),
            std::string::npos);
  o.gap.unit.clear();
  o.gap.missing = {{10, 2}};  // the record's own gaps, which the study sets
  EXPECT_NE(o.Validate().find("missing unset: the study sets them per column"), std::string::npos);
  o.gap.missing.clear();
  o.gap.replicates = 5;
  EXPECT_EQ(o.Validate(), "replicates must be in [20, 100000], got 5");
}

TEST(GapCandidates, ParseTheWvEffectsAndRefuseTheSeriesOnesNamingTheKnownOnes) {
  EXPECT_EQ(gap::parse_gap_candidates("DR,AR1", "--effects"),
            (std::vector<gap::GapEffect>{gap::GapEffect::kDR, gap::GapEffect::kAR1}));
  try {
    gap::parse_gap_candidates("DR,OUTLIERS", "--effects");
    FAIL() << "OUTLIERS is tested on the series, not a WV candidate";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--effects 'DR,OUTLIERS': unknown effect 'OUTLIERS', expected some of WN, QN, RW, DR, AR1, FLICKER, "
              "SIN, REPARAMETERISE");
  }
  EXPECT_THROW(gap::parse_gap_candidates("", "effects"), InputError);
}

TEST(ExportStudyOptions, RefusesConsistentForWithAnInflationOrAGaussMarkovFormat) {
  ExportStudyOptions o;
  o.consistent_for = ConsistencyOptions{};
  EXPECT_EQ(o.Validate(), "");
  o.format.inflate = 2.0;
  EXPECT_EQ(o.Validate(), "--consistent-for derives the inflation; leave out --inflate");
  o.format.inflate = 1.0;
  o.format.format = io::ExportFormat::kGzSdf;
  EXPECT_NE(o.Validate().find("for the WN + RW formats"), std::string::npos);
}

TEST(ConsistencyFrom, TakesARateAHorizonAndAnOptionalUpdateErrorAsEveryFaceGivesThem) {
  const std::vector<double> two = {20.0, 60.0}, three = {20.0, 60.0, 0.1};
  const auto a = consistency_from(two);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->update_rate, 20.0);
  EXPECT_EQ(a->horizon, 60.0);
  EXPECT_EQ(a->fix_sigma, ConsistencyOptions{}.fix_sigma);  // the default update error
  const auto b = consistency_from(three);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->fix_sigma, 0.1);
  EXPECT_EQ(b->Validate(), "");
}

TEST(ConsistencyFrom, RefusesOneOrFourNumbersAndAnyNotPositiveAndFinite) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::vector<double>& v : std::vector<std::vector<double>>{
           {20.0}, {20.0, 60.0, 0.1, 1.0}, {}, {0.0, 60.0}, {20.0, -60.0}, {20.0, 60.0, nan}, {inf, 60.0}})
    EXPECT_FALSE(consistency_from(v)) << v.size() << " numbers";
}

TEST(ExportFit, RefusesAColumnWhoseUnitNobodySaidNamingIt) {
  io::SignalSet set;
  set.path = "run.csv";
  set.freq = 100.0;
  set.freq_known = true;
  std::vector<double> x(4096);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * static_cast<double>(i * i));
  set.signals.push_back({"gyro_x", x, ""});
  ExportFitOptions o;
  o.model = "WN";
  std::vector<std::string> warnings;
  try {
    fitted_export_columns(set, o, warnings);
    FAIL() << "a unit was assumed";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "run.csv: column 'gyro_x': the file does not say its unit; give --units gyro=UNIT (rad/s, deg/s or "
              "deg/h)");
  }
}

}  // namespace
}  // namespace gmwm::pipeline

namespace gmwm::pipeline {
namespace {

std::string select_models_error(const std::string& model, const std::string& models) {
  SelectStudyOptions o;
  try {
    set_select_models(o, model, models);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SelectModels, TakesAMaximalModelOrSplitsAListAtItsSemicolons) {
  SelectStudyOptions o;
  set_select_models(o, "3*AR1+WN", "");
  ASSERT_EQ(o.models.size(), 1u);
  EXPECT_EQ(o.models[0].text(), "3*AR1+WN");
  EXPECT_FALSE(o.listed);
  set_select_models(o, "", "WN+RW; AR1+WN ;QN");
  ASSERT_EQ(o.models.size(), 3u);
  EXPECT_TRUE(o.listed);
  EXPECT_EQ(o.models[1].text(), " AR1+WN ");
}

TEST(SelectModels, RefusesNeitherOrBothAndAnEmptyEntryNamingTheList) {
  EXPECT_EQ(select_models_error("", ""),
            "select: give either --model SPEC (every sub-model) or --models \"SPEC1;SPEC2;...\"");
  EXPECT_EQ(select_models_error("WN", "WN;RW"), select_models_error("", ""));
  EXPECT_EQ(select_models_error(" ", " \t"), select_models_error("", ""));
  EXPECT_EQ(select_models_error("", "WN;;RW"), "--models \"WN;;RW\": empty model in the list");
  EXPECT_EQ(select_models_error("", "WN;RW;"), "--models \"WN;RW;\": empty model in the list");
}

}  // namespace
}  // namespace gmwm::pipeline
