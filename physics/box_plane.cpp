#include "physics/box_plane.h"

#include <algorithm>
#include <array>
#include <new>

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace dw::physics {
namespace {

class BoxPlaneAlgorithm final : public btCollisionAlgorithm {
 public:
  BoxPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* box,
                    const btCollisionObjectWrapper* plane, bool swapped)
      : btCollisionAlgorithm(info), swapped_(swapped) {
    manifold_ = m_dispatcher->getNewManifold(box->getCollisionObject(), plane->getCollisionObject());
  }
  ~BoxPlaneAlgorithm() override { m_dispatcher->releaseManifold(manifold_); }

  void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                        const btDispatcherInfo&, btManifoldResult* result) override {
    const btCollisionObjectWrapper* box = swapped_ ? body1 : body0;
    const btCollisionObjectWrapper* plane = swapped_ ? body0 : body1;
    const auto& shape = *static_cast<const btBoxShape*>(box->getCollisionShape());
    const auto& ground = *static_cast<const btStaticPlaneShape*>(plane->getCollisionShape());
    result->setPersistentManifold(manifold_);
    const btTransform& at = box->getWorldTransform();
    const btVector3 normal = plane->getWorldTransform().getBasis() * ground.getPlaneNormal();
    const btVector3 on_plane = plane->getWorldTransform()(ground.getPlaneNormal() * ground.getPlaneConstant());
    const btVector3 half = shape.getHalfExtentsWithoutMargin();
    const btScalar margin = shape.getMargin(), reach = manifold_->getContactBreakingThreshold();
    // The corners within reach, deepest first (corner order breaks ties: the result is a function
    // of the poses alone).
    std::array<std::pair<btScalar, int>, 8> near{};
    int found = 0;
    for (int corner = 0; corner < 8; ++corner) {
      const btVector3 local((corner & 1) ? half.x() : -half.x(), (corner & 2) ? half.y() : -half.y(),
                            (corner & 4) ? half.z() : -half.z());
      const btScalar distance = normal.dot(at(local) - on_plane) - margin;
      if (distance < reach) near[size_t(found++)] = {distance, corner};
    }
    std::sort(near.begin(), near.begin() + found);
    for (int i = 0; i < std::min(found, 4); ++i) {
      const int corner = near[size_t(i)].second;
      const btVector3 local((corner & 1) ? half.x() : -half.x(), (corner & 2) ? half.y() : -half.y(),
                            (corner & 4) ? half.z() : -half.z());
      const btScalar distance = near[size_t(i)].first;
      // The plane's point under the corner's rounded tip; the normal points from the plane to the box.
      result->addContactPoint(normal, at(local) - normal * (margin + distance), distance);
    }
    result->refreshContactPoints();
  }

  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return 1;
  }
  void getAllContactManifolds(btManifoldArray& manifolds) override { manifolds.push_back(manifold_); }

 private:
  btPersistentManifold* manifold_;
  bool swapped_;
};

}  // namespace

btCollisionAlgorithm* BoxPlaneCreateFunc::CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                                   const btCollisionObjectWrapper* body0,
                                                                   const btCollisionObjectWrapper* body1) {
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(BoxPlaneAlgorithm));
  return m_swapped ? new (memory) BoxPlaneAlgorithm(info, body1, body0, true)
                   : new (memory) BoxPlaneAlgorithm(info, body0, body1, false);
}

}  // namespace dw::physics
