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
  // Poses by default at the cells of a lattice (carried with them), a few modules moved off.
  const LatticeSpec lattice{LatticeKind::Cubic, {10, 10, 1000}};
  b.poses = decltype(b.poses)(CellPose{lattice, 1});
  b.poses.resize(modules);
  b.velocities.resize(modules);
  b.local.resize(modules);
  b.cluster_of.resize(modules);
  // Latched by default; some of those bonds gone (pages of bytes kept), a few listed.
  b.bonds = BondSet(lattice, true, modules);
  for (uint32_t m = 0; m < modules; ++m) {
    if (m % 5000 < 3000) b.poses.set(m, pose());
    // Runs of modules at rest: pages of velocities that are not kept.
    if (m % 2000 < 1000) b.velocities.set(m, {{any(random), 0, 0}, {0, any(random), 0}});
    b.local.set(m, pose());
    b.cluster_of.set(m, m % 3 == 0 ? kNoCluster : m / 10);
    b.members.push_back(m);
    if (m % 700 < 100) b.bonds.erase({m, m + 1});
    if (m % 13 == 0 && m + 3 < modules) b.bonds.insert({m, m + 3});
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
    const BodySlice whole(bodies, 0, 1);
    EXPECT_EQ(bodies_from_slices(whole, nullptr), bodies);
    for (int ranks : {1, 2, 3, 4}) {
      const auto seen = on_ranks(ranks, [&](RankExchange& r) {
        const BodySlice slice(bodies, r.rank(), r.ranks());
        return std::pair(slice.size(), bodies_from_slices(slice, &r) == bodies);
      });
      size_t total = 0;
      for (const auto& [bytes, equal] : seen) {
        EXPECT_TRUE(equal) << modules << " modules on " << ranks << " ranks";
        EXPECT_LE(bytes, whole.size() / size_t(ranks) + 1);
        total += bytes;
      }
      EXPECT_EQ(total, whole.size());
    }
  }
}

// A copy shares with the one before it every chunk whose bytes did not change, and only those:
// a still world adds nothing; a module that moves adds the chunks its pose and velocity lie in;
// bodies that grew share what comes before the growth. Read back, each copy is its own bodies.
TEST(BodySlices, ACopySharesTheChunksThatDidNotChangeSinceTheLastOne) {
  constexpr uint32_t kModules = 20'000;  // poses alone span 35 chunks
  const Bodies still = some_bodies(kModules);
  const BodySlice first(still, 0, 1);
  ASSERT_GT(first.chunks().size(), 50u);
  EXPECT_EQ(first.bytes_beyond(nullptr), first.size());

  const BodySlice again(still, 0, 1, &first);
  EXPECT_EQ(again.bytes_beyond(&first), 0u);
  EXPECT_EQ(bodies_from_slices(again, nullptr), still);

  Bodies moved = still;
  Pose further = moved.poses[kModules / 2];
  further.position[0] += 1e-3f;
  moved.poses.set(kModules / 2, further);
  Velocity faster = moved.velocities[kModules / 2];
  faster.linear[1] = 0.5f;
  moved.velocities.set(kModules / 2, faster);
  const BodySlice after_move(moved, 0, 1, &again);
  EXPECT_EQ(after_move.bytes_beyond(&again), 2 * BodySlice::kChunkBytes);
  EXPECT_EQ(bodies_from_slices(after_move, nullptr), moved);
  EXPECT_EQ(bodies_from_slices(again, nullptr), still);  // the copy it shares with is untouched

  Bodies grown = moved;
  grown.prop_poses.push_back({});  // the last vectors: the chunks before them stay
  const BodySlice after_growth(grown, 0, 1, &after_move);
  EXPECT_LE(after_growth.bytes_beyond(&after_move), 2 * BodySlice::kChunkBytes);
  EXPECT_EQ(bodies_from_slices(after_growth, nullptr), grown);

  // A module at rest starting to move keeps a page more: what follows it shifts, and is read
  // back all the same.
  Bodies started = grown;
  ASSERT_EQ(started.velocities[kModules / 2 + 1500], Velocity{});
  started.velocities.set(kModules / 2 + 1500, {{1, 2, 3}, {}});
  const BodySlice after_start(started, 0, 1, &after_growth);
  EXPECT_EQ(after_start.size(), after_growth.size() + PagedArray<Velocity>::kPage * sizeof(Velocity));
  EXPECT_EQ(bodies_from_slices(after_start, nullptr), started);
  EXPECT_NE(started, grown);

  // Over ranks each rank's slice shares alike.
  const auto added = on_ranks(3, [&](RankExchange& r) {
    const BodySlice before(still, r.rank(), r.ranks());
    const BodySlice now(still, r.rank(), r.ranks(), &before);
    return std::pair(now.bytes_beyond(&before), bodies_from_slices(now, &r) == still);
  });
  for (const auto& [bytes, equal] : added) {
    EXPECT_EQ(bytes, 0u);
    EXPECT_TRUE(equal);
  }
}

}  // namespace
}  // namespace dw::sim
