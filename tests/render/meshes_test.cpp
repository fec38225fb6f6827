#include "render/meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/glm.hpp>

namespace dw::render {
namespace {

// Every triangle winds counter-clockwise seen from outside (the renderer culls back faces), its
// normals point outwards, and the shape is one unit across (`half`: half its extent along each
// axis; a hexagonal prism reaches its corners, 1/sqrt(3), along y).
void expect_closed_outward(Shape shape, glm::vec3 half = glm::vec3(0.5f)) {
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
    EXPECT_NEAR(lo[d], -half[d], 1e-5);
    EXPECT_NEAR(hi[d], half[d], 1e-5);
  }
}

TEST(Meshes, BoxIsClosedAndOutward) {
  expect_closed_outward(Shape::Box);
  EXPECT_EQ(make_mesh(Shape::Box).size(), 36u);
}
TEST(Meshes, CylinderIsClosedAndOutward) { expect_closed_outward(Shape::Cylinder); }
TEST(Meshes, SphereIsClosedAndOutward) { expect_closed_outward(Shape::Sphere); }
// A 2-D catom of a vertical plane: the cylinder lying along y, round in x-z.
TEST(Meshes, DiscIsClosedOutwardAndLiesAlongY) {
  expect_closed_outward(Shape::Disc);
  for (const MeshVertex& v : make_mesh(Shape::Disc)) {
    if (std::abs(v.normal[1]) < 0.5f) {
      EXPECT_NEAR(std::hypot(v.position[0], v.position[2]), 0.5f, 1e-5);
    }
  }
}
// A Hexanode: six flat sides whose normals point at hex2d's six neighbours (0, 60, ... 300
// degrees), each half a size from the centre; corners 1/sqrt(3) out.
TEST(Meshes, HexPrismIsClosedOutwardWithFacesTowardsTheSixNeighbours) {
  expect_closed_outward(Shape::HexPrism, glm::vec3(0.5f, 1 / std::sqrt(3.0f), 0.5f));
  int sides = 0;
  for (const MeshVertex& v : make_mesh(Shape::HexPrism)) {
    if (std::abs(v.normal[2]) > 0.5f) continue;
    ++sides;
    const float angle = std::atan2(v.normal[1], v.normal[0]) * 3 / float(M_PI);  // in sixths of a turn
    EXPECT_NEAR(angle, std::round(angle), 1e-5);
    EXPECT_NEAR(v.position[0] * v.normal[0] + v.position[1] * v.normal[1], 0.5f, 1e-5);
  }
  EXPECT_EQ(sides, 6 * 6);
}

// The indexed form draws the very triangles of the list, in its order, bit for bit, with each
// distinct vertex stored once.
TEST(Meshes, TheIndexedFormHoldsTheSameTrianglesWithFewerVertices) {
  for (Shape shape : {Shape::Box, Shape::Cylinder, Shape::Sphere, Shape::Disc, Shape::HexPrism}) {
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
