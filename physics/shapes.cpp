#include "physics/shapes.h"

#include <cmath>
#include <numbers>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

namespace dw::physics {

ModuleShape default_shape(sim::LatticeKind kind) {
  switch (kind) {
    case sim::LatticeKind::Cubic:
    case sim::LatticeKind::Square2d: return ModuleShape::Box;
    case sim::LatticeKind::Hex2d: return ModuleShape::Cylinder;
    case sim::LatticeKind::Hex2dVertical: return ModuleShape::Disc;  // 2-D catoms standing in x-z
    case sim::LatticeKind::Ring:
    case sim::LatticeKind::Line:
    case sim::LatticeKind::Fcc: return ModuleShape::Sphere;  // Catoms 3D are round
  }
  return ModuleShape::Box;
}

namespace {

// A Hexanode: an upright hexagonal prism one size across its faces and one high, its faces
// square to the six ways to hex2d's neighbours (0, 60, ... 300 degrees about z), so its corners
// point at 30, 90, ... 270. A hull's margin lies outside its points: they are drawn in by it, so
// that faces one size apart touch at distance 0 (the corners are rounded by the margin).
std::unique_ptr<btCollisionShape> hex_prism() {
  auto hull = std::make_unique<btConvexHullShape>();
  const btScalar margin = hull->getMargin(), apothem = 0.5f - margin;
  const btScalar corner = apothem / std::cos(std::numbers::pi_v<btScalar> / 6), half_height = 0.5f - margin;
  for (int k = 0; k < 6; ++k) {
    const btScalar a = std::numbers::pi_v<btScalar> / 6 + k * std::numbers::pi_v<btScalar> / 3;
    for (btScalar z : {-half_height, half_height})
      hull->addPoint(btVector3(corner * std::cos(a), corner * std::sin(a), z), false);
  }
  hull->recalcLocalAabb();
  return hull;
}

}  // namespace

std::unique_ptr<btCollisionShape> make_module_shape(ModuleShape shape) {
  const btVector3 half(0.5f, 0.5f, 0.5f);
  switch (shape) {
    case ModuleShape::Box: return std::make_unique<btBoxShape>(half);
    case ModuleShape::Cylinder: return std::make_unique<btCylinderShapeZ>(half);  // upright
    case ModuleShape::Sphere: return std::make_unique<btSphereShape>(0.5f);
    case ModuleShape::Disc: return std::make_unique<btCylinderShape>(half);  // axis y: across the x-z plane
    case ModuleShape::HexPrism: return hex_prism();
  }
  return nullptr;
}

bool rolls(ModuleShape shape) {
  return shape == ModuleShape::Sphere || shape == ModuleShape::Cylinder || shape == ModuleShape::Disc;
}

std::unique_ptr<btCollisionShape> make_prop_shape(const PropSpec& prop) {
  if (prop.shape == ModuleShape::Box)
    return std::make_unique<btBoxShape>(btVector3(prop.size[0], prop.size[1], prop.size[2]) * 0.5f);
  if (prop.shape == ModuleShape::Cylinder)
    return std::make_unique<btCylinderShapeZ>(btVector3(prop.size[0], prop.size[1], prop.size[2]) * 0.5f);
  return std::make_unique<btSphereShape>(prop.size[0] * 0.5f);
}

}  // namespace dw::physics
