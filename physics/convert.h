// Between the plain poses of State and Bullet's transforms (physics/ only: no Bullet header is
// seen outside this folder).
#pragma once

#include <LinearMath/btTransform.h>

#include "sim/bodies.h"

namespace dw::physics {

inline btVector3 to_bt(const sim::Vec3& v) { return {v[0], v[1], v[2]}; }
inline sim::Vec3 from_bt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

inline btTransform to_bt(const sim::Pose& p) {
  const auto& q = p.orientation;
  return btTransform(btQuaternion(q[0], q[1], q[2], q[3]), to_bt(p.position));
}

inline sim::Pose from_bt(const btTransform& t) {
  const btQuaternion q = t.getRotation();
  return {from_bt(t.getOrigin()), {q.x(), q.y(), q.z(), q.w()}};
}

}  // namespace dw::physics
