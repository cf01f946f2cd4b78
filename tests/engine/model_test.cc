#include <gtest/gtest.h>

#include "gmwm/engine/model.h"
#include "gmwm/engine/process_registry.h"

TEST(ModelTest, WhiteNoiseIsRegistered) {
  EXPECT_NE(gmwm::ProcessRegistry::instance().find("wn"), nullptr);
}
