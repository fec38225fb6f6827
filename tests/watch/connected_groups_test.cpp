#include "watch/connected_groups.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "cube.h"

namespace dw::watch {
namespace {

StepHistory::Graph graph_of(const std::vector<std::vector<uint32_t>>& nbrs, std::vector<uint8_t> present = {}) {
  StepHistory::Graph g;
  g.present = present.empty() ? std::vector<uint8_t>(nbrs.size(), 1) : std::move(present);
  g.begin.push_back(0);
  for (const auto& l : nbrs) {
    g.ids.insert(g.ids.end(), l.begin(), l.end());
    g.begin.push_back(static_cast<uint32_t>(g.ids.size()));
  }
  return g;
}

std::vector<std::vector<uint32_t>> groups(const StepHistory::Graph& g, uint32_t k) {
  ConnectedGroups cg(static_cast<uint32_t>(g.present.size()));
  std::vector<std::vector<uint32_t>> out;
  cg.enumerate(g, g.present, k, [&](std::span<const uint32_t> group) {
    out.emplace_back(group.begin(), group.end());
    return true;
  });
  return out;
}

TEST(ConnectedGroups, CountsTheConnectedFourModuleGroupsOfTheTableICube) {
  const auto g = graph_of(testing::cube_neighbors(10));
  EXPECT_EQ(groups(g, 4).size(), 62'418u);
  EXPECT_EQ(groups(g, 2).size(), 2'700u);  // the cube's edges
  EXPECT_EQ(groups(g, 1).size(), 1'000u);
}

// The budget bounds the groups grown, whole or partial: past it the enumeration stops at once
// (it reports it did not reach every group), within it nothing changes.
TEST(ConnectedGroups, TheBudgetStopsTheEnumerationOfGroupsGrown) {
  const auto g = graph_of(testing::cube_neighbors(10));
  ConnectedGroups cg(1000);
  size_t found = 0;
  auto count = [&](std::span<const uint32_t>) { return ++found, true; };
  EXPECT_FALSE(cg.enumerate(g, g.present, 4, count, 5'000));
  EXPECT_GT(found, 0u);
  EXPECT_LT(found, 5'000u);
  found = 0;
  EXPECT_TRUE(cg.enumerate(g, g.present, 4, count, 10'000'000));
  EXPECT_EQ(found, 62'418u);
  // fn stops it too.
  found = 0;
  EXPECT_FALSE(cg.enumerate(g, g.present, 4, [&](std::span<const uint32_t>) { return ++found < 10; }));
  EXPECT_EQ(found, 10u);
}

// Brute force: every k-subset whose induced subgraph has a root reaching every member.
std::set<std::vector<uint32_t>> brute(const std::vector<std::vector<uint32_t>>& nbrs,
                                      const std::vector<uint8_t>& present, uint32_t k) {
  std::set<std::vector<uint32_t>> out;
  const uint32_t n = static_cast<uint32_t>(nbrs.size());
  for (uint32_t mask = 0; mask < (1u << n); ++mask) {
    if (static_cast<uint32_t>(__builtin_popcount(mask)) != k) continue;
    std::vector<uint32_t> set;
    bool ok = true;
    for (uint32_t m = 0; m < n; ++m)
      if (mask >> m & 1) {
        set.push_back(m);
        ok &= present[m] != 0;
      }
    if (!ok) continue;
    for (uint32_t root : set) {
      uint32_t reached = 1u << root, frontier = reached;
      while (frontier) {
        uint32_t next = 0;
        for (uint32_t a : set)
          if (frontier >> a & 1)
            for (uint32_t b : nbrs[a])
              if ((mask >> b & 1) && !(reached >> b & 1)) next |= 1u << b;
        reached |= next;
        frontier = next;
      }
      if (reached == mask) {
        out.insert(set);
        break;
      }
    }
  }
  return out;
}

TEST(ConnectedGroups, EveryGroupOnceOnRandomDirectedGraphsWithAbsentModules) {
  std::mt19937 rng(17);
  for (int c = 0; c < 300; ++c) {
    const uint32_t n = 2 + rng() % 8;
    std::vector<std::vector<uint32_t>> nbrs(n);
    std::vector<uint8_t> present(n);
    for (uint32_t a = 0; a < n; ++a) {
      present[a] = rng() % 6 != 0;
      for (uint32_t b = 0; b < n; ++b)
        if (a != b && rng() % 3 == 0) nbrs[a].push_back(b);
      if (rng() % 5 == 0 && !nbrs[a].empty()) nbrs[a].push_back(nbrs[a].front());  // a repeat
    }
    const auto g = graph_of(nbrs, present);
    for (uint32_t k = 1; k <= std::min(n, 5u); ++k) {
      std::set<std::vector<uint32_t>> got;
      for (std::vector<uint32_t> group : groups(g, k)) {
        std::sort(group.begin(), group.end());
        EXPECT_TRUE(got.insert(group).second) << "a group enumerated twice, case " << c;
      }
      EXPECT_EQ(got, brute(nbrs, present, k)) << "case " << c << " k " << k;
    }
  }
}

TEST(ConnectedGroups, RootedNeedsOneMemberReachingEveryOther) {
  // 0 -> 1, 2 -> 1: connected both ways, but no member reaches the two others.
  const auto g = graph_of({{1}, {}, {1}});
  const std::vector<uint32_t> all{0, 1, 2}, pair{0, 1};
  EXPECT_FALSE(rooted(g, all));
  EXPECT_TRUE(rooted(g, pair));
  UndirectedGraph u;
  EXPECT_FALSE(u.build(g, g.present));
  EXPECT_EQ(std::vector<uint32_t>(u.neighbors(1).begin(), u.neighbors(1).end()), (std::vector<uint32_t>{0, 2}));
}

}  // namespace
}  // namespace dw::watch
