#include "physics/contact_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "physics/clusters.h"
#include "physics/dynamics.h"
#include "tests/physics/latched_block.h"
#include "tests/sim/thread_ranks.h"

namespace dw::physics {
namespace {

// 4x4x4: 144 face pairs; every module has up to 26 candidates, 13 a module counted once.
TEST(ContactGraph, MeasuresEveryPairOnceThenOnlyWhatChanged) {
  const PhysicsSettings settings;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);  // holds the box shape clusters are made of
  btCollisionShape& shape = dynamics.module_shape();
  sim::WorkerPool workers(2);
  for (const bool anchored : {true, false}) {
    sim::Bodies b = test::latched_block(4, anchored, shape);
    const std::vector<uint8_t> present(b.poses.size(), 1);
    ContactGraph contacts(ModuleShape::Box, 0.01f);
    const auto first = contacts.update(b, present, workers);
    EXPECT_EQ(first->edge_count(), 2u * 144);
    EXPECT_EQ(contacts.pairs_measured(), 3u * 48 + 6u * 36 + 4u * 27);  // face, edge and corner diagonals
    // Nothing changed: nothing measured, the same graph.
    EXPECT_EQ(contacts.update(b, present, workers), first);
    EXPECT_EQ(contacts.pairs_measured(), 0u);
    // The whole block moves rigidly (a free one): its pairs keep their measurement, and nothing
    // else is near it.
    if (!anchored) {
      b.clusters[0].pose.position[0] += 0.25f;
      place_members(b);
      EXPECT_EQ(contacts.update(b, present, workers), first);
      EXPECT_EQ(contacts.pairs_measured(), 0u);
    }
    // One corner module leaves its cluster and moves off: only its own candidates are measured.
    b.cluster_of.set(63, sim::kNoCluster);
    test::shift(b, 63, {0.5f, 0.5f, 0.5f});
    const auto moved = contacts.update(b, present, workers);
    EXPECT_LE(contacts.pairs_measured(), 7u);
    EXPECT_GT(contacts.pairs_measured(), 0u);
    EXPECT_EQ(moved->edge_count(), 2u * 141) << "its three faces came apart";
    EXPECT_EQ(moved->neighbors(63).size(), 0u);
  }
}

// Read by what changed, the graph is the one a fresh ContactGraph measures from scratch, through
// frames that appear (an anchored block let go: its members get frames where none were kept),
// change and go (a module leaving its cluster, moving off and coming back).
TEST(ContactGraph, WhatChangedGivesTheGraphOfAFreshMeasurement) {
  const PhysicsSettings settings;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);
  sim::WorkerPool workers(2);
  sim::Bodies b = test::latched_block(4, true, dynamics.module_shape());
  const std::vector<uint8_t> present(b.poses.size(), 1);
  std::vector<sim::ModuleId> all(b.poses.size());
  for (sim::ModuleId m = 0; m < all.size(); ++m) all[m] = m;
  ContactGraph contacts(ModuleShape::Box, 0.01f);
  contacts.update(b, present, workers);
  auto expect_fresh = [&](const std::vector<sim::ModuleId>& changed, const char* what) {
    const auto read = contacts.update(b, present, workers, &changed);
    ContactGraph fresh(ModuleShape::Box, 0.01f);
    const auto measured = fresh.update(b, present, workers);
    EXPECT_EQ(read->begin, measured->begin) << what;
    EXPECT_EQ(read->ids, measured->ids) << what;
    return read->edge_count();
  };
  // Let go, its frame still the world's: every member now has a frame in the cluster, its world
  // pose kept as its pose in the cluster (Bodies::pose_in_cluster).
  for (sim::ModuleId m = 0; m < b.poses.size(); ++m) b.local.set(m, b.poses[m]);
  b.clusters[0].anchored = false;
  EXPECT_EQ(expect_fresh(all, "let go"), 2u * 144);
  b.clusters[0].pose.position[0] += 0.25f;
  place_members(b);
  EXPECT_EQ(expect_fresh(all, "moved rigidly"), 2u * 144);
  EXPECT_EQ(contacts.pairs_measured(), 0u) << "the frames taken when it was let go were kept";
  const sim::Pose home = b.poses[63];
  b.cluster_of.set(63, sim::kNoCluster);
  test::shift(b, 63, {0.5f, 0.5f, 0.5f});
  EXPECT_EQ(expect_fresh({63}, "63 left and moved off"), 2u * 141);
  b.poses.set(63, home);
  EXPECT_EQ(expect_fresh({63}, "63 back in its cell, in no cluster"), 2u * 144);
  b.cluster_of.set(63, 0);  // and latched again, at the same pose in the cluster
  EXPECT_EQ(expect_fresh({63}, "63 in its cluster again"), 2u * 144);
}

