#include <gtest/gtest.h>

#include "gmwm/engine/model.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/process_registry.h"

TEST(ModelTest, WhiteNoiseIsRegistered) { EXPECT_NE(gmwm::ProcessRegistry::instance().find("wn"), nullptr); }

namespace gmwm {
namespace {

TEST(ModelSum, PutsTheFirstModelsComponentsAndParametersFirst) {
  const Model a = parse_model("WN(sigma2=2)+RW(gamma2=3)"), b = parse_model("AR1(phi=0.5,sigma2=1)");
  const Model s = a + b;
  EXPECT_EQ(s.to_string(), "WN+RW+AR1");
  EXPECT_EQ(s.num_parameters(), 4);
  EXPECT_EQ(s.offset(2), 2);
  Eigen::VectorXd theta(4);
  theta << a.given_values(), b.given_values();
  EXPECT_EQ(s.to_string(theta), "WN(sigma2=2)+RW(gamma2=3)+AR1(phi=0.5,sigma2=1)");
  EXPECT_EQ(s.canonical().to_string(), "AR1+WN+RW");
}

}  // namespace
}  // namespace gmwm
