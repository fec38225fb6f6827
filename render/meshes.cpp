#include "render/meshes.h"

#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <numbers>

namespace dw::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

void add(std::vector<MeshVertex>& out, float x, float y, float z, float nx, float ny, float nz) {
  out.push_back({{x, y, z}, {nx, ny, nz}});
}

std::vector<MeshVertex> box() {
  std::vector<MeshVertex> v;
  // Each face: its normal axis, the sign, and two axes spanning it (counter-clockwise seen from
  // outside).
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      float corners[4][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
      if (sign < 0)
        for (auto& c : corners) std::swap(c[0], c[1]);
      for (int i : {0, 1, 2, 0, 2, 3}) {
        float p[3], n[3] = {0, 0, 0};
        p[axis] = 0.5f * sign;
        p[u] = corners[i][0];
        p[w] = corners[i][1];
        n[axis] = sign;
        add(v, p[0], p[1], p[2], n[0], n[1], n[2]);
      }
    }
  }
  return v;
}

std::vector<MeshVertex> cylinder() {
  constexpr int kSegments = 32;
  std::vector<MeshVertex> v;
  for (int i = 0; i < kSegments; ++i) {
    const float a0 = 2 * kPi * float(i) / kSegments, a1 = 2 * kPi * float(i + 1) / kSegments;
    const float c0 = std::cos(a0), s0 = std::sin(a0), c1 = std::cos(a1), s1 = std::sin(a1);
    // Side: two triangles with radial normals.
    add(v, 0.5f * c0, 0.5f * s0, -0.5f, c0, s0, 0);
    add(v, 0.5f * c1, 0.5f * s1, -0.5f, c1, s1, 0);
    add(v, 0.5f * c1, 0.5f * s1, 0.5f, c1, s1, 0);
    add(v, 0.5f * c0, 0.5f * s0, -0.5f, c0, s0, 0);
    add(v, 0.5f * c1, 0.5f * s1, 0.5f, c1, s1, 0);
    add(v, 0.5f * c0, 0.5f * s0, 0.5f, c0, s0, 0);
    // Caps.
    add(v, 0, 0, 0.5f, 0, 0, 1);
    add(v, 0.5f * c0, 0.5f * s0, 0.5f, 0, 0, 1);
    add(v, 0.5f * c1, 0.5f * s1, 0.5f, 0, 0, 1);
    add(v, 0, 0, -0.5f, 0, 0, -1);
    add(v, 0.5f * c1, 0.5f * s1, -0.5f, 0, 0, -1);
    add(v, 0.5f * c0, 0.5f * s0, -0.5f, 0, 0, -1);
  }
  return v;
}

// A 2-D catom of a vertical plane: the cylinder turned a quarter about x, its axis along y (a
// proper turn, (x, y, z) -> (x, -z, y): the triangles keep their winding).
std::vector<MeshVertex> disc() {
  std::vector<MeshVertex> v = cylinder();
  for (MeshVertex& m : v) {
    for (float* a : {m.position, m.normal}) {
      const float y = a[1];
      a[1] = -a[2];
      a[2] = y;
    }
  }
  return v;
}

// A Hexanode: an upright hexagonal prism one size across its faces (apothem 0.5), its corners at
// 30, 90, ... 330 degrees about z, its faces square to the ways to hex2d's six neighbours.
std::vector<MeshVertex> hex_prism() {
  std::vector<MeshVertex> v;
  const float corner = 0.5f / std::cos(kPi / 6);
  for (int k = 0; k < 6; ++k) {
    const float a0 = kPi / 6 + float(k) * kPi / 3, a1 = a0 + kPi / 3, face = a0 + kPi / 6;
    const float x0 = corner * std::cos(a0), y0 = corner * std::sin(a0), x1 = corner * std::cos(a1),
                y1 = corner * std::sin(a1), nx = std::cos(face), ny = std::sin(face);
    add(v, x0, y0, -0.5f, nx, ny, 0);
    add(v, x1, y1, -0.5f, nx, ny, 0);
    add(v, x1, y1, 0.5f, nx, ny, 0);
    add(v, x0, y0, -0.5f, nx, ny, 0);
    add(v, x1, y1, 0.5f, nx, ny, 0);
    add(v, x0, y0, 0.5f, nx, ny, 0);
    add(v, 0, 0, 0.5f, 0, 0, 1);
    add(v, x0, y0, 0.5f, 0, 0, 1);
    add(v, x1, y1, 0.5f, 0, 0, 1);
    add(v, 0, 0, -0.5f, 0, 0, -1);
    add(v, x1, y1, -0.5f, 0, 0, -1);
    add(v, x0, y0, -0.5f, 0, 0, -1);
  }
  return v;
}

std::vector<MeshVertex> sphere() {
  constexpr int kRings = 16, kSegments = 32;
  std::vector<MeshVertex> v;
  auto point = [&](int ring, int segment) {
    const float theta = kPi * float(ring) / kRings;  // from the top
    const float phi = 2 * kPi * float(segment) / kSegments;
    const float x = std::sin(theta) * std::cos(phi), y = std::sin(theta) * std::sin(phi), z = std::cos(theta);
    add(v, 0.5f * x, 0.5f * y, 0.5f * z, x, y, z);
  };
  for (int r = 0; r < kRings; ++r) {
    for (int s = 0; s < kSegments; ++s) {
      if (r > 0) {  // the top row is a fan of triangles
        point(r, s), point(r + 1, s), point(r, s + 1);
      }
      if (r < kRings - 1) {
        point(r, s + 1), point(r + 1, s), point(r + 1, s + 1);
      }
    }
  }
  return v;
}

}  // namespace

std::vector<MeshVertex> make_mesh(Shape shape) {
  switch (shape) {
    case Shape::Box: return box();
    case Shape::Cylinder: return cylinder();
    case Shape::Sphere: return sphere();
    case Shape::Disc: return disc();
    case Shape::HexPrism: return hex_prism();
  }
  return {};
}

IndexedMesh make_indexed_mesh(Shape shape) {
  IndexedMesh mesh;
  // Vertices are the same when their bits are: merged, they draw exactly the triangles they did.
  std::map<std::array<uint32_t, 6>, uint32_t> index_of;
  for (const MeshVertex& v : make_mesh(shape)) {
    const std::array<uint32_t, 6> bits{std::bit_cast<uint32_t>(v.position[0]), std::bit_cast<uint32_t>(v.position[1]),
                                       std::bit_cast<uint32_t>(v.position[2]), std::bit_cast<uint32_t>(v.normal[0]),
                                       std::bit_cast<uint32_t>(v.normal[1]),   std::bit_cast<uint32_t>(v.normal[2])};
    const auto [at, added] = index_of.try_emplace(bits, uint32_t(mesh.vertices.size()));
    if (added) mesh.vertices.push_back(v);
    mesh.indices.push_back(at->second);
  }
  return mesh;
}

}  // namespace dw::render
