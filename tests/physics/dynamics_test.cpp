#include "physics/dynamics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "tests/physics/latched_block.h"

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
    dynamics.step(b, {}, step, force, workers);
    for (sim::ModuleId m = 0; m < n; ++m) total[m] += force[m];
  }
  EXPECT_GT(total[26], 0.0f);
  for (sim::ModuleId m = 0; m < 26; ++m) EXPECT_EQ(total[m], 0.0f) << "module " << m;
}

}  // namespace
}  // namespace dw::physics
