#include "physics/dynamics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "physics/clusters.h"
#include "tests/physics/latched_block.h"
#include "tests/sim/thread_ranks.h"

namespace dw::physics {
namespace {

// A 4x3x3 block of boxes, turned and moved as a cluster's frame may turn it.
std::vector<sim::Pose> block(float turn) {
  const float c = std::cos(turn / 2), s = std::sin(turn / 2);
  std::vector<sim::Pose> out;
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        // Rotated about z by `turn`, around (1.5, 1, 1), then shifted off the grid.
        const float px = float(x) - 1.5f, py = float(y) - 1.f;
        sim::Pose p;
        p.position = {px * std::cos(turn) - py * std::sin(turn) + 0.3f,
                      px * std::sin(turn) + py * std::cos(turn) - 7.1f, float(z) - 1.f};
        p.orientation = {0, 0, s, c};
        out.push_back(p);
      }
  return out;
}

// An island whose fastest point could move more than substep_travel in a substep gets as many
// as keep it within (a 14 m/s ball: 0.233 over a 60th of a second), between substeps and
// max_substeps; a NaN speed gets the most rather than none.
TEST(Dynamics, AFastIslandIsSolvedInMoreSubsteps) {
  const PhysicsSettings s;  // 4 substeps, 0.0125 a substep, at most 16
  EXPECT_EQ(substeps_for(s, 0), 4);
  EXPECT_EQ(substeps_for(s, 0.05f), 4) << "4 substeps of 0.0125";
  EXPECT_EQ(substeps_for(s, 0.0501f), 5);
  EXPECT_EQ(substeps_for(s, 14.0f / 60), 16) << "19 wanted, 16 at most";
  EXPECT_EQ(substeps_for(s, 1e30f), 16);
  EXPECT_EQ(substeps_for(s, std::nanf("")), 16);
  PhysicsSettings fixed = s;
  fixed.max_substeps = fixed.substeps;
  EXPECT_EQ(substeps_for(fixed, 1), 4) << "max_substeps = substeps: every step alike";
}

TEST(Dynamics, OnlyBoxesWithBoxesOnAllSixFacesAreEnclosed) {
  for (float turn : {0.f, 0.4f, 1.2f}) {
    const std::vector<uint8_t> inside = enclosed_boxes(block(turn));
    // In a 4x3x3 block the boxes at (1..2, 1, 1) are the inner ones.
    std::vector<uint8_t> expected(36, 0);
    expected[1 + 4 * (1 + 3 * 1)] = expected[2 + 4 * (1 + 3 * 1)] = 1;
    EXPECT_EQ(inside, expected) << "turned by " << turn;
  }
  // One face uncovered (its neighbour gone): on the surface again.
  std::vector<sim::Pose> holed = block(0.4f);
  holed.erase(holed.begin() + (1 + 4 * (0 + 3 * 1)));  // the box below (1, 1, 1) in y
  const std::vector<uint8_t> inside = enclosed_boxes(holed);
  EXPECT_EQ(std::accumulate(inside.begin(), inside.end(), 0), 1);
}

// A ball dropped on the top corner of a 3x3x3 cube latched to the ground: the contact force goes
// to that corner, module 26, although the cube's compound leaves out its enclosed centre (13), so
// that the compound's child 25 is member 26.
TEST(Dynamics, ContactForceGoesToTheMemberTouchedNotToTheChildsIndex) {
  PhysicsSettings settings;
  PropSpec ball;
  ball.mass = 5;
  ball.pose.position = {2, 2, 3.01f};
  ball.velocity.linear = {0, 0, -1};
  settings.props.push_back(ball);
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);

  sim::Bodies b = test::latched_block(3, true, dynamics.module_shape());
  const auto n = static_cast<sim::ModuleId>(b.poses.size());
  b.prop_poses = {ball.pose};
  b.prop_velocities = {ball.velocity};
  ASSERT_EQ(b.clusters.size(), 1u);
  ASSERT_TRUE(b.clusters[0].anchored);

  std::vector<float> force, total(n, 0.0f);
  sim::WorkerPool workers(1);
  for (int64_t step = 1; step <= 30; ++step) {
    dynamics.step(b, {}, step, &force, workers);
    for (sim::ModuleId m = 0; m < n; ++m) total[m] += force[m];
  }
  EXPECT_GT(total[26], 0.0f);
  for (sim::ModuleId m = 0; m < 26; ++m) EXPECT_EQ(total[m], 0.0f) << "module " << m;
}

