#include "physics/warm_start.h"

#include <algorithm>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>

#include "physics/convert.h"

namespace dw::physics {

WarmStartedWorld::WarmStartedWorld(btDispatcher* dispatcher, btBroadphaseInterface* broadphase,
                                   btConstraintSolver* solver, btCollisionConfiguration* config)
    : btDiscreteDynamicsWorld(dispatcher, broadphase, solver, config) {
  getSolverInfo().m_solverMode = kSolverMode;
}

void WarmStartedWorld::begin_step(std::span<const sim::ContactPoint> cache, ContactSide side) {
  cache_ = cache;
  side_ = std::move(side);
  started_ = false;
  btDispatcher& dispatcher = *getDispatcher();
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i)
    dispatcher.clearManifold(dispatcher.getManifoldByIndexInternal(i));
}

namespace {

// A point of the cache as a manifold point between `a` and `b` at their poses now, if Bullet's
// btPersistentManifold::refreshContactPoints would keep it: within the breaking threshold along
// its normal, and not slid further than that across it.
bool still_touching(const sim::ContactPoint& c, const btCollisionObject& a, const btCollisionObject& b, int child_a,
                    int child_b, btScalar threshold, btManifoldPoint& out) {
  out = btManifoldPoint(to_bt(c.local_a), to_bt(c.local_b), to_bt(c.normal), c.distance);
  out.m_positionWorldOnA = a.getWorldTransform()(out.m_localPointA);
  out.m_positionWorldOnB = b.getWorldTransform()(out.m_localPointB);
  out.m_distance1 = (out.m_positionWorldOnA - out.m_positionWorldOnB).dot(out.m_normalWorldOnB);
  if (out.m_distance1 > threshold) return false;
  const btVector3 across = out.m_positionWorldOnB - (out.m_positionWorldOnA - out.m_normalWorldOnB * out.m_distance1);
  if (across.length2() > threshold * threshold) return false;
  out.m_index0 = out.m_partId0 = child_a;
  out.m_index1 = out.m_partId1 = child_b;
  out.m_combinedFriction = btManifoldResult::calculateCombinedFriction(&a, &b);
  out.m_combinedRestitution = btManifoldResult::calculateCombinedRestitution(&a, &b);
  return true;
}

void carry_over(const sim::ContactPoint& c, btManifoldPoint& point) {
  point.m_appliedImpulse = c.impulse;
  point.m_appliedImpulseLateral1 = c.friction[0];
  point.m_appliedImpulseLateral2 = c.friction[1];
  point.m_lateralFrictionDir1 = to_bt(c.direction[0]);
  point.m_lateralFrictionDir2 = to_bt(c.direction[1]);
  point.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
  point.m_lifeTime = int(c.age) + 1;
}

}  // namespace

// Per manifold: each new point takes over the nearest cached point of its two modules (each
// cached point once: its impulse was applied once), and the cached points no new point took stay
// if Bullet's refresh would keep them — so a contact builds up its points over steps, as in one
// long-lived Bullet world. A manifold's two modules are those of its first point, or of its two
// bodies when it has none and neither is a compound (a compound's child is known only by a point).
void WarmStartedWorld::warm_start() {
  btDispatcher& dispatcher = *getDispatcher();
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(i);
    const btCollisionObject& a = *manifold.getBody0();
    const btCollisionObject& b = *manifold.getBody1();
    const int child_a = manifold.getNumContacts() > 0 ? manifold.getContactPoint(0).m_index0 : -1;
    const int child_b = manifold.getNumContacts() > 0 ? manifold.getContactPoint(0).m_index1 : -1;
    const int64_t side_a = side_(&a, child_a), side_b = side_(&b, child_b);
    if (side_a < 0 || side_b < 0) continue;
    const sim::ContactPoint key{.a = uint32_t(side_a), .b = uint32_t(side_b)};
    const auto [first, last] = std::equal_range(cache_.begin(), cache_.end(), key, sim::contact_pair_less);
    if (first == last) continue;
    const btScalar threshold = manifold.getContactBreakingThreshold();
    uint32_t taken = 0;  // bit k: the pair's k-th cached point is taken (a pair holds a few)
    const auto cached = std::span(first, std::min<size_t>(size_t(last - first), 32));
    for (int p = 0; p < manifold.getNumContacts(); ++p) {
      btManifoldPoint& point = manifold.getContactPoint(p);
      if (point.m_index0 != child_a || point.m_index1 != child_b) continue;
      int nearest = -1;
      btScalar shortest = threshold * threshold;
      for (size_t k = 0; k < cached.size(); ++k) {
        const btScalar d = (to_bt(cached[k].local_a) - point.m_localPointA).length2();
        if (d < shortest && !(taken >> k & 1u)) {
          shortest = d;
          nearest = int(k);
        }
      }
      if (nearest < 0) continue;
      taken |= 1u << nearest;
      carry_over(cached[size_t(nearest)], point);
    }
    for (size_t k = 0; k < cached.size(); ++k) {
      btManifoldPoint kept;
      if ((taken >> k & 1u) || !still_touching(cached[k], a, b, child_a, child_b, threshold, kept)) continue;
      carry_over(cached[k], kept);
      manifold.addManifoldPoint(kept);
    }
  }
}

