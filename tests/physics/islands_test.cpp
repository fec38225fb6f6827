#include "physics/islands.h"

#include <gtest/gtest.h>

namespace dw::physics {
namespace {

ReachBox box(float x0, float x1, float y0 = 0, float y1 = 1) { return {{x0, y0, 0}, {x1, y1, 1}}; }

TEST(Islands, OverlapsJoinDirectlyAndThroughOthers) {
  // 0 and 2 overlap only through 1; 3 is apart; 4 overlaps 3 in x but not in y.
  const std::vector<ReachBox> boxes = {box(0, 1), box(5, 6), box(0.5f, 5.5f), box(10, 11), box(10.5f, 12, 3, 4)};
  uint32_t count = 0;
  EXPECT_EQ(islands_of(boxes, count), (std::vector<uint32_t>{0, 0, 0, 1, 2}));
  EXPECT_EQ(count, 3u);
  // Touching edges count as overlapping: a box grown to where another starts can meet it.
  EXPECT_EQ(islands_of(std::vector{box(0, 1), box(1, 2)}, count), (std::vector<uint32_t>{0, 0}));
  EXPECT_TRUE(islands_of({}, count).empty());
  EXPECT_EQ(count, 0u);
}

}  // namespace
}  // namespace dw::physics