// Blocks of 2x2x2 boxes, each latched into a free cluster, `apart` module sizes apart along x,
// falling onto the ground from z = 3; block k moves along x at speed[k]. The first block is at
// x = first.
sim::Bodies falling_blocks(const std::vector<float>& speed, float apart, btCollisionShape& shape, float first = 0) {
  sim::Bodies b;
  for (size_t k = 0; k < speed.size(); ++k)
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
          const auto m = static_cast<sim::ModuleId>(b.poses.size());
          b.poses.resize(m + 1);
          b.poses.set(m, {.position = {first + float(k) * apart + float(x), float(y), 3.0f + float(z)}});
        }
  const auto n = static_cast<sim::ModuleId>(b.poses.size());
  b.velocities.resize(n);
  for (sim::ModuleId m = 0; m < n; ++m) b.velocities.set(m, {.linear = {speed[m / 8], 0, 0}});
  b.local.resize(n);
  b.bonds = sim::BondSet({}, false, n);  // off any lattice: every bond listed
  for (sim::ModuleId m = 0; m < n; ++m)
    for (sim::ModuleId o = m + 1; o < n; ++o) {
      const auto &p = b.poses[m].position, &q = b.poses[o].position;
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) == 1) b.bonds.insert({m, o});
    }
  form_clusters(b, std::vector<uint8_t>(n, 1), shape);
  return b;
}

void run(Dynamics& dynamics, sim::Bodies& b, int steps, unsigned threads, std::vector<uint32_t>* islands = nullptr) {
  sim::WorkerPool workers(threads);
  std::vector<float> force;
  for (int64_t step = 1; step <= steps; ++step) {
    dynamics.step(b, {}, step, &force, workers);
    place_members(b);
    if (islands) islands->push_back(dynamics.islands());
  }
}

// Four blocks falling far apart are four islands: stepped on one thread or two, the same bits;
// and, each in a world of its own, each block falls exactly as it falls alone.
TEST(Dynamics, IslandsSteppedApartGiveTheSameBitsOnAnyThreadAndAlone) {
  PhysicsSettings settings;
  settings.anchor = false;
  Dynamics one(settings, ModuleShape::Box, -0.5f, 1), two(settings, ModuleShape::Box, -0.5f, 1);
  const std::vector<float> speed = {0.5f, -0.3f, 0.2f, 0.0f};
  sim::Bodies a = falling_blocks(speed, 6, one.module_shape()), b = a;
  std::vector<uint32_t> islands;
  run(one, a, 60, 1, &islands);
  run(two, b, 60, 2);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(islands.front(), 4u);
  EXPECT_LT(a.poses[0].position[2], 2.5f);  // they fell
  for (size_t k = 0; k < speed.size(); ++k) {
    Dynamics alone_dynamics(settings, ModuleShape::Box, -0.5f, 1);
    sim::Bodies alone = falling_blocks({speed[k]}, 6, alone_dynamics.module_shape(), 6 * float(k));
    run(alone_dynamics, alone, 60, 1);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(alone.poses[size_t(i)], a.poses[8 * k + size_t(i)]) << "block " << k;
  }
}

// Islands stepped in batches (two blocks a world here): the same bits on one thread or two.
TEST(Dynamics, BatchesOfIslandsGiveTheSameBitsOnAnyThread) {
  PhysicsSettings settings;
  settings.anchor = false;
  Dynamics one(settings, ModuleShape::Box, -0.5f, 2), two(settings, ModuleShape::Box, -0.5f, 2);
  sim::Bodies a = falling_blocks({0.5f, -0.3f, 0.2f, 0.0f, 0.1f}, 6, one.module_shape()), b = a;
  std::vector<uint32_t> islands;
  run(one, a, 60, 1, &islands);
  run(two, b, 60, 2);
  EXPECT_EQ(islands.front(), 5u);
  EXPECT_TRUE(a == b);
  EXPECT_LT(a.poses[0].position[2], 2.5f);  // they fell
}

// Two blocks heading for each other become one island before they can touch, and collide.
TEST(Dynamics, BodiesThatCanMeetWithinAStepShareAnIsland) {
  PhysicsSettings settings;
  settings.anchor = false;
  Dynamics dynamics(settings, ModuleShape::Box, -0.5f);
  sim::Bodies b = falling_blocks({2.0f, -2.0f}, 4, dynamics.module_shape());
  std::vector<uint32_t> islands;
  run(dynamics, b, 40, 2, &islands);
  EXPECT_EQ(islands.front(), 2u);
  EXPECT_EQ(islands.back(), 1u);
  // They met: neither went on through the other (the left block's right face stays left of the
  // right block's left face).
  float left_max = -1e9f, right_min = 1e9f;
  for (int i = 0; i < 8; ++i) left_max = std::max(left_max, b.poses[size_t(i)].position[0]);
  for (int i = 8; i < 16; ++i) right_min = std::min(right_min, b.poses[size_t(i)].position[0]);
  EXPECT_LT(left_max, right_min - 0.9f);
  EXPECT_LT(b.clusters[0].velocity.linear[0], 1.0f);  // slowed by the hit
}