namespace {

// A manifold's place in the solver's order: its bodies' broadphase ids (given in the order the
// bodies were added, the same in every world made from the same bodies), then the children its
// points lie on (a cluster's pair has a manifold for each pair of children that touch).
struct ManifoldKey {
  int body0, body1, child0, child1;
  explicit ManifoldKey(const btPersistentManifold* m)
      : body0(m->getBody0()->getBroadphaseHandle()->m_uniqueId),
        body1(m->getBody1()->getBroadphaseHandle()->m_uniqueId),
        child0(m->getContactPoint(0).m_index0),
        child1(m->getContactPoint(0).m_index1) {}
  auto operator<=>(const ManifoldKey&) const = default;
};

// A contact resists rolling and spinning as much as the more resistant of its two bodies does (a
// round module's rolling_friction, physics/settings.h; the ground, boxes, prisms and props have
// none), not as Bullet combines them (each body's rolling friction times the other's sliding
// friction, summed: a disc would meet on the ground half the resistance it meets on another disc).
// Set on every point before each solve, the points Bullet adds in a substep included.
void resist_rolling(btPersistentManifold& manifold) {
  const btCollisionObject& a = *manifold.getBody0();
  const btCollisionObject& b = *manifold.getBody1();
  const btScalar rolling = std::max(a.getRollingFriction(), b.getRollingFriction());
  const btScalar spinning = std::max(a.getSpinningFriction(), b.getSpinningFriction());
  for (int p = 0; p < manifold.getNumContacts(); ++p) {
    btManifoldPoint& point = manifold.getContactPoint(p);
    point.m_combinedRollingFriction = rolling;
    point.m_combinedSpinningFriction = spinning;
  }
}

}  // namespace

// Bullet's own solveConstraints without its islands (docs: the class comment): one group of every
// body, and the manifolds with points in their canonical order.
void WarmStartedWorld::solveConstraints(btContactSolverInfo& info) {
  if (!started_) warm_start();
  started_ = true;
  btDispatcher& dispatcher = *getDispatcher();
  solved_.clear();
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(i);
    if (manifold->getNumContacts() > 0 && dispatcher.needsResponse(manifold->getBody0(), manifold->getBody1())) {
      solved_.push_back(manifold);
      resist_rolling(*manifold);
    }
  }
  std::sort(solved_.begin(), solved_.end(), [](const btPersistentManifold* x, const btPersistentManifold* y) {
    return ManifoldKey(x) < ManifoldKey(y);
  });
  btCollisionObjectArray& objects = getCollisionObjectArray();
  m_constraintSolver->prepareSolve(objects.size(), int(solved_.size()));
  m_constraintSolver->solveGroup(objects.size() > 0 ? &objects[0] : nullptr, objects.size(),
                                 solved_.empty() ? nullptr : solved_.data(), int(solved_.size()), nullptr, 0, info,
                                 m_debugDrawer, &dispatcher);
  m_constraintSolver->allSolved(info, m_debugDrawer);
}

void WarmStartedWorld::keep_contacts(std::vector<sim::ContactPoint>& out) {
  btDispatcher& dispatcher = *getDispatcher();
  size_t points = 0;
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i)
    points += size_t(dispatcher.getManifoldByIndexInternal(i)->getNumContacts());
  out.reserve(out.size() + points);
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(i);
    for (int p = 0; p < manifold.getNumContacts(); ++p) {
      const btManifoldPoint& point = manifold.getContactPoint(p);
      const int64_t a = side_(manifold.getBody0(), point.m_index0), b = side_(manifold.getBody1(), point.m_index1);
      if (a < 0 || b < 0) continue;
      out.push_back({.a = uint32_t(a),
                     .b = uint32_t(b),
                     .local_a = from_bt(point.m_localPointA),
                     .local_b = from_bt(point.m_localPointB),
                     .normal = from_bt(point.m_normalWorldOnB),
                     .distance = float(point.getDistance()),
                     .impulse = float(point.m_appliedImpulse),
                     .friction = {float(point.m_appliedImpulseLateral1), float(point.m_appliedImpulseLateral2)},
                     .direction = {from_bt(point.m_lateralFrictionDir1), from_bt(point.m_lateralFrictionDir2)},
                     .age = uint32_t(std::max(point.m_lifeTime, 0))});
    }
  }
}

}  // namespace dw::physics
