#include "render/meshes.h"

#include <gtest/gtest.h>

#include <cstring>

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

// The indexed form draws the very triangles of the list, in its order, bit for bit, with each
// distinct vertex stored once.
TEST(Meshes, TheIndexedFormHoldsTheSameTrianglesWithFewerVertices) {
  for (Shape shape : {Shape::Box, Shape::Cylinder, Shape::Sphere}) {
    const std::vector<MeshVertex> list = make_mesh(shape);
    const IndexedMesh indexed = make_indexed_mesh(shape);
    ASSERT_EQ(indexed.indices.size(), list.size());
    for (size_t i = 0; i < list.size(); ++i) {
      ASSERT_LT(indexed.indices[i], indexed.vertices.size());
      const MeshVertex& v = indexed.vertices[indexed.indices[i]];
      EXPECT_EQ(std::memcmp(&v, &list[i], sizeof v), 0) << "vertex " << i;
    }
    EXPECT_LE(indexed.vertices.size() * 3, list.size() * 2) << "at most two thirds of the vertices";
  }
  EXPECT_EQ(make_indexed_mesh(Shape::Box).vertices.size(), 24u);
}

}  // namespace
}  // namespace dw::render
