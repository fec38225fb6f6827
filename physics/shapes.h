// The collision shapes of modules and props: one module size across, Bullet's margin inside it
// (so that shapes one size apart touch at distance 0).
#pragma once

#include <memory>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

#include "physics/settings.h"

namespace dw::physics {

std::unique_ptr<btCollisionShape> make_module_shape(ModuleShape shape);
// Whether a module of this shape rolls on its round side (and so has rolling resistance:
// PhysicsSettings::rolling_friction).
bool rolls(ModuleShape shape);
std::unique_ptr<btCollisionShape> make_prop_shape(const PropSpec& prop);

}  // namespace dw::physics
