// The JSON documents (io/json_output.h) directly: null for non-finite numbers, full
// precision, the common top level, and a failed fit that has no values.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/report/json_output.h"

namespace {

using gmwm::report::Json;

TEST(GmwmJsonOutput, WritesNaNAndInfinityAsNull) {
  Json doc = gmwm::report::json_document("wv");
  doc["a"] = gmwm::report::json_number(std::numeric_limits<double>::quiet_NaN());
  doc["b"] = gmwm::report::json_number(-std::numeric_limits<double>::infinity());
  const Json back = Json::parse(gmwm::report::dump_json(doc));
  EXPECT_TRUE(back["a"].is_null());
  EXPECT_TRUE(back["b"].is_null());
}

TEST(GmwmJsonOutput, KeepsEveryDigitOfADouble) {
  const double x = 0.1 + 0.2;  // 0.30000000000000004
  Json doc = gmwm::report::json_document("wv");
  doc["x"] = gmwm::report::json_number(x);
  EXPECT_EQ(Json::parse(gmwm::report::dump_json(doc))["x"].get<double>(), x);
}

TEST(GmwmJsonOutput, StartsWithToolVersionCommandAndColumns) {
  const Json doc = gmwm::report::json_document("fit");
  auto it = doc.begin();
  EXPECT_EQ(it.key(), "tool");
  EXPECT_EQ((++it).key(), "version");
  EXPECT_EQ((++it).key(), "command");
  EXPECT_EQ((++it).key(), "columns");
  EXPECT_EQ(doc["tool"], "gmwm");
  EXPECT_EQ(doc["version"], gmwm::report::version());
}

TEST(GmwmJsonOutput, WvLevelsHaveNullSecondsWhenTheRateIsUnknown) {
  std::vector<double> x(64);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.7 * static_cast<double>(i * i));
  const auto wv = gmwm::classical_wv(x.data(), 64);
  const Json c = gmwm::report::wv_column_json({"x", 64, 0.0, false, {}}, wv);
  EXPECT_TRUE(c["freq"].is_null());
  ASSERT_EQ(c["levels"].size(), 6u);
  EXPECT_TRUE(c["levels"][0]["tau_seconds"].is_null());
  EXPECT_EQ(c["levels"][5]["coefficients"], 1);
}

TEST(GmwmJsonOutput, AFailedFitHasANullModelAndNoParameters) {
  std::vector<double> x(256);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.3 * static_cast<double>(i * i));
  const auto wv = gmwm::classical_wv(x.data(), 256);
  gmwm::FitResult fit;
  fit.model = gmwm::parse_model("AR1+WN");
  fit.theta = Eigen::VectorXd::Constant(3, std::numeric_limits<double>::quiet_NaN());
  fit.status = gmwm::FitStatus::kFailed;
  fit.message = "no starting point gave a finite objective";
  fit.objective = std::numeric_limits<double>::quiet_NaN();
  const Json c = gmwm::report::fit_column_json({"x", 256, 100.0, true, {}}, wv, fit, gmwm::OmegaKind::kDiag);
  EXPECT_TRUE(c["model"].is_null());
  EXPECT_TRUE(c["parameters"].empty());
  EXPECT_TRUE(c["objective"].is_null());
  EXPECT_EQ(c["status"], "failed");
  EXPECT_EQ(c["message"], fit.message);
  EXPECT_EQ(c["omega"], "diag");
}

}  // namespace
