#include "physics/pivot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "physics/dynamics.h"

namespace dw::physics {
namespace {

float distance(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

sim::Mover mover_of(const PivotArc& arc, const sim::Vec3& from) {
  sim::Mover m;
  m.from.position = from;
  m.pivot = arc.pivot;
  m.axis = arc.axis;
  m.angle = arc.angle;
  m.spin = arc.spin;
  return m;
}

// A cube on top of another rolls about the edge on the side it goes to, a quarter turn; over the
// edge onto the side face, half a turn about the same edge.
TEST(PivotArcs, CubesTurnAboutTheSharedEdge) {
  for (const auto& [offset, angle] :
       {std::pair{sim::Vec3{1, 0, 0}, float(M_PI / 2)}, {sim::Vec3{1, 0, -1}, float(M_PI)}}) {
    const auto planned = pivot_arcs(ModuleShape::Box, {0, 0, 1}, {0, 0, 0}, offset);
    ASSERT_TRUE(std::holds_alternative<std::vector<PivotArc>>(planned)) << std::get<std::string>(planned);
    const auto& arcs = std::get<std::vector<PivotArc>>(planned);
    ASSERT_EQ(arcs.size(), 1u);
    EXPECT_EQ(arcs[0].pivot, (sim::Vec3{0.5f, 0, 0.5f}));
    EXPECT_EQ(arcs[0].axis, (sim::Vec3{0, 1, 0}));
    EXPECT_FLOAT_EQ(arcs[0].angle, angle);
    const sim::Pose end = turn(mover_of(arcs[0], {0, 0, 1}), 1);
    EXPECT_LT(distance(end.position, {offset[0], offset[1], 1 + offset[2]}), 1e-5f);
  }
  EXPECT_TRUE(std::holds_alternative<std::string>(pivot_arcs(ModuleShape::Box, {0, 0, 1}, {0, 0, 0}, {1, 1, 0})));
  EXPECT_TRUE(std::holds_alternative<std::string>(pivot_arcs(ModuleShape::Box, {0, 0, 1}, {1, 0, 0}, {1, 0, 0})))
      << "a diagonal module shares no face";
}

// A sphere has three ways from one cell to the next around a neighbour: over its top, and in the
// groove between it and either sphere touching all three. Each ends in the cell and keeps touching
// the neighbour all the way; the groove arcs keep touching their second sphere too.
TEST(PivotArcs, SpheresRollOverTheNeighbourOrAlongAGroove) {
  const sim::Vec3 c{0.5f, 0.5f, std::sqrt(0.5f)}, p{1, 0, 0}, offset{1, 0, 0};
  const sim::Vec3 d{c[0] + offset[0], c[1], c[2]};
  const auto planned = pivot_arcs(ModuleShape::Sphere, c, p, offset);
  ASSERT_TRUE(std::holds_alternative<std::vector<PivotArc>>(planned)) << std::get<std::string>(planned);
  const auto& arcs = std::get<std::vector<PivotArc>>(planned);
  ASSERT_EQ(arcs.size(), 3u);
  const sim::Vec3 grooves[] = {{1, 1, 0}, {1, -1 / 3.f, 2 * std::sqrt(2.f) / 3}};  // under, and the other side
  for (size_t i = 0; i < arcs.size(); ++i) {
    const sim::Mover m = mover_of(arcs[i], c);
    EXPECT_LT(distance(turn(m, 1).position, d), 1e-5f) << "arc " << i;
    for (float f = 0; f <= 1; f += 0.125f) {
      EXPECT_NEAR(distance(turn(m, f).position, p), 1, 1e-5f) << "arc " << i << " at " << f;
      if (i > 0) {
        EXPECT_NEAR(distance(turn(m, f).position, grooves[i - 1]), 1, 1e-4f) << "arc " << i << " at " << f;
      }
    }
  }
  EXPECT_TRUE(std::holds_alternative<std::string>(pivot_arcs(ModuleShape::Sphere, c, p, {2, 0, 0})));
}

}  // namespace
}  // namespace dw::physics
