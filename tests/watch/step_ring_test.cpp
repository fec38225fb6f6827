#include "watch/step_ring.h"

#include <gtest/gtest.h>

namespace dw::watch {
namespace {

TEST(StepRing, KeepsExactlyTheLastDepthSteps) {
  StepRing<int> r;
  r.configure(3);
  for (int s = 0; s < 10; ++s) r.write(s) = s * 10;
  EXPECT_EQ(r.find(6), nullptr);
  ASSERT_NE(r.find(7), nullptr);
  EXPECT_EQ(*r.find(7), 70);
  EXPECT_EQ(*r.find(9), 90);
  EXPECT_EQ(r.find(10), nullptr);
  EXPECT_EQ(r.find(-1), nullptr);
  EXPECT_EQ(r.held(), 3);
}

TEST(StepRing, UnboundedKeepsEverything) {
  StepRing<int> r;
  r.configure(0);
  for (int s = 0; s < 100; ++s) r.write(s) = s;
  EXPECT_EQ(*r.find(0), 0);
  EXPECT_EQ(*r.find(99), 99);
  EXPECT_EQ(r.held(), 100);
}

}  // namespace
}  // namespace dw::watch
