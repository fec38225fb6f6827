#include "physics/shapes.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

namespace dw::physics {

ModuleShape default_shape(sim::LatticeKind kind) {
  switch (kind) {
    case sim::LatticeKind::Cubic:
    case sim::LatticeKind::Square2d: return ModuleShape::Box;
    case sim::LatticeKind::Hex2d: return ModuleShape::Cylinder;
    case sim::LatticeKind::Ring:
    case sim::LatticeKind::Line:
    case sim::LatticeKind::Fcc: return ModuleShape::Sphere;  // Catoms 3D are round
  }
  return ModuleShape::Box;
}

std::unique_ptr<btCollisionShape> make_module_shape(ModuleShape shape) {
  const btVector3 half(0.5f, 0.5f, 0.5f);
  switch (shape) {
    case ModuleShape::Box: return std::make_unique<btBoxShape>(half);
    case ModuleShape::Cylinder: return std::make_unique<btCylinderShapeZ>(half);  // upright
    case ModuleShape::Sphere: return std::make_unique<btSphereShape>(0.5f);
  }
  return nullptr;
}

std::unique_ptr<btCollisionShape> make_prop_shape(const PropSpec& prop) {
  if (prop.shape == ModuleShape::Box)
    return std::make_unique<btBoxShape>(btVector3(prop.size[0], prop.size[1], prop.size[2]) * 0.5f);
  if (prop.shape == ModuleShape::Cylinder)
    return std::make_unique<btCylinderShapeZ>(btVector3(prop.size[0], prop.size[1], prop.size[2]) * 0.5f);
  return std::make_unique<btSphereShape>(prop.size[0] * 0.5f);
}

}  // namespace dw::physics
