#include "physics/islands.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include "physics/union_find.h"

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

// The grid finds what testing every pair finds: boxes of a lattice touching edge to edge, of many
// sizes, a few wide ones (a cluster, a prop) and one that is not finite.
TEST(Islands, TheGridJoinsWhatEveryPairTestedJoins) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> where(0, 30), size(0.2f, 1.5f), wide(5, 20);
  std::vector<ReachBox> boxes;
  for (int x = 0; x < 6; ++x)  // a row touching edge to edge, then a gap
    boxes.push_back(box(float(x), float(x + 1)));
  for (int i = 0; i < 600; ++i) {
    const float x = where(random), y = where(random), z = where(random), s = i % 50 == 0 ? wide(random) : size(random);
    boxes.push_back({{x, y, z}, {x + s, y + s * 0.7f, z + s * 0.5f}});
  }
  boxes.push_back({{std::nanf(""), 0, 0}, {1, 1, 1}});
  std::vector<uint32_t> parent(boxes.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (uint32_t a = 0; a < boxes.size(); ++a)
    for (uint32_t b = a + 1; b < boxes.size(); ++b)
      if (boxes[a].overlaps(boxes[b])) {
        const uint32_t ra = find_root(parent, a), rb = find_root(parent, b);
        parent[std::max(ra, rb)] = std::min(ra, rb);
      }
  std::vector<uint32_t> expected(boxes.size()), number(boxes.size(), UINT32_MAX);
  uint32_t expected_count = 0;
  for (uint32_t i = 0; i < boxes.size(); ++i) {
    const uint32_t r = find_root(parent, i);
    if (number[r] == UINT32_MAX) number[r] = expected_count++;
    expected[i] = number[r];
  }
  uint32_t count = 0;
  EXPECT_EQ(islands_of(boxes, count), expected);
  EXPECT_EQ(count, expected_count);
  EXPECT_GT(count, 10u);  // the scene has islands to find
  EXPECT_LT(count, uint32_t(boxes.size()));
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