// The same graph on one worker as on two; near() finds the modules around a point.
TEST(ContactGraph, WorkersDoNotChangeTheGraphAndNearFindsCentres) {
  const PhysicsSettings settings;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);
  const sim::Bodies b = test::latched_block(4, true, dynamics.module_shape());
  const std::vector<uint8_t> present(b.poses.size(), 1);
  sim::WorkerPool one(1), two(2);
  ContactGraph a(ModuleShape::Box, 0.01f), c(ModuleShape::Box, 0.01f);
  EXPECT_EQ(a.update(b, present, one)->ids, c.update(b, present, two)->ids);
  EXPECT_EQ(a.near({1, 1, 1}, 0.5f), std::vector<sim::ModuleId>{21});
  EXPECT_EQ(a.near({1.5f, 1, 1}, 0.6f), (std::vector<sim::ModuleId>{21, 22}));
  EXPECT_TRUE(a.near({10, 10, 10}, 1.5f).empty());
  EXPECT_LT(a.distance(b.poses[0], b.poses[1]), 0.001f);
  EXPECT_GT(a.distance(b.poses[0], b.poses[5]), 0.01f) << "edge diagonals are apart (rounded edges)";
}

// Over ranks each holds the graph of its window: the modules it owns and those within reach of
// them, each list whole, the others' empty; so every neighbour of a module it owns has its list
// held. Each measures the pairs of its window, and no rank sends another a pair: the lists held
// are one process's, and so is the count of pairs measured, whole or read by what changed, as
// modules leave, one crosses from one rank's slab to another's, and comes back. The block's
// layers of 64 modules are the ranks' slabs.
TEST(ContactGraph, RanksHoldTheGraphOfTheirWindowAsOneProcessHasIt) {
  const PhysicsSettings settings;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);
  const sim::Bodies start = test::latched_block(8, true, dynamics.module_shape());
  const std::vector<uint8_t> present(start.poses.size(), 1);
  struct Seen {
    std::shared_ptr<const sim::NeighborGraph> graph;
    uint64_t measured;
  };
  const auto updates = [&](sim::RankExchange* ranks, const sim::ModuleOwners* owners) {
    sim::Bodies b = start;
    sim::WorkerPool workers(2);
    ContactGraph contacts(ModuleShape::Box, 0.01f);
    std::vector<Seen> seen;
    const auto update = [&](const std::vector<sim::ModuleId>* changed) {
      seen.push_back({contacts.update(b, present, workers, changed, ranks, owners), 0});
      seen.back().measured = contacts.pairs_measured();
    };
    update(nullptr);
    // Corner and edge modules of the top and bottom layers lift off.
    const std::vector<sim::ModuleId> leaving = {3, 12, 63, 511, 448};
    for (sim::ModuleId m : leaving) {
      b.cluster_of.set(m, sim::kNoCluster);
      test::shift(b, m, {0, 0, 0.6f});
    }
    update(&leaving);
    // Module 0 (bottom layer) goes up the block's side to touch module 320's face (layer 5).
    const std::vector<sim::ModuleId> climbing = {0};
    b.cluster_of.set(0, sim::kNoCluster);
    b.poses.set(0, {.position = {-1.0f, 0.0f, 5.0f}});
    update(&climbing);
    // And comes back, as do the others.
    b.poses.set(0, start.poses[0]);
    update(&climbing);
    for (sim::ModuleId m : leaving) b.poses.set(m, start.poses[m]);
    update(&leaving);
    // The top layer said to have changed, though it did not: a rank that never held it cannot
    // tell, and measures it again; the others find nothing changed.
    std::vector<sim::ModuleId> top(64);
    std::iota(top.begin(), top.end(), 448u);
    update(&top);
    update(nullptr);  // a restored world compares every module
    return seen;
  };
  const auto one = updates(nullptr, nullptr);
  ASSERT_EQ(one.size(), 7u);
  ASSERT_NE(one[0].graph->ids, one[1].graph->ids);
  ASSERT_TRUE(one[2].graph->adjacent(0, 320));
  ASSERT_GT(one[1].measured, 0u);
  for (uint32_t ranks : {2u, 3u, 4u}) {
    sim::ModuleOwners owners{.block_shift = 6};
    for (uint32_t layer = 0; layer < 8; ++layer) owners.block_rank.push_back(layer * ranks / 8);
    const auto all = sim::on_ranks(int(ranks), [&](sim::RankExchange& rank) {
      sim::CountedGathers counted(rank);
      auto seen = updates(&counted, &owners);
      return std::pair(std::move(seen), counted.gathers);
    });
    for (uint32_t r = 0; r < ranks; ++r) {
      const auto& [seen, gathers] = all[r];
      EXPECT_EQ(gathers, 0u);
      ASSERT_EQ(seen.size(), one.size());
      for (size_t u = 0; u < one.size(); ++u) {
        SCOPED_TRACE(std::to_string(ranks) + " ranks, rank " + std::to_string(r) + ", update " + std::to_string(u));
        const sim::NeighborGraph &window = *seen[u].graph, &whole = *one[u].graph;
        EXPECT_EQ(seen[u].measured, one[u].measured);
        size_t held = 0, owned = 0;
        for (sim::ModuleId m = 0; m < whole.module_count(); ++m) {
          const std::span<const sim::ModuleId> list = window.neighbors(m), expected = whole.neighbors(m);
          held += window.holds(m);
          if (window.holds(m)) EXPECT_TRUE(std::ranges::equal(list, expected)) << "module " << m;
          else EXPECT_TRUE(list.empty()) << "module " << m;
          if (owners.rank_of(m) == r) {
            ++owned;
            EXPECT_TRUE(window.holds(m)) << "module " << m;
            for (sim::ModuleId o : expected) EXPECT_TRUE(window.holds(o)) << "module " << m << "'s neighbour " << o;
          }
        }
        // Its own layers, the layer on either side and the modules moving: not the whole block.
        EXPECT_LE(held, owned + 2 * 64 + 6);
        EXPECT_LT(held, whole.module_count());
      }
    }
  }
}

