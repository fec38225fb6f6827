#include "physics/contact_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <span>
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
    b.cluster_of[63] = sim::kNoCluster;
    for (float& x : b.poses[63].position) x += 0.5f;
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
  b.clusters[0].anchored = false;  // every member now has a frame in the cluster
  EXPECT_EQ(expect_fresh(all, "let go"), 2u * 144);
  b.clusters[0].pose.position[0] += 0.25f;
  place_members(b);
  EXPECT_EQ(expect_fresh(all, "moved rigidly"), 2u * 144);
  EXPECT_EQ(contacts.pairs_measured(), 0u) << "the frames taken when it was let go were kept";
  const sim::Pose home = b.poses[63];
  b.cluster_of[63] = sim::kNoCluster;
  for (float& x : b.poses[63].position) x += 0.5f;
  EXPECT_EQ(expect_fresh({63}, "63 left and moved off"), 2u * 141);
  b.poses[63] = home;
  EXPECT_EQ(expect_fresh({63}, "63 back in its cell, in no cluster"), 2u * 144);
  b.cluster_of[63] = 0;  // and latched again, at the same pose in the cluster
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

// A rank that counts the pairs it gives to the swap (the measured count, then (a, b) words) of
// which it owns neither module.
class PairsOfOthers final : public sim::RankExchange {
 public:
  PairsOfOthers(sim::RankExchange& rank, const sim::ModuleOwners& owners) : rank_(rank), owners_(owners) {}
  int rank() const override { return rank_.rank(); }
  int ranks() const override { return rank_.ranks(); }
  void start_exchange(std::vector<std::vector<std::byte>> out) override { rank_.start_exchange(std::move(out)); }
  std::vector<std::vector<std::byte>> finish_exchange() override { return rank_.finish_exchange(); }
  sim::Gathered all_gather(std::span<const std::byte> mine) override {
    const auto pairs = sim::records_of<uint32_t>(mine.subspan(sizeof(uint64_t)));
    const auto me = static_cast<uint32_t>(rank());
    for (size_t i = 0; i + 1 < pairs.size(); i += 2)
      others += owners_.rank_of(pairs[i]) != me && owners_.rank_of(pairs[i + 1]) != me;
    found += pairs.size() / 2;
    return rank_.all_gather(mine);
  }
  void sum(std::span<uint64_t> values) override { rank_.sum(values); }
  size_t others = 0, found = 0;

 private:
  sim::RankExchange& rank_;
  const sim::ModuleOwners& owners_;
};

// Over ranks each measures the pairs of the changed modules it owns, and they swap what they
// found: every rank gets one process's graph and count of pairs measured, whole or read by what
// changed, and no rank measures a pair of two modules it does not own (the blocks of 4 modules
// dealt round-robin, so that a run of ids is never one rank's).
TEST(ContactGraph, RanksMeasuringTheirOwnModulesGetTheGraphOfOneProcess) {
  const PhysicsSettings settings;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);
  sim::Bodies start = test::latched_block(4, true, dynamics.module_shape());
  const std::vector<uint8_t> present(start.poses.size(), 1);
  // Three corner and edge modules leave the block and move off; then one comes back.
  const std::vector<sim::ModuleId> leaving = {3, 12, 63};
  const auto updates = [&](sim::RankExchange* ranks, const sim::ModuleOwners* owners) {
    sim::Bodies b = start;
    sim::WorkerPool workers(1);
    ContactGraph contacts(ModuleShape::Box, 0.01f);
    std::vector<std::pair<std::vector<sim::ModuleId>, uint64_t>> seen;
    seen.emplace_back(contacts.update(b, present, workers, nullptr, ranks, owners)->ids, contacts.pairs_measured());
    for (sim::ModuleId m : leaving) {
      b.cluster_of[m] = sim::kNoCluster;
      b.poses[m].position[2] += 0.6f;
    }
    seen.emplace_back(contacts.update(b, present, workers, &leaving, ranks, owners)->ids, contacts.pairs_measured());
    b.poses[63] = start.poses[63];
    const std::vector<sim::ModuleId> back = {63};
    seen.emplace_back(contacts.update(b, present, workers, &back, ranks, owners)->ids, contacts.pairs_measured());
    return seen;
  };
  const auto one = updates(nullptr, nullptr);
  ASSERT_NE(one[0].first, one[1].first);
  ASSERT_GT(one[1].second, 0u);
  for (uint32_t ranks : {2u, 3u}) {
    sim::ModuleOwners owners{.block_shift = 2};
    for (uint32_t block = 0; block < 16; ++block) owners.block_rank.push_back(block % ranks);
    const auto all = sim::on_ranks(int(ranks), [&](sim::RankExchange& rank) {
      PairsOfOthers counted(rank, owners);
      auto seen = updates(&counted, &owners);
      return std::tuple(std::move(seen), counted.others, counted.found);
    });
    size_t found = 0;
    for (uint32_t r = 0; r < ranks; ++r) {
      const auto& [seen, others, by_rank] = all[r];
      EXPECT_EQ(seen, one) << ranks << " ranks, rank " << r;
      EXPECT_EQ(others, 0u) << ranks << " ranks, rank " << r;
      found += by_rank;
    }
    EXPECT_GT(found, 0u);
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
