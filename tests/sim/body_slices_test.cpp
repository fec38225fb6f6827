// A rank's share of the bodies (sim/body_slices.cpp): the slices split the bodies' bytes about
// equally among the ranks and put back together give the bodies bit for bit.
#include "sim/body_slices.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/sim/thread_ranks.h"

namespace dw::sim {
namespace {

Bodies some_bodies(uint32_t modules) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> any(-5, 5);
  const auto pose = [&] { return Pose{{any(random), any(random), any(random)}, {0, 0, any(random), 1}}; };
  Bodies b;
  for (uint32_t m = 0; m < modules; ++m) {
    b.poses.push_back(pose());
    b.velocities.push_back({{any(random), 0, 0}, {0, any(random), 0}});
    b.local.push_back(pose());
    b.cluster_of.push_back(m % 3 == 0 ? kNoCluster : m / 10);
    b.members.push_back(m);
    if (m + 1 < modules) b.bonds.push_back({m, m + 1});
  }
  for (uint32_t c = 0; c * 10 < modules; ++c)
    b.clusters.push_back({pose(), {{any(random), 0, 0}, {}}, c * 10, 10, c == 0});
  b.movers.push_back({.module = 3, .from = pose(), .to = pose(), .start = 4, .steps = 10, .angle = 1.5f});
  b.prop_poses.push_back(pose());
  b.prop_velocities.push_back({});
  return b;
}

TEST(BodySlices, TheRanksSlicesAreAboutEqualAndPutTogetherGiveTheBodies) {
  for (const uint32_t modules : {0u, 1u, 1000u}) {
    const Bodies bodies = some_bodies(modules);
    const size_t whole = body_slice(bodies, 0, 1).size();
    for (int ranks : {1, 2, 3, 4}) {
      const auto seen = on_ranks(ranks, [&](RankExchange& r) {
        const std::vector<std::byte> slice = body_slice(bodies, r.rank(), r.ranks());
        return std::pair(slice.size(), bodies_from_slices(slice, r) == bodies);
      });
      size_t total = 0;
      for (const auto& [bytes, equal] : seen) {
        EXPECT_TRUE(equal) << modules << " modules on " << ranks << " ranks";
        EXPECT_LE(bytes, whole / size_t(ranks) + 1);
        total += bytes;
      }
      EXPECT_EQ(total, whole);
    }
  }
}

}  // namespace
}  // namespace dw::sim
