#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"

namespace gmwm {
namespace {

std::string error_of(const std::string& spec) {
  try {
    parse_model(spec);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModelSyntax, ParsesRepeatsWithAndWithoutParentheses) {
  const Model a = parse_model("3*AR1()+WN()+RW()");
  const Model b = parse_model("3*AR1+WN+RW");
  EXPECT_EQ(a.num_components(), 5);
  EXPECT_EQ(a.num_parameters(), 8);
  EXPECT_EQ(a.to_string(), "3*AR1+WN+RW");
  EXPECT_EQ(b.to_string(), a.to_string());
}

TEST(ModelSyntax, IsCaseInsensitiveAndIgnoresSpaces) {
  EXPECT_EQ(parse_model(" wn ( sigma2 = 0.5 ) + rw ").to_string(), "WN+RW");
}

TEST(ModelSyntax, CanonicalOrderPutsAr1ByIncreasingPhiFirst) {
  const Model m = parse_model("RW+WN(sigma2=1)+AR1(phi=0.9,sigma2=1)+AR1(phi=0.1,sigma2=2)+QN+DR");
  Eigen::VectorXd theta(m.num_parameters());
  theta << 1e-4, 1.0, 0.9, 1.0, 0.1, 2.0, 0.01, 0.001;
  const Model c = m.canonical(&theta);
  EXPECT_EQ(c.to_string(), "2*AR1+WN+QN+RW+DR");
  EXPECT_EQ(c.to_string(theta),
            "AR1(phi=0.10000000000000001,sigma2=2)+AR1(phi=0.90000000000000002,sigma2=1)+"
            "WN(sigma2=1)+QN(Q2=0.01)+RW(gamma2=0.0001)+DR(omega=0.001)");
}

TEST(ModelSyntax, ValuesRoundTripThroughTheCanonicalString) {
  const Model m = parse_model("AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=0.01)");
  ASSERT_TRUE(m.fully_specified());
  const Eigen::VectorXd theta = m.given_values();
  const Model again = parse_model(m.to_string(theta));
  EXPECT_EQ((again.given_values() - theta).norm(), 0.0);
}

TEST(ModelSyntax, RejectsAnUnknownProcessNamingItAndItsColumn) {
  const std::string e = error_of("WN+FOO()");
  EXPECT_NE(e.find("unknown process 'FOO' at column 4"), std::string::npos) << e;
}

TEST(ModelSyntax, RejectsAnUnknownParameterListingTheValidOnes) {
  EXPECT_EQ(error_of("WN(sigma=1)"), "model 'WN(sigma=1)': WN has no parameter 'sigma' (parameters: sigma2)");
}

TEST(ModelSyntax, RejectsMalformedStringsSayingWhatWasExpected) {
  EXPECT_EQ(error_of("WN+"),
            "model 'WN+', column 4: found the end of the model, expected a process name such as WN, AR1 or RW");
  EXPECT_EQ(error_of("WN(sigma2=)"), "model 'WN(sigma2=)', column 11: found ')', expected a finite number");
  EXPECT_EQ(error_of("WN RW"), "model 'WN RW', column 4: found 'R', expected '+' or the end of the model");
  EXPECT_EQ(error_of(""), "model '', column 1: found an empty model, expected a process name such as WN or 3*AR1");
  EXPECT_EQ(error_of("3 AR1"), "model '3 AR1', column 3: found 'A', expected '*' after a repeat count");
  EXPECT_EQ(error_of("WN(sigma2=1"), "model 'WN(sigma2=1', column 12: found the end of the model, expected ',' or ')'");
}

TEST(ModelSyntax, RejectsANegativeVarianceGivenAsAStartingValue) {
  EXPECT_EQ(error_of("WN(sigma2=-0.5)"), "model 'WN(sigma2=-0.5)': WN: sigma2 must be positive (got -0.5)");
}

TEST(ModelSyntax, RejectsRepeatedWhiteNoiseAsNotIdentifiable) {
  const std::string e = error_of("2*WN");
  EXPECT_NE(e.find("WN appears more than once"), std::string::npos) << e;
}

TEST(ModelSyntax, RejectsMoreParametersThanLevels) {
  const Model m = parse_model("3*AR1+WN+RW+QN+DR");
  EXPECT_THROW(check_model_fits_levels(m, 9), InputError);
  EXPECT_NO_THROW(check_model_fits_levels(m, 10));
}

}  // namespace
}  // namespace gmwm

namespace gmwm {
namespace {

std::string spec_error(const std::string& text) {
  try {
    ModelSpec{text};
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModelSpec, ChecksTheTextWithoutTheRateAndTheValuesWhenBound) {
  // SIN's f in Hz: 2 Hz is a valid frequency at 100 Hz, not 2 cycles per sample.
  const ModelSpec sin("SIN(A2=1e-4,f=2)+WN");
  EXPECT_EQ(sin.text(), "SIN(A2=1e-4,f=2)+WN");
  const Model at_100 = sin.bind(ProcessContext{100.0, true});
  EXPECT_DOUBLE_EQ(at_100.given_values()(1), 0.02);  // cycles per sample
  EXPECT_THROW(sin.bind(ProcessContext{}), InputError);
  // A value out of range is the binding's to refuse, as parse_model does.
  const ModelSpec phi("AR1(phi=2)");
  try {
    phi.bind(ProcessContext{});
    FAIL() << "phi = 2 bound";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("phi"), std::string::npos) << e.what();
  }
}

TEST(ModelSpec, RefusesWhatNoRateCouldMendWithParseModelsMessage) {
  EXPECT_EQ(spec_error("2*AR1+FOO"), error_of("2*AR1+FOO"));
  EXPECT_EQ(spec_error("WN+WN"), error_of("WN+WN"));
  EXPECT_EQ(spec_error("AR1(rho=0.5)"), error_of("AR1(rho=0.5)"));
  EXPECT_EQ(spec_error("WN(sigma2=1,sigma2=2)"), error_of("WN(sigma2=1,sigma2=2)"));
  EXPECT_EQ(spec_error("3*"), error_of("3*"));
}

TEST(ModelSpec, AnEmptyTextIsAnEmptySpecThatDoesNotBind) {
  const ModelSpec none("");
  EXPECT_TRUE(none.empty());
  EXPECT_TRUE(ModelSpec().empty());
  EXPECT_THROW(none.bind(ProcessContext{}), InputError);
}

}  // namespace
}  // namespace gmwm