// The closed forms for spheres and unturned boxes say what GJK says, wherever GJK's distance is
// not within rounding of the threshold: faces one size apart, edges and corners diagonal, small
// gaps, overlaps, offsets along every axis; and turned boxes still go to GJK.
TEST(ContactGraph, ClosedFormsAgreeWithGjk) {
  for (const ModuleShape shape : {ModuleShape::Box, ModuleShape::Sphere, ModuleShape::Cylinder}) {
    ContactGraph graph(shape, 0.01f);
    int compared = 0, touching = 0;
    const sim::Pose a{.position = {0.25f, -1.5f, 3.0f}};
    for (float x : {0.0f, 0.5f, 0.9f, 0.995f, 1.0f, 1.004f, 1.02f, 1.2f, 1.5f})
      for (float y : {0.0f, 0.3f, 0.98f, 1.0f, 1.005f, 1.03f})
        for (float z : {0.0f, -0.7f, 1.0f, -1.0f, 1.008f}) {
          for (const float turn : {0.0f, 0.3f}) {
            sim::Pose b{.position = {a.position[0] + x, a.position[1] + y, a.position[2] + z}};
            b.orientation = {0, 0, std::sin(turn / 2), std::cos(turn / 2)};
            if (x == 0 && y == 0 && z == 0) continue;
            const float d = graph.distance(a, b);
            if (std::abs(d - 0.01f) < 1e-4f) continue;  // at the threshold itself
            ++compared;
            touching += d <= 0.01f;
            EXPECT_EQ(graph.touching(a, b), d <= 0.01f) << "shape " << int(shape) << " offset " << x << ", " << y
                                                        << ", " << z << " turn " << turn << ": GJK distance " << d;
          }
        }
    EXPECT_GT(compared, 400);
    EXPECT_GT(touching, 20);
    EXPECT_LT(touching, compared - 50);
  }
}

}  // namespace
}  // namespace dw::physics
