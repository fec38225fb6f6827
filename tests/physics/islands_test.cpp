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

// Ranks take runs of the islands in order, each island where its middle falls along the weights.
TEST(Islands, RanksTakeRunsOfAboutEqualWeightInIslandOrder) {
  const std::vector<uint64_t> even = {8, 8, 8, 8};
  EXPECT_EQ(rank_runs(even, 2), (std::vector<uint32_t>{0, 2, 4}));
  EXPECT_EQ(rank_runs(even, 4), (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(rank_runs(even, 1), (std::vector<uint32_t>{0, 4}));
  // One heavy island is a rank's run alone; the light ones share the other.
  EXPECT_EQ(rank_runs(std::vector<uint64_t>{1, 1, 100, 1}, 2), (std::vector<uint32_t>{0, 2, 4}));
  EXPECT_EQ(rank_runs(std::vector<uint64_t>{100, 1, 1, 1}, 2), (std::vector<uint32_t>{0, 1, 4}));
  // More ranks than islands: some ranks step none (one island goes to the rank at its middle).
  EXPECT_EQ(rank_runs(std::vector<uint64_t>{5}, 3), (std::vector<uint32_t>{0, 0, 1, 1}));
  EXPECT_EQ(rank_runs({}, 3), (std::vector<uint32_t>{0, 0, 0, 0}));
}

}  // namespace
}  // namespace dw::physics