// A batch's Bullet world is kept from step to step while it holds the same bodies, and must
// compute what a world made afresh from the state computes (or a seek would change the run): two
// clusters colliding in the air and landing, stepped by one Dynamics throughout and by a new one
// at each step, have the same bits and forces at every step (a world whose manifolds kept their
// points fails at step 49). That the solver's order does not depend on the world's history, the
// seeks of PushWall show: there manifolds come and go (Bullet's islands fail them).
TEST(Dynamics, AKeptWorldComputesWhatAWorldMadeAfreshComputes) {
  PhysicsSettings settings;
  settings.anchor = false;
  Dynamics kept(settings, ModuleShape::Box, -0.5f);
  sim::Bodies a = falling_blocks({2.0f, -2.0f}, 4, kept.module_shape()), b = a;
  sim::WorkerPool workers(1);
  std::vector<float> force_a, force_b;
  for (int64_t step = 1; step <= 60; ++step) {
    kept.step(a, {}, step, &force_a, workers);
    place_members(a);
    Dynamics fresh(settings, ModuleShape::Box, -0.5f);
    fresh.step(b, {}, step, &force_b, workers);
    place_members(b);
    ASSERT_TRUE(a == b) << "step " << step;
    ASSERT_EQ(force_a, force_b) << "step " << step;
  }
  EXPECT_FALSE(a.contacts.empty());         // they touched
  EXPECT_LT(a.poses[0].position[2], 0.6f);  // and landed
}

// Over ranks each rank steps a run of the islands and the ranks swap what their islands wrote:
// every rank ends every step with the bits of one process. Three blocks: the first two heading
// for each other, the third falling on its own. On two ranks the second block is its own island,
// stepped by rank 1, until the two blocks can meet; then it shares the first block's island and
// rank 0 steps it: handed over mid-move, across the ranks' boundary.
TEST(Dynamics, RanksSteppingRunsOfTheIslandsEndEveryStepWithTheBitsOfOneProcess) {
  PhysicsSettings settings;
  settings.anchor = false;
  const std::vector<float> speed = {2.0f, -2.0f, 0.0f};
  constexpr int kSteps = 40;
  std::vector<sim::Bodies> expected;
  std::vector<std::vector<float>> expected_force;
  std::vector<uint32_t> islands;
  {
    Dynamics dynamics(settings, ModuleShape::Box, -0.5f, 1);
    sim::Bodies b = falling_blocks(speed, 4, dynamics.module_shape());
    sim::WorkerPool workers(1);
    std::vector<float> force;
    for (int64_t step = 1; step <= kSteps; ++step) {
      dynamics.step(b, {}, step, &force, workers);
      place_members(b);
      expected.push_back(b);
      expected_force.push_back(force);
      islands.push_back(dynamics.islands());
    }
  }
  ASSERT_EQ(islands.front(), 3u);
  ASSERT_EQ(islands.back(), 2u);  // the first two met
  struct Seen {
    int mismatch = -1;                           // the first step this rank's bodies differed
    std::vector<std::vector<uint32_t>> stepped;  // per step: the clusters it stepped
  };
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const std::vector<Seen> seen = sim::on_ranks(ranks, [&](sim::RankExchange& rank) {
      Dynamics dynamics(settings, ModuleShape::Box, -0.5f, 1);
      sim::Bodies b = falling_blocks(speed, 4, dynamics.module_shape());
      sim::WorkerPool workers(1);
      std::vector<float> force;
      Seen out;
      for (int64_t step = 1; step <= kSteps; ++step) {
        dynamics.step(b, {}, step, &force, workers, &rank);
        place_members(b);
        if (out.mismatch < 0 && (!(b == expected[size_t(step - 1)]) || force != expected_force[size_t(step - 1)]))
          out.mismatch = int(step);
        out.stepped.push_back(dynamics.stepped_clusters());
      }
      return out;
    });
    for (int r = 0; r < ranks; ++r) EXPECT_EQ(seen[size_t(r)].mismatch, -1) << "rank " << r;
    // Each cluster is stepped by exactly one rank, every step.
    for (int t = 0; t < kSteps; ++t) {
      std::vector<uint32_t> all;
      for (const Seen& s : seen) all.insert(all.end(), s.stepped[size_t(t)].begin(), s.stepped[size_t(t)].end());
      std::sort(all.begin(), all.end());
      EXPECT_EQ(all, (std::vector<uint32_t>{0, 1, 2})) << "step " << t + 1;
    }
    if (ranks == 2) {  // the hand-over
      EXPECT_EQ(seen[1].stepped.front(), (std::vector<uint32_t>{1, 2}));
      EXPECT_EQ(seen[0].stepped.back(), (std::vector<uint32_t>{0, 1}));
    }
  }
}

}  // namespace
}  // namespace dw::physics
