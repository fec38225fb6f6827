// Boxes on the ground in one query (docs/design.md §8a). Bullet's convex-plane algorithm finds the
// deepest point of a box (and a few more by tilting it), leaving the face's other corners to build
// up over later steps; a box resting on the ground then stands on three corners and rocks, and one
// pressed by a heavy load sinks through. Here every corner of the box's core (its extents less the
// margin, rounded by the margin as Bullet rounds it) within the contact breaking threshold of the
// plane is a point, the four deepest at most: a box on a face has its four corners at once.
#pragma once

#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>

namespace dw::physics {

// The algorithm's factory for (box, plane) pairs, or (plane, box) when `swapped`; registered with
// btCollisionDispatcher::registerCollisionCreateFunc.
struct BoxPlaneCreateFunc final : btCollisionAlgorithmCreateFunc {
  explicit BoxPlaneCreateFunc(bool swapped) { m_swapped = swapped; }
  btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                 const btCollisionObjectWrapper* body0,
                                                 const btCollisionObjectWrapper* body1) override;
};

}  // namespace dw::physics
