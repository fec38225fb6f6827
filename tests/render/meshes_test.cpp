#include "render/meshes.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace dw::render {
namespace {

// Every triangle winds counter-clockwise seen from outside (the renderer culls back faces), its
// normals point outwards, and the shape is one unit across.
void expect_closed_outward(Shape shape) {
  const std::vector<MeshVertex> v = make_mesh(shape);
  ASSERT_FALSE(v.empty());
  ASSERT_EQ(v.size() % 3, 0u);
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (size_t i = 0; i < v.size(); i += 3) {
    const glm::vec3 a(v[i].position[0], v[i].position[1], v[i].position[2]);
    const glm::vec3 b(v[i + 1].position[0], v[i + 1].position[1], v[i + 1].position[2]);
    const glm::vec3 c(v[i + 2].position[0], v[i + 2].position[1], v[i + 2].position[2]);
    const glm::vec3 face = glm::cross(b - a, c - a);
    const glm::vec3 centroid = (a + b + c) / 3.0f;
    EXPECT_GT(glm::dot(face, centroid), 0) << "triangle " << i / 3;
    for (size_t k = i; k < i + 3; ++k) {
      const glm::vec3 n(v[k].normal[0], v[k].normal[1], v[k].normal[2]);
      EXPECT_NEAR(glm::length(n), 1, 1e-5);
      EXPECT_GT(glm::dot(n, face), 0) << "vertex " << k;
      lo = glm::min(lo, glm::vec3(v[k].position[0], v[k].position[1], v[k].position[2]));
      hi = glm::max(hi, glm::vec3(v[k].position[0], v[k].position[1], v[k].position[2]));
    }
  }
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(lo[d], -0.5f, 1e-5);
    EXPECT_NEAR(hi[d], 0.5f, 1e-5);
  }
}

TEST(Meshes, BoxIsClosedAndOutward) {
  expect_closed_outward(Shape::Box);
  EXPECT_EQ(make_mesh(Shape::Box).size(), 36u);
}
TEST(Meshes, CylinderIsClosedAndOutward) { expect_closed_outward(Shape::Cylinder); }
TEST(Meshes, SphereIsClosedAndOutward) { expect_closed_outward(Shape::Sphere); }

}  // namespace
}  // namespace dw::render
