#include "physics/settings.h"  // default_shape, defined in physics/shapes.cpp

#include <gtest/gtest.h>

namespace dw::physics {
namespace {

// The one mapping from lattice to module shape; the view draws what the physics simulates.
TEST(DefaultShape, BoxesCylindersAndSpheresByLattice) {
  EXPECT_EQ(default_shape(sim::LatticeKind::Cubic), ModuleShape::Box);
  EXPECT_EQ(default_shape(sim::LatticeKind::Square2d), ModuleShape::Box);
  EXPECT_EQ(default_shape(sim::LatticeKind::Hex2d), ModuleShape::Cylinder);
  EXPECT_EQ(default_shape(sim::LatticeKind::Ring), ModuleShape::Sphere);
  EXPECT_EQ(default_shape(sim::LatticeKind::Line), ModuleShape::Sphere);
}

}  // namespace
}  // namespace dw::physics
